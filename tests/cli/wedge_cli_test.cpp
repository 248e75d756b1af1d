// End-to-end: a steel bar meshed with 15-node wedges (C3D15), written by the test as a .inp,
// through `stickslip modes`, against CalculiX *FREQUENCY on the same deck. The element's
// stiffness rule is CalculiX's (fe/element.h); ccx integrates the mass with that 9-point rule,
// stickslip with its exact mass rule (7-point triangle x 4 Gauss points), so the frequencies
// differ by the mass rule only (7.4e-5 at most on this mesh).
#include <gtest/gtest.h>

#include "cli_test_support.h"
#include "wedge_decks.h"

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>

namespace {

using namespace stickslip::cli_test;

// A bar [0, 0.2] x [0, 0.03] x [0, 0.02] m of nx x ny x nz cells, each split into two wedges
// along its x-y diagonal, C3D15 with mid-edge nodes; FIX = nodes at x = 0, TIP = a tip corner.
std::string wedge_bar_inp(int nx, int ny, int nz) {
  constexpr double kIdentity[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  return wedge_box_inp(nx, ny, nz, 0.2, 0.03, 0.02, kIdentity, /*quadratic=*/true);
}

TEST(WedgeCli, C3D15BarModesMatchCalculixOnTheSameDeck) {
  constexpr int kModes = 6;
  const fs::path dir = fresh_dir("wedge");
  const std::string mesh = wedge_bar_inp(8, 2, 2);
  std::ofstream(dir / "bar.inp") << mesh;
  std::ofstream(dir / "job.inp")
      << mesh
      << "*MATERIAL, NAME=STEEL\n*ELASTIC\n2e11, 0.3\n*DENSITY\n7800\n"
         "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*STEP\n*FREQUENCY\n"
      << kModes << "\n*BOUNDARY\nFIX, 1, 3\n*END STEP\n";
  run_stage("modes", write_case(dir, "bar", tip_spring_bar_case((dir / "bar.inp").string())),
            dir / "out");
  const auto rows = read_csv(dir / "out" / "modes" / "frequencies.csv");
  ASSERT_GE(static_cast<int>(rows.size()), kModes);
  const std::vector<double> lambda = ccx_job_eigenvalues(dir);
  ASSERT_EQ(static_cast<int>(lambda.size()), kModes) << slurp(dir / "ccx.log");
  // Same stiffness; mass rules differ (exact here, ccx's 9-point stiffness rule), and ccx prints
  // 7 significant digits.
  // Measured: 7.4e-5 at most over the 6 modes.
  constexpr double kMassRuleTolerance = 2e-4;
  const double worst = expect_frequencies_match(rows, lambda, kModes, kMassRuleTolerance);
  std::printf("[ CalculiX ] C3D15 bar 8x2x2 cells: max relative frequency difference %.2e\n",
              worst);
  RecordProperty("max_relative_frequency_difference_to_ccx", std::to_string(worst));
}

}  // namespace
