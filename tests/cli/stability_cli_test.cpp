// analysis.stability through the program (issue 14 item 1): a Duffing oscillator (example 01's
// 1-DOF body, m = 1 kg, k = 1e6 N/m, with a `cubic` element to the ground) followed by
// continuation through both folds of its hardening response. Theory independent of the program:
// the branch between the two folds (where the curve runs backwards in frequency) is a saddle, so
// unstable, the two outer branches are stable; the multiplier is > 1 exactly on the unstable
// points. points.csv gets `stable` and `floquet_multiplier`, summary.json `stability`; without
// the key neither appears.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <cmath>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace {

using namespace stickslip::cli_test;

const fs::path kExample =
    fs::path(STICKSLIP_TEST_DATA_DIR) / ".." / ".." / "examples" / "01_jenkins_oscillator";

// ẍ + α ẋ + ω0² x + k3 x³ = F cos Ωt with ω0 = 1000 rad/s, α = 20 1/s (ζ = 1 %), k3 = 1e12 N/m³,
// F = 30 N: in units of ω0 and 1 mm the Duffing oscillator ω0 = 1, c = 0.02, k3 = 1, F = 0.03,
// whose response folds twice between 0.5 ω0 and 2 ω0 (80–318 Hz).
std::string duffing_case(bool stability) {
  return std::string(R"(stickslip: 1
bodies:
  oscillator:
    reduced: {stiffness: K.hb, mass: M.hb}
contacts:
  - name: duffing
    law: cubic
    bodies: [oscillator, ground]
    pairs: [1]
    direction: x
    per_pair: {k1: 0, k3: 1.0e12}
excitation:
  - {body: oscillator, node: 1, direction: x, amplitude: 30}
damping: {alpha: 20.0, beta: 0.0}
analysis:
  frequency: {start_hz: 80, stop_hz: 318, step_hz: 1}
  method: continuation
  harmonics: 5
  time_samples: 64
  static: coupled
)") + (stability ? "  stability: true\n" : "") +
         R"(recovery: {points: none}
output: {directory: results, plots: false}
)";
}

TEST(StabilityCli, DuffingMiddleBranchIsUnstableAndTheOuterBranchesStable) {
  const fs::path dir = fresh_dir("stability_cli");
  for (const char* f : {"K.hb", "K.mapping", "M.hb", "M.mapping"}) {
    fs::copy_file(kExample / f, dir / f);
  }
  const fs::path file = write_case(dir, "duffing", duffing_case(true));
  ASSERT_EQ(run("run -q " + file.string() + " -o " + (dir / "out").string(), dir / "run.log"), 0)
      << slurp(dir / "run.log");
  const auto points = read_csv(dir / "out" / "points.csv");
  const int n = static_cast<int>(points.size());
  ASSERT_GT(n, 30);
  auto f = [&](int i) { return std::stod(points[i].at("frequency_hz")); };
  int unstable = 0, backwards = 0, folds = 0;
  for (int i = 0; i < n; ++i) {
    ASSERT_EQ(points[i].at("converged"), "1");
    const bool stable = points[i].at("stable") == "1";
    const double multiplier = std::stod(points[i].at("floquet_multiplier"));
    unstable += stable ? 0 : 1;
    EXPECT_EQ(stable, multiplier <= 1 + 1e-6) << "point " << i << ": " << multiplier;
    if (i == 0 || i + 1 == n) continue;
    const bool before = f(i) < f(i - 1), after = f(i + 1) < f(i);
    if (before != after) {
      ++folds;  // at a fold a multiplier passes through 1: either answer is right there
      continue;
    }
    backwards += before ? 1 : 0;
    EXPECT_EQ(stable, !before) << "point " << i << " at " << f(i) << " Hz";
  }
  EXPECT_EQ(folds, 2);
  EXPECT_GT(backwards, 3);
  const nlohmann::json summary = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
  EXPECT_EQ(summary.at("stability").at("unstable_points").get<int>(), unstable);
  EXPECT_GT(summary.at("stability").at("largest_multiplier").get<double>(), 1.0);

  // Without the key: no columns, summary's stability null.
  const fs::path plain = write_case(dir, "plain", duffing_case(false));
  ASSERT_EQ(run("run -q " + plain.string() + " -o " + (dir / "plain").string(), dir / "p.log"), 0)
      << slurp(dir / "p.log");
  const auto rows = read_csv(dir / "plain" / "points.csv");
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0].count("stable"), 0u);
  EXPECT_TRUE(
      nlohmann::json::parse(slurp(dir / "plain" / "summary.json")).at("stability").is_null());
  fs::remove_all(dir);
}

}  // namespace
