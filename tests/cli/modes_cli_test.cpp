// End-to-end: the `stickslip modes` program on the reference two-beam joint (coarse mesh so the
// test is quick). References are independent of our code: Euler–Bernoulli bounds for the first
// bending mode, and the file formats' own consistency.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace stickslip::cli_test;

std::vector<double> read_frequencies(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "mode,frequency_hz");
  std::vector<double> f;
  while (std::getline(in, line)) f.push_back(std::stod(line.substr(line.find(',') + 1)));
  return f;
}

TEST(ModesCli, ButtJointFrequenciesAreOrderedAndFirstBendingLiesInBeamTheoryBounds) {
  const fs::path dir = fresh_dir("butt");
  ASSERT_EQ(run("modes --coarse --modes 6 -o " + dir.string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  const std::vector<double> f = read_frequencies(dir / "frequencies.csv");
  ASSERT_EQ(f.size(), 6u);
  for (size_t j = 1; j < f.size(); ++j) EXPECT_GT(f[j], f[j - 1]);
  // Stuck butt joint = a clamped–clamped beam of length 0.6 m whose thickness (z) is 0.03 m
  // except 0.015 m over the middle 0.1 m. Its first bending frequency lies between those of
  // uniform clamped–clamped Euler–Bernoulli beams of thickness 0.015 and 0.03:
  //   f1 = (4.7300^2 / (2 pi L^2)) sqrt(E t^2 / (12 rho)).
  const double E = 2e11, rho = 7800, L = 0.6, beta2 = 4.730040745 * 4.730040745;
  const auto f1 = [&](double t) {
    return beta2 / (2 * M_PI * L * L) * std::sqrt(E * t * t / (12 * rho));
  };
  EXPECT_GT(f[0], f1(0.015));
  EXPECT_LT(f[0], f1(0.03));
  // The VTU holds one field per mode and names each frequency.
  const std::string vtu = slurp(dir / "modes.vtu");
  EXPECT_NE(vtu.find("Name=\"mode_6\""), std::string::npos);
  EXPECT_NE(vtu.find("mode_6_frequency_hz"), std::string::npos);
  // Nothing but the two results (no temporary files left behind).
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name == "log.txt") continue;
    ++files;
    EXPECT_TRUE(name == "frequencies.csv" || name == "modes.vtu") << name;
  }
  EXPECT_EQ(files, 2);
}

TEST(ModesCli, BadArgumentsFailWithAMessage) {
  const fs::path dir = fresh_dir("bad");
  EXPECT_NE(run("modes --arrangement sideways -o " + dir.string(), dir / "log.txt"), 0);
  EXPECT_NE(slurp(dir / "log.txt").find("arrangement"), std::string::npos);
  EXPECT_EQ(run("modes --element S4R -o " + dir.string(), dir / "log2.txt"), 2);
  EXPECT_NE(slurp(dir / "log2.txt").find("unknown element type S4R"), std::string::npos);
}

TEST(ModesCli, VersionAndHelp) {
  const fs::path dir = fresh_dir("version");
  EXPECT_EQ(run("--version", dir / "v.txt"), 0);
  EXPECT_NE(slurp(dir / "v.txt").find("stickslip "), std::string::npos);
  EXPECT_EQ(run("modes --help", dir / "h.txt"), 0);
  EXPECT_NE(slurp(dir / "h.txt").find("--arrangement"), std::string::npos);
}

}  // namespace
