// End-to-end: a CalculiX deck with SPRING1, SPRING2, SPRINGA and MASS elements (*SPRING, *MASS)
// read by `stickslip modes CASE`, against ccx *FREQUENCY run by the test on the very same deck;
// and the springs and masses matter (ccx without them differs by far more than the tolerance).
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace stickslip::cli_test;

// A bar [0, 1] x [0, 0.2]^2 of 4 x 1 x 1 C3D8, clamped at x = 0 (FIX). Node id 1 + i + 5 (j + 2k)
// at (0.25 i, 0.2 j, 0.2 k). With discrete: a SPRING1 to ground in y at the tip node 5, a SPRING2
// between node 10 (x of node 10) and node 20 (z of node 20), a SPRINGA along the diagonal from
// node 3 to node 20, and point masses on nodes 15 and 4.
void write_deck(const fs::path& file, int num_modes, bool discrete) {
  std::ostringstream s;
  auto id = [](int i, int j, int k) { return 1 + i + 5 * (j + 2 * k); };
  s << "*NODE, NSET=ALL\n";
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 5; ++i)
        s << id(i, j, k) << ", " << 0.25 * i << ", " << 0.2 * j << ", " << 0.2 * k << "\n";
  s << "*ELEMENT, TYPE=C3D8, ELSET=EALL\n";
  for (int i = 0; i < 4; ++i) {
    s << i + 1 << ", " << id(i, 0, 0) << ", " << id(i + 1, 0, 0) << ", " << id(i + 1, 1, 0) << ", "
      << id(i, 1, 0) << ", " << id(i, 0, 1) << ", " << id(i + 1, 0, 1) << ", " << id(i + 1, 1, 1)
      << ", " << id(i, 1, 1) << "\n";
  }
  s << "*NSET, NSET=FIX\n1, 6, 11, 16\n*NSET, NSET=TIP\n5\n";
  if (discrete) {
    s << "*ELEMENT, TYPE=SPRING1, ELSET=KG\n101, 5\n*SPRING, ELSET=KG\n2\n3.0e7\n"
         "*ELEMENT, TYPE=SPRING2, ELSET=KC\n102, 10, 20\n*SPRING, ELSET=KC\n1, 3\n5.0e7\n"
         "*ELEMENT, TYPE=SPRINGA, ELSET=KA\n103, 3, 20\n*SPRING, ELSET=KA\n\n8.0e7\n"
         "*ELEMENT, TYPE=MASS, ELSET=M1\n104, 15\n105, 4\n*MASS, ELSET=M1\n40.0\n";
  }
  s << "*MATERIAL, NAME=STEEL\n*ELASTIC\n2.0e11, 0.3\n*DENSITY\n7800\n"
       "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*STEP\n*FREQUENCY\n"
    << num_modes << "\n*BOUNDARY\nFIX, 1, 3\n*END STEP\n";
  std::ofstream(file) << s.str();
}

TEST(SpringMassCli, SpringsAndPointMassesGiveCalculixFrequencies) {
  constexpr int kModes = 6;
  const fs::path dir = fresh_dir("springs");
  write_deck(dir / "job.inp", kModes, true);
  const fs::path file = write_case(dir, "bar", tip_spring_bar_case("job.inp"));
  const std::string log = run_stage("modes", file, dir / "out");
  EXPECT_EQ(log.find("*SPRING"), std::string::npos) << log;  // used, not skipped
  EXPECT_EQ(log.find("*MASS"), std::string::npos) << log;
  const auto rows = read_csv(dir / "out" / "modes" / "frequencies.csv");
  const std::vector<double> lambda = ccx_job_eigenvalues(dir);
  ASSERT_EQ(static_cast<int>(lambda.size()), kModes) << slurp(dir / "ccx.log");
  ASSERT_GE(static_cast<int>(rows.size()), kModes);
  // ccx prints eigenvalues to 7 significant digits; C3D8 and the discrete elements are the same
  // formulation in both, the mass of C3D8 (2x2x2) too.
  constexpr double kFrequencyTolerance = 1e-6;
  const double worst = expect_frequencies_match(rows, lambda, kModes, kFrequencyTolerance);
  RecordProperty("max_relative_frequency_difference", std::to_string(worst));
  // Without the springs and masses ccx's frequencies differ by far more.
  fs::create_directories(dir / "plain");
  write_deck(dir / "plain" / "job.inp", kModes, false);
  const std::vector<double> plain = ccx_job_eigenvalues(dir / "plain");
  ASSERT_EQ(static_cast<int>(plain.size()), kModes);
  double shift = 0.0;
  for (int j = 0; j < kModes; ++j)
    shift = std::max(shift, std::abs(std::sqrt(plain[j] / lambda[j]) - 1.0));
  RecordProperty("max_relative_shift_without_springs_and_masses", std::to_string(shift));
  EXPECT_GT(shift, 1e3 * kFrequencyTolerance);
}

}  // namespace
