// End-to-end: a joint pressed by static loads (static_loads + preload: computed, issues 23.3 and
// 19.2) through `stickslip run`. Two square steel bars in series along x, each clamped at its far
// end, touch at x = L1 through a friction contact whose preload is computed; bar 2 is pushed
// towards bar 1 by a total force F over one of its cross-sections (x_F). With ν = 0 the exact
// static solution is one-dimensional (uniaxial stress, no lateral strain, so the clamps and the
// contact's lateral stiffness play no part) and lies in the C3D8 space; the contact's stiffness
// split by area keeps the interface pressure uniform. The hand calculation: the load point
// moves by δ = F / (k_A + k_B), with the path through the joint k_A = (1/k1 + 1/kc + 1/k2a)⁻¹
// (bar 1, the joint's normal stiffness, bar 2 up to the load) and the path to clamp 2
// k_B = EA / (L1 + L2 − x_F); the joint carries N = k_A δ, bar 1 the mean stress σ_xx = −N/A,
// bar 1's end moves by −N/k1. The test also checks the per-pair normal forces (N a_i / A,
// a_i the pair's tributary area), that the static state is stuck (τ = 0), and, with a torque
// that the friction cannot hold, a static state that slips (|τ_i| = μ N_i) while the normal
// forces stay the hand calculation's.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <string>

namespace {

using namespace stickslip::cli_test;

constexpr double kL1 = 0.1, kL2 = 0.1, kSide = 0.02;  // m
constexpr int kNx = 10, kNs = 2;                      // elements per bar along x, per side
constexpr int kLoadSection = 4;                       // x_F = L1 + 4 dx
constexpr double kE = 2.0e11, kForce = 4500.0;        // Pa, N
constexpr double kKnTotal = 2.0e9, kKtTotal = 1.5e9, kMu = 0.5;

// Two bars of kNx x kNs x kNs C3D8, bar 1 on [0, L1], bar 2 on [L1, L1 + L2]; node sets CLAMP1,
// CLAMP2, CONTACT1 (bar 1 at x = L1), CONTACT2 (bar 2 at x = L1), LOAD (bar 2 at x_F), MID1
// (bar 1's centre node at x = L1/2, excited).
std::string two_bars_inp() {
  std::ostringstream s;
  const int per_bar = (kNx + 1) * (kNs + 1) * (kNs + 1);
  const auto id = [&](int bar, int i, int j, int k) {
    return 1 + bar * per_bar + (i * (kNs + 1) + j) * (kNs + 1) + k;
  };
  const double dx = kL1 / kNx, ds = kSide / kNs;
  s << "*NODE\n";
  for (int bar = 0; bar < 2; ++bar)
    for (int i = 0; i <= kNx; ++i)
      for (int j = 0; j <= kNs; ++j)
        for (int k = 0; k <= kNs; ++k)
          s << id(bar, i, j, k) << ", " << bar * kL1 + i * dx << ", " << j * ds << ", " << k * ds
            << "\n";
  int e = 1;
  for (int bar = 0; bar < 2; ++bar) {
    s << "*ELEMENT, TYPE=C3D8, ELSET=BAR" << bar + 1 << "\n";
    for (int i = 0; i < kNx; ++i)
      for (int j = 0; j < kNs; ++j)
        for (int k = 0; k < kNs; ++k) {
          s << e++ << ", " << id(bar, i, j, k) << ", " << id(bar, i + 1, j, k) << ", "
            << id(bar, i + 1, j + 1, k) << ", " << id(bar, i, j + 1, k) << ", "
            << id(bar, i, j, k + 1) << ", " << id(bar, i + 1, j, k + 1) << ", "
            << id(bar, i + 1, j + 1, k + 1) << ", " << id(bar, i, j + 1, k + 1) << "\n";
        }
  }
  const auto section = [&](const std::string& name, int bar, int i) {
    s << "*NSET, NSET=" << name << "\n";
    for (int j = 0; j <= kNs; ++j)
      for (int k = 0; k <= kNs; ++k) s << id(bar, i, j, k) << ",\n";
  };
  section("CLAMP1", 0, 0);
  section("CONTACT1", 0, kNx);
  section("CONTACT2", 1, 0);
  section("CLAMP2", 1, kNx);
  section("LOAD", 1, kLoadSection);
  s << "*NSET, NSET=MID1\n" << id(0, kNx / 2, kNs / 2, kNs / 2) << "\n";
  return s.str();
}

// The case: F pressing bar 2 towards bar 1 over LOAD, `extra` more static loads, a tiny y force
// (1 mN) on MID1 so that the vibration does not disturb the mean values checked.
std::string pressed_bars_case(const std::string& extra_loads) {
  std::ostringstream s;
  s << R"(stickslip: 1
materials:
  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.0, density: 7800}
meshes:
  bars: {file: bars.inp}
bodies:
  bar1: {mesh: bars, element_set: BAR1, material: steel, clamp: CLAMP1, modes: 20}
  bar2: {mesh: bars, element_set: BAR2, material: steel, clamp: CLAMP2, modes: 20}
contacts:
  - name: joint
    law: friction
    between: {bar1: CONTACT1, bar2: CONTACT2}
    normal: [1, 0, 0]
    total: {kt: 1.5e9, kn: 2.0e9, mu: 0.5, preload: computed, split: area}
excitation:
  - {body: bar1, node_set: MID1, direction: y, amplitude: 1.0e-3}
static_loads:
  - {body: bar2, node_set: LOAD, total_force: [-4500, 0, 0]}
)" << extra_loads
    << R"(damping: {alpha: 5.0}
analysis:
  frequency: {around_mode: 1, half_width_hz: 2, step_hz: 1}
  harmonics: 1
recovery: {points: peak, method: direct, fields: [displacement, stress], nodes: [91]}
output: {plots: false, vtu: true}
)";
  return s.str();
}

struct Hand {
  double N, delta_contact;
};
Hand hand_calculation() {
  const double A = kSide * kSide, dx = kL1 / kNx;
  const double k1 = kE * A / kL1, k2a = kE * A / (kLoadSection * dx),
               k2b = kE * A / (kL2 - kLoadSection * dx);
  const double kA = 1.0 / (1.0 / k1 + 1.0 / kKnTotal + 1.0 / k2a);
  const double delta = kForce / (kA + k2b);
  const double N = kA * delta;
  return {N, -N / k1};
}

// Static (harmonic 0) local force per pair: axis -> value, from contact_forces.csv.
std::map<int, std::map<std::string, double>> static_pair_forces(const fs::path& out) {
  std::map<int, std::map<std::string, double>> f;
  for (const auto& r : read_csv(out / "contact_forces.csv")) {
    if (r.at("harmonic") != "0" || r.at("frame") != "local") continue;
    f[std::stoi(r.at("pair"))][r.at("axis")] = std::stod(r.at("real_n"));
  }
  return f;
}

TEST(StaticLoadsCli, PressedJointHasTheHandCalculatedPreloadAndMeanStress) {
  const fs::path dir = fresh_dir("static_loads");
  {
    std::ofstream(dir / "bars.inp") << two_bars_inp();
  }
  const fs::path c = write_case(dir, "pressed", pressed_bars_case(""));
  ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / "out").string(), dir / "run.log"), 0)
      << slurp(dir / "run.log");
  const Hand hand = hand_calculation();
  const double A = kSide * kSide;

  // Normal force per pair: the uniform pressure N/A times each pair's tributary area (2 x 2
  // faces of (A/4): corner A/16, edge A/8, centre A/4); stuck, τ = 0.
  const auto forces = static_pair_forces(dir / "out");
  ASSERT_EQ(forces.size(), 9u);
  double total = 0.0;
  int corners = 0, edges = 0, centres = 0;
  for (const auto& [pair, f] : forces) {
    const double n = f.at("n");
    total += n;
    const double share = n / hand.N;
    if (std::abs(share - 1.0 / 16) < 1e-6) ++corners;
    if (std::abs(share - 1.0 / 8) < 1e-6) ++edges;
    if (std::abs(share - 1.0 / 4) < 1e-6) ++centres;
    EXPECT_LT(std::hypot(f.at("t1"), f.at("t2")), 1e-6 * n) << pair;
  }
  EXPECT_NEAR(total, hand.N, 1e-8 * hand.N);
  EXPECT_EQ(corners, 4);
  EXPECT_EQ(edges, 4);
  EXPECT_EQ(centres, 1);

  // The recovered mean displacement of bar 1's contact node 91 (x = L1, y = z = 0).
  bool found = false;
  for (const auto& r : read_csv(dir / "out" / "recovered_nodes.csv")) {
    if (r.at("node") != "91" || r.at("axis") != "x" || r.at("harmonic") != "0") continue;
    EXPECT_NEAR(std::stod(r.at("real_m")), hand.delta_contact, 1e-7 * std::abs(hand.delta_contact));
    found = true;
  }
  EXPECT_TRUE(found);

  // The recovered mean stress of bar 1 away from the clamp and the joint, read by VTK: σ_xx of
  // harmonic 0 and von_mises_mean both −N/A and N/A (the 1 mN vibration is negligible).
  std::ofstream(dir / "stress.py") << R"(import glob, sys
import vtk
from vtk.util.numpy_support import vtk_to_numpy
path = glob.glob(sys.argv[1] + '/recovery/bar1/p*.vtu')[0]
r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(path)
r.Update()
g = r.GetOutput()
x = vtk_to_numpy(g.GetPoints().GetData())
s = vtk_to_numpy(g.GetPointData().GetArray('stress_h0_real'))
vm = vtk_to_numpy(g.GetPointData().GetArray('von_mises_mean'))
sel = (x[:, 0] > 0.02) & (x[:, 0] < 0.08)
print('COUNT', int(sel.sum()))
print('SXX', repr(float(s[sel, 0].min())), repr(float(s[sel, 0].max())))
print('VM', repr(float(vm[sel].min())), repr(float(vm[sel].max())))
)";
  ASSERT_EQ(shell("/usr/bin/python3 " + (dir / "stress.py").string() + " " +
                      (dir / "out").string(),
                  dir / "stress.log"),
            0)
      << slurp(dir / "stress.log");
  std::istringstream in(slurp(dir / "stress.log"));
  std::string tag;
  int count = 0;
  double sxx_min = 0, sxx_max = 0, vm_min = 0, vm_max = 0;
  in >> tag >> count >> tag >> sxx_min >> sxx_max >> tag >> vm_min >> vm_max;
  ASSERT_EQ(count, 5 * 9) << slurp(dir / "stress.log");
  const double sigma = -hand.N / A;
  EXPECT_NEAR(sxx_min, sigma, 1e-6 * std::abs(sigma));
  EXPECT_NEAR(sxx_max, sigma, 1e-6 * std::abs(sigma));
  // Signed von Mises (stress_envelope.h): negative in compression.
  EXPECT_NEAR(vm_min, sigma, 1e-4 * std::abs(sigma));
  EXPECT_NEAR(vm_max, sigma, 1e-4 * std::abs(sigma));
}

// A torque on bar 2 (four tangential forces of ±f at the mid-edge nodes of its loaded section,
// 4 f × 1 cm about x) is carried partly by the joint's friction: it changes no normal force (a
// square bar twists without axial strain when ν = 0, and both sides warp alike) and loads the
// pairs tangentially in proportion to their distance from the axis. With μ = 10 the static state
// sticks and asks more than |τ|/N = 0.5 at every pair but the centre; with μ = 0.5 those pairs slip
// at exactly |τ|/N = μ, and the normal forces stay the hand calculation's.
TEST(StaticLoadsCli, ATorqueTheFrictionCannotHoldMakesTheStaticStateSlip) {
  const fs::path dir = fresh_dir("static_loads_slip");
  {
    std::ofstream(dir / "bars.inp") << two_bars_inp();
  }
  // Bar 2's nodes of the loaded section (x_F) at mid-edges: 137 (y = 0, z = 1 cm), 143 (y = 2 cm,
  // z = 1 cm), 139 (y = 1 cm, z = 0), 141 (y = 1 cm, z = 2 cm); the axis is y = z = 1 cm.
  const std::string torque =
      "  - {body: bar2, node: 137, force: [0, 0, -1000]}\n"
      "  - {body: bar2, node: 143, force: [0, 0, 1000]}\n"
      "  - {body: bar2, node: 139, force: [0, 1000, 0]}\n"
      "  - {body: bar2, node: 141, force: [0, -1000, 0]}\n";
  const Hand hand = hand_calculation();
  for (const double mu : {10.0, kMu}) {
    std::string text = pressed_bars_case(torque);
    const size_t at = text.find("mu: 0.5,");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 8, "mu: " + std::to_string(mu) + ",");
    const std::string name = mu > 1 ? "stuck" : "slipping";
    const fs::path c = write_case(dir, name, text);
    ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / name).string(), dir / (name + ".log")),
              0)
        << slurp(dir / (name + ".log"));
    const auto forces = static_pair_forces(dir / name);
    ASSERT_EQ(forces.size(), 9u);
    int at_limit = 0;
    double total_n = 0.0;
    for (const auto& [pair, f] : forces) {
      const double n = f.at("n"), ratio = std::hypot(f.at("t1"), f.at("t2")) / n;
      total_n += n;
      // Per pair the hand calculation's uniform pressure: N/16, N/8 or N/4 by tributary area.
      const double share = n / hand.N;
      EXPECT_TRUE(std::abs(share - 1.0 / 16) < 1e-6 || std::abs(share - 1.0 / 8) < 1e-6 ||
                  std::abs(share - 1.0 / 4) < 1e-6)
          << pair << " " << share;
      if (std::abs(share - 1.0 / 4) < 1e-6) {
        EXPECT_LT(ratio, 1e-9) << "the centre pair sits on the axis";
        continue;
      }
      if (mu > 1) {
        EXPECT_GT(ratio, kMu) << "pair " << pair << ": the stuck state should need more than μ";
      } else {
        EXPECT_NEAR(ratio, kMu, 1e-9) << "pair " << pair << " does not slip";
        ++at_limit;
      }
    }
    EXPECT_NEAR(total_n, hand.N, 1e-8 * hand.N);
    if (mu < 1) {
      EXPECT_EQ(at_limit, 8);
    }
  }
}

// A pressure on an inner cross-section (faces shared by two elements) is refused before any
// solve, at the entry's line, naming the body and the elements.
TEST(StaticLoadsCli, APressureOnInnerFacesIsAnInputError) {
  const fs::path dir = fresh_dir("static_loads_inner");
  {
    std::ofstream(dir / "bars.inp") << two_bars_inp();
  }
  std::string text = pressed_bars_case("");
  const std::string load = "total_force: [-4500, 0, 0]";
  text.replace(text.find(load), load.size(), "pressure: 1.0e6");
  const fs::path c = write_case(dir, "inner", text);
  EXPECT_EQ(run("run -q " + c.string() + " -o " + (dir / "out").string(), dir / "run.log"), 2);
  const std::string log = slurp(dir / "run.log");
  EXPECT_NE(log.find("inner.yaml:18: static_loads[0]: body bar2: the pressure's nodes hold a face "
                     "shared by elements"),
            std::string::npos)
      << log;
}

// A lateral load on bar 2 bends it and opens two rows of the joint in its static state (N = 0);
// the 1 mN vibration keeps them open over the whole cycle. The frozen static state is then right
// for those pairs (mean force 0 = static force 0): the uncoupled check must not flag them.
TEST(StaticLoadsCli, PairsTheStaticStateLeavesOpenAreNotFlaggedByTheUncoupledCheck) {
  const fs::path dir = fresh_dir("static_loads_open");
  {
    std::ofstream(dir / "bars.inp") << two_bars_inp();
  }
  const fs::path c = write_case(
      dir, "open",
      pressed_bars_case("  - {body: bar2, node_set: LOAD, total_force: [0, 3000, 0]}\n"));
  ASSERT_EQ(run("run " + c.string() + " -o " + (dir / "out").string(), dir / "run.log"), 0)
      << slurp(dir / "run.log");
  int open = 0;
  for (const auto& [pair, f] : static_pair_forces(dir / "out")) open += f.at("n") == 0.0;
  EXPECT_EQ(open, 6) << "the lateral load no longer opens two rows";
  int whole_cycle = 0;
  for (const auto& r : read_csv(dir / "out" / "contact_state.csv")) {
    whole_cycle += std::stod(r.at("separation")) == 1.0;
  }
  EXPECT_EQ(whole_cycle, 6 * 5);  // 6 pairs at each of the 5 points
  for (const auto& r : read_csv(dir / "out" / "points.csv")) {
    EXPECT_EQ(r.at("static_warning"), "0") << r.at("point");
  }
  EXPECT_EQ(slurp(dir / "run.log").find("warning:"), std::string::npos) << slurp(dir / "run.log");
}

// A study of the pressing force (the computed preload's counterpart of the thesis's preload
// factor): each folder's joint force is the hand calculation's for its force (linear in F).
TEST(StaticLoadsCli, AStudyOfThePressingForceScalesTheComputedPreload) {
  const fs::path dir = fresh_dir("static_loads_study");
  {
    std::ofstream(dir / "bars.inp") << two_bars_inp();
  }
  const fs::path c = write_case(
      dir, "study",
      pressed_bars_case("") +
          "study:\n  parameter: static_loads[0].total_force\n  values: [4500, 900]\n");
  ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / "out").string(), dir / "run.log"), 0)
      << slurp(dir / "run.log");
  const Hand hand = hand_calculation();
  for (const double F : {4500.0, 900.0}) {
    const fs::path folder = dir / "out" / ("total_force_" + std::to_string(int(F)));
    double total = 0.0;
    for (const auto& [pair, f] : static_pair_forces(folder)) total += f.at("n");
    EXPECT_NEAR(total, hand.N * F / kForce, 1e-8 * hand.N) << folder;
  }
}

// The reference butt joint (generated mesh, C3D8) pressed by 4500 N: beam 2 is held at its far end
// in y and z only (supports), and the force acts on its cross-section one element from that end,
// so the whole force must pass the joint: the static normal forces sum to F (equilibrium of beam
// 2 along x), and the joint is not uniformly pressed (the end blocks are off the beams' axis).
TEST(StaticLoadsCli, ReferenceJointPressedThroughItsEndCarriesTheWholeForce) {
  const fs::path dir = fresh_dir("static_loads_reference");
  const std::string head = R"(stickslip: 1
materials:
  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}
meshes:
  joint: {generate: two_beam, element: C3D8}
bodies:
  beam1: {mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1}
  beam2: {mesh: joint, element_set: BEAM2, material: steel, supports: [{nodes: CLAMP2, directions: [y, z]}]}
analysis:
  frequency: {start_hz: 1488, stop_hz: 1490, step_hz: 1}
)";
  const fs::path mesh_case = write_case(dir, "mesh", head);
  ASSERT_EQ(run("mesh " + mesh_case.string() + " -o " + (dir / "m").string(), dir / "mesh.log"), 0)
      << slurp(dir / "mesh.log");
  // Beam 2's nodes at x = 0.59 m (its far end is x = 0.6 m).
  std::string section;
  {
    std::istringstream in(slurp(dir / "m" / "mesh" / "beam2.inp"));
    std::string line;
    bool in_nodes = false;
    while (std::getline(in, line)) {
      if (!line.empty() && line[0] == '*') {
        in_nodes = line.rfind("*NODE", 0) == 0;
        continue;
      }
      if (!in_nodes || line.empty()) continue;
      std::istringstream fields(line);
      std::string id, x;
      std::getline(fields, id, ',');
      std::getline(fields, x, ',');
      if (std::abs(std::stod(x) - 0.59) < 1e-9) section += (section.empty() ? "" : ", ") + id;
    }
  }
  ASSERT_FALSE(section.empty());
  const fs::path c = write_case(dir, "pressed", head + R"(contacts:
  - name: joint
    law: friction
    between: {beam1: CONTACT1, beam2: CONTACT2}
    normal: [1, 0, 0]
    total: {kt: 1.3401e11, kn: 1.68927e11, mu: 0.5, preload: computed, split: area}
excitation:
  - {body: beam1, node_set: FORCE1, direction: z, amplitude: 1.0e-3}
static_loads:
  - {body: beam2, node: [)" + section + R"(], total_force: [-4500, 0, 0]}
damping: {alpha: 5.0}
recovery: {points: none}
output: {plots: false, vtu: false}
)");
  ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / "out").string(), dir / "run.log"), 0)
      << slurp(dir / "run.log");
  double total = 0.0, smallest = kForce, largest = 0.0;
  const auto forces = static_pair_forces(dir / "out");
  ASSERT_EQ(forces.size(), 30u);
  for (const auto& [pair, f] : forces) {
    total += f.at("n");
    smallest = std::min(smallest, f.at("n"));
    largest = std::max(largest, f.at("n"));
    EXPECT_LE(std::hypot(f.at("t1"), f.at("t2")), kMu * f.at("n") * (1 + 1e-9)) << pair;
  }
  EXPECT_NEAR(total, kForce, 1e-8 * kForce);
  EXPECT_EQ(smallest, 0.0) << "no pair lifts off";
  EXPECT_GT(largest, 2.0 * kForce / 30) << "the joint is pressed uniformly";
}

}  // namespace
