// The reference model of docs/conventions.md, stuck: both beams clamped, every contact node pair
// joined by linear springs (kt = 4.467e9 N/m in both tangential directions, kn = 5.6309e9 N/m
// normal), for the butt and lap arrangements. The lowest 8 frequencies are checked against CalculiX
// on the same mesh, with the springs written as SPRING2 elements (ccx assembles them itself).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "fe/assembly.h"
#include "fe/springs.h"
#include "io/two_beam_model.h"
#include "validation_support.h"
#include "../required_tool.h"

namespace stickslip::validation {
namespace {

constexpr int kNumModes = 8;
constexpr double kTangentialStiffness = 4.467e9;  // N/m per node pair (docs/conventions.md)
constexpr double kNormalStiffness = 5.6309e9;     // N/m per node pair
// Same formulation (C3D8) in both codes: eigensolver accuracy (see calculix_modal_test.cpp).
constexpr double kSameFormulationTolerance = 1e-6;
// C3D8I: CalculiX gives the incompatible modes mass, stickslip does not (calculix_modal_test.cpp
// proves that this is the only difference). The gap grows with the mode's curvature per element:
// on the 8x2x2 box it went from 0.2 % (mode 1) to 20 % (mode 10) on ω²; on this mesh it measured
// 0.01 % (mode 1) to 0.62 % (mode 8). 1 % bounds the lowest 8 modes; a larger gap would mean a
// different stiffness or spring model, which the C3D8 cases pin down to 1e-6.
constexpr double kIncompatibleMassTolerance = 1e-2;

struct StuckModel {
  TwoBeamModel model;
  std::vector<int> clamped;
};

StuckModel make_stuck_model(TwoBeamOptions::Arrangement arrangement, ElementType type) {
  TwoBeamOptions options;
  options.arrangement = arrangement;
  options.element_type = type;
  StuckModel stuck{make_two_beam_model(options), {}};
  const Mesh& mesh = stuck.model.mesh;
  std::set<int> clamped(mesh.node_sets.at("CLAMP1").begin(), mesh.node_sets.at("CLAMP1").end());
  clamped.insert(mesh.node_sets.at("CLAMP2").begin(), mesh.node_sets.at("CLAMP2").end());
  stuck.clamped.assign(clamped.begin(), clamped.end());
  return stuck;
}

// Our stuck assembly: fe assembly + fe/springs.h, clamped, lowest modes.
ModalResult stickslip_modes(const StuckModel& stuck) {
  const Steel steel;
  IsotropicMaterial material{steel.youngs_modulus, steel.poisson_ratio, steel.density};
  SparseMatrix K, M;
  assemble_stiffness_mass(stuck.model.mesh, material, AssemblyOptions{}, &K, &M);
  // Frame rows t1, t2, n with n the contact normal (x for butt, z for lap).
  const Eigen::Vector3d n = stuck.model.contact_normal;
  const Eigen::Vector3d t1 = n.unitOrthogonal();
  const Eigen::Vector3d t2 = n.cross(t1);
  std::vector<NodePairSpring> springs;
  for (const auto& [a, b] : stuck.model.contact_pairs) {
    NodePairSpring s;
    s.node_a = a;
    s.node_b = b;
    s.frame.row(0) = t1;
    s.frame.row(1) = t2;
    s.frame.row(2) = n;
    s.k_t1 = s.k_t2 = kTangentialStiffness;
    s.k_n = kNormalStiffness;
    springs.push_back(s);
  }
  add_springs(springs, K);
  return clamped_modes(K, M, stuck.clamped, kNumModes);
}

// CalculiX deck of the same model: the mesh, FIX = both clamps, and per pair three SPRING2
// elements along x, y, z (the contact frames are axis-aligned).
std::string calculix_stuck_deck(const StuckModel& stuck, int num_modes) {
  Mesh mesh = stuck.model.mesh;
  mesh.node_sets = {{"FIX", stuck.clamped}};
  mesh.element_sets.clear();
  const int normal_axis =
      stuck.model.contact_normal.cwiseAbs().maxCoeff() == std::abs(stuck.model.contact_normal.x())
          ? 0
          : 2;
  int next_id = *std::max_element(mesh.element_ids.begin(), mesh.element_ids.end());
  std::ostringstream springs;
  for (int axis = 0; axis < 3; ++axis) {
    springs << "*ELEMENT, TYPE=SPRING2, ELSET=SPRING" << axis + 1 << "\n";
    for (const auto& [a, b] : stuck.model.contact_pairs) {
      springs << ++next_id << ", " << mesh.node_ids[static_cast<size_t>(a)] << ", "
              << mesh.node_ids[static_cast<size_t>(b)] << "\n";
    }
  }
  // ccx tells DOF lines from constant lines by integer vs real (write reals) and reads at most
  // 20 characters per field.
  springs.precision(10);
  springs << std::scientific;
  for (int axis = 0; axis < 3; ++axis) {
    springs << "*SPRING, ELSET=SPRING" << axis + 1 << "\n"
            << axis + 1 << ", " << axis + 1 << "\n"
            << (axis == normal_axis ? kNormalStiffness : kTangentialStiffness) << "\n";
  }
  return calculix_frequency_deck(mesh, Steel{}, num_modes, springs.str());
}

struct Case {
  TwoBeamOptions::Arrangement arrangement;
  ElementType type;
  double tolerance;
};

class StuckTwoBeam : public ::testing::TestWithParam<Case> {};

TEST_P(StuckTwoBeam, LowestEightFrequenciesAgreeWithCalculix) {
  const Case& c = GetParam();
  const StuckModel stuck = make_stuck_model(c.arrangement, c.type);
  const ModalResult ours = stickslip_modes(stuck);
  ASSERT_TRUE(ours.summary.ok()) << ours.summary.message;
  const char* name = c.arrangement == TwoBeamOptions::Arrangement::kButt ? "butt" : "lap";
  const Eigen::VectorXd f = ours.frequencies_hz();
  std::printf("[ stuck ] %s %s, %d nodes, %zu pairs, stickslip Hz:", name,
              element_type_name(c.type), stuck.model.mesh.num_nodes(),
              stuck.model.contact_pairs.size());
  for (int j = 0; j < kNumModes; ++j) std::printf(" %.1f", f(j));
  std::printf("\n");
  STICKSLIP_REQUIRE_TOOL(find_ccx(), "ccx (CalculiX)");

  const CalculixEigenvalues ccx =
      run_calculix_frequency(calculix_stuck_deck(stuck, kNumModes),
                             std::string("stuck_") + name + "_" + element_type_name(c.type));
  ASSERT_EQ(ccx.best().size(), static_cast<size_t>(kNumModes)) << ccx.log;
  std::printf("[ stuck ] %s %s, CalculiX  Hz:", name, element_type_name(c.type));
  for (int j = 0; j < kNumModes; ++j) {
    const double reference = ccx.best()[static_cast<size_t>(j)];
    std::printf(" %.1f", std::sqrt(reference) / (2 * kPi));
    EXPECT_LT(relative_difference(ours.eigenvalues(j), reference), c.tolerance)
        << name << " " << element_type_name(c.type) << " mode " << j + 1;
  }
  std::printf("\n");
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return std::string(info.param.arrangement == TwoBeamOptions::Arrangement::kButt ? "Butt"
                                                                                  : "Lap") +
         element_type_name(info.param.type);
}

INSTANTIATE_TEST_SUITE_P(
    ReferenceModel, StuckTwoBeam,
    ::testing::Values(
        Case{TwoBeamOptions::Arrangement::kButt, ElementType::kC3D8, kSameFormulationTolerance},
        Case{TwoBeamOptions::Arrangement::kLap, ElementType::kC3D8, kSameFormulationTolerance},
        Case{TwoBeamOptions::Arrangement::kButt, ElementType::kC3D8I, kIncompatibleMassTolerance},
        Case{TwoBeamOptions::Arrangement::kLap, ElementType::kC3D8I, kIncompatibleMassTolerance}),
    case_name);

}  // namespace
}  // namespace stickslip::validation
