// The reader of Abaqus *MATRIX GENERATE matrices (matrix input format) as a reduced body:
// entries against the springs and masses the files describe (their header comments), the DOF
// list, and one refusal per rule at its line. The files in tests/data/abaqus are hand-written in
// the documented layout (no Abaqus here).
#include "io/abaqus_matrix.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include <Eigen/Eigenvalues>

#include "core/errors.h"

namespace stickslip {
namespace {

const std::string kDir = std::string(STICKSLIP_TEST_DATA_DIR) + "/abaqus/";

int dof_of(const ReducedBody& b, int node, int direction) {
  for (int k = 0; k < b.size(); ++k) {
    if (b.dofs[k].node_id == node && b.dofs[k].direction == direction) return k;
  }
  ADD_FAILURE() << "no DOF " << node << "/" << direction;
  return 0;
}

TEST(AbaqusMatrix, TwoMassesOnSpringsGiveTheirMatricesAndFrequencies) {
  const ReducedBody b =
      read_abaqus_reduced_body(kDir + "two_masses_STIF1.mtx", kDir + "two_masses_MASS1.mtx");
  ASSERT_EQ(b.size(), 6);
  EXPECT_EQ(b.num_physical(), 6);
  const double k[3] = {2e6, 3e6, 4e6}, ground = 1e6, m1 = 2.0, m2 = 0.5;
  for (int d = 0; d < 3; ++d) {
    const int a = dof_of(b, 10, d), c = dof_of(b, 20, d);
    EXPECT_EQ(b.K(a, a), k[d] + ground);
    EXPECT_EQ(b.K(c, c), k[d]);
    EXPECT_EQ(b.K(a, c), -k[d]);  // given once (lower triangle), mirrored
    EXPECT_EQ(b.K(c, a), -k[d]);
    EXPECT_EQ(b.M(a, a), m1);
    EXPECT_EQ(b.M(c, c), m2);
    // Two masses on springs: ω² are the roots of m1 m2 ω⁴ − (m1 k + m2 (k + g)) ω² + k g = 0.
    const double p = (m1 * k[d] + m2 * (k[d] + ground)) / (m1 * m2), q = k[d] * ground / (m1 * m2);
    const double w2[2] = {0.5 * (p - std::sqrt(p * p - 4 * q)),
                          0.5 * (p + std::sqrt(p * p - 4 * q))};
    Eigen::Matrix2d K2, M2;
    K2 << b.K(a, a), b.K(a, c), b.K(c, a), b.K(c, c);
    M2 << b.M(a, a), 0.0, 0.0, b.M(c, c);
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> eig(K2, M2);
    for (int j = 0; j < 2; ++j) EXPECT_NEAR(eig.eigenvalues()(j) / w2[j], 1.0, 1e-12);
  }
}

InvalidInput error_of(const std::string& stiffness, const std::string& mass = "1,1,1,1,1.0\n") {
  std::istringstream k(stiffness), m(mass);
  try {
    read_abaqus_reduced_body(k, "K.mtx", m, "M.mtx");
  } catch (const InvalidInput& e) {
    return e;
  }
  ADD_FAILURE() << "no InvalidInput for:\n" << stiffness;
  return InvalidInput("none");
}

TEST(AbaqusMatrix, RefusesWhatIsNotASolidBodysSymmetricMatrixAtItsLine) {
  const auto check = [](const InvalidInput& e, int line, const std::string& part) {
    EXPECT_EQ(e.where().file, "K.mtx");
    EXPECT_EQ(e.where().line, line) << e.message();
    EXPECT_NE(e.message().find(part), std::string::npos) << e.message();
  };
  check(error_of("** header\n1,1,1,1,1.0\n1,4,1,4,2.0\n"), 3, "rotations");
  check(error_of("1,1,1,1,1.0\n2,1,1,1,-1.0\n1,1,2,1,-1.5\n"), 3, "not symmetric");
  check(error_of("1,1,1,1,1.0\n1,1,1,1,1.0\n"), 2, "given twice");
  check(error_of("1,1,1,1\n"), 1, "found 4 fields");
  check(error_of("-3,1,1,1,1.0\n"), 1, "not a positive integer");
  check(error_of("1,1,1,1,nan\n"), 1, "not a finite number");
  check(error_of("%%MatrixMarket matrix coordinate real symmetric\n"), 1, "format: matrix_market");
  check(error_of("** only comments\n"), 1, "no matrix entries");
  // Both triangles given and equal: accepted.
  std::istringstream k("1 1 1 1 2.0\n2 1 1 1 -1.0\n1 1 2 1 -1.0\n2 1 2 1 1.0\n"), m("1,1,1,1,1\n");
  const ReducedBody b = read_abaqus_reduced_body(k, "K.mtx", m, "M.mtx");
  EXPECT_EQ(b.size(), 2);
  EXPECT_EQ(b.K(0, 1), -1.0);
}

}  // namespace
}  // namespace stickslip
