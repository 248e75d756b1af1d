// End-to-end: `rotation` through the program (docs/rotation.md).
//
// 1. The centrifugal load presses a blade's tip onto a stop (a preload from rotation, issue 13
//    item 4): a square steel bar (ν = 0) on [r0, r0 + L] radially, spinning about an axis through
//    x = 0, held axially at its hub face x = r0 (a roller, plus the lateral supports of its centre
//    lines: the exact solution needs no other reaction), its tip face against a stop at the gap g
//    (law gap to the ground, kn split by area so that the tip face stays plane). With ν = 0 the
//    exact solution is one-dimensional and the C3D8 mesh holds it at its nodes: the hand
//    calculation
//      free tip   u_free = ρΩ²/(2E) [R²L − (R³ − r0³)/3],  R = r0 + L (σ(x) = ρΩ²(R² − x²)/2),
//      contact    N = (u_free − g) / (L/(EA) + 1/kn),
//    and with spin softening (the centrifugal force on the displaced mass, E u'' + ρΩ²(x + u) = 0)
//    the same with u_free and the tip compliance tan(βL)/(EAβ) of that equation, β = Ω √(ρ/E).
// 2. The Campbell diagram of a cantilever (clamped at the hub, every fixed-interface mode kept:
//    the reduced model is exact) through `stickslip modes`, against CalculiX at each speed (low
//    speeds, where ccx's initial-displacement stiffness is below its printed digits): a
//    *STATIC step with CENTRIF, then *FREQUENCY with PERTURBATION (which includes the stress
//    stiffening and the spin softening, tests/fe/rotation_test.cpp), the free system, and the
//    stuck one with the tip's springs (ccx SPRING1); the engine-order lines in the plot's data.
// 3. A cyclic sector's Campbell diagram (per nodal diameter, the sector spinning about its cyclic
//    axis: its prestress from its nodal-diameter-0 problem) against the whole ring's, built as one
//    ordinary body spinning about the same axis: every frequency of the sector is the ring's.
// 4. A spinning sector's forced response (its centrifugal load condensed on its masters, every
//    diameter reduced with the spinning stiffness) against the whole spinning ring's, both through
//    `stickslip run` (tests/bladed_ring.h: 6 shrouded blades, shrouds joined by springs).
#include <gtest/gtest.h>

#include "cli_test_support.h"
#include "vtk_cells.h"

#include <cmath>
#include <complex>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include <Eigen/Geometry>

#include "../bladed_ring.h"
#include "../cyclic_annulus.h"

namespace {

using namespace stickslip::cli_test;

constexpr double kR0 = 0.1, kL = 0.1, kSide = 0.02;  // m
constexpr int kNx = 10, kNs = 2;
constexpr double kE = 2.0e11, kRho = 7800.0;
constexpr double kKnTotal = 2.0e9;  // N/m
constexpr double kGap = 5.0e-6;     // m
constexpr double kRpm = 6000.0;

// The bar on [0, L] x [0, side]² (the axis passes through x = −r0, y = z = side/2, along z) with
// node sets HUB (x = 0), HUBY (x = 0, y = side/2: held in y), HUBZ (x = 0, z = side/2: held in
// z), TIP (x = L), EXC (the tip's corner node, excited).
std::string bar_inp() {
  std::ostringstream s;
  s << hex_grid_inp(kNx, kNs, kNs, kL, kSide, kSide);
  const auto node = [](int i, int j, int k) { return grid_node(kNx, kNs, i, j, k); };
  const auto set = [&](const std::string& name, auto pick) {
    s << "*NSET, NSET=" << name << "\n";
    for (int k = 0; k <= kNs; ++k)
      for (int j = 0; j <= kNs; ++j)
        for (int i = 0; i <= kNx; ++i)
          if (pick(i, j, k)) s << node(i, j, k) << ",\n";
  };
  set("HUB", [](int i, int, int) { return i == 0; });
  set("HUBY", [](int i, int j, int) { return i == 0 && j == kNs / 2; });
  set("HUBZ", [](int i, int, int k) { return i == 0 && k == kNs / 2; });
  set("TIP", [](int i, int, int) { return i == kNx; });
  set("EXC", [](int i, int j, int k) { return i == kNx && j == 0 && k == 0; });
  return s.str();
}

std::string pressed_case(bool spin_softening) {
  std::ostringstream s;
  s << R"(stickslip: 1
materials:
  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.0, density: 7800}
meshes:
  bar: {file: bar.inp}
bodies:
  blade:
    mesh: bar
    material: steel
    modes: 20
    supports:
      - {nodes: HUB, directions: [x]}
      - {nodes: HUBY, directions: [y]}
      - {nodes: HUBZ, directions: [z]}
contacts:
  - name: stop
    law: gap
    between: {blade: TIP}
    direction: [1, 0, 0]
    gap: 5.0e-6
    total: {kn: 2.0e9, split: area}
excitation:
  - {body: blade, node_set: EXC, direction: y, amplitude: 1.0e-3}
rotation:
  speed_rpm: 6000
  axis: {point: [-0.1, 0.01, 0.01], direction: z}
  stress_stiffening: false
  spin_softening: )"
    << (spin_softening ? "true" : "false") << R"(
damping: {alpha: 5.0}
analysis:
  frequency: {start_hz: 100, stop_hz: 102, step_hz: 1}
  harmonics: 1
recovery: {points: none}
output: {plots: false, vtu: false}
)";
  return s.str();
}

// Static normal force summed over the stop's pairs (contact_forces.csv, harmonic 0, local u) at
// the first frequency point (with `static: uncoupled` the same at every point).
double static_contact_force(const fs::path& out, int* pairs) {
  double total = 0.0;
  *pairs = 0;
  const auto rows = read_csv(out / "contact_forces.csv");
  if (rows.empty()) return 0.0;
  for (const auto& r : rows) {
    if (r.at("point") != rows.front().at("point")) continue;
    if (r.at("harmonic") != "0" || r.at("frame") != "local") continue;
    total += std::stod(r.at("real_n"));
    ++*pairs;
  }
  return total;
}

// The hand calculation of the header: the static contact force at `rpm`, N.
double hand_contact_force(double rpm, bool softening) {
  const double omega = rpm * 2 * M_PI / 60, A = kSide * kSide, R = kR0 + kL;
  double u_free = 0.0, compliance = 0.0;
  if (!softening) {
    u_free = kRho * omega * omega / (2 * kE) * (R * R * kL - (R * R * R - kR0 * kR0 * kR0) / 3);
    compliance = kL / (kE * A);
  } else {
    // u = −x + C1 cos βx + C2 sin βx with u(r0) = 0 and u'(R) = 0 (free tip); the tip's
    // compliance from w = a sin β(x − r0), EA w'(R) = −1.
    const double beta = omega * std::sqrt(kRho / kE);
    Eigen::Matrix2d M;
    M << std::cos(beta * kR0), std::sin(beta * kR0), -beta * std::sin(beta * R),
        beta * std::cos(beta * R);
    const Eigen::Vector2d C = M.lu().solve(Eigen::Vector2d(kR0, 1.0));
    u_free = -R + C(0) * std::cos(beta * R) + C(1) * std::sin(beta * R);
    compliance = std::tan(beta * kL) / (kE * A * beta);
  }
  return (u_free - kGap) / (compliance + 1.0 / kKnTotal);
}

TEST(RotationCli, TheCentrifugalForcePressesTheTipOntoItsStopAsTheHandCalculationSays) {
  const fs::path dir = fresh_dir("rotation_pressed");
  std::ofstream(dir / "bar.inp") << bar_inp();
  std::map<bool, double> hand, ours;
  for (const bool softening : {false, true}) {
    const std::string name = softening ? "softened" : "plain";
    const fs::path c = write_case(dir, name, pressed_case(softening));
    ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / name).string(), dir / (name + ".log")),
              0)
        << slurp(dir / (name + ".log"));
    hand[softening] = hand_contact_force(kRpm, softening);
    ASSERT_GT(hand[softening], 1000.0);  // the stop is reached and pressed
    int pairs = 0;
    ours[softening] = static_contact_force(dir / name, &pairs);
    EXPECT_EQ(pairs, (kNs + 1) * (kNs + 1));
  }
  // Without spin softening the FE solution is the 1D one at the nodes (round-off; measured
  // 1.2e-13). With it the Galerkin solution of u'' + β²u = −β²x is not nodally exact: its
  // softening term sees u linearly interpolated between nodes, an error of order (h/L)² = 1e-2 of
  // the softening's own share (6.7e-5 of N here; measured 3e-3 of it, 2e-7 of N).
  EXPECT_NEAR(ours[false], hand[false], 1e-9 * hand[false]);
  EXPECT_NEAR(ours[true], hand[true], 1e-6 * hand[true]);
  const double softening_share = hand[true] - hand[false];
  EXPECT_GT(softening_share, 1e-5 * hand[false]);  // the softened tip presses harder
  EXPECT_NEAR(ours[true] - ours[false], softening_share, 1e-2 * softening_share);
}

TEST(RotationCli, AStudyOverTheSpeedReducesTheSpinningBodyAgainForEachSpeed) {
  // With spin softening the stiffness depends on the speed: each value's reduction is its own
  // (the reduction's fingerprint holds the speed), so each folder has its speed's hand force.
  const fs::path dir = fresh_dir("rotation_study");
  std::ofstream(dir / "bar.inp") << bar_inp();
  const fs::path c = write_case(
      dir, "study",
      pressed_case(true) + "study: {parameter: rotation.speed_rpm, values: [6000, 4000]}\n");
  ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / "out").string(), dir / "run.log"), 0)
      << slurp(dir / "run.log");
  for (const double rpm : {6000.0, 4000.0}) {
    const double hand = hand_contact_force(rpm, true);
    ASSERT_GT(hand, 100.0);
    int pairs = 0;
    const fs::path folder = dir / "out" / ("speed_rpm_" + std::to_string(static_cast<int>(rpm)));
    EXPECT_NEAR(static_contact_force(folder, &pairs), hand, 1e-6 * hand) << folder;
  }
}

// The recovery of the pressed bar: the full body under its centrifugal body force (every node,
// not the load condensed on the masters) and the stop's static force. With ν = 0 and no
// stiffening or softening the exact solution is one-dimensional and held at the nodes:
//   u(x) = ρΩ²/(2E) [R²(x − r0) − (x³ − r0³)/3] − N (x − r0)/(EA),
//   σ_xx(x) = ρΩ²(R² − x²)/2 − N/A,
// N the stop's force of the hand calculation; across the section (the axis along z through its
// centre line y = y_c) the body force ρΩ²(y − y_c) stretches it alone (ν = 0):
//   u_y = −ρΩ²/(2E) [(y − y_c)³/3 − a²(y − y_c)] (a the half side; −ρΩ²a³/(3E) at y = 0), u_z = 0.
// The C3D8's strain is constant in each element (the mean of u' over it, u being exact at the
// nodes), and a node's stress is the mean of its elements': σ_xx = ρΩ²(R² − x² − h²/3)/2 − N/A at
// an inner node, σ_yy = ρΩ²a²/3 at every node, the others 0, exactly.
TEST(RotationCli, TheRecoveredMeanStateOfASpinningBarIsTheOneDimensionalSolution) {
  const fs::path dir = fresh_dir("rotation_recovery");
  std::ofstream(dir / "bar.inp") << bar_inp();
  std::string text = pressed_case(false);
  std::ostringstream nodes;  // the bar's edge y = z = 0, hub to tip
  for (int i = 0; i <= kNx; ++i) nodes << (i ? ", " : "") << grid_node(kNx, kNs, i, 0, 0);
  text.replace(text.find("recovery: {points: none}"), 24,
               "recovery: {points: peak, nodes: [" + nodes.str() + "]}");
  const bool vtk = vtk_available();
  if (vtk) text.replace(text.find("vtu: false"), 10, "vtu: true");
  const fs::path c = write_case(dir, "spin", text);
  ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / "out").string(), dir / "run.log"), 0)
      << slurp(dir / "run.log");
  const double omega = kRpm * 2 * M_PI / 60, A = kSide * kSide, R = kR0 + kL;
  const double N = hand_contact_force(kRpm, false), c2 = kRho * omega * omega;
  const auto u_exact = [&](double x) {
    return c2 / (2 * kE) * (R * R * (x - kR0) - (x * x * x - kR0 * kR0 * kR0) / 3) -
           N * (x - kR0) / (kE * A);
  };
  const double u_tip = u_exact(R);
  ASSERT_GT(u_tip, kGap);  // the stop is reached
  int found = 0;
  for (const auto& r : read_csv(dir / "out" / "recovered_nodes.csv")) {
    if (r.at("harmonic") != "0") continue;
    const int i = std::stoi(r.at("node")) - 1;  // grid_node(i, 0, 0) = 1 + i
    const double value = std::stod(r.at("real_m"));
    const double a = kSide / 2;
    if (r.at("axis") == "x") {
      EXPECT_NEAR(value, u_exact(kR0 + kL * i / kNx), 1e-9 * u_tip) << "node " << i + 1;
      ++found;
    } else {
      const double exact = r.at("axis") == "y" ? -c2 * a * a * a / (3 * kE) : 0.0;
      EXPECT_NEAR(value, exact, 1e-9 * u_tip) << "node " << i + 1 << " " << r.at("axis");
    }
  }
  EXPECT_EQ(found, kNx + 1);
  // The recovery's check at the masters: the reduced model's static state is the full one's
  // (static condensation is exact).
  for (const auto& r : read_csv(dir / "out" / "recovery_check.csv")) {
    if (r.at("harmonic") == "0") {
      EXPECT_LT(std::stod(r.at("max_relative")), 1e-9);
    }
  }
  if (!vtk) GTEST_SKIP() << "the stresses need /usr/bin/python3 with VTK (python3-vtk9)";
  std::ofstream(dir / "stress.py") << R"(import glob, sys
import vtk
from vtk.util.numpy_support import vtk_to_numpy
r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(glob.glob(sys.argv[1] + '/recovery/blade/p*.vtu')[0])
r.Update()
g = r.GetOutput()
x = vtk_to_numpy(g.GetPoints().GetData())
s = vtk_to_numpy(g.GetPointData().GetArray('stress_h0_real'))
for p, t in zip(x, s):
    print(repr(float(p[0])), repr(float(t[0])), repr(float(t[1])), repr(float(abs(t[2:]).max())))
)";
  ASSERT_EQ(shell("/usr/bin/python3 " + (dir / "stress.py").string() + " " + (dir / "out").string(),
                  dir / "stress.log"),
            0)
      << slurp(dir / "stress.log");
  std::istringstream in(slurp(dir / "stress.log"));
  const double h = kL / kNx, scale = c2 * R * R / 2;
  double x = 0, sxx = 0, syy = 0, others = 0;
  int inner = 0;
  while (in >> x >> sxx >> syy >> others) {
    const double r = kR0 + x;  // the mesh's x = 0 is the hub, r0 from the axis
    EXPECT_NEAR(syy, c2 * kSide * kSide / 12, 1e-9 * scale) << "x = " << x;
    EXPECT_LT(others, 1e-9 * scale) << "x = " << x;
    if (x < 0.5 * h || x > kL - 0.5 * h) continue;  // the hub's and the tip's nodes
    EXPECT_NEAR(sxx, c2 * (R * R - r * r - h * h / 3) / 2 - N / A, 1e-9 * scale) << "x = " << x;
    ++inner;
  }
  EXPECT_EQ(inner, (kNx - 1) * (kNs + 1) * (kNs + 1));
}

// With stress stiffening and spin softening the full body is recovered with the spinning
// stiffness the reduction used: the full model and the reduced one agree at the masters in the
// static state (static condensation, exact) and in the vibration (every one of the bar's
// 20 lowest fixed-interface modes kept, 100 Hz far below them). Recovered with the stiffness at
// rest instead, the vibration would differ by about Ω²/ω₁² ≈ 4e-3.
TEST(RotationCli, ASpinningBodyIsRecoveredWithTheStiffnessItWasReducedWith) {
  const fs::path dir = fresh_dir("rotation_recovery_stiffened");
  std::ofstream(dir / "bar.inp") << bar_inp();
  std::string text = pressed_case(true);
  text.replace(text.find("stress_stiffening: false"), 24, "stress_stiffening: true");
  text.replace(text.find("recovery: {points: none}"), 24, "recovery: {points: all}");
  const fs::path c = write_case(dir, "spin", text);
  ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / "out").string(), dir / "run.log"), 0)
      << slurp(dir / "run.log");
  int rows = 0;
  for (const auto& r : read_csv(dir / "out" / "recovery_check.csv")) {
    EXPECT_LT(std::stod(r.at("max_relative")), r.at("harmonic") == "0" ? 1e-9 : 1e-6)
        << "point " << r.at("point") << " harmonic " << r.at("harmonic");
    ++rows;
  }
  EXPECT_EQ(rows, 3 * 2);
}

TEST(RotationCli, BadRotationInputExitsWithCodeTwoNamingItsKey) {
  const fs::path dir = fresh_dir("rotation_bad");
  std::ofstream(dir / "bar.inp") << bar_inp();
  std::string text = pressed_case(false);
  // A hand-off to another program would miss the centrifugal load and the spinning stiffness.
  text.replace(text.find("recovery: {points: none}"), 24,
               "recovery: {points: peak}\noutput: {calculix_deck: true}");
  text.replace(text.find("output: {plots: false, vtu: false}"), 34, "");
  const fs::path c = write_case(dir, "recovery", text);
  EXPECT_EQ(run("run -q " + c.string() + " -o " + (dir / "out").string(), dir / "recovery.log"), 2);
  EXPECT_NE(slurp(dir / "recovery.log").find("output.calculix_deck"), std::string::npos)
      << slurp(dir / "recovery.log");
  EXPECT_NE(slurp(dir / "recovery.log").find("centrifugal load"), std::string::npos)
      << slurp(dir / "recovery.log");
  // A speed below zero, at its line.
  text = pressed_case(false);
  text.replace(text.find("speed_rpm: 6000"), 15, "speed_rpm: -6000");
  const fs::path n = write_case(dir, "negative", text);
  EXPECT_EQ(run("run -q " + n.string() + " -o " + (dir / "out").string(), dir / "negative.log"), 2);
  EXPECT_NE(slurp(dir / "negative.log").find("rotation.speed_rpm"), std::string::npos)
      << slurp(dir / "negative.log");
}

// --- Campbell diagram against CalculiX ---

// A slender blade, 1 m x 2 cm x 2 cm of 20 x 2 x 2 C3D8 on [0, 1] x [0, 2 cm]², its hub 0.1 m
// from the axis (x = −0.1 m, y = z = 1 cm, along z): node sets HUB (x = 0), TIP (x = 1 m), EXC.
// ccx's perturbation step takes the stiffness at the displaced state (the initial-displacement
// matrix, which stickslip leaves out: tests/fe/rotation_test.cpp), a change of order of the
// largest centrifugal strain ε0 = ρΩ²R²/(2E); up to 28 rpm ε0 ≤ 2e-7, below ccx's printed
// digits, while the slender blade's bending frequencies move by up to 1.6e-4 (ω² by 3e-4).
constexpr int kBladeNx = 20;
std::string blade_inp() {
  std::ostringstream s;
  s << hex_grid_inp(kBladeNx, kNs, kNs, 1.0, kSide, kSide);
  const auto node = [](int i, int j, int k) { return grid_node(kBladeNx, kNs, i, j, k); };
  const auto set = [&](const std::string& name, auto pick) {
    s << "*NSET, NSET=" << name << "\n";
    for (int k = 0; k <= kNs; ++k)
      for (int j = 0; j <= kNs; ++j)
        for (int i = 0; i <= kBladeNx; ++i)
          if (pick(i, j, k)) s << node(i, j, k) << ",\n";
  };
  set("HUB", [](int i, int, int) { return i == 0; });
  set("TIP", [](int i, int, int) { return i == kBladeNx; });
  set("EXC", [](int i, int j, int k) { return i == kBladeNx / 2 && j == 0 && k == 0; });
  return s.str();
}

std::string campbell_case() {
  return R"(stickslip: 1
title: "blade 'A'"
materials:
  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}
meshes:
  blade: {file: blade.inp}
bodies:
  blade: {mesh: blade, material: steel, clamp: HUB, modes: 1000}
contacts:
  - name: tipspring
    law: linear
    between: {blade: TIP}
    direction: [0, 1, 0]
    per_pair: {k: 1.0e6}
excitation:
  - {body: blade, node_set: EXC, direction: y, amplitude: 1.0e-3}
rotation:
  speed_rpm: 0
  axis: {point: [-0.1, 0.01, 0.01], direction: z}
  campbell: {speeds_rpm: [0, 15, 28], engine_orders: [1, 2]}
analysis:
  frequency: {start_hz: 10, stop_hz: 12, step_hz: 1}
  harmonics: 1
recovery: {points: none}
output: {plots: true, vtu: false}
)";
}

// ccx on the blade's mesh: clamped HUB, CENTRIF at Ω² about the case's axis, then a
// PERTURBATION frequency step (at Ω = 0 a plain *FREQUENCY step); with `springs` the stuck
// system's tip springs as SPRING1 elements along y.
std::vector<double> ccx_campbell_eigenvalues(const fs::path& dir, double omega, bool springs,
                                             int modes) {
  fs::create_directories(dir);
  std::ostringstream s;
  s.precision(13);
  s << blade_inp();
  if (springs) {
    s << "*ELEMENT, TYPE=SPRING1, ELSET=SPR\n";
    int e = 100000;
    for (int k = 0; k <= kNs; ++k)
      for (int j = 0; j <= kNs; ++j)
        s << e++ << ", " << grid_node(kBladeNx, kNs, kBladeNx, j, k) << "\n";
    // The case's k; ccx reads a stiffness only with a decimal point.
    s << "*SPRING, ELSET=SPR\n2\n1.0e6\n";
  }
  s << "*MATERIAL, NAME=STEEL\n*ELASTIC\n2e11, 0.3\n*DENSITY\n7800\n"
       "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*BOUNDARY\nHUB, 1, 3\n";
  if (omega > 0) {
    s << "*STEP\n*STATIC\n*DLOAD\nEALL, CENTRIF, " << omega * omega
      << ", -0.1, 0.01, 0.01, 0., 0., 1.\n*END STEP\n*STEP, PERTURBATION\n";
  } else {
    s << "*STEP\n";
  }
  s << "*FREQUENCY\n" << modes << "\n*END STEP\n";
  std::ofstream(dir / "job.inp") << s.str();
  return ccx_job_eigenvalues(dir);
}

TEST(RotationCli, TheCampbellDiagramMatchesCalculixPrestressedFrequencies) {
  if (!find_ccx()) {
    if (std::getenv("STICKSLIP_REQUIRE_TOOLS")) FAIL() << "ccx is missing";
    GTEST_SKIP() << "ccx is missing";
  }
  const fs::path dir = fresh_dir("rotation_campbell");
  std::ofstream(dir / "blade.inp") << blade_inp();
  const fs::path c = write_case(dir, "campbell", campbell_case());
  const int modes = 4;
  ASSERT_EQ(
      run("modes " + c.string() + " --modes 4 -o " + (dir / "out").string(), dir / "modes.log"), 0)
      << slurp(dir / "modes.log");
  // (system, speed) -> frequencies by mode.
  std::map<std::pair<std::string, double>, std::map<int, double>> ours;
  for (const auto& r : read_csv(dir / "out/modes/campbell.csv")) {
    EXPECT_EQ(r.at("nodal_diameter"), "");
    ours[{r.at("system"), std::stod(r.at("speed_rpm"))}][std::stoi(r.at("mode"))] =
        std::stod(r.at("frequency_hz"));
  }
  ASSERT_EQ(ours.size(), 6u);  // stuck and free at three speeds
  double largest_shift = 0.0;
  for (const double rpm : {0.0, 15.0, 28.0}) {
    for (const bool stuck : {false, true}) {
      const std::string system = stuck ? "stuck" : "free";
      const fs::path job = dir / (system + "_" + std::to_string(static_cast<int>(rpm)));
      const std::vector<double> lambda =
          ccx_campbell_eigenvalues(job, rpm * 2 * M_PI / 60, stuck, modes);
      ASSERT_EQ(static_cast<int>(lambda.size()), modes) << slurp(job / "ccx.log");
      const auto& f = ours.at({system, rpm});
      ASSERT_EQ(static_cast<int>(f.size()), modes);
      for (int j = 0; j < modes; ++j) {
        const double theirs = std::sqrt(lambda[j]) / (2 * M_PI);
        // ccx prints 7 significant digits of ω² (half of that in f).
        EXPECT_NEAR(f.at(j + 1) / theirs, 1.0, 1e-6) << system << " " << rpm << " mode " << j + 1;
        if (rpm > 0)
          largest_shift =
              std::max(largest_shift, std::abs(f.at(j + 1) / ours.at({system, 0.0}).at(j + 1) - 1));
      }
    }
  }
  // The speed moves the bending frequencies far beyond the tolerance (measured: f by 1.6e-4 at
  // 28 rpm, 160 times the tolerance).
  EXPECT_GT(largest_shift, 1e-4);
  // The plot's data: the engine-order lines f = EO · rpm / 60 among the curves.
  const std::string dat = slurp(dir / "out/modes/campbell.dat");
  EXPECT_NE(dat.find("EO 2"), std::string::npos) << dat.substr(0, 400);
}

// --- A cyclic sector against the whole ring ---

namespace cyc = stickslip::testing_cyclic;

// Nodes, C3D8 elements (ELSET=ALL) and the node sets LOW, HIGH (matching order; a sector only)
// and INNER.
std::string annulus_inp(const cyc::Annulus& a, bool sector) {
  std::ostringstream deck;
  deck.precision(17);
  const stickslip::Mesh& m = a.mesh;
  deck << "*NODE\n";
  for (int n = 0; n < m.num_nodes(); ++n) {
    deck << m.node_ids[n] << ", " << m.coordinates(0, n) << ", " << m.coordinates(1, n) << ", "
         << m.coordinates(2, n) << "\n";
  }
  deck << "*ELEMENT, TYPE=C3D8, ELSET=ALL\n";
  for (int e = 0; e < m.num_elements(); ++e) {
    deck << m.element_ids[e];
    for (int n : m.element_nodes(e)) deck << ", " << m.node_ids[n];
    deck << "\n";
  }
  const auto nset = [&](const char* name, const std::vector<int>& nodes) {
    deck << "*NSET, NSET=" << name << "\n";
    for (int n : nodes) deck << m.node_ids[n] << "\n";
  };
  if (sector) {
    nset("LOW", cyc::low_nodes(a));
    nset("HIGH", cyc::high_nodes(a));
  }
  nset("INNER", cyc::inner_nodes(a));
  return deck.str();
}

std::string disk_case(bool sector) {
  return std::string(R"(stickslip: 1
materials:
  steel: {youngs_modulus: 2.1e11, poisson_ratio: 0.3, density: 7800}
meshes:
  disk: {file: )") +
         (sector ? "sector.inp" : "ring.inp") + R"(}
bodies:
  disk:
    mesh: disk
    material: steel
    clamp: INNER
    modes: 1000
)" +
         (sector ? R"(    cyclic:
      sectors: 6
      axis: {point: [0.1, -0.2, 0.3], direction: z}
      low: LOW
      high: HIGH
rotation:
  speed_rpm: 0
)"
                 : R"(rotation:
  speed_rpm: 0
  axis: {point: [0.1, -0.2, 0.3], direction: z}
)") + R"(  campbell: {speeds_rpm: [0, 3000, 6000]}
analysis:
  frequency: {start_hz: 100, stop_hz: 200, step_hz: 10}
recovery: {points: none}
output: {plots: false}
)";
}

TEST(RotationCli, ASectorsCampbellDiagramIsTheWholeRingsPerNodalDiameter) {
  const fs::path dir = fresh_dir("rotation_sector");
  const cyc::AnnulusShape shape{.radial = 2, .axial = 1, .centre = {0.1, -0.2, 0.3}};
  std::ofstream(dir / "sector.inp") << annulus_inp(cyc::annulus(6, 2, 1, shape), true);
  std::ofstream(dir / "ring.inp") << annulus_inp(cyc::annulus(6, 2, 6, shape), false);
  const fs::path sector = write_case(dir, "sector", disk_case(true));
  const fs::path ring = write_case(dir, "ring", disk_case(false));
  ASSERT_EQ(run("modes " + sector.string() + " --modes 3 -o " + (dir / "sector").string(),
                dir / "sector.log"),
            0)
      << slurp(dir / "sector.log");
  ASSERT_EQ(
      run("modes " + ring.string() + " --modes 40 -o " + (dir / "ring").string(), dir / "ring.log"),
      0)
      << slurp(dir / "ring.log");
  std::map<double, std::vector<double>> ring_f;  // speed -> ascending frequencies
  for (const auto& r : read_csv(dir / "ring/modes/campbell.csv")) {
    EXPECT_EQ(r.at("system"), "free");
    ring_f[std::stod(r.at("speed_rpm"))].push_back(std::stod(r.at("frequency_hz")));
  }
  ASSERT_EQ(ring_f.size(), 3u);
  int checked = 0;
  double largest_shift = 0.0;
  std::map<std::pair<int, int>, double> at_rest;  // (h, mode) -> frequency at 0 rpm
  for (const auto& r : read_csv(dir / "sector/modes/campbell.csv")) {
    const double rpm = std::stod(r.at("speed_rpm")), f = std::stod(r.at("frequency_hz"));
    const int h = std::stoi(r.at("nodal_diameter")), mode = std::stoi(r.at("mode"));
    const std::vector<double>& all = ring_f.at(rpm);
    ASSERT_LT(f, all.back()) << "the ring's list is too short to hold " << f;
    double nearest = all.front();
    for (double g : all) nearest = std::abs(g - f) < std::abs(nearest - f) ? g : nearest;
    // Both are exact models (every interior mode kept); round-off of the eigen-solves.
    EXPECT_NEAR(nearest / f, 1.0, 1e-8) << rpm << " rpm, nodal diameter " << h << " mode " << mode;
    if (rpm == 0) at_rest[{h, mode}] = f;
    if (rpm > 0) largest_shift = std::max(largest_shift, std::abs(f / at_rest.at({h, mode}) - 1));
    ++checked;
  }
  EXPECT_EQ(checked, 3 * 4 * 3);  // speeds x nodal diameters 0..3 x modes
  EXPECT_GT(largest_shift, 1e-2);
}

// --- A spinning sector's forced response against the whole spinning ring's ---

constexpr int kBlades = 6;

void write_ring_mesh(const fs::path& file, const cyc::BladedRing& b) {
  std::ofstream deck(file);
  deck.precision(17);
  const stickslip::Mesh& m = b.mesh;
  deck << "*NODE\n";
  for (int n = 0; n < m.num_nodes(); ++n) {
    deck << m.node_ids[n] << ", " << m.coordinates(0, n) << ", " << m.coordinates(1, n) << ", "
         << m.coordinates(2, n) << "\n";
  }
  deck << "*ELEMENT, TYPE=C3D8, ELSET=ALL\n";
  for (int e = 0; e < m.num_elements(); ++e) {
    deck << m.element_ids[e];
    for (int n : m.element_nodes(e)) deck << ", " << m.node_ids[n];
    deck << "\n";
  }
  const auto nset = [&](const char* name, const std::vector<int>& nodes) {
    deck << "*NSET, NSET=" << name << "\n";
    for (int n : nodes) deck << m.node_ids[n] << "\n";
  };
  nset("INNER", b.clamped_nodes());
  if (b.sectors == 1) {
    nset("LOW", b.ring_low());
    nset("HIGH", b.ring_high());
  }
}

// Blade s's shroud joined to blade s + 1's by springs (the sector: `neighbour: next`).
std::string shroud_springs(const cyc::BladedRing& b, int s, const std::string& body,
                           bool neighbour) {
  const double t = 2 * M_PI * (s + 1) / kBlades;
  const std::vector<int> a = b.high_shroud(s);
  const std::vector<int> o = neighbour ? b.low_shroud(s) : b.low_shroud((s + 1) % kBlades);
  std::ostringstream c;
  c.precision(17);
  c << "  - name: shroud" << s << "\n    law: linear\n    bodies: [" << body << ", " << body
    << "]\n    pairs: [";
  for (size_t i = 0; i < a.size(); ++i)
    c << (i ? ", " : "") << "[" << b.mesh.node_ids[a[i]] << ", " << b.mesh.node_ids[o[i]] << "]";
  c << "]\n"
    << (neighbour ? "    neighbour: next\n" : "") << "    normal: [" << -std::sin(t) << ", "
    << std::cos(t) << ", 0]\n    per_pair: {kt: 2.0e7, kn: 3.0e7}\n";
  return c.str();
}

std::string spinning_case(const cyc::BladedRing& b, bool sector) {
  const Eigen::Vector3d force{80.0, 200.0, 400.0};  // on blade 0's forced node, N; EO 1
  std::ostringstream c;
  c.precision(17);
  c << "stickslip: 1\nmaterials:\n  steel: {youngs_modulus: 2.1e11, poisson_ratio: 0.3, density: "
       "7800}\nmeshes:\n  m: {file: "
    << (sector ? "sector.inp" : "ring.inp")
    << "}\ndamping: {alpha: 20, beta: 2.0e-7}\nbodies:\n  disk:\n    mesh: m\n    material: "
       "steel\n    clamp: INNER\n    modes: 1000\n";
  if (sector) {
    c << "    cyclic:\n      sectors: 6\n      axis: {point: [0, 0, 0], direction: z}\n"
         "      low: LOW\n      high: HIGH\n";
  }
  c << "contacts:\n";
  for (int s = 0; s < (sector ? 1 : kBlades); ++s) c << shroud_springs(b, s, "disk", sector);
  c << "excitation:\n";
  for (int s = 0; s < (sector ? 1 : kBlades); ++s) {
    const Eigen::Vector3d f =
        Eigen::AngleAxisd(2 * M_PI * s / kBlades, Eigen::Vector3d::UnitZ()) * force;
    const std::complex<double> phase = std::polar(1.0, 2 * M_PI * s / kBlades);
    c << "  - {body: disk, node: " << b.mesh.node_ids[b.forced(s)] << ", force: [";
    for (int i = 0; i < 3; ++i) {
      const std::complex<double> v = phase * f[i];
      c << (i ? ", " : "") << "[" << v.real() << ", " << v.imag() << "]";
    }
    c << "]" << (sector ? ", engine_order: 1" : "") << "}\n";
  }
  // The sector spins about its cyclic axis (the default); the ring about the same axis.
  c << "rotation:\n  speed_rpm: 20000\n"
    << (sector ? "" : "  axis: {point: [0, 0, 0], direction: z}\n")
    << "analysis:\n  frequency: {start_hz: 1100, stop_hz: 1120, step_hz: 10}\n  harmonics: 1\n"
       "  tolerance: 1.0e-11\nrecovery: {points: none}\noutput: {plots: false}\n";
  return c.str();
}

TEST(RotationCli, ASpinningSectorsForcedResponseIsTheWholeSpinningRings) {
  const fs::path dir = fresh_dir("rotation_ring");
  const cyc::BladedRing sector = cyc::bladed_ring(kBlades, 1),
                        ring = cyc::bladed_ring(kBlades, kBlades);
  write_ring_mesh(dir / "sector.inp", sector);
  write_ring_mesh(dir / "ring.inp", ring);
  // Both recovered at every point (the full sector per nodal diameter; the whole ring as one
  // body), at blade 0's forced node and nodes spread over sector 0 (the same ids in the ring).
  std::ostringstream nodes;
  nodes << sector.mesh.node_ids[sector.forced(0)];
  const int n = sector.mesh.num_nodes();
  for (int i : {0, n / 3, 2 * n / 3, n - 1}) nodes << ", " << sector.mesh.node_ids[i];
  for (const bool is_sector : {true, false}) {
    std::string text = spinning_case(is_sector ? sector : ring, is_sector);
    text.replace(text.find("recovery: {points: none}"), 24,
                 "recovery: {points: all, nodes: [" + nodes.str() + "]}");
    std::ofstream(dir / (is_sector ? "sector.yaml" : "ring.yaml")) << text;
  }
  for (const std::string name : {"sector", "ring"}) {
    ASSERT_EQ(run("run " + (dir / (name + ".yaml")).string() + " -o " + (dir / name).string(),
                  dir / (name + ".log")),
              0)
        << slurp(dir / (name + ".log"));
  }
  // Blade 0's shroud forces (local frame), every point and harmonic: the static ones (harmonic
  // 0, from the centrifugal load alone) and the vibration's.
  const auto forces = [](const fs::path& csv) {
    std::map<std::string, std::complex<double>> out;
    for (const auto& r : read_csv(csv)) {
      if (r.at("contact") != "shroud0" || r.at("frame") != "local") continue;
      out[r.at("point") + "|" + r.at("pair") + "|" + r.at("axis") + "|" + r.at("harmonic")] = {
          std::stod(r.at("real_n")), std::stod(r.at("imag_n"))};
    }
    return out;
  };
  const auto a = forces(dir / "sector/contact_forces.csv"),
             b = forces(dir / "ring/contact_forces.csv");
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 0u);
  double worst = 0.0, scale = 0.0, static_scale = 0.0;
  for (const auto& [k, v] : a) {
    worst = std::max(worst, std::abs(v - b.at(k)));
    scale = std::max(scale, std::abs(v));
    if (k.substr(k.size() - 2) == "|0") static_scale = std::max(static_scale, std::abs(v));
  }
  // Exact reductions of the same linear problem on both sides: round-off.
  EXPECT_LT(worst, 1e-8 * scale);
  EXPECT_GT(static_scale, 1e-3 * scale);  // the centrifugal load strains the shroud springs
  // The recovered fields: the static state under the centrifugal load (every node's body force,
  // the spinning stiffness) and the vibration, the same on the sector as on the ring.
  const auto recovered = [](const fs::path& csv) {
    std::map<std::string, std::complex<double>> out;
    for (const auto& r : read_csv(csv)) {
      out[r.at("point") + "|" + r.at("node") + "|" + r.at("axis") + "|" + r.at("harmonic")] = {
          std::stod(r.at("real_m")), std::stod(r.at("imag_m"))};
    }
    return out;
  };
  const auto ua = recovered(dir / "sector/recovered_nodes.csv"),
             ub = recovered(dir / "ring/recovered_nodes.csv");
  ASSERT_EQ(ua.size(), 3u * 5 * 3 * 2);  // points x nodes x axes x harmonics
  ASSERT_EQ(ua.size(), ub.size());
  double u_worst = 0.0, u_scale = 0.0;
  for (const auto& [k, v] : ua) {
    u_worst = std::max(u_worst, std::abs(v - ub.at(k)));
    u_scale = std::max(u_scale, std::abs(v));
  }
  EXPECT_LT(u_worst, 1e-9 * u_scale);  // measured 1e-12
  // The spinning sector's log says what it does.
  EXPECT_NE(slurp(dir / "sector.log").find("rotation: 20000 rpm"), std::string::npos);
}

}  // namespace
