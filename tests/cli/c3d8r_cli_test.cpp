// End-to-end: a deck of C3D8R bricks (one integration point, CalculiX's hourglass stiffness)
// through `stickslip modes`, against ccx *FREQUENCY on the same deck (C3D8R is ccx's own element;
// with `mass_rule: calculix` both use its one-point mass ρV/64 per node pair). The bar is bent
// through two elements of thickness, where the hourglass stiffness carries much of the bending:
// the frequencies test the hourglass factor and vectors, not only the one-point part.
#include <gtest/gtest.h>

#include "../required_tool.h"
#include "cli_test_support.h"

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace {

using namespace stickslip::cli_test;

constexpr int kNx = 10, kNy = 2, kNz = 2;
constexpr double kLx = 0.2, kLy = 0.03, kLz = 0.02;

// The bar of hex_grid_inp as C3D8R, clamped at x = 0 (FIX), TIP its far corner.
std::string reduced_bar() {
  std::string inp = hex_grid_inp(kNx, kNy, kNz, kLx, kLy, kLz);
  const std::string c3d8 = "TYPE=C3D8,";
  inp.replace(inp.find(c3d8), c3d8.size(), "TYPE=C3D8R,");
  inp += "*NSET, NSET=FIX\n";
  for (int k = 0; k <= kNz; ++k)
    for (int j = 0; j <= kNy; ++j) inp += std::to_string(grid_node(kNx, kNy, 0, j, k)) + ",\n";
  inp += "*NSET, NSET=TIP\n" + std::to_string(grid_node(kNx, kNy, kNx, 0, kNz)) + "\n";
  return inp;
}

TEST(ReducedBrickCli, BarModesMatchCalculixC3D8R) {
  STICKSLIP_REQUIRE_TOOL(find_ccx(), "ccx (CalculiX)");
  constexpr int kModes = 8;
  const fs::path dir = fresh_dir("c3d8r_ccx");
  std::ofstream(dir / "bar.inp") << reduced_bar();
  std::ofstream(dir / "job.inp")
      << reduced_bar()
      << "*MATERIAL, NAME=STEEL\n*ELASTIC\n2e11, 0.3\n*DENSITY\n7800\n"
         "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*STEP\n*FREQUENCY\n"
      << kModes << "\n*BOUNDARY\nFIX, 1, 3\n*END STEP\n";
  const std::string plain = tip_spring_bar_case((dir / "bar.inp").string());
  const std::string body = "clamp: FIX,";
  const size_t at = plain.find(body);
  ASSERT_NE(at, std::string::npos);
  std::string yaml =
      plain.substr(0, at) + "clamp: FIX, mass_rule: calculix," + plain.substr(at + body.size());
  // CalculiX's one-point mass has rank 3 per element (3 x 40 here): fewer fixed-interface modes
  // than that, enough for the lowest eight to ccx's digits.
  yaml.replace(yaml.find("modes: 1000"), 11, "modes: 100");
  run_stage("modes", write_case(dir, "bar", yaml), dir / "out");
  const auto rows = read_csv(dir / "out" / "modes" / "frequencies.csv");
  ASSERT_GE(static_cast<int>(rows.size()), kModes);
  const std::vector<double> lambda = ccx_job_eigenvalues(dir);
  ASSERT_EQ(static_cast<int>(lambda.size()), kModes) << slurp(dir / "ccx.log");
  // Same K and M; ccx prints 7 significant digits (eigenvalue to 5e-8, frequency half of it).
  constexpr double kPrintedDigits = 1e-6;
  const double worst = expect_frequencies_match(rows, lambda, kModes, kPrintedDigits);
  std::printf(
      "[ CalculiX ] C3D8R bar %dx%dx%d: f1 = %s Hz, max relative frequency difference "
      "%.2e\n",
      kNx, kNy, kNz, rows[0].at("frequency_hz").c_str(), worst);
  RecordProperty("max_relative_frequency_difference_to_ccx", std::to_string(worst));
  fs::remove_all(dir);
}

}  // namespace
