// The examples run in CI (issue 6): each one through the program as a user would run it, with a
// check that does not rely on the program's own numbers.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace stickslip::cli_test;

const fs::path kExamples = fs::path(STICKSLIP_TEST_DATA_DIR) / ".." / ".." / "examples";

fs::path ex03_case_path(const fs::path& copy) {
  return copy / "examples" / "03_imported_hbmat" / "case.yaml";
}

// A row's complex value: master_response.csv (m) or, with unit "n", contact_forces.csv (N).
std::complex<double> value(const std::map<std::string, std::string>& r,
                           const std::string& unit = "m") {
  return {std::stod(r.at("real_" + unit)), std::stod(r.at("imag_" + unit))};
}

TEST(Examples, JenkinsOscillatorIsTheStuckLinearOscillatorBelowTheStickLimit) {
  const fs::path out = fresh_dir("example_01");
  ASSERT_EQ(shell(kProgram + " run -q " + (kExamples / "01_jenkins_oscillator/case.yaml").string() +
                      " -o " + out.string(),
                  out / "log.txt"),
            0)
      << slurp(out / "log.txt");
  // At 120 Hz the stuck amplitude F / |k + kt − mω² + iωc| (c = α m) is below the stick limit
  // μN/kt = 1e-5 m, so the response is exactly the stuck linear one.
  const double m = 1, k = 1e6, kt = 1e6, alpha = 5, F = 5, w = 2 * M_PI * 120;
  const std::complex<double> x_stuck = F / std::complex<double>(k + kt - m * w * w, w * alpha * m);
  ASSERT_LT(std::abs(x_stuck), 1e-5);
  bool found = false;
  for (const auto& r : read_csv(out / "master_response.csv")) {
    if (r.at("point") == "0" && r.at("axis") == "x" && r.at("harmonic") == "1") {
      found = true;
      EXPECT_LT(std::abs(value(r) - x_stuck), 1e-9 * std::abs(x_stuck));
    }
  }
  EXPECT_TRUE(found);
  for (const auto& r : read_csv(out / "points.csv")) EXPECT_EQ(r.at("converged"), "1");
  // The phase plot's first point: arg of the same closed form, in degrees.
  std::ifstream phase(out / "frf_phase.dat");
  std::string line;
  ASSERT_TRUE(std::getline(phase, line) && line.rfind("# ", 0) == 0) << line;
  double f = 0, deg = 0;
  ASSERT_TRUE(phase >> f >> deg);
  EXPECT_NEAR(f, 120.0, 1e-9);
  EXPECT_NEAR(deg, std::arg(x_stuck) * 180 / M_PI, 1e-6);
}

TEST(Examples, TwoBeamJointRecoversTheReducedResponseOnTheFullMeshesAndHbmatImportMatches) {
  const fs::path out02 = fresh_dir("example_02");
  ASSERT_EQ(shell(kProgram + " run -q " + (kExamples / "02_two_beam_joint/case.yaml").string() +
                      " -o " + out02.string(),
                  out02 / "log.txt"),
            0)
      << slurp(out02 / "log.txt");
  for (const char* study : {"preload_150", "preload_80", "preload_50"}) {
    for (const auto& r : read_csv(out02 / study / "points.csv")) EXPECT_EQ(r.at("converged"), "1");
    for (const auto& r : read_csv(out02 / study / "recovery_check.csv")) {
      // The full FE beams, solved directly under the contact forces, against the reduced
      // nonlinear response: Craig–Bampton truncation (60 modes) is the only difference.
      if (r.at("harmonic") == "1") {
        EXPECT_LT(std::stod(r.at("max_relative")), 1e-3) << study;
      }
    }
  }
  // `stickslip plot` draws run's plots again from the files, the same: the study overlay (the
  // example's values 150, 80, 50 are not in order; both draw them by value) and each folder's.
  std::map<std::string, std::string> drawn;
  const std::vector<std::string> scripts = {
      "frf_study.gp",           "preload_150/frf.gp",         "preload_150/dissipation.gp",
      "preload_150/dissipation.dat", "preload_50/hysteresis.gp", "preload_50/hysteresis.dat"};
  for (const std::string& f : scripts) drawn[f] = slurp(out02 / f);
  ASSERT_EQ(run("plot -q " + out02.string(), out02 / "plot.log"), 0) << slurp(out02 / "plot.log");
  for (const std::string& f : scripts) {
    EXPECT_FALSE(drawn[f].empty()) << f;
    EXPECT_EQ(slurp(out02 / f), drawn[f]) << f;
  }
  // Example 03: the same beams as HBMAT matrices. Copy the example (it writes its matrices next
  // to the case file) and run its script with this build's program.
  const fs::path ex03 = fresh_dir("example_03");
  fs::create_directories(ex03 / "examples");
  fs::copy(kExamples / "03_imported_hbmat", ex03 / "examples" / "03_imported_hbmat",
           fs::copy_options::recursive);
  fs::copy(kExamples / "02_two_beam_joint", ex03 / "examples" / "02_two_beam_joint",
           fs::copy_options::recursive);
  ASSERT_EQ(
      shell("STICKSLIP=" + kProgram + " " +
                (ex03 / "examples" / "03_imported_hbmat/run.sh").string() + " -q",
            ex03 / "log.txt"),
      0)
      << slurp(ex03 / "log.txt");
  std::map<std::string, std::complex<double>> a, b;
  const auto key = [](const std::map<std::string, std::string>& r) {
    return r.at("point") + "/" + r.at("body") + "/" + r.at("node") + "/" + r.at("axis") + "/" +
           r.at("harmonic");
  };
  for (const auto& r : read_csv(out02 / "preload_150" / "master_response.csv"))
    a[key(r)] = value(r);
  // The example writes into the repository's out/, never into examples/.
  EXPECT_FALSE(fs::exists(ex03 / "examples" / "03_imported_hbmat" / "results"));
  for (const auto& r : read_csv(ex03 / "out" / "03_imported_hbmat" / "master_response.csv")) {
    b[key(r)] = value(r);
  }
  ASSERT_FALSE(b.empty());
  double scale = 0, diff = 0;
  int compared = 0;
  for (const auto& [k, v] : b) {
    const auto it = a.find(k);
    if (it == a.end()) continue;
    ++compared;
    scale = std::max(scale, std::abs(it->second));
    diff = std::max(diff, std::abs(it->second - v));
  }
  EXPECT_GT(compared, 1000);
  // The matrices went through text with 16 significant digits: agreement to well below 1e-6.
  EXPECT_LT(diff, 1e-6 * scale);
  // The thesis's route: the loads of each matrix body as an APDL macro on its mapping's node
  // numbers, for the points asked. Reference: contact_forces.csv (global frame; A = beam1 receives
  // the negative of the force on B) plus the 50 N excitation of node 11 along z, harmonic 1.
  EXPECT_EQ(run("export -q " + ex03_case_path(ex03).string() + " --point 0,2 --format apdl",
                ex03 / "export.log"),
            0)
      << slurp(ex03 / "export.log");
  const fs::path results03 = ex03 / "out" / "03_imported_hbmat";
  for (int point : {0, 2}) {
    std::map<int, std::array<std::complex<double>, 3>> expected;  // beam1 node -> (x, y, z)
    expected[11][2] += 50.0;
    for (const auto& r : read_csv(results03 / "contact_forces.csv")) {
      if (std::stoi(r.at("point")) != point || r.at("frame") != "global" ||
          r.at("harmonic") != "1") {
        continue;
      }
      const int axis = r.at("axis") == "x" ? 0 : r.at("axis") == "y" ? 1 : 2;
      expected[std::stoi(r.at("node_a"))][axis] -= value(r, "n");
    }
    // F,node,FX|FY|FZ,Re,Im lines after HARFRQ (the harmonic-1 load step).
    std::ifstream mac(results03 / ("loads_p" + std::to_string(point) + "_beam1.mac"));
    ASSERT_TRUE(mac) << point;
    std::string line;
    bool harmonic = false;
    int compared_forces = 0;
    double scale = 0, diff = 0;
    while (std::getline(mac, line)) {
      if (line.rfind("HARFRQ,", 0) == 0) harmonic = true;
      if (!harmonic || line.rfind("F,", 0) != 0) continue;
      std::stringstream ss(line.substr(2));
      std::string node, label, re, im;
      std::getline(ss, node, ','), std::getline(ss, label, ','), std::getline(ss, re, ',');
      std::getline(ss, im, ',');
      const int axis = label[1] - 'X';
      const auto it = expected.find(std::stoi(node));
      ASSERT_NE(it, expected.end()) << line;
      const std::complex<double> want = it->second[axis];
      scale = std::max(scale, std::abs(want));
      diff = std::max(diff, std::abs(want - std::complex<double>(std::stod(re), std::stod(im))));
      ++compared_forces;
    }
    // Every node with a load has its three F commands (a separated pair's node may have none).
    const auto loaded = std::count_if(expected.begin(), expected.end(), [](const auto& e) {
      return std::abs(e.second[0]) + std::abs(e.second[1]) + std::abs(e.second[2]) > 0;
    });
    EXPECT_EQ(compared_forces, 3 * loaded) << point;
    // Shortest round-trip decimals on both sides: equal to the last bit but for the sums.
    EXPECT_LT(diff, 1e-12 * scale) << point;
    EXPECT_TRUE(fs::exists(results03 / ("loads_p" + std::to_string(point) + "_beam2.mac")));
  }
  // A CalculiX deck needs a mesh: refused at the case's bodies line.
  EXPECT_EQ(run("export -q " + ex03_case_path(ex03).string() + " --point 0 --format calculix",
                ex03 / "export.log"),
            2);
  EXPECT_NE(slurp(ex03 / "export.log").find("a CalculiX deck needs the full model"),
            std::string::npos)
      << slurp(ex03 / "export.log");
  // Bodies given by matrices have no full model: `recover` says so at the case's `bodies` line
  // (it used to report "recovered 1 point(s)" and write an empty file).
  const fs::path ex03_case = ex03_case_path(ex03);
  EXPECT_EQ(run("recover -q " + ex03_case.string() + " --point 0", ex03 / "recover.log"), 2);
  const std::string recover_log = slurp(ex03 / "recover.log");
  EXPECT_NE(recover_log.find(ex03_case.string() + ":10: bodies"), std::string::npos) << recover_log;
  EXPECT_NE(recover_log.find("recover needs a body given by a mesh"), std::string::npos)
      << recover_log;
}

// Example 04: one node on a friction contact that lifts off, swept up and down. Checks that do not
// use the program's numbers: (1) where the contact stays closed the normal motion is linear and
// decoupled from the tangential slip, Z1 = F_z / (k + kn − Ω² + iΩc) (m = 1); (2) at every point
// the work of the excitation per cycle equals the viscous plus the friction dissipation; (3) the
// two sweeps are one response outside the fold and two inside it: the downward sweep on a branch
// that separates over most of the cycle, the upward one on a nearly closed one (both stable:
// README, checked by time integration).
struct LiftOffPoint {
  double omega = 0, friction_energy = 0, separation = 0;
  std::map<std::pair<std::string, int>, std::complex<double>> X;  // (dof, harmonic)
};

std::map<int, LiftOffPoint> lift_off_sweep(const fs::path& dir) {
  std::map<int, LiftOffPoint> pts;
  for (const auto& r : read_csv(dir / "points.csv")) {
    LiftOffPoint& p = pts[std::stoi(r.at("point"))];
    EXPECT_EQ(r.at("converged"), "1") << dir << " point " << r.at("point");
    p.omega = 2 * M_PI * std::stod(r.at("frequency_hz"));
    p.friction_energy = std::stod(r.at("dissipated_energy_j"));
  }
  for (const auto& r : read_csv(dir / "master_response.csv")) {
    pts[std::stoi(r.at("point"))].X[{r.at("axis"), std::stoi(r.at("harmonic"))}] = value(r);
  }
  for (const auto& r : read_csv(dir / "contact_state.csv")) {
    pts[std::stoi(r.at("point"))].separation = std::stod(r.at("separation"));
  }
  return pts;
}

TEST(Examples, LiftOffNodeSweptUpAndDownFindsBothCoexistingResponses) {
  const fs::path out = fresh_dir("example_04");
  for (const char* name : {"case", "down"}) {
    const fs::path c = kExamples / "04_lift_off_branches" / (std::string(name) + ".yaml");
    ASSERT_EQ(shell(kProgram + " run -q " + c.string() + " -o " + (out / name).string(),
                    out / (std::string(name) + ".log")),
              0)
        << slurp(out / (std::string(name) + ".log"));
  }
  const auto up = lift_off_sweep(out / "case"), down = lift_off_sweep(out / "down");
  ASSERT_EQ(up.size(), 121u);
  ASSERT_EQ(down.size(), up.size());
  for (const auto& [i, d] : down) {  // `sweep: down`: from 0.64 Hz down by 0.004 Hz
    EXPECT_NEAR(d.omega, 2 * M_PI * (0.64 - 0.004 * i), 1e-9) << "point " << i;
  }
  const double k = 1, kn = 8, c = 0.05, Fx = 0.3, Fz = 0.8, N0 = 1;
  // The up sweep's points by frequency, to pair them with the down sweep's.
  std::map<long, const LiftOffPoint*> up_at;
  for (const auto& [i, p] : up) up_at[std::lround(p.omega * 1e6)] = &p;
  int closed_checked = 0, overlap = 0;
  for (const auto* sweep : {&up, &down}) {
    for (const auto& [i, p] : *sweep) {
      const double w = p.omega;
      // (1) Closed throughout (kn |Z1| below N0 with a margin): linear in z, no other harmonic.
      const std::complex<double> z1 = Fz / std::complex<double>(k + kn - w * w, w * c);
      if (kn * std::abs(z1) < 0.9 * N0) {
        ++closed_checked;
        EXPECT_LT(std::abs(p.X.at({"z", 1}) - z1), 1e-8 * std::abs(z1)) << "rad/s " << w;
        EXPECT_LT(std::abs(p.X.at({"z", 0})), 1e-8 * std::abs(z1)) << "rad/s " << w;
        EXPECT_EQ(p.separation, 0.0) << "rad/s " << w;
      }
      // (2) Work per cycle: π Im(F̄ X1) in = π c Ω Σ_k k² |X_k|² + friction out. The friction
      // energy is the sampled AFT's (N = 512): measured within 5e-4 of the input at the lift-off
      // points, round-off where the contact is stuck and closed.
      const double input = -M_PI * (Fx * p.X.at({"x", 1}).imag() + Fz * p.X.at({"z", 1}).imag());
      double viscous = 0;
      for (const auto& [key, v] : p.X) viscous += M_PI * c * w * key.second * key.second * std::norm(v);
      EXPECT_NEAR(viscous + p.friction_energy, input, 2e-3 * input) << "rad/s " << w;
    }
  }
  EXPECT_GE(closed_checked, 30);  // 16 per sweep: 1.0–1.37 and 4.02 rad/s
  for (const auto& [i, d] : down) {
    const LiftOffPoint& u = *up_at.at(std::lround(d.omega * 1e6));
    const double zu = std::abs(u.X.at({"z", 1})), zd = std::abs(d.X.at({"z", 1}));
    if (d.omega < 1.5 || d.omega > 2.05) {  // one response: both sweeps find the same
      EXPECT_LT(std::abs(u.X.at({"z", 1}) - d.X.at({"z", 1})), 1e-6 * zd) << "rad/s " << d.omega;
    } else if (zd > 10 * zu) {  // two: the downward sweep stays on the lift-off branch
      ++overlap;
      EXPECT_GT(d.separation, 0.5) << "rad/s " << d.omega;
      EXPECT_LT(u.separation, 0.25) << "rad/s " << d.omega;
    }
  }
  EXPECT_GE(overlap, 10) << "the sweeps no longer show the two coexisting responses";
}

// A continuation that stops before the end of its range is not a success: exit code 1, a line on
// stderr saying where, summary.json "completed": false, the points before kept. Stopped here by
// max_points; `sweep: down` starts it at the high end.
TEST(Examples, ContinuationStoppedShortOfTheRangeExitsOneAndSaysWhere) {
  const fs::path out = fresh_dir("example_04_short");
  fs::copy(kExamples / "04_lift_off_branches", out / "ex", fs::copy_options::recursive);
  std::string text = slurp(out / "ex" / "down.yaml");
  const std::string static_line = "  static: coupled";
  ASSERT_NE(text.find(static_line), std::string::npos);
  text.replace(text.find(static_line), static_line.size(),
               "  static: coupled\n  method: continuation\n  max_points: 20");
  std::ofstream(out / "ex" / "short.yaml") << text;
  ASSERT_EQ(shell(kProgram + " run -q " + (out / "ex" / "short.yaml").string() + " -o " +
                      (out / "res").string(),
                  out / "log.txt"),
            1)
      << slurp(out / "log.txt");
  const std::string log = slurp(out / "log.txt");
  EXPECT_NE(log.find("the analysis stopped at"), std::string::npos) << log;
  EXPECT_NE(log.find("max_points"), std::string::npos) << log;
  const auto points = read_csv(out / "res" / "points.csv");
  ASSERT_EQ(points.size(), 20u);
  for (const auto& r : points) EXPECT_EQ(r.at("converged"), "1");
  EXPECT_NEAR(std::stod(points.front().at("frequency_hz")), 0.64, 1e-12);
  EXPECT_LT(std::stod(points.back().at("frequency_hz")), 0.64);
  EXPECT_NE(slurp(out / "res" / "summary.json").find("\"completed\": false"), std::string::npos);
}

// Example 07: beam 2 meshed finer than beam 1 (the surfaces do not match, so the default coupling
// is mortar) and the preload computed from a pressing force of 4500 N on each beam's forced node.
// Checked against hand calculations, not stored numbers: the mortar points' areas make up the
// contact face (0.05 x 0.015 m) and each point's weights sum to 1 (the face lies wholly over
// beam 2's); the joint's mean normal force balances beam 1 with its clamp's recovered reaction
// (N = 4500 N + R_x, full FE model); the README's story, that the eccentric pressing force opens
// most of the joint (most points separated over the whole cycle) and puts the resonance below the
// stuck mode 4, which the window holds; the full-model recovery matches the reduced response.
TEST(Examples, NonMatchingJointWithAComputedPreload) {
  const fs::path out = fresh_dir("example_07");
  ASSERT_EQ(shell(kProgram + " run -q " + (kExamples / "07_non_matching_joint/case.yaml").string() +
                      " -o " + out.string(),
                  out / "log.txt"),
            0)
      << slurp(out / "log.txt");
  for (const auto& r : read_csv(out / "points.csv")) EXPECT_EQ(r.at("converged"), "1");
  std::map<std::string, double> area, weights;
  for (const auto& r : read_csv(out / "contact_coupling.csv")) {
    area[r.at("pair")] = std::stod(r.at("area_m2"));
    weights[r.at("pair")] += std::stod(r.at("weight"));
  }
  ASSERT_EQ(area.size(), 30u);  // beam 1's 6 x 5 contact nodes
  double total_area = 0;
  for (const auto& [pair, a] : area) {
    total_area += a;
    EXPECT_NEAR(weights.at(pair), 1.0, 1e-12) << pair;
  }
  EXPECT_NEAR(total_area, 0.05 * 0.015, 1e-15);
  // The recovered point (the peak): beam 1's balance along x at harmonic 0.
  const auto check = read_csv(out / "recovery_check.csv");
  ASSERT_FALSE(check.empty());
  const std::string point = check.front().at("point");
  for (const auto& r : check) {
    if (r.at("harmonic") == "1") {
      EXPECT_LT(std::stod(r.at("max_relative")), 1e-3);
    }
  }
  double reaction = 0, normal = 0;
  for (const auto& r : read_csv(out / "reactions.csv"))
    if (r.at("point") == point && r.at("body") == "beam1" && r.at("axis") == "x" &&
        r.at("harmonic") == "0")
      reaction += std::stod(r.at("real_n"));
  for (const auto& r : read_csv(out / "contact_forces.csv"))
    if (r.at("point") == point && r.at("harmonic") == "0" && r.at("frame") == "local" &&
        r.at("axis") == "n")
      normal += std::stod(r.at("real_n"));
  EXPECT_NEAR(normal, 4500.0 + reaction, 1e-8 * 4500.0);
  EXPECT_GT(normal, 0.0);
  EXPECT_LT(normal, 4500.0);
  int separated = 0;
  for (const auto& r : read_csv(out / "contact_state.csv"))
    if (r.at("point") == point && std::stod(r.at("separation")) > 0.99) ++separated;
  EXPECT_GE(separated, 15) << "the pressing force no longer opens most of the joint";
  // The peak lies inside the window and below the stuck assembly's mode 4 (example 02's window
  // centre, 1762.9 Hz with beam 1's mesh on both sides).
  const std::string summary = slurp(out / "summary.json");
  EXPECT_EQ(summary.find("\"peak_at_window_edge\": true"), std::string::npos) << summary;
  const double peak = std::stod(check.front().at("frequency_hz"));
  EXPECT_GT(peak, 1400.0);
  EXPECT_LT(peak, 1762.9);
}

}  // namespace
