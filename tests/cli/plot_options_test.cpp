// End-to-end: the amplitude plots on a logarithmic axis (output.log_amplitude, `plot --log`),
// `stickslip plot` redrawing exactly what `run` drew (the same scripts, byte for byte), and the
// contact map contact_map.vtu read back by VTK (Debian python3-vtk9) against contact_state.csv and
// points.csv (docs/output-files.md).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "../required_tool.h"
#include "cli_test_support.h"

namespace stickslip {
namespace {

using namespace cli_test;

bool have_gnuplot() { return std::system("command -v gnuplot > /dev/null 2>&1") == 0; }
bool have_vtk() { return std::system("/usr/bin/python3 -c 'import vtk' > /dev/null 2>&1") == 0; }

// The coarse joint over ±20 Hz around its stuck mode 4, with plots, histories and an FRF DOF.
std::string plotted_case(bool log_amplitude, bool plots = true) {
  return coarse_joint_head(20, 2, "5") + R"(recovery: {points: none}
output:
  vtu: false
  plots: )" +
         std::string(plots ? "true" : "false") + R"(
  log_amplitude: )" +
         std::string(log_amplitude ? "true" : "false") + R"(
  histories: {joint: [0]}
  frf: [{body: beam1, node: 11, direction: y}]
)";
}

const char* const kScripts[] = {"frf.gp",         "frf_phase.gp",  "contact_state.gp",
                                "dissipation.gp", "hysteresis.gp", "hysteresis_t2.gp"};

TEST(PlotOptions, LogAmplitudeOfTheCaseIsDrawnByRunAndAgainByPlot) {
  STICKSLIP_REQUIRE_TOOL(have_gnuplot(), "gnuplot");
  const fs::path dir = fresh_dir("plot_options_log");
  const fs::path file = write_case(dir, "case", plotted_case(true));
  ASSERT_EQ(run("run -q " + file.string() + " -o " + (dir / "out").string(), dir / "log"), 0)
      << slurp(dir / "log");
  const fs::path out = dir / "out";
  // The amplitude plot only: a phase or a fraction has no logarithmic axis.
  EXPECT_NE(slurp(out / "frf.gp").find("\nset logscale y\n"), std::string::npos)
      << slurp(out / "frf.gp");
  for (const char* other : {"frf_phase.gp", "contact_state.gp", "dissipation.gp"}) {
    EXPECT_EQ(slurp(out / other).find("logscale"), std::string::npos) << other;
  }
  // `plot` writes the same scripts and data again (the choice read from summary.json).
  std::map<std::string, std::string> drawn;
  for (const char* gp : kScripts) {
    ASSERT_TRUE(fs::exists(out / gp)) << gp;
    drawn[gp] = slurp(out / gp);
    const std::string dat = fs::path(gp).replace_extension(".dat").string();
    drawn[dat] = slurp(out / dat);
    fs::remove(out / gp);
    fs::remove(out / dat);
  }
  ASSERT_EQ(run("plot -q " + out.string(), dir / "plot.log"), 0) << slurp(dir / "plot.log");
  for (const auto& [name, text] : drawn) EXPECT_EQ(slurp(out / name), text) << name;

  // The hysteresis plots show the pair that dissipates most at the most dissipative point
  // (contact_state.csv, points.csv), named so, with its cycle from histories.csv, beside the
  // requested pair 0.
  std::string best;
  double most = -1;
  for (const auto& r : read_csv(out / "points.csv")) {
    if (r.at("converged") == "1" && std::stod(r.at("dissipated_energy_j")) > most) {
      most = std::stod(r.at("dissipated_energy_j")), best = r.at("point");
    }
  }
  ASSERT_GT(most, 0);
  std::string pair;
  double pair_most = -1;
  for (const auto& r : read_csv(out / "contact_state.csv")) {
    if (r.at("point") == best && std::stod(r.at("dissipated_energy_j")) > pair_most) {
      pair_most = std::stod(r.at("dissipated_energy_j")), pair = r.at("pair");
    }
  }
  size_t samples = 0;
  for (const auto& r : read_csv(out / "histories.csv")) {
    samples += r.at("point") == best && r.at("pair") == pair && r.at("axis") == "t1" ? 1 : 0;
  }
  EXPECT_EQ(samples, 32u) << "pair " << pair << " point " << best;  // time_samples: 32
  for (const char* stem : {"hysteresis", "hysteresis_t2"}) {
    const std::string label = "joint pair " + pair + " (most dissipative)";
    EXPECT_NE(slurp(out / (std::string(stem) + ".gp")).find("'" + label + "'"), std::string::npos)
        << stem << " " << label;
    EXPECT_NE(slurp(out / (std::string(stem) + ".dat")).find("# " + label + "\n"),
              std::string::npos)
        << stem;
    if (pair != "0") {
      EXPECT_NE(slurp(out / (std::string(stem) + ".dat")).find("# joint pair 0\n"),
                std::string::npos);
    }
  }
}

TEST(PlotOptions, PlotLogDrawsALinearRunLogarithmic) {
  STICKSLIP_REQUIRE_TOOL(have_gnuplot(), "gnuplot");
  const fs::path dir = fresh_dir("plot_options_linear");
  const fs::path file = write_case(dir, "case", plotted_case(false));
  ASSERT_EQ(run("run -q " + file.string() + " -o " + (dir / "out").string(), dir / "log"), 0)
      << slurp(dir / "log");
  const fs::path out = dir / "out";
  const std::string linear = slurp(out / "frf.gp");
  EXPECT_EQ(linear.find("logscale"), std::string::npos) << linear;
  ASSERT_EQ(run("plot -q " + out.string(), dir / "plot.log"), 0) << slurp(dir / "plot.log");
  EXPECT_EQ(slurp(out / "frf.gp"), linear);
  ASSERT_EQ(run("plot -q --log " + out.string(), dir / "plot.log"), 0) << slurp(dir / "plot.log");
  const std::string log = slurp(out / "frf.gp");
  EXPECT_NE(log.find("\nset logscale y\n"), std::string::npos) << log;
  // Only that line differs.
  std::string without = log;
  without.erase(without.find("set logscale y\n"), 15);
  EXPECT_EQ(without, linear);
  EXPECT_TRUE(fs::exists(out / "frf.png"));
  EXPECT_TRUE(fs::exists(out / "frf.svg"));
}

TEST(PlotOptions, ContactMapHoldsEachPairsStateAtTheMostDissipativePoint) {
  STICKSLIP_REQUIRE_TOOL(have_vtk(), "Debian's python3 with VTK (python3-vtk9)");
  const fs::path dir = fresh_dir("plot_options_contact_map");
  const fs::path file = write_case(dir, "case", plotted_case(false, false));
  ASSERT_EQ(run("solve -q " + file.string() + " -o " + (dir / "out").string(), dir / "log"), 0)
      << slurp(dir / "log");
  // VTK reads the map; each point is a pair of contact_state.csv at the point of points.csv that
  // dissipates most, on its A node; the pairs lie on the contact plane (normal x), and the
  // fractions of a cycle add up to 1.
  const std::string script = R"(import csv, os, sys
import vtk
from vtk.util.numpy_support import vtk_to_numpy
out = sys.argv[1]
points = list(csv.DictReader(open(os.path.join(out, 'points.csv'))))
best = max((r for r in points if r['converged'] == '1'),
           key=lambda r: float(r['dissipated_energy_j']))
assert float(best['dissipated_energy_j']) > 0, best
state = [r for r in csv.DictReader(open(os.path.join(out, 'contact_state.csv')))
         if r['point'] == best['point']]
reader = vtk.vtkXMLUnstructuredGridReader()
reader.SetFileName(os.path.join(out, 'contact_map.vtu'))
reader.Update()
grid = reader.GetOutput()
n = grid.GetNumberOfPoints()
assert n == len(state) > 0 and grid.GetNumberOfCells() == n, (n, len(state))
assert all(grid.GetCellType(i) == vtk.VTK_VERTEX for i in range(n))
pd = grid.GetPointData()
a = {name: vtk_to_numpy(pd.GetArray(name)) for name in
     ('stick', 'slip', 'separation', 'dissipated_energy_j', 'pair', 'node_a', 'node_b', 'node_id')}
assert abs(grid.GetFieldData().GetArray('frequency_hz').GetValue(0) -
           float(best['frequency_hz'])) <= 1e-12 * float(best['frequency_hz'])
assert int(grid.GetFieldData().GetArray('point').GetValue(0)) == int(best['point'])
xyz = vtk_to_numpy(grid.GetPoints().GetData())
assert xyz[:, 0].max() - xyz[:, 0].min() < 1e-12, xyz[:, 0]
assert len({(round(y, 12), round(z, 12)) for _, y, z in xyz}) == n
for i, r in enumerate(state):
    assert int(a['pair'][i]) == int(r['pair']) and int(a['node_a'][i]) == int(r['node_a'])
    assert int(a['node_b'][i]) == int(r['node_b']) and int(a['node_id'][i]) == int(r['node_a'])
    for k in ('stick', 'slip', 'separation', 'dissipated_energy_j'):
        assert a[k][i] == float(r[k]), (i, k, a[k][i], r[k])
    assert abs(a['stick'][i] + a['slip'][i] + a['separation'][i] - 1) < 1e-12
assert a['slip'].max() > 0
print('OK', n)
)";
  std::ofstream(dir / "map.py") << script;
  ASSERT_EQ(shell("/usr/bin/python3 " + (dir / "map.py").string() + " " + (dir / "out").string(),
                  dir / "py.log"),
            0)
      << slurp(dir / "py.log");
  EXPECT_NE(slurp(dir / "py.log").find("OK "), std::string::npos);
}

}  // namespace
}  // namespace stickslip
