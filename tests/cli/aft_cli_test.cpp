// analysis.aft through the program (issue 25): example 01's Jenkins oscillator at H = 1 with
// `aft: event` and 16 time samples equals the one-harmonic balance with the Jenkins describing
// function solved here in closed form; `aft: sampled` with the same samples does not; a wrong
// value stops at the key. The fallback count of points.csv and summary.json on the coarse joint,
// whose contact slips on ellipses: against the pairs whose tangential forces leave a line.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace {

using namespace stickslip::cli_test;

const fs::path kExample =
    fs::path(STICKSLIP_TEST_DATA_DIR) / ".." / ".." / "examples" / "01_jenkins_oscillator";

// m = 1, k = 1e6, kt = 1e6, μN = 10 N, F = 5 N, C = α m, α = 5 (example 01's case.yaml).
constexpr double kM = 1, kK = 1e6, kKt = 1e6, kFs = 10, kF = 5, kAlpha = 5;

// |X| of the one-harmonic balance x0 |k − mω² + iωc + ν(x0)| = F, ν = (a1 − i b1)/x0 the
// Jenkins describing function (u = x0 cos θ: cos β = 1 − 2Fs/(kt x0), a1 = kt x0 (β − sin 2β/2)/π,
// b1 = −(4Fs/π)(1 − Fs/(kt x0))), by bisection (the residual grows with x0 here).
double describing_function_amplitude(double omega) {
  auto residual = [&](double x0) {
    std::complex<double> nu = kKt;
    if (kKt * x0 > kFs) {
      const double beta = std::acos(1 - 2 * kFs / (kKt * x0));
      const double a1 = kKt * x0 * (beta - 0.5 * std::sin(2 * beta)) / M_PI;
      const double b1 = -4 * kFs / M_PI * (1 - kFs / (kKt * x0));
      nu = std::complex<double>(a1, -b1) / x0;
    }
    return x0 * std::abs(std::complex<double>(kK - kM * omega * omega, omega * kAlpha * kM) + nu) -
           kF;
  };
  double lo = 1e-12, hi = 1.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = std::sqrt(lo * hi);
    (residual(mid) < 0 ? lo : hi) = mid;
  }
  return std::sqrt(lo * hi);
}

std::string jenkins_case(const std::string& aft) {
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
excitation:
  - {body: oscillator, node: 1, direction: x, amplitude: 5}
damping: {alpha: 5.0, beta: 0.0}
analysis:
  frequency: {start_hz: 210, stop_hz: 240, step_hz: 15}
  harmonics: 1
  time_samples: 16
  tolerance: 1.0e-13
  aft: )" + aft + R"(
recovery: {points: none}
output: {directory: results, plots: false}
)";
}

// Largest relative difference of |X1| at node 1 from the describing-function amplitude.
double worst_error(const fs::path& dir) {
  double worst = 0;
  int points = 0;
  const auto pts = read_csv(dir / "points.csv");
  for (const auto& r : read_csv(dir / "master_response.csv")) {
    if (r.at("axis") != "x" || r.at("harmonic") != "1") continue;
    const int point = std::stoi(r.at("point"));
    const double omega = 2 * M_PI * std::stod(pts.at(point).at("frequency_hz"));
    const double ref = describing_function_amplitude(omega);
    const double amp = std::hypot(std::stod(r.at("real_m")), std::stod(r.at("imag_m")));
    EXPECT_GT(amp, kFs / kKt) << "point " << point << " does not slip";
    worst = std::max(worst, std::abs(amp - ref) / ref);
    ++points;
  }
  EXPECT_EQ(points, 3);
  return worst;
}

TEST(AftCli, EventAftGivesTheDescribingFunctionSolutionWithSixteenSamples) {
  constexpr double kExactTolerance = 1e-9;  // Newton at 1e-13; the AFT is exact
  const fs::path dir = fresh_dir("aft_event");
  for (const char* f : {"K.hb", "K.mapping", "M.hb", "M.mapping"}) {
    fs::copy_file(kExample / f, dir / f);
  }
  const fs::path event = write_case(dir, "event", jenkins_case("event"));
  ASSERT_EQ(run("run -q " + event.string() + " -o " + (dir / "event").string(), dir / "e.log"), 0)
      << slurp(dir / "e.log");
  EXPECT_EQ(slurp(dir / "e.log").find("warning"), std::string::npos) << slurp(dir / "e.log");
  const double event_error = worst_error(dir / "event");
  EXPECT_LE(event_error, kExactTolerance);

  const fs::path sampled = write_case(dir, "sampled", jenkins_case("sampled"));
  ASSERT_EQ(run("run -q " + sampled.string() + " -o " + (dir / "sampled").string(),
                dir / "s.log"),
            0)
      << slurp(dir / "s.log");
  const double sampled_error = worst_error(dir / "sampled");
  std::printf("|X1| against the describing function, N = 16: event %.2e, sampled %.2e\n",
              event_error, sampled_error);
  EXPECT_GT(sampled_error, 1e3 * kExactTolerance);

  const fs::path bad = write_case(dir, "bad", jenkins_case("exact"));
  const fs::path log = dir / "bad.log";
  EXPECT_EQ(run("run -q " + bad.string() + " -o " + (dir / "bad").string(), log), 2);
  EXPECT_NE(slurp(log).find("analysis.aft"), std::string::npos) << slurp(log);
  EXPECT_NE(slurp(log).find(":20"), std::string::npos) << slurp(log);  // its line
  fs::remove_all(dir);
}

TEST(AftCli, FallbackCountIsThePairsWhoseTangentialMotionLeavesALine) {
  // `aft: event` computes a pair exactly when its tangential motion stays on a line and falls back
  // to the sampled AFT otherwise; the force of a collinear cycle is collinear too (τ = ±μN e or
  // kt-proportional along e), that of a pair moving on an ellipse is not. So the pairs counted in
  // points.csv aft_fallback_pairs are those whose harmonic-1 tangential force (X_t1, X_t2) in
  // contact_forces.csv spans the plane: Im(X_t1 conj X_t2) beyond round-off of |X_t1||X_t2|.
  // summary.json aft.fallback_points counts the points with any. `sampled` never falls back, and
  // `event_planar` computes these ellipses itself.
  constexpr double kLineTolerance = 1e-9;
  const fs::path dir = fresh_dir("aft_fallback");
  for (const std::string aft : {"event", "sampled", "event_planar"}) {
    SCOPED_TRACE(aft);
    const fs::path c = write_case(dir, aft, coarse_joint_head(2.0, 1.0, "50") + "  aft: " + aft +
                                                "\nrecovery: {points: none}\n"
                                                "output: {directory: results, plots: false, "
                                                "vtu: false}\n");
    const fs::path out = dir / aft, log = dir / (aft + ".log");
    ASSERT_EQ(run("run -q " + c.string() + " -o " + out.string(), log), 0) << slurp(log);
    std::map<std::pair<int, int>, std::complex<double>> t1, t2;
    for (const auto& r : read_csv(out / "contact_forces.csv")) {
      if (r.at("frame") != "local" || r.at("harmonic") != "1") continue;
      const auto key = std::make_pair(std::stoi(r.at("point")), std::stoi(r.at("pair")));
      const std::complex<double> x(std::stod(r.at("real_n")), std::stod(r.at("imag_n")));
      if (r.at("axis") == "t1") t1[key] = x;
      if (r.at("axis") == "t2") t2[key] = x;
    }
    std::map<int, int> planar;  // point -> pairs whose tangential force spans the plane
    for (const auto& [key, x1] : t1) {
      const std::complex<double> x2 = t2.at(key);
      planar[key.first] += std::abs((x1 * std::conj(x2)).imag()) >
                           kLineTolerance * std::abs(x1) * std::abs(x2);
    }
    int points_with = 0, total = 0;
    for (const auto& r : read_csv(out / "points.csv")) {
      const int point = std::stoi(r.at("point")), n = std::stoi(r.at("aft_fallback_pairs"));
      EXPECT_EQ(n, aft == "event" ? planar[point] : 0) << "point " << point;
      points_with += n > 0;
      total += n;
    }
    std::ifstream in(out / "summary.json");
    const nlohmann::json summary = nlohmann::json::parse(in);
    EXPECT_EQ(summary["aft"]["method"], aft);
    EXPECT_EQ(summary["aft"]["fallback_points"], points_with);
    if (aft == "event") {
      EXPECT_GT(total, 0);  // the case this test is about: elliptical slip at some points
      std::printf("aft: event: %d pair cycles fell back at %d points\n", total, points_with);
    }
  }
  fs::remove_all(dir);
}

}  // namespace
