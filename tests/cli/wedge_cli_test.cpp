// End-to-end: a steel bar meshed with 15-node wedges (C3D15), written by the test as a .inp,
// through `stickslip modes`, against CalculiX *FREQUENCY on the same deck. The element's
// stiffness rule is CalculiX's (fe/element.h); ccx integrates the mass with that 9-point rule,
// stickslip with its exact mass rule (7-point triangle x 4 Gauss points), so the frequencies
// differ by the mass rule only (7.4e-5 at most on this mesh).
#include <gtest/gtest.h>

#include "cli_test_support.h"

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
  const double lx = 0.2, ly = 0.03, lz = 0.02;
  std::map<std::tuple<int, int, int>, int> ids;  // half-grid point -> node id
  std::ostringstream nodes, elements, fix;
  nodes.precision(17);
  const auto node = [&](int i, int j, int k) {
    const auto key = std::make_tuple(i, j, k);
    const auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    const int id = static_cast<int>(ids.size()) + 1;
    ids[key] = id;
    nodes << id << ", " << lx * i / (2 * nx) << ", " << ly * j / (2 * ny) << ", "
          << lz * k / (2 * nz) << "\n";
    if (i == 0) fix << id << ",\n";
    return id;
  };
  int e = 0;
  constexpr int kHalves[2][3][2] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
  constexpr int kEdges[9][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5},
                                {5, 3}, {0, 3}, {1, 4}, {2, 5}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& h : kHalves) {
          int c[6][3];
          for (int a = 0; a < 6; ++a) {
            c[a][0] = 2 * (i + h[a % 3][0]);
            c[a][1] = 2 * (j + h[a % 3][1]);
            c[a][2] = 2 * (k + (a < 3 ? 0 : 1));
          }
          elements << ++e;
          for (int a = 0; a < 6; ++a) elements << ", " << node(c[a][0], c[a][1], c[a][2]);
          for (int m = 0; m < 9; ++m) {
            const int* p = c[kEdges[m][0]];
            const int* q = c[kEdges[m][1]];
            elements << (m == 3 ? ",\n" : ", ")
                     << node((p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2);
          }
          elements << "\n";
        }
  const int tip = node(2 * nx, 0, 2 * nz);
  return "*NODE\n" + nodes.str() + "*ELEMENT, TYPE=C3D15, ELSET=EALL\n" + elements.str() +
         "*NSET, NSET=FIX\n" + fix.str() + "*NSET, NSET=TIP\n" + std::to_string(tip) + "\n";
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
