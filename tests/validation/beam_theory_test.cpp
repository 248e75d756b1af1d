// Cantilever bending (both planes) and torsion frequencies of a slender solid box beam against
// Euler–Bernoulli beam theory and Saint-Venant torsion, under mesh refinement (C3D8I, the
// project's default hexahedron for bending of thin parts).
//
// Beam: x in [0, L] clamped at x = 0, rectangular section b (y) x c (z), steel.
//   bending, deflection along z:  ω_k = (β_k L)² / L² · sqrt(E I_y / (ρ A)),  I_y = b c³ / 12
//   bending, deflection along y:  ω_k = (β_k L)² / L² · sqrt(E I_z / (ρ A)),  I_z = c b³ / 12
//   with β_1 L = 1.8751040687, β_2 L = 4.6940911330 (roots of cos βL cosh βL = −1)
//   torsion:  ω_k = (2k − 1) π / (2L) · sqrt(G J / (ρ I_p)),  I_p = A (b² + c²) / 12,
//   J = (b c³ / 3) [1 − (192 c / (π⁵ b)) Σ_{n odd} tanh(n π b / (2c)) / n⁵]  (b >= c).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "fe/assembly.h"
#include "validation_support.h"

namespace stickslip::validation {
namespace {

constexpr double kLength = 2.0;  // L/b = 40: shear and rotary inertia stay small (see below)
constexpr double kWidth = 0.05;  // b, along y
constexpr double kDepth = 0.03;  // c, along z

// What 3D elasticity adds to the beam theories at the finest mesh, besides discretisation:
// Timoshenko shear + rotary inertia lower bending mode k by about (1 + E/(κG)) (β_k r / L)² / 2
// with r² = I/A: 0.04 % (mode 1) and 0.24 % (mode 2) for y bending, less for z bending. The
// clamp also blocks the Poisson contraction and the torsional warping of the root section,
// stiffening the beam by a fraction of the order of (section size / L). Hence:
constexpr double kBendingTolerance = 0.005;  // 0.5 % on the frequency
constexpr double kTorsionTolerance = 0.01;   // 1 %

struct Level {
  int nx, ny, nz;
};
// Refinement sequence: every cell halves (roughly) from one level to the next.
const std::vector<Level> kLevels = {{16, 2, 2}, {32, 4, 3}, {64, 10, 6}};

double torsion_constant(double b, double c) {
  double sum = 0.0;
  for (int n = 1; n <= 99; n += 2) sum += std::tanh(n * kPi * b / (2 * c)) / std::pow(n, 5);
  return b * c * c * c / 3.0 * (1.0 - 192.0 * c / (std::pow(kPi, 5) * b) * sum);
}

enum Family { kBendZ = 0, kBendY = 1, kTorsion = 2 };
const char* kFamilyName[] = {"bending z", "bending y", "torsion"};

// Frequencies (Hz) of the first modes of each family, classified by effective mass: the mode's
// M-weighted projection on uniform y and z translation and on rotation about the beam axis.
std::vector<std::vector<double>> family_frequencies(const Mesh& mesh, const SparseMatrix& M,
                                                    const ModalResult& r) {
  const int n = mesh.num_nodes();
  Eigen::VectorXd ty = Eigen::VectorXd::Zero(3 * n), tz = ty, rx = ty;
  for (int i = 0; i < n; ++i) {
    const double y = mesh.coordinates(1, i) - kWidth / 2, z = mesh.coordinates(2, i) - kDepth / 2;
    ty(dof_of(i, 1)) = 1.0;
    tz(dof_of(i, 2)) = 1.0;
    rx(dof_of(i, 1)) = -z;
    rx(dof_of(i, 2)) = y;
  }
  const Eigen::VectorXd Mty = M * ty, Mtz = M * tz, Mrx = M * rx;
  std::vector<std::vector<double>> result(3);
  const Eigen::VectorXd f = r.frequencies_hz();
  for (Eigen::Index j = 0; j < r.modes.cols(); ++j) {
    const auto phi = r.modes.col(j);
    const double p[3] = {std::pow(phi.dot(Mtz), 2) / tz.dot(Mtz),
                         std::pow(phi.dot(Mty), 2) / ty.dot(Mty),
                         std::pow(phi.dot(Mrx), 2) / rx.dot(Mrx)};
    int family = 0;
    for (int k = 1; k < 3; ++k) {
      if (p[k] > p[family]) family = k;
    }
    // Axial modes have none of the three; they are not classified.
    if (p[family] > 1e-3) result[static_cast<size_t>(family)].push_back(f(j));
  }
  return result;
}

TEST(BeamTheory, CantileverBendingAndTorsionConvergeUnderRefinement) {
  const Steel steel;
  const double E = steel.youngs_modulus, rho = steel.density;
  const double G = E / (2 * (1 + steel.poisson_ratio));
  const double A = kWidth * kDepth;
  const double Iy = kWidth * std::pow(kDepth, 3) / 12, Iz = kDepth * std::pow(kWidth, 3) / 12;
  const double beta[2] = {1.8751040687, 4.6940911330};
  const double J = torsion_constant(kWidth, kDepth);
  const double Ip = A * (kWidth * kWidth + kDepth * kDepth) / 12;
  const auto hz = [](double omega) { return omega / (2 * kPi); };
  // reference[family][k]
  const double reference[3][2] = {
      {hz(beta[0] * beta[0] / (kLength * kLength) * std::sqrt(E * Iy / (rho * A))),
       hz(beta[1] * beta[1] / (kLength * kLength) * std::sqrt(E * Iy / (rho * A)))},
      {hz(beta[0] * beta[0] / (kLength * kLength) * std::sqrt(E * Iz / (rho * A))),
       hz(beta[1] * beta[1] / (kLength * kLength) * std::sqrt(E * Iz / (rho * A)))},
      {hz(kPi / (2 * kLength) * std::sqrt(G * J / (rho * Ip))), 0.0}};
  const int modes_checked[3] = {2, 2, 1};

  IsotropicMaterial material{steel.youngs_modulus, steel.poisson_ratio, steel.density};
  std::vector<std::array<std::array<double, 2>, 3>> errors;
  for (const Level& level : kLevels) {
    BoxOptions box{kLength, kWidth, kDepth, level.nx, level.ny, level.nz, ElementType::kC3D8I};
    const Mesh mesh = make_box_mesh(box);
    SparseMatrix K, M;
    assemble_stiffness_mass(mesh, material, AssemblyOptions{}, &K, &M);
    // Enough modes to reach torsion 1 (above bending z 1..3, bending y 1..2, axial is higher).
    const ModalResult r = clamped_modes(K, M, mesh.node_sets.at("FIX"), 8);
    ASSERT_TRUE(r.summary.ok()) << r.summary.message;
    const auto families = family_frequencies(mesh, M, r);
    std::array<std::array<double, 2>, 3> e{};
    for (int fam = 0; fam < 3; ++fam) {
      ASSERT_GE(families[static_cast<size_t>(fam)].size(), static_cast<size_t>(modes_checked[fam]))
          << kFamilyName[fam] << " modes missing at level " << level.nx;
      for (int k = 0; k < modes_checked[fam]; ++k) {
        const double computed = families[static_cast<size_t>(fam)][static_cast<size_t>(k)];
        e[fam][k] = computed / reference[fam][k] - 1.0;
        std::printf("[ beam ] %2dx%dx%d %-9s %d: %9.4f Hz, theory %9.4f Hz, error %+.3f %%\n",
                    level.nx, level.ny, level.nz, kFamilyName[fam], k + 1, computed,
                    reference[fam][k], 100 * e[fam][k]);
      }
    }
    errors.push_back(e);
  }
  for (int fam = 0; fam < 3; ++fam) {
    for (int k = 0; k < modes_checked[fam]; ++k) {
      const double coarse = std::abs(errors.front()[fam][k]);
      const double fine = std::abs(errors.back()[fam][k]);
      EXPECT_LT(fine, coarse) << kFamilyName[fam] << " " << k + 1 << ": no convergence";
      EXPECT_LT(fine, fam == kTorsion ? kTorsionTolerance : kBendingTolerance)
          << kFamilyName[fam] << " " << k + 1;
    }
  }
}

}  // namespace
}  // namespace stickslip::validation
