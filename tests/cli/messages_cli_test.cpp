// Messages and exit codes of the stickslip program (docs/command-line.md): usage errors exit 2
// with the program's one error format; the log says which window around which stuck mode was
// swept, reports reduction, modes and recovery as they go, and warns when the response peak is
// at the edge of the window.
#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <complex>
#include <fstream>
#include <string>

#include "cli_test_support.h"

namespace stickslip {
namespace {

using namespace cli_test;

TEST(MessagesCli, UsageErrorsExitTwoWithTheProgramsErrorFormat) {
  const fs::path dir = fresh_dir("messages_usage");
  struct Case {
    std::string args, says;
  };
  std::ofstream(dir / "x.yaml") << "stickslip: 1\n";
  for (const Case& c :
       {Case{"run " + (dir / "missing.yaml").string(), "missing.yaml"}, Case{"", "subcommand"},
        Case{"frobnicate case.yaml", "'frobnicate'"}, Case{"solve", "case"},
        Case{"run --no-such-option " + (dir / "x.yaml").string(), "no-such"}}) {
    SCOPED_TRACE(c.args);
    EXPECT_EQ(run(c.args, dir / "log"), 2);
    const std::string log = slurp(dir / "log");
    EXPECT_EQ(log.rfind("stickslip: error: ", 0), 0u) << log;
    EXPECT_NE(log.find(c.says), std::string::npos) << log;
  }
  EXPECT_EQ(run("--help", dir / "log"), 0);
  EXPECT_EQ(run("--version", dir / "log"), 0);
  EXPECT_EQ(run("run --help", dir / "log"), 0);
}

// The two-beam joint, a window [around mode 4 - w, + w] in 1 Hz steps, `preload` N per pair.
std::string joint(double half_width_hz, double preload, const std::string& recovery) {
  return coarse_joint_head(half_width_hz, 1, std::to_string(preload)) +
         "recovery: {points: " + recovery +
         "}\n"
         "output:\n"
         "  plots: false\n"
         "  frf:\n    - {body: beam1, node: 11, direction: y}\n";
}

TEST(MessagesCli, TheLogSaysTheWindowTheStagesAndAPeakAtTheEdge) {
  const fs::path dir = fresh_dir("messages_log");
  // A window too narrow to hold the resonance of mode 4 (softened by slip): the largest
  // response sits at an end of the sweep.
  const fs::path narrow = write_case(dir, "narrow", joint(0.5, 50, "all"));
  ASSERT_EQ(run("run " + narrow.string() + " -o " + (dir / "narrow").string(), dir / "n.log"), 0)
      << slurp(dir / "n.log");
  const std::string log = slurp(dir / "n.log");
  const nlohmann::json s = nlohmann::json::parse(slurp(dir / "narrow" / "summary.json"));
  // The window and the stuck mode it came from.
  const double mode_hz = s["window"]["stuck_mode_hz"].get<double>();
  EXPECT_NE(log.find(fmt::format("around stuck mode 4 at {:.6g} Hz", mode_hz)), std::string::npos)
      << log;
  EXPECT_NE(log.find(fmt::format("sweep window {:.6g} to {:.6g} Hz", mode_hz - 0.5, mode_hz + 0.5)),
            std::string::npos)
      << log;
  // Progress of the reduction and the modes.
  EXPECT_EQ(count(log, "reduced DOFs in"), 2) << log;
  EXPECT_EQ(count(log, "reduced-model modes: done in"), 1) << log;
  // The peak is at the edge, by the table: the largest |harmonic 1| of the FRF DOF.
  int peak_point = -1, last = -1;
  double peak = -1;
  for (const auto& r : read_csv(dir / "narrow" / "master_response.csv")) {
    if (r.at("body") != "beam1" || r.at("node") != "11" || r.at("harmonic") != "1" ||
        r.at(r.count("axis") ? "axis" : "dof") != "y")
      continue;
    const int point = std::stoi(r.at("point"));
    const double a =
        std::abs(std::complex<double>(std::stod(r.at("real")), std::stod(r.at("imag"))));
    last = std::max(last, point);
    if (a > peak) peak = a, peak_point = point;
  }
  ASSERT_TRUE(peak_point == 0 || peak_point == last) << "the case no longer peaks at an edge";
  EXPECT_EQ(count(log, "warning: the response peak of beam1 node 11 y is at the edge"), 1) << log;
  EXPECT_TRUE(s["frf"][0]["peak_at_window_edge"].get<bool>());

  // Stuck (a large preload) the peak is the stuck mode, in the middle of the window: no warning;
  // with ten or more recovered points the recovery reports its progress.
  const fs::path wide = write_case(dir, "wide", joint(6, 1e6, "all"));
  ASSERT_EQ(run("run " + wide.string() + " -o " + (dir / "wide").string(), dir / "w.log"), 0)
      << slurp(dir / "w.log");
  const std::string wlog = slurp(dir / "w.log");
  const nlohmann::json w = nlohmann::json::parse(slurp(dir / "wide" / "summary.json"));
  EXPECT_FALSE(w["frf"][0]["peak_at_window_edge"].get<bool>()) << w["frf"].dump();
  EXPECT_EQ(wlog.find("warning"), std::string::npos) << wlog;
  EXPECT_GE(count(wlog, "recovery of beam1: "), 3) << wlog;
  EXPECT_NE(wlog.find("points, "), std::string::npos) << wlog;
}

// `stickslip keys`: the key table on stdout, one section on request, an unknown section refused.
TEST(MessagesCli, KeysListsTheCaseFileKeysFromTheTable) {
  const fs::path dir = fresh_dir("keys_cli");
  ASSERT_EQ(run("keys analysis", dir / "analysis.txt"), 0);
  const std::string analysis = slurp(dir / "analysis.txt");
  for (const char* key : {"analysis.method", "analysis.frequency.step_hz", "analysis.predictor"})
    EXPECT_NE(analysis.find(key), std::string::npos) << key << "\n" << analysis;
  EXPECT_EQ(analysis.find("recovery.method"), std::string::npos) << analysis;
  ASSERT_EQ(run("keys", dir / "all.txt"), 0);
  const std::string all = slurp(dir / "all.txt");
  const size_t at = all.find("materials.NAME.youngs_modulus ");
  ASSERT_NE(at, std::string::npos) << all;
  const std::string line = all.substr(at, all.find('\n', at) - at);
  EXPECT_NE(line.find("number > 0 (Pa); default required; a study may vary it"), std::string::npos)
      << line;
  EXPECT_EQ(run("keys analysis.nothing", dir / "bad.txt"), 2);
  EXPECT_NE(slurp(dir / "bad.txt").find("the sections are"), std::string::npos);
}

}  // namespace
}  // namespace stickslip
