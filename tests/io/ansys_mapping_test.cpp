// ANSYS HBMAT mapping files and reduced bodies read from Harwell–Boeing + mapping: parsing, the
// DOF map (nodal translations vs generalised coordinates), a write/read round trip, and one test
// per kind of malformed mapping file.
#include "io/ansys_mapping.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/errors.h"
#include "core/types.h"
#include "io/harwell_boeing.h"
#include "io/matrix_market.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

fs::path scratch_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  fs::path dir = fs::temp_directory_path() /
                 ("stickslip_map_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

void expect_invalid(const std::string& text, int line, const std::string& fragment) {
  std::istringstream in(text);
  try {
    read_ansys_mapping(in, "K2.mapping");
    FAIL() << "no InvalidInput; expected one mentioning '" << fragment << "'";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, "K2.mapping");
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(AnsysMapping, ReadsHeaderAndRowsInAnyOrder) {
  std::istringstream in(
      "Matrix Eqn   Node   DOF\n"
      "     2     17   UY\n"
      "     1     17   UX\n"
      "\n"
      "     3     17   uz\n"
      "     4      0   GEN\n");
  const AnsysMapping m = read_ansys_mapping(in, "K2.mapping");
  ASSERT_EQ(m.entries.size(), 4u);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(m.entries[k].equation, k + 1);
  EXPECT_EQ(m.entries[0].label, "UX");
  EXPECT_EQ(m.entries[1].label, "UY");
  EXPECT_EQ(m.entries[1].line, 2);
  EXPECT_EQ(m.entries[2].node, 17);
  int dir = -1;
  EXPECT_EQ(classify_ansys_label("uz", &dir), AnsysDofKind::kTranslation);
  EXPECT_EQ(dir, 2);
  EXPECT_EQ(classify_ansys_label("ROTY", &dir), AnsysDofKind::kRotation);
  EXPECT_EQ(dir, 1);
  EXPECT_EQ(classify_ansys_label("GEN", &dir), AnsysDofKind::kGeneralized);
  EXPECT_EQ(dir, -1);
}

TEST(AnsysMapping, FileWithoutHeaderIsAccepted) {
  std::istringstream in("1 5 UX\n2 5 UY\n");
  EXPECT_EQ(read_ansys_mapping(in, "m").entries.size(), 2u);
}

TEST(AnsysMapping, MappingPathReplacesTheExtension) {
  EXPECT_EQ(ansys_mapping_path("dir/K2.txt"), "dir/K2.mapping");
  EXPECT_EQ(ansys_mapping_path("K2"), "K2.mapping");
}

// A two-node boundary (6 translations) plus two generalised coordinates, as a CMS superelement:
// K's modal block diagonal (ω²), M's modal block the identity. Written as RSA + mapping, read
// back as a ReducedBody.
TEST(AnsysMapping, ReducedBodyFromHarwellBoeingAndMappingFiles) {
  const fs::path dir = scratch_dir();
  const int n = 8;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n), M = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < 6; ++i) {
    K(i, i) = 2e8;
    M(i, i) = 0.5;
  }
  K(0, 3) = K(3, 0) = -1e8;
  M(1, 7) = M(7, 1) = 0.01;
  const double w1 = hz_to_rad_s(1234.5), w2 = hz_to_rad_s(2345.25);
  K(6, 6) = w1 * w1;
  K(7, 7) = w2 * w2;
  M(6, 6) = M(7, 7) = 1.0;
  HarwellBoeingWriteOptions o;
  write_harwell_boeing((dir / "K2.txt").string(), K.sparseView(), o);
  write_harwell_boeing((dir / "M2.txt").string(), M.sparseView(), o);
  {
    std::ofstream map(dir / "K2.mapping");
    map << "Matrix Eqn   Node   DOF\n";
    const char* labels[] = {"UX", "UY", "UZ"};
    for (int k = 0; k < 6; ++k)
      map << k + 1 << " " << (k < 3 ? 101 : 205) << " " << labels[k % 3] << "\n";
    map << "7 0 GC\n8 0 GC\n";
  }
  const ReducedBody body =
      read_ansys_reduced_body((dir / "K2.txt").string(), (dir / "M2.txt").string());
  ASSERT_EQ(body.size(), n);
  EXPECT_EQ(body.num_physical(), 6);
  EXPECT_EQ(body.num_modal(), 2);
  EXPECT_EQ(body.K, K);
  EXPECT_EQ(body.M, M);
  EXPECT_EQ(body.dofs[4].kind, ReducedDof::Kind::kPhysical);
  EXPECT_EQ(body.dofs[4].node_id, 205);
  EXPECT_EQ(body.dofs[4].direction, 1);
  EXPECT_EQ(body.dofs[4].node_index, -1);  // a file knows node numbers, not mesh indices
  EXPECT_EQ(body.dofs[7].kind, ReducedDof::Kind::kModal);
  EXPECT_EQ(body.dofs[7].mode, 1);
  // sqrt(K_jj / M_jj) / 2π of a diagonal modal block is the frequency put in.
  constexpr double kFrequencyTolerance = 1e-9;  // relative; only round-off of sqrt and 2π
  EXPECT_NEAR(body.dofs[6].frequency_hz, 1234.5, kFrequencyTolerance * 1234.5);
  EXPECT_NEAR(body.dofs[7].frequency_hz, 2345.25, kFrequencyTolerance * 2345.25);

  // Writing it back (RSA + mapping next to each matrix) and reading again gives the same body.
  ReducedBody copy = body;
  write_ansys_reduced_body((dir / "K3.txt").string(), (dir / "M3.txt").string(), copy);
  EXPECT_TRUE(fs::exists(dir / "K3.mapping"));
  EXPECT_TRUE(fs::exists(dir / "M3.mapping"));
  const ReducedBody again =
      read_ansys_reduced_body((dir / "K3.txt").string(), (dir / "M3.txt").string());
  EXPECT_EQ(again.K, K);
  EXPECT_EQ(again.M, M);
  for (int k = 0; k < n; ++k) {
    EXPECT_EQ(again.dofs[k].kind, body.dofs[k].kind);
    EXPECT_EQ(again.dofs[k].node_id, body.dofs[k].node_id);
    EXPECT_EQ(again.dofs[k].direction, body.dofs[k].direction);
    EXPECT_EQ(again.dofs[k].mode, body.dofs[k].mode);
  }
  fs::remove_all(dir);
}

TEST(AnsysMapping, RotationalDofsAreRejectedNamingTheLine) {
  const fs::path dir = scratch_dir();
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(2, 2);
  write_harwell_boeing((dir / "K.txt").string(), I.sparseView(), {});
  {
    std::ofstream map(dir / "K.mapping");
    map << "Matrix Eqn   Node   DOF\n1 3 UX\n2 3 ROTZ\n";
  }
  try {
    read_ansys_reduced_body((dir / "K.txt").string(), (dir / "K.txt").string());
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().line, 3);
    EXPECT_NE(std::string(e.what()).find("ROTZ"), std::string::npos);
  }
  fs::remove_all(dir);
}

TEST(AnsysMapping, MatrixSizeMustMatchMapping) {
  const fs::path dir = scratch_dir();
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(3, 3);
  write_harwell_boeing((dir / "K.txt").string(), I.sparseView(), {});
  {
    std::ofstream map(dir / "K.mapping");
    map << "Matrix Eqn   Node   DOF\n1 3 UX\n2 3 UY\n";
  }
  EXPECT_THROW(read_ansys_reduced_body((dir / "K.txt").string(), (dir / "K.txt").string()),
               InvalidInput);
  fs::remove_all(dir);
}

// A mapping of more than kMaxReducedBodyDofs rows (a 2 MB file can ask for a 160 GB dense
// matrix) is refused before the matrices are read: the (missing) matrix files are never opened,
// and the message gives the row, the count, the bytes and the limit. At the limit the mapping is
// accepted and the matrices must have its size (line 3, NROW NCOL) before they are made dense.
TEST(AnsysMapping, MappingAboveTheLargestReducedBodyIsRefusedBeforeTheMatrices) {
  const fs::path dir = scratch_dir();
  const auto write_mapping = [&](int rows) {
    std::ofstream map(dir / "K.mapping");
    map << "Matrix Eqn   Node   DOF\n";
    for (int k = 1; k <= rows; ++k) {
      map << k << " " << (k + 2) / 3 << " U"
          << "XYZ"[(k - 1) % 3] << "\n";
    }
  };
  write_mapping(kMaxReducedBodyDofs + 5000);
  try {
    read_ansys_reduced_body((dir / "missing_K.txt").string(), (dir / "missing_M.txt").string(),
                            (dir / "K.mapping").string());
    FAIL() << "accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, (dir / "K.mapping").string()) << e.what();
    EXPECT_EQ(e.where().line, kMaxReducedBodyDofs + 2) << e.what();  // header + 20000 rows
    EXPECT_NE(e.message().find("the mapping has 25000 equations: a reduced body of 25000 DOFs "
                               "needs dense K and M of 5 GB each (n² x 8 bytes): at most 20000 "
                               "DOFs (3.2 GB each) are accepted"),
              std::string::npos)
        << e.what();
  }

  write_mapping(kMaxReducedBodyDofs);
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(2, 2);
  write_harwell_boeing((dir / "K.txt").string(), I.sparseView(), {});
  try {
    read_ansys_reduced_body((dir / "K.txt").string(), (dir / "K.txt").string(),
                            (dir / "K.mapping").string());
    FAIL() << "accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, (dir / "K.txt").string()) << e.what();
    EXPECT_EQ(e.where().line, 3) << e.what();
    EXPECT_NE(e.message().find("matrix is 2 x 2 but the mapping"), std::string::npos) << e.what();
    EXPECT_NE(e.message().find("has 20000 equations"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// The DOF map alone, from matrices of any source: physical DOFs, modal DOFs numbered in order
// with f = sqrt(K_jj / M_jj) / 2π (closed form of the chosen diagonal), rotations and sizes
// rejected naming the mapping.
TEST(AnsysMapping, ReducedBodyFromMatricesAndAParsedMapping) {
  std::istringstream in("Matrix Eqn   Node   DOF\n1 7 UZ\n2 0 GEN\n3 0 GEN\n");
  const AnsysMapping mapping = read_ansys_mapping(in, "B.mapping");
  const Eigen::MatrixXd K = Eigen::Vector3d(5.0, 4.0 * kPi * kPi * 100.0, -1.0).asDiagonal();
  const Eigen::MatrixXd M = Eigen::Vector3d(1.0, 1.0, 1.0).asDiagonal();
  const ReducedBody body = reduced_body_from_mapping(K, M, mapping, "B.mapping");
  ASSERT_EQ(body.size(), 3);
  EXPECT_EQ(body.dofs[0].kind, ReducedDof::Kind::kPhysical);
  EXPECT_EQ(body.dofs[0].node_id, 7);
  EXPECT_EQ(body.dofs[0].direction, 2);
  EXPECT_EQ(body.dofs[1].kind, ReducedDof::Kind::kModal);
  EXPECT_EQ(body.dofs[1].mode, 0);
  EXPECT_NEAR(body.dofs[1].frequency_hz, 10.0, 1e-12);  // sqrt(4π²·100)/2π = 10 Hz
  EXPECT_EQ(body.dofs[2].mode, 1);
  EXPECT_EQ(body.dofs[2].frequency_hz, 0.0);  // K_jj < 0: no frequency
  EXPECT_EQ(body.K, K);
  EXPECT_EQ(body.M, M);
  EXPECT_THROW(reduced_body_from_mapping(Eigen::MatrixXd::Identity(2, 2), M, mapping, "B.mapping"),
               InvalidInput);
  std::istringstream rot("1 7 UX\n2 7 ROTX\n");
  const AnsysMapping with_rotation = read_ansys_mapping(rot, "R.mapping");
  try {
    reduced_body_from_mapping(Eigen::MatrixXd::Identity(2, 2), Eigen::MatrixXd::Identity(2, 2),
                              with_rotation, "R.mapping");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().line, 2);
    EXPECT_NE(std::string(e.what()).find("R.mapping"), std::string::npos);
  }
}

// The Matrix Market writer for Python users (scipy.io.mmread reads symmetric coordinate files):
// written and read back through the Matrix Market reader and the mapping, the same body.
TEST(AnsysMapping, MatrixMarketReducedBodyRoundTrips) {
  ReducedBody body;
  body.K.resize(4, 4);
  body.K << 4.0, -1.0, 0.0, 0.5, -1.0, 3.0, 1.0 / 3.0, 0.0, 0.0, 1.0 / 3.0, 2.0, -0.25, 0.5,
      0.0, -0.25, 1.0e9;
  body.M = Eigen::Vector4d(2.0, 2.0, 2.0, 1.0).asDiagonal();
  body.M(0, 1) = body.M(1, 0) = 0.1;
  body.dofs.resize(4);
  for (int d = 0; d < 3; ++d) {
    body.dofs[d].node_id = 12;
    body.dofs[d].direction = d;
  }
  body.dofs[3].kind = ReducedDof::Kind::kModal;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("stickslip_mm_body_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string k = (dir / "K.mtx").string(), m = (dir / "M.mtx").string(),
                    map = (dir / "body.mapping").string();
  write_matrix_market_reduced_body(k, m, map, body);
  const AnsysMapping mapping = read_ansys_mapping(map);
  const ReducedBody back =
      reduced_body_from_mapping(Eigen::MatrixXd(read_matrix_market(k).matrix),
                                Eigen::MatrixXd(read_matrix_market(m).matrix), mapping, map);
  EXPECT_EQ(read_matrix_market(k).symmetry, MatrixMarketSymmetry::kSymmetric);
  EXPECT_EQ(back.K, body.K);  // 17 significant digits: every double back exactly
  EXPECT_EQ(back.M, body.M);
  ASSERT_EQ(back.size(), 4);
  for (int d = 0; d < 3; ++d) {
    EXPECT_EQ(back.dofs[d].node_id, 12);
    EXPECT_EQ(back.dofs[d].direction, d);
  }
  EXPECT_EQ(back.dofs[3].kind, ReducedDof::Kind::kModal);
  std::filesystem::remove_all(dir);
}

// ---- Malformed mapping files: one test per kind of error. ----

TEST(AnsysMappingMalformed, WrongFieldCount) {
  expect_invalid("Matrix Eqn   Node   DOF\n1 3 UX\n2 3\n", 3, "found 2 fields");
}

TEST(AnsysMappingMalformed, NonIntegerNode) {
  expect_invalid("Matrix Eqn   Node   DOF\n1 3 UX\n2 x3 UY\n", 3, "'x3' is not an integer");
}

TEST(AnsysMappingMalformed, EquationBelowOne) {
  expect_invalid("Matrix Eqn   Node   DOF\n0 3 UX\n", 2, "start at 1");
}

TEST(AnsysMappingMalformed, NegativeNode) {
  expect_invalid("Matrix Eqn   Node   DOF\n1 -3 UX\n", 2, "must not be negative");
}

TEST(AnsysMappingMalformed, EquationBeyondRowCount) {
  expect_invalid("Matrix Eqn   Node   DOF\n1 3 UX\n3 3 UZ\n", 3, "equations must be numbered 1..2");
}

TEST(AnsysMappingMalformed, RepeatedEquation) {
  expect_invalid("Matrix Eqn   Node   DOF\n1 3 UX\n1 3 UY\n", 3, "already mapped on line 2");
}

TEST(AnsysMappingMalformed, NoRows) {
  expect_invalid("Matrix Eqn   Node   DOF\n\n", 2, "no mapping rows");
}

}  // namespace
}  // namespace stickslip
