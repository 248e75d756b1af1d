// End-to-end: `stickslip run` on a small two-beam joint (coarse conforming mesh, few modes, few
// frequency points). References independent of the pipeline's own numbers:
//  - the full-model linear recovery (a different solver on a different model: the full FE body
//    loaded by the contact forces) reproduces the reduced nonlinear response at the master DOFs
//    (the thesis's validation);
//  - with friction so high that the joint cannot slip, the response peaks at the stuck
//    assembly's natural frequency (the window is centred on it) and nothing is dissipated;
//  - with a lower preload more of the cycle slips (friction limit μN falls);
//  - bad input stops with the case file's line.
#include <gtest/gtest.h>

#include "cli_test_support.h"

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

// The small joint (cli_test_support.h) with direct recovery of the peak point.
std::string small_case(double mu, double preload, const std::string& extra = "") {
  return small_joint_case(mu, preload,
                          "recovery: {points: peak, method: direct, fields: [displacement, "
                          "stress]}\noutput: {vtu: true, plots: false}\n" +
                              extra);
}

fs::path write_case(const std::string& name, const std::string& text) {
  const fs::path dir = fresh_dir("run_" + name);
  std::ofstream(dir / "case.yaml") << text;
  return dir;
}

struct Sweep {
  std::vector<double> f_hz;
  std::vector<double> amplitude;  // |y harmonic 1| of the forced node of beam 1
  std::vector<double> slip;       // mean slip fraction over the pairs
  std::vector<double> energy;     // dissipated energy per cycle, J
};

Sweep read_sweep(const fs::path& out) {
  Sweep s;
  for (const auto& r : read_csv(out / "points.csv")) {
    EXPECT_EQ(r.at("converged"), "1") << "point " << r.at("point");
    s.f_hz.push_back(std::stod(r.at("frequency_hz")));
    s.energy.push_back(std::stod(r.at("dissipated_energy_j")));
  }
  s.amplitude.assign(s.f_hz.size(), 0.0);
  s.slip.assign(s.f_hz.size(), 0.0);
  // The forced node of beam 1 is the only non-contact master of beam1: take the largest y
  // amplitude among beam1's masters that are not on the contact face (x = 0.30).
  std::map<std::string, int> contact_nodes;
  for (const auto& r : read_csv(out / "contact_state.csv")) {
    contact_nodes[r.at("node_a")] = 1;
    s.slip[std::stoi(r.at("point"))] += std::stod(r.at("slip"));
  }
  for (double& v : s.slip) v /= static_cast<double>(contact_nodes.size());
  for (const auto& r : read_csv(out / "master_response.csv")) {
    if (r.at("body") != "beam1" || r.at("axis") != "y" || r.at("harmonic") != "1") continue;
    if (contact_nodes.count(r.at("node"))) continue;
    const double a =
        std::abs(std::complex<double>(std::stod(r.at("real_m")), std::stod(r.at("imag_m"))));
    double& slot = s.amplitude[std::stoi(r.at("point"))];
    slot = std::max(slot, a);
  }
  return s;
}

TEST(RunCli, StuckJointPeaksAtTheStuckNaturalFrequencyAndFullRecoveryMatchesReduced) {
  const fs::path dir = write_case("stuck", small_case(1000.0, 500.0));
  ASSERT_EQ(run("run -q " + (dir / "case.yaml").string() + " -o " + (dir / "out").string(),
                dir / "log.txt"),
            0)
      << slurp(dir / "log.txt");
  const Sweep s = read_sweep(dir / "out");
  ASSERT_EQ(s.f_hz.size(), 9u);
  // The window is centred (point 4) on the stuck mode 4; a lightly damped (α = 5 1/s, ζ ≈ 2e-4)
  // linear resonance peaks within the 1 Hz step of its natural frequency.
  int peak = 0;
  for (size_t i = 1; i < s.amplitude.size(); ++i) {
    if (s.amplitude[i] > s.amplitude[peak]) peak = static_cast<int>(i);
  }
  EXPECT_EQ(peak, 4);
  for (size_t i = 0; i < s.f_hz.size(); ++i) {
    EXPECT_DOUBLE_EQ(s.slip[i], 0.0) << "point " << i;
    EXPECT_LT(std::abs(s.energy[i]), 1e-12) << "point " << i;
  }
  // Full model vs reduced at the masters, harmonic 1: the only difference is the Craig–Bampton
  // truncation (20 fixed-interface modes per beam, modes up to ~10x the window frequency).
  bool saw_h1 = false;
  for (const auto& r : read_csv(dir / "out" / "recovery_check.csv")) {
    if (r.at("harmonic") != "1") continue;
    saw_h1 = true;
    EXPECT_LT(std::stod(r.at("max_relative")), 1e-2) << r.at("body");
  }
  EXPECT_TRUE(saw_h1);
  EXPECT_TRUE(fs::exists(dir / "out" / "recovery_p4.vtm"));
  EXPECT_TRUE(fs::exists(dir / "out" / "recovery.pvd"));
  EXPECT_NE(slurp(dir / "out" / "recovery" / "beam1" / "p4.vtu").find("von_mises_alternating"),
            std::string::npos);
  EXPECT_NE(slurp(dir / "out" / "summary.json").find("\"converged_points\": 9"), std::string::npos);
}

TEST(RunCli, LowerPreloadSlipsMoreAndDissipates) {
  const fs::path high = write_case("high", small_case(0.5, 50.0));
  const fs::path low = write_case("low", small_case(0.5, 5.0));
  ASSERT_EQ(run("run -q " + (high / "case.yaml").string() + " -o " + (high / "out").string(),
                high / "log.txt"),
            0)
      << slurp(high / "log.txt");
  ASSERT_EQ(run("run -q " + (low / "case.yaml").string() + " -o " + (low / "out").string(),
                low / "log.txt"),
            0)
      << slurp(low / "log.txt");
  const Sweep h = read_sweep(high / "out");
  const Sweep l = read_sweep(low / "out");
  ASSERT_EQ(h.f_hz.size(), l.f_hz.size());
  double slip_h = 0, slip_l = 0;
  for (size_t i = 0; i < h.f_hz.size(); ++i) {
    slip_h += h.slip[i];
    slip_l += l.slip[i];
    EXPECT_GE(l.energy[i], -1e-30);  // friction only takes energy out (round-off aside)
  }
  EXPECT_GT(slip_l, slip_h);
  EXPECT_GT(*std::max_element(l.energy.begin(), l.energy.end()), 0.0);
}

TEST(RunCli, RecoveringEveryPointChecksEachAndWritesTheEnvelopeOverTheSweep) {
  std::string text = small_case(1000.0, 500.0);
  const std::string peak = "recovery: {points: peak,";
  text.replace(text.find(peak), peak.size(), "recovery: {points: all,");
  const fs::path dir = write_case("all", text);
  ASSERT_EQ(run("run -q " + (dir / "case.yaml").string() + " -o " + (dir / "out").string(),
                dir / "log.txt"),
            0)
      << slurp(dir / "log.txt");
  int rows = 0;
  for (const auto& r : read_csv(dir / "out" / "recovery_check.csv")) {
    ++rows;
    if (r.at("harmonic") == "1") {
      EXPECT_LT(std::stod(r.at("max_relative")), 1e-2);
    }
  }
  EXPECT_EQ(rows, 9 * 2 * 2);  // points x bodies x harmonics (0 and 1)
  EXPECT_TRUE(fs::exists(dir / "out" / "recovery" / "beam1" / "envelope.vtu"));
  EXPECT_TRUE(fs::exists(dir / "out" / "recovery" / "beam2" / "envelope.vtu"));
  EXPECT_TRUE(fs::exists(dir / "out" / "recovery_envelope.vtm"));
}

TEST(RunCli, BadCaseStopsWithFileLineAndRule) {
  const fs::path dir = write_case("bad", small_case(0.5, 50.0, "bogus_key: 3\n"));
  EXPECT_EQ(run("run " + (dir / "case.yaml").string(), dir / "log.txt"), 2);
  const std::string log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("case.yaml:26"), std::string::npos) << log;
  EXPECT_NE(log.find("bogus_key"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "results"));
}

}  // namespace
