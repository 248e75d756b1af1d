// End-to-end: the load-incremental static contact problem (`analysis.static_increments`, issue 23
// item 3) through `stickslip run`, against the hand calculation of
// tests/hbm/static_contact_test.cpp (StaticContact.TwoContactsClosingInSequenceFollowTheLoadPath):
// one node (a body given by its matrices, K = k_s I, M = I kg) on ground springs, touching the
// ground through two friction contacts with initial gaps g1 < g2 (`gap`), and a static load (Q
// along x, P along z, harmonic 0) that presses it. Contact 1 closes at λ1 = g1 k_s / P, after the
// node moved a1 = λ1 Q / k_s along x; contact 2 at λ2 = (g2 (k_s + kn) − kn g1) / P, at x = a2 =
// (λ2 Q + kt a1)/(k_s + kt). At λ = 1: x = (Q + kt (a1 + a2))/(k_s + 2 kt), both stuck, τ_i = kt (x
// − a_i); one proportional step (`static_increments: 1`) starts both springs at x = 0 and contact 2
// slips, τ2 = μN2.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <cmath>
#include <fstream>
#include <map>
#include <string>

#include <fmt/core.h>

namespace {

using namespace stickslip::cli_test;

constexpr double kS = 1.0e6, kKt = 1.0e6, kKn = 1.0e6, kMu = 0.5, kP = 1000.0, kQ = 300.0;
constexpr double kG1 = 1.5e-4, kG2 = 3.2e-4;
// Newton's static tolerance (1e-8 of the linear static response) on a piecewise-linear problem
// whose last step lands to round-off; the CSV's shortest round-trip digits.
constexpr double kTolerance = 1e-9;

std::string node_case(const std::string& increments) {
  return fmt::format(R"(stickslip: 1
bodies:
  block: {{reduced: {{stiffness: k.mtx, mass: m.mtx, mapping: k.mapping}}}}
contacts:
  - name: first
    law: friction
    bodies: [block, ground]
    pairs: [1]
    normal: [0, 0, 1]
    t1: [1, 0, 0]
    gap: {g1}
    per_pair: {{kt: {kt}, kn: {kn}, mu: {mu}}}
  - name: second
    law: friction
    bodies: [block, ground]
    pairs: [1]
    normal: [0, 0, 1]
    t1: [1, 0, 0]
    gap: {g2}
    per_pair: {{kt: {kt}, kn: {kn}, mu: {mu}}}
excitation:
  - {{body: block, node: 1, force: [{Q}, 0, {P}], harmonic: 0}}
  - {{body: block, node: 1, direction: y, amplitude: 1.0e-3}}
damping: {{alpha: 5.0}}
analysis:
  frequency: {{start_hz: 50, stop_hz: 60, step_hz: 10}}
  harmonics: 1
  time_samples: 16{increments}
recovery: {{points: none}}
output: {{plots: false}}
)",
                     fmt::arg("kt", kKt), fmt::arg("kn", kKn), fmt::arg("mu", kMu),
                     fmt::arg("g1", kG1), fmt::arg("g2", kG2), fmt::arg("Q", kQ), fmt::arg("P", kP),
                     fmt::arg("increments", increments));
}

// contact -> axis -> harmonic-0 local force of point 0.
std::map<std::string, std::map<std::string, double>> static_forces(const fs::path& out) {
  std::map<std::string, std::map<std::string, double>> f;
  for (const auto& r : read_csv(out / "contact_forces.csv")) {
    if (r.at("harmonic") != "0" || r.at("frame") != "local" || r.at("point") != "0") continue;
    f[r.at("contact")][r.at("axis")] = std::stod(r.at("real_n"));
  }
  return f;
}

TEST(StaticPathCli, ContactsClosingInSequenceKeepTheTangentialForcesOfTheLoadPath) {
  const fs::path dir = fresh_dir("static_path");
  {
    std::ofstream k(dir / "k.mtx"), m(dir / "m.mtx"), map(dir / "k.mapping");
    k << "%%MatrixMarket matrix coordinate real general\n3 3 3\n1 1 " << kS << "\n2 2 " << kS
      << "\n3 3 " << kS << "\n";
    m << "%%MatrixMarket matrix coordinate real general\n3 3 3\n1 1 1\n2 2 1\n3 3 1\n";
    map << "Matrix Eqn   Node   DOF\n1 1 UX\n2 1 UY\n3 1 UZ\n";
  }
  // The hand calculation (the header).
  const double l1 = kG1 * kS / kP, a1 = l1 * kQ / kS;
  const double l2 = (kG2 * (kS + kKn) - kKn * kG1) / kP, a2 = (l2 * kQ + kKt * a1) / (kS + kKt);
  const double x = (kQ + kKt * (a1 + a2)) / (kS + 2 * kKt);
  const double z = (kP + kKn * (kG1 + kG2)) / (kS + 2 * kKn);
  const double N1 = kKn * (z - kG1), N2 = kKn * (z - kG2);
  const double tau1 = kKt * (x - a1), tau2 = kKt * (x - a2);
  const double tau2_one = kMu * N2, tau1_one = kKt * (kQ - tau2_one) / (kS + kKt);
  ASSERT_LT(tau2, kMu * N2);
  ASSERT_GT(kKt * kQ / (kS + 2 * kKt), kMu * N2);  // one step: contact 2 slips

  for (const auto& [name, increments] :
       std::map<std::string, std::string>{{"automatic", ""},
                                          {"three", "\n  static_increments: 3"},
                                          {"one", "\n  static_increments: 1"}}) {
    SCOPED_TRACE(name);
    const fs::path c = write_case(dir, name, node_case(increments));
    const fs::path out = dir / ("out_" + name);
    ASSERT_EQ(run("run -q " + c.string() + " -o " + out.string(), dir / (name + ".log")), 0)
        << slurp(dir / (name + ".log"));
    const auto f = static_forces(out);
    ASSERT_EQ(f.size(), 2u);
    const bool one = name == "one";
    EXPECT_NEAR(f.at("first").at("n"), N1, kTolerance * kP);
    EXPECT_NEAR(f.at("second").at("n"), N2, kTolerance * kP);
    EXPECT_NEAR(f.at("first").at("t1"), one ? tau1_one : tau1, kTolerance * kP);
    EXPECT_NEAR(f.at("second").at("t1"), one ? tau2_one : tau2, kTolerance * kP);
    EXPECT_NEAR(f.at("first").at("t2"), 0.0, kTolerance * kP);
    // The harmonic balance started from that state: with a 1 mN shake the cycles stay stuck
    // about it (points.csv static_mismatch: the cycle-mean force against the static one).
    for (const auto& p : read_csv(out / "points.csv")) {
      EXPECT_EQ(p.at("converged"), "1");
      EXPECT_LT(std::stod(p.at("static_mismatch")), 1e-6);
    }
    // The case the run replays (summary.json inputs) keeps the key.
    EXPECT_EQ(slurp(out / "summary.json").find("static_increments") != std::string::npos,
              !increments.empty());
  }
  std::printf(
      "[ hand calculation ] two stops closing in sequence: path tau = %.6g, %.6g N, one "
      "step %.6g, %.6g N\n",
      tau1, tau2, tau1_one, tau2_one);
}

}  // namespace
