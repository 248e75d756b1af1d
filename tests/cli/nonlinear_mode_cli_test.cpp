// `analysis.method: nonlinear_mode` through the program (issue 14): example 01's Jenkins oscillator
// (m = 1 kg, k = 1e6 N/m, kt = 1e6 N/m, μN = 10 N, C = α M with α = 5 1/s) written as a case, its
// nonlinear mode at H = 1 against the closed form of the Jenkins describing function derived here,
// the files and summary.json entry it writes, and bad input stopped at its key and line. The
// reduced body has x, y, z at the node (k = 1e6 each) and the element acts along x: the stuck
// modes are y and z at 1000 rad/s (modes 1, 2) and x at √2·1000 rad/s (mode 3).
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <cmath>
#include <complex>
#include <cstdio>
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

void replace_once(std::string& text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
}

// printf-style formatting of a case text fragment (two numbers).
std::string fmt_case(const char* format, double a, double b) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer, format, a, b);
  return buffer;
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

// A forced response with analysis.nonlinear_mode: the same oscillator forced along x by F at
// H = 1. The prediction (single nonlinear mode theory, hbm/nonlinear_mode.h) solves, per modal
// amplitude a = x (m = 1, ψ = 1), (ω(x)² − Ω² + i ξ(x) Ω) x e^{iθ} = F: with s = Ω², the quadratic
// (ω² − s)² + ξ² s = (F/x)², whose positive roots are the rows of snmt.csv. F is chosen so that the
// largest amplitude x* sits on the backbone (F = ξ(x*) ω(x*) x*: s = ω² is a root there), and the
// sweep starts at f* = ω(x*)/2π: the harmonic balance at that frequency balances the describing
// function |i(cω + E/(πx²))| x = F, whose solution is x* too, with the same phase (−90°: the
// response lags the force by a quarter period at the backbone).
TEST(NonlinearModeCli, ForcedResponsePredictionFromTheMode) {
  constexpr double kTolerance = 1e-8;  // Newton to 1e-12, exact AFT: as above
  const double x_star = 1e-4;          // 10 a_s
  const Reference star = jenkins_mode(x_star);
  const double F = star.xi * star.omega * x_star;
  const double f_star = star.omega / (2 * M_PI);
  const fs::path dir = example_dir("nonlinear_mode_prediction");
  std::string text = mode_case("");
  replace_once(text, "  method: nonlinear_mode\n",
               fmt_case("  method: stepped\n  frequency: {start_hz: %.17g, stop_hz: %.17g, "
                        "step_hz: 1}\n  nonlinear_mode:\n    mode: 3\n    amplitude: {start: "
                        "2.0e-6, stop: 1.0e-4, points: 30}\n",
                        f_star, f_star + 2));
  replace_once(text, "damping:",
               fmt_case("excitation:\n  - {body: oscillator, node: 1, direction: x, "
                        "amplitude: %.17g}\n",
                        F, 0.0) +
                   "damping:");
  replace_once(text, "output: {directory: results, plots: false}",
               "output:\n  directory: results\n  plots: true\n  frf:\n    - {body: oscillator, "
               "node: 1, direction: x}");
  const fs::path file = write_case(dir, "forced", text);
  const fs::path out = dir / "out";
  // 4: every result written, pictures missing (no gnuplot here); the .dat files are written.
  const int code = run("run " + file.string() + " -o " + out.string(), dir / "log");
  ASSERT_TRUE(code == 0 || code == 4) << code << "\n" << slurp(dir / "log") << text;

  const auto modes = read_csv(out / "nonlinear_modes.csv");
  ASSERT_EQ(modes.size(), 30u);
  const auto rows = read_csv(out / "snmt.csv");
  std::map<std::pair<int, std::string>, std::complex<double>> response;  // (row, axis) → X_1
  for (const auto& r : read_csv(out / "snmt_response.csv")) {
    if (r.at("node") == "1" && r.at("harmonic") == "1") {
      response[{std::stoi(r.at("row")), r.at("axis")}] = {std::stod(r.at("real_m")),
                                                          std::stod(r.at("imag_m"))};
    }
  }
  size_t expected_rows = 0;
  for (const auto& m : modes) {
    const double x = std::stod(m.at("modal_amplitude"));
    const Reference ref = jenkins_mode(x);
    const double w2 = ref.omega * ref.omega, P2 = (F / x) * (F / x);
    const double disc = P2 - ref.xi * ref.xi * w2 + 0.25 * std::pow(ref.xi, 4);
    if (disc >= 0) expected_rows += w2 - 0.5 * ref.xi * ref.xi - std::sqrt(disc) > 0 ? 2 : 1;
  }
  ASSERT_EQ(rows.size(), expected_rows);
  ASSERT_GE(rows.size(), 20u);
  int at_backbone = -1;
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    SCOPED_TRACE(::testing::Message() << "row " << i);
    ASSERT_EQ(r.at("row"), std::to_string(i));
    const int point = std::stoi(r.at("point"));
    const double x = std::stod(modes.at(point).at("modal_amplitude"));
    EXPECT_EQ(std::stod(r.at("modal_amplitude")), x);
    const Reference ref = jenkins_mode(x);
    const double w2 = ref.omega * ref.omega, P2 = (F / x) * (F / x);
    const double root = std::sqrt(P2 - ref.xi * ref.xi * w2 + 0.25 * std::pow(ref.xi, 4));
    const bool above = r.at("branch") == "above";
    const double omega = std::sqrt(w2 - 0.5 * ref.xi * ref.xi + (above ? root : -root));
    EXPECT_NEAR(2 * M_PI * std::stod(r.at("frequency_hz")), omega, kTolerance * omega);
    EXPECT_NEAR(2 * M_PI * std::stod(r.at("mode_frequency_hz")), ref.omega, kTolerance * ref.omega);
    const std::complex<double> X = F / std::complex<double>(w2 - omega * omega, ref.xi * omega);
    EXPECT_NEAR(std::abs(response.at({static_cast<int>(i), "x"}) - X), 0.0, kTolerance * x);
    EXPECT_EQ(std::abs(response.at({static_cast<int>(i), "y"})), 0.0);
    if (point == 29 && above) at_backbone = static_cast<int>(i);
  }
  ASSERT_GE(at_backbone, 0);
  EXPECT_NEAR(std::stod(rows[at_backbone].at("frequency_hz")), f_star, 1e-10 * f_star);
  // The harmonic balance at f*: point 0 of the sweep.
  const auto points = read_csv(out / "points.csv");
  ASSERT_EQ(points.at(0).at("converged"), "1");
  EXPECT_NEAR(std::stod(points.at(0).at("frequency_hz")), f_star, 1e-14 * f_star);
  std::complex<double> hb;
  for (const auto& r : read_csv(out / "master_response.csv")) {
    if (r.at("point") == "0" && r.at("node") == "1" && r.at("axis") == "x" &&
        r.at("harmonic") == "1")
      hb = {std::stod(r.at("real_m")), std::stod(r.at("imag_m"))};
  }
  EXPECT_NEAR(std::abs(hb - response.at({at_backbone, "x"})), 0.0, kTolerance * x_star);
  EXPECT_NEAR(std::abs(hb), x_star, kTolerance * x_star);
  // summary.json and the FRF plot's data.
  const nlohmann::json s = nlohmann::json::parse(slurp(out / "summary.json"));
  const auto& nm = s.at("nonlinear_mode");
  EXPECT_EQ(nm.at("mode"), 3);
  EXPECT_EQ(nm.at("prediction_points"), rows.size());
  EXPECT_NEAR(nm.at("first_slip_amplitude").get<double>(), kFs / kKt, 1e-12);
  EXPECT_EQ(nm.at("predicted_peak").at("point"), 29);
  EXPECT_NEAR(nm.at("predicted_peak").at("frf").at(0).at("amplitude_m").get<double>(), x_star,
              kTolerance * x_star);
  const std::string dat = slurp(out / "frf.dat");
  EXPECT_NE(dat.find("# nonlinear mode prediction: oscillator node 1 x"), std::string::npos);
  EXPECT_NE(dat.find("# backbone: oscillator node 1 x"), std::string::npos);
  // `stickslip plot` draws the same from the files.
  fs::remove(out / "frf.dat");
  const int plot_code = run("plot " + out.string(), dir / "plot.log");
  ASSERT_TRUE(plot_code == 0 || plot_code == 4) << slurp(dir / "plot.log");
  EXPECT_EQ(slurp(out / "frf.dat"), dat);
}

TEST(NonlinearModeCli, BadPredictionInputNamesTheKeyAndLine) {
  const fs::path dir = example_dir("nonlinear_mode_prediction_bad");
  const std::string forced = R"(stickslip: 1
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
EXCITATION
analysis:
  method: stepped
  frequency: {start_hz: 200, stop_hz: 210, step_hz: 5}
  harmonics: 1
TAIL
recovery: {points: none}
output: {directory: results, plots: false}
)";
  const std::string excitation =
      "excitation:\n  - {body: oscillator, node: 1, direction: x, amplitude: 5}";
  struct Bad {
    std::string excitation, tail, key, line;
  };
  // With the excitation (lines 12-13), analysis starts on line 14: method 15, frequency 16,
  // harmonics 17, the tail from 18. Without it, analysis starts on line 12 (the tail on 16).
  const std::vector<Bad> cases{
      {"", "  nonlinear_mode:\n    mode: 3\n    amplitude: {start: 1.0e-6, stop: 1.0e-4}",
       "analysis.nonlinear_mode", ":16"},
      {excitation, "  nonlinear_mode:\n    mode: 4\n    amplitude: {start: 1.0e-6, stop: 1.0e-4}",
       "analysis.nonlinear_mode.mode", ":19"},
      {excitation, "  nonlinear_mode:\n    mode: 3\n    amplitude: {start: 1.0e-4, stop: 1.0e-6}",
       "analysis.nonlinear_mode.amplitude.stop", ":20"},
      {excitation, "  nonlinear_mode:\n    amplitude: {start: 1.0e-6, stop: 1.0e-4}",
       "analysis.nonlinear_mode.mode", ""},
      {excitation,
       "  nonlinear_mode:\n    mode: 3\n    amplitude: {start: 1.0e-6, stop: 1.0e-4}\n"
       "    points: 3",
       "analysis.nonlinear_mode", ":21"},
      {excitation, "  mode: 3", "analysis.mode", ":18"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(cases[i].tail);
    std::string text = forced;
    text.replace(text.find("EXCITATION"), 10, cases[i].excitation);
    if (cases[i].excitation.empty()) text.erase(text.find("\nanalysis:"), 1);
    text.replace(text.find("TAIL"), 4, cases[i].tail);
    const fs::path file = write_case(dir, "bad" + std::to_string(i), text);
    const fs::path log = dir / ("bad" + std::to_string(i) + ".log");
    EXPECT_EQ(run("run -q " + file.string() + " -o " + (dir / "out").string(), log), 2)
        << slurp(log);
    EXPECT_NE(slurp(log).find(cases[i].key), std::string::npos) << slurp(log);
    EXPECT_NE(slurp(log).find(cases[i].line), std::string::npos) << slurp(log);
  }
  // With method nonlinear_mode the block is refused: its keys belong to analysis itself.
  const fs::path file = write_case(
      dir, "mode",
      mode_case("  mode: 3\n  amplitude: {start: 1.0e-6, stop: 1.0e-3}\n  nonlinear_mode:\n"
                "    mode: 3\n    amplitude: {start: 1.0e-6, stop: 1.0e-3}\n"));
  EXPECT_EQ(run("run -q " + file.string() + " -o " + (dir / "out").string(), dir / "m.log"), 2);
  EXPECT_NE(slurp(dir / "m.log").find("analysis.nonlinear_mode"), std::string::npos)
      << slurp(dir / "m.log");
}

}  // namespace

// Example 02's nonlinear-mode study (examples/02_two_beam_joint/nonlinear_mode.yaml: mode 4 of the
// two-beam joint at 150, 80 and 50 N per pair), run by the program on a copy with fewer
// amplitudes. Independent references: the stuck mode's frequency from `stickslip modes` on the
// full finite-element model (no Craig–Bampton, the contact pairs as springs kt, kt, kn: a different
// code path and model; the reduced model's frequency is a Rayleigh–Ritz upper bound of it), the
// linear limit of the damping (C = αM: every mode has ξ = α, D = α/(2ω)), and the physics of a
// friction joint: the frequency falls (softening) and the damping rises from the stuck value as
// the amplitude grows.
TEST(NonlinearModeCli, TwoBeamJointExampleSoftensFromTheStuckMode) {
  const fs::path examples = fs::path(STICKSLIP_TEST_DATA_DIR) / ".." / ".." / "examples";
  const fs::path dir = fresh_dir("nonlinear_mode_example_02");
  std::string text = slurp(examples / "02_two_beam_joint" / "nonlinear_mode.yaml");
  replace_once(text, "amplitude: {start: 1.0e-6, stop: 1.0e-3, points: 200}",
               "amplitude: {start: 1.0e-7, stop: 1.0e-3, points: 17}");
  replace_once(text, "plots: true", "plots: false");
  const fs::path file = write_case(dir, "mode", text);
  ASSERT_EQ(run("run -q " + file.string() + " -o " + (dir / "out").string(), dir / "log"), 0)
      << slurp(dir / "log");
  ASSERT_EQ(run("modes --modes 4 -o " + (dir / "full").string(), dir / "full.log"), 0)
      << slurp(dir / "full.log");
  const auto full = read_csv(dir / "full" / "frequencies.csv");
  ASSERT_EQ(full.size(), 4u);
  const double f4 = std::stod(full[3].at("frequency_hz"));
  // Craig–Bampton with 60 fixed-interface modes per beam against the full model: measured
  // 2.1e-7 (1762.86611 against 1762.86574 Hz); 1e-5 bounds the truncation with a margin.
  constexpr double kReduction = 1e-5;
  constexpr double kAlphaExample = 5.0;  // damping: {alpha: 5.0}
  for (const char* study : {"preload_150", "preload_80", "preload_50"}) {
    SCOPED_TRACE(study);
    const auto rows = read_csv(dir / "out" / study / "nonlinear_modes.csv");
    ASSERT_EQ(rows.size(), 17u);
    for (const auto& r : rows) ASSERT_EQ(r.at("converged"), "1") << r.at("point");
    const double f0 = std::stod(rows[0].at("frequency_hz"));
    EXPECT_GE(f0, f4 * (1 - 1e-9));  // the reduced model is stiffer (Ritz)
    EXPECT_LE(f0, f4 * (1 + kReduction));
    // Stuck at 1e-7 (the first pair slips above 1e-6 at every preload: summary.json).
    EXPECT_EQ(std::stod(rows[0].at("pairs_slipping")), 0.0);
    EXPECT_NEAR(std::stod(rows[0].at("xi_per_s")), kAlphaExample, 1e-6 * kAlphaExample);
    EXPECT_NEAR(std::stod(rows[0].at("damping_ratio")), kAlphaExample / (4 * M_PI * f0),
                1e-6 * kAlphaExample / (4 * M_PI * f0));
    double previous = f0;
    for (size_t i = 1; i < rows.size(); ++i) {
      const double f = std::stod(rows[i].at("frequency_hz"));
      EXPECT_LE(f, previous * (1 + 1e-9)) << "point " << i;
      EXPECT_GE(std::stod(rows[i].at("damping_ratio")), (1 - 1e-6) * kAlphaExample / (4 * M_PI * f))
          << "point " << i;
      previous = f;
    }
    // The range reaches well into slip: the frequency has fallen by more than 1 %.
    EXPECT_LT(previous, 0.99 * f0);
  }
}
