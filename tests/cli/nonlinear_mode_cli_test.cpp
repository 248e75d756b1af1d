// `analysis.method: nonlinear_mode` through the program (issue 14): example 01's Jenkins oscillator
// (m = 1 kg, k = 1e6 N/m, kt = 1e6 N/m, μN = 10 N, C = α M with α = 5 1/s) written as a case, its
// nonlinear mode at H = 1 against the closed form of the Jenkins describing function derived here,
// the files and summary.json entry it writes, and bad input stopped at its key and line. The
// reduced body has x, y, z at the node (k = 1e6 each) and the element acts along x: the stuck
// modes are y and z at 1000 rad/s (modes 1, 2) and x at √2·1000 rad/s (mode 3).
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace {

using namespace stickslip::cli_test;

const fs::path kExample =
    fs::path(STICKSLIP_TEST_DATA_DIR) / ".." / ".." / "examples" / "01_jenkins_oscillator";

constexpr double kM = 1, kK = 1e6, kKt = 1e6, kFs = 10, kAlpha = 5;

// x = a cos Ωt through the Jenkins element: stuck below a_s = μN/kt; above it the force reverses
// at cos θ* = 1 − 2a_s/a, its in-phase fundamental is k_eq a with k_eq = kt (θ* − sin 2θ*/2)/π,
// and the loop dissipates E = 4μN(a − a_s) per cycle. The EPMC balance of m ẍ + (c − ξm) ẋ + kx +
// f = 0 at H = 1: Ω² = (k + k_eq)/m, ξ = c/m + E/(π m Ω a²), D = ξ/(2Ω). The modal amplitude of
// the mass-normalised mode φ = 1/√m is √m a = a here.
struct Reference {
  double omega, xi;
};
Reference jenkins_mode(double a) {
  const double as = kFs / kKt;
  double keq = kKt, energy = 0;
  if (a > as) {
    const double theta = std::acos(1 - 2 * as / a);
    keq = kKt * (theta - 0.5 * std::sin(2 * theta)) / M_PI;
    energy = 4 * kFs * (a - as);
  }
  const double omega = std::sqrt((kK + keq) / kM);
  return {omega, kAlpha + energy / (M_PI * kM * omega * a * a)};
}

std::string mode_case(const std::string& analysis_tail) {
  return R"(stickslip: 1
bodies:
  oscillator:
    reduced: {stiffness: K.hb, mass: M.hb}
contacts:
  - name: jenkins
    law: jenkins
    bodies: [oscillator, ground]
    pairs: [1]
    direction: x
    per_pair: {kt: 1.0e6, mu: 0.5, preload: 20}
damping: {alpha: 5.0, beta: 0.0}
analysis:
  method: nonlinear_mode
  harmonics: 1
  tolerance: 1.0e-12
)" + analysis_tail +
         R"(recovery: {points: none}
output: {directory: results, plots: false}
)";
}

fs::path example_dir(const std::string& name) {
  const fs::path dir = fresh_dir(name);
  for (const char* f : {"K.hb", "K.mapping", "M.hb", "M.mapping"})
    fs::copy_file(kExample / f, dir / f);
  return dir;
}

TEST(NonlinearModeCli, JenkinsOscillatorMatchesTheDescribingFunction) {
  // Newton to 1e-12 relative and an exact AFT (event, the Jenkins law): the closed form is met to
  // the residual; 1e-8 leaves room for the conditioning near the stick limit.
  constexpr double kTolerance = 1e-8;
  const fs::path dir = example_dir("nonlinear_mode_jenkins");
  const fs::path file =
      write_case(dir, "mode",
                 mode_case("  mode: 3\n  amplitude: {start: 2.0e-6, stop: 1.0e-3, points: 25}\n"));
  const fs::path out = dir / "out";
  ASSERT_EQ(run("run " + file.string() + " -o " + out.string(), dir / "log"), 0)
      << slurp(dir / "log");
  const auto rows = read_csv(out / "nonlinear_modes.csv");
  ASSERT_EQ(rows.size(), 25u);
  const double a0 = 2e-6, a1 = 1e-3;
  int slipping = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    ASSERT_EQ(r.at("converged"), "1") << "point " << i;
    const double a = std::stod(r.at("modal_amplitude"));
    EXPECT_NEAR(a, a0 * std::pow(a1 / a0, i / 24.0), 1e-12 * a);  // evenly spaced in ln a
    const Reference ref = jenkins_mode(a);
    EXPECT_NEAR(2 * M_PI * std::stod(r.at("frequency_hz")), ref.omega, kTolerance * ref.omega)
        << "point " << i;
    EXPECT_NEAR(std::stod(r.at("xi_per_s")), ref.xi, kTolerance * ref.xi) << "point " << i;
    EXPECT_NEAR(std::stod(r.at("damping_ratio")), ref.xi / (2 * ref.omega),
                kTolerance * ref.xi / ref.omega)
        << "point " << i;
    slipping += a > kFs / kKt ? 1 : 0;
  }
  EXPECT_GE(slipping, 15);
  // The shape: node 1, x, harmonic 1 = a (real, the mode's phase), harmonic 0 = 0; y and z rest.
  int shapes = 0;
  for (const auto& r : read_csv(out / "nonlinear_mode_shapes.csv")) {
    if (r.at("node") != "1") continue;
    const double a = std::stod(rows.at(std::stoi(r.at("point"))).at("modal_amplitude"));
    const double expected = r.at("harmonic") == "1" && r.at("axis") == "x" ? a : 0.0;
    EXPECT_NEAR(std::stod(r.at("real_m")), expected, 1e-9 * a);
    EXPECT_NEAR(std::stod(r.at("imag_m")), 0.0, 1e-9 * a);
    ++shapes;
  }
  EXPECT_EQ(shapes, 150);  // 25 points x 3 axes x harmonics 0, 1
  const nlohmann::json s = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(s.at("analysis"), "nonlinear_mode");
  EXPECT_EQ(s.at("nonlinear_mode").at("mode"), 3);
  EXPECT_NEAR(s.at("nonlinear_mode").at("linear_frequency_hz").get<double>(),
              std::sqrt((kK + kKt) / kM) / (2 * M_PI), 1e-9);
  EXPECT_NEAR(s.at("nonlinear_mode").at("linear_damping_ratio").get<double>(),
              kAlpha / (2 * std::sqrt((kK + kKt) / kM)), 1e-12);
  EXPECT_EQ(s.at("converged_points"), 25);
  EXPECT_TRUE(s.at("completed").get<bool>());
  // The written inputs make the same analysis again.
  std::ofstream(dir / "again.yaml") << s.at("inputs").get<std::string>();
  ASSERT_EQ(run("solve -q " + (dir / "again.yaml").string() + " -o " + (dir / "again").string(),
                dir / "again.log"),
            0)
      << slurp(dir / "again.log");
  expect_same_csv(out / "nonlinear_modes.csv", dir / "again" / "nonlinear_modes.csv");
}

TEST(NonlinearModeCli, BadInputNamesTheKeyAndLine) {
  const fs::path dir = example_dir("nonlinear_mode_bad");
  struct Bad {
    std::string tail, key, line;
  };
  // The analysis block starts on line 13: method 14, harmonics 15, tolerance 16, then the tail
  // (17).
  const std::vector<Bad> cases{
      {"  mode: 4\n  amplitude: {start: 1.0e-6, stop: 1.0e-3}\n", "analysis.mode", ":17"},
      // A mode that does not move the contact (y): its nonlinear mode is the linear one.
      {"  mode: 1\n  amplitude: {start: 1.0e-6, stop: 1.0e-3}\n", "analysis.mode", ":17"},
      {"  mode: 0\n  amplitude: {start: 1.0e-6, stop: 1.0e-3}\n", "analysis.mode", ":17"},
      {"  mode: 1\n  amplitude: {start: 1.0e-3, stop: 1.0e-3}\n", "analysis.amplitude.stop", ":18"},
      {"  mode: 1\n  amplitude: {start: -1.0e-3, stop: 1.0e-3}\n", "analysis.amplitude.start",
       ":18"},
      {"  mode: 1\n  amplitude: {start: 1.0e-6, stop: 1.0e-3, points: 1}\n",
       "analysis.amplitude.points", ":18"},
      {"  amplitude: {start: 1.0e-6, stop: 1.0e-3}\n", "analysis.mode", ""},
      {"  mode: 1\n", "analysis.amplitude", ""},
      {"  mode: 1\n  amplitude: {start: 1.0e-6, stop: 1.0e-3}\n  frequency: {start_hz: 1, "
       "stop_hz: 2, step_hz: 1}\n",
       "analysis.frequency", ":19"},
      {"  mode: 1\n  amplitude: {start: 1.0e-6, stop: 1.0e-3}\n  stability: true\n",
       "analysis.stability", ":19"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(cases[i].tail);
    const fs::path file = write_case(dir, "bad" + std::to_string(i), mode_case(cases[i].tail));
    const fs::path log = dir / ("bad" + std::to_string(i) + ".log");
    EXPECT_EQ(run("run -q " + file.string() + " -o " + (dir / "out").string(), log), 2)
        << slurp(log);
    EXPECT_NE(slurp(log).find(cases[i].key), std::string::npos) << slurp(log);
    EXPECT_NE(slurp(log).find(cases[i].line), std::string::npos) << slurp(log);
  }
  // mode and amplitude belong to nonlinear_mode only.
  std::string stepped = mode_case("  mode: 1\n");
  stepped.replace(stepped.find("method: nonlinear_mode"), 22, "method: stepped");
  stepped.replace(stepped.find("  harmonics: 1"), 0,
                  "  frequency: {start_hz: 200, stop_hz: 210, step_hz: 5}\n");
  const fs::path file = write_case(dir, "stepped", stepped);
  EXPECT_EQ(run("run -q " + file.string() + " -o " + (dir / "out").string(), dir / "s.log"), 2);
  EXPECT_NE(slurp(dir / "s.log").find("analysis.mode"), std::string::npos) << slurp(dir / "s.log");
}

}  // namespace
