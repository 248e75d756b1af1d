// The full-model recovery of one body through the library (model/body_recovery.h), without the
// command line: a steel bar (ν = 0) clamped at one end and pulled along its axis by a force F
// spread as the consistent loads of a uniform traction over its end face, at 1 and 2 Hz, far
// below its first axial mode (c / 4L ≈ 12.7 kHz: the dynamic part is (f / f₁)² < 3e-8 of the
// response). Closed forms of the static bar, which linear hexahedra reproduce exactly for
// ν = 0: end displacement F L / (E A), axial stress F / A everywhere, the clamp's reaction −F;
// for each recovery method (direct, modal + residual, expansion through the Craig–Bampton basis).
#include <cmath>
#include <complex>
#include <fstream>
#include <string>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "cli_test_support.h"
#include "io/case_file.h"
#include "model/body_recovery.h"
#include "model/case_model.h"

namespace stickslip {
namespace {

using namespace cli_test;

constexpr int kNx = 4;
constexpr double kLength = 0.1, kSide = 0.01;  // m
constexpr double kYoung = 2.0e11;              // Pa
constexpr double kForce = 1000.0;              // N, along x

std::string bar_inp() {
  std::string s = hex_grid_inp(kNx, 1, 1, kLength, kSide, kSide);
  for (const auto& [name, i] : {std::pair<const char*, int>{"FIX", 0}, {"TIP", kNx}}) {
    s += fmt::format("*NSET,NSET={}\n{},{},{},{}\n", name, grid_node(kNx, 1, i, 0, 0),
                     grid_node(kNx, 1, i, 1, 0), grid_node(kNx, 1, i, 0, 1),
                     grid_node(kNx, 1, i, 1, 1));
  }
  return s;
}

std::string bar_case() {
  std::string excitation;
  for (int j = 0; j <= 1; ++j) {
    for (int k = 0; k <= 1; ++k) {
      excitation += fmt::format("  - {{body: bar, node: {}, direction: x, amplitude: {}}}\n",
                                grid_node(kNx, 1, kNx, j, k), kForce / 4);
    }
  }
  return fmt::format(R"(stickslip: 1
materials:
  steel: {{youngs_modulus: {}, poisson_ratio: 0.0, density: 7800}}
meshes:
  bar: {{file: bar.inp}}
bodies:
  bar: {{mesh: bar, material: steel, clamp: FIX, masters: [TIP], modes: 6}}
contacts:
  - name: tiny
    law: linear
    between: {{bar: TIP}}
    direction: [0, 1, 0]
    per_pair: {{k: 1.0e-3}}
excitation:
{}analysis:
  frequency: {{start_hz: 1, stop_hz: 2, step_hz: 1}}
  harmonics: 1
recovery: {{points: all}}
output: {{plots: false, vtu: false}}
)",
                     kYoung, excitation);
}

TEST(BodyRecovery, AxiallyPulledBarMatchesTheStaticClosedFormsWithEveryMethod) {
  const fs::path dir = fresh_dir("body_recovery_bar");
  std::ofstream(dir / "bar.inp") << bar_inp();
  CaseDefinition def = parse_case(bar_case(), "case.yaml", dir.string());
  const PreparedModel model = prepare_model(def, nullptr);
  const SolvedCase solved = solve_case(model, def, nullptr);
  ASSERT_EQ(solved.response.points.size(), 2u);
  const double stretch = kForce * kLength / (kYoung * kSide * kSide);  // 5e-6 m
  const double stress = kForce / (kSide * kSide);                      // 1e7 Pa
  for (RecoveryMethod method :
       {RecoveryMethod::kDirect, RecoveryMethod::kModal, RecoveryMethod::kExpansion}) {
    SCOPED_TRACE(case_name(method));
    def.recovery.method = method;
    const BodyRecovery recovery(def, model, 0, {.stresses = true});
    const Mesh& mesh = recovery.body().mesh;
    ASSERT_EQ(recovery.held_nodes().size(), 4u);  // the clamped face
    for (const FrequencyPoint& p : solved.response.points) {
      ASSERT_TRUE(p.converged);
      const RecoveredPoint r = recovery.recover(p, solved.response.harmonics);
      ASSERT_TRUE(r.summary.ok()) << r.summary.message;
      // harmonics 0 and 1: nothing static loads the bar, so harmonic 0 is zero.
      ASSERT_EQ(solved.response.harmonics, (std::vector<int>{0, 1}));
      const int h = 1;
      EXPECT_LT(r.displacement.col(0).cwiseAbs().maxCoeff(), 1e-12 * stretch);
      for (int node = 0; node < mesh.num_nodes(); ++node) {
        const double x = mesh.coordinates(0, node);
        EXPECT_NEAR(std::abs(r.displacement(dof_of(node, 0), h)), stretch * x / kLength,
                    1e-7 * stretch);
        EXPECT_LT(std::abs(r.displacement(dof_of(node, 1), h)), 1e-7 * stretch);
        EXPECT_LT(std::abs(r.displacement(dof_of(node, 2), h)), 1e-7 * stretch);
      }
      std::complex<double> reaction = 0;
      for (size_t i = 0; i < recovery.held_nodes().size(); ++i) reaction += r.reactions(3 * i, h);
      EXPECT_NEAR(reaction.real(), -kForce, 1e-7 * kForce);
      EXPECT_NEAR(reaction.imag(), 0.0, 1e-7 * kForce);
      EXPECT_LT(r.check.max_relative[h], 1e-7);  // the reduced response at TIP is the same
      EXPECT_NEAR(r.reduced_max[h], stretch, 1e-7 * stretch);
      const std::vector<ComplexStressMatrix> s = recovery.stresses(r.displacement);
      ASSERT_EQ(s.size(), 2u);
      for (int node = 0; node < mesh.num_nodes(); ++node) {
        EXPECT_NEAR(std::abs(s[h](0, node)), stress, 1e-6 * stress);  // σ_xx
        for (int c = 1; c < 6; ++c) EXPECT_LT(std::abs(s[h](c, node)), 1e-6 * stress);
      }
    }
  }
}

TEST(BodyRecovery, StressesNeedTheOptionAndBodiesNeedAMesh) {
  const fs::path dir = fresh_dir("body_recovery_options");
  std::ofstream(dir / "bar.inp") << bar_inp();
  const CaseDefinition def = parse_case(bar_case(), "case.yaml", dir.string());
  const PreparedModel model = prepare_model(def, nullptr);
  const BodyRecovery recovery(def, model, 0);
  EXPECT_THROW(recovery.stresses(Eigen::MatrixXcd::Zero(recovery.body().mesh.num_dofs(), 1)),
               std::logic_error);
}

}  // namespace
}  // namespace stickslip
