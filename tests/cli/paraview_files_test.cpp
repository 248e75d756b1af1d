// End-to-end: the ParaView files of a recovery and of the stuck modes, read back by VTK itself (Debian python3-vtk9,
// an implementation we did not write) — the sweep's .pvd, each point's .vtm of the bodies, the
// envelope's .vtm, the modes' .vtm and the zlib-compressed per-body .vtu files. References, independent of the
// VTU writer: points.csv (the frequencies, the pvd's time values) and recovered_nodes.csv (the
// full-model displacement of two listed nodes, written as text by another path).
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <filesystem>
#include <fstream>
#include <string>

namespace {

using namespace stickslip::cli_test;

constexpr const char* kVtkCheck = R"PY(
import csv, sys, os
import xml.etree.ElementTree as ET
import vtk
from vtk.util.numpy_support import vtk_to_numpy
out = sys.argv[1]
freq = {int(r['point']): float(r['frequency_hz']) for r in csv.DictReader(open(os.path.join(out, 'points.csv')))}
nodes = {}
for r in csv.DictReader(open(os.path.join(out, 'recovered_nodes.csv'))):
    if r['harmonic'] == '1':
        nodes[(int(r['point']), r['body'], int(r['node']), r['axis'])] = complex(float(r['real_m']), float(r['imag_m']))
def read_vtu(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    assert grid.GetNumberOfPoints() > 0 and grid.GetNumberOfCells() > 0, path
    return grid
# The sweep: one dataset per point and body, time = the point's frequency, part = the body.
entries = ET.parse(os.path.join(out, 'recovery.pvd')).getroot().find('Collection').findall('DataSet')
assert len(entries) == 2 * len(freq), (len(entries), len(freq))
checked = 0
for e in entries:
    path = os.path.join(out, e.get('file'))
    body, point = e.get('name'), int(os.path.basename(path)[1:-4])
    assert abs(float(e.get('timestep')) - freq[point]) <= 1e-12 * freq[point], e.attrib
    assert e.get('part') == ('0' if body == 'beam1' else '1'), e.attrib
    grid = read_vtu(path)
    pd = grid.GetPointData()
    ids = vtk_to_numpy(pd.GetArray('node_id'))
    re = vtk_to_numpy(pd.GetArray('displacement_h1_real'))
    im = vtk_to_numpy(pd.GetArray('displacement_h1_imag'))
    assert pd.GetArray('von_mises_mean') is not None and pd.GetArray('stress_h1_real') is not None
    assert grid.GetFieldData().GetArray('frequency_hz').GetValue(0) == freq[point]
    for (p, b, node, dof), v in nodes.items():
        if p != point or b != body:
            continue
        i = list(ids).index(node)
        d = 'xyz'.index(dof)
        got = complex(re[i][d], im[i][d])
        assert abs(got - v) <= 1e-14 * abs(v) + 1e-300, (p, b, node, dof, got, v)
        checked += 1
assert checked == 6 * len(freq), checked  # nodes 200 (beam1) and 550 (beam2), x y z
# Each point: a multiblock of the two bodies, the same grids as the pvd's.
for point in freq:
    reader = vtk.vtkXMLMultiBlockDataReader()
    reader.SetFileName(os.path.join(out, 'recovery_p%d.vtm' % point))
    reader.Update()
    mb = reader.GetOutput()
    assert mb.GetNumberOfBlocks() == 2, mb.GetNumberOfBlocks()
    for b, name in enumerate(['beam1', 'beam2']):
        assert mb.GetMetaData(b).Get(vtk.vtkCompositeDataSet.NAME()) == name
        assert mb.GetBlock(b).GetNumberOfPoints() == read_vtu(os.path.join(out, 'recovery', name, 'p%d.vtu' % point)).GetNumberOfPoints()
# The envelope over the sweep.
reader = vtk.vtkXMLMultiBlockDataReader()
reader.SetFileName(os.path.join(out, 'recovery_envelope.vtm'))
reader.Update()
env = reader.GetOutput()
assert env.GetNumberOfBlocks() == 2
for b in range(2):
    vm = vtk_to_numpy(env.GetBlock(b).GetPointData().GetArray('von_mises_max'))
    assert vm.max() > 0
# The stuck modes (stickslip modes CASE): the bodies' shapes as one multiblock, with the
# frequencies of frequencies.csv.
modes = {int(r['mode']): float(r['frequency_hz']) for r in csv.DictReader(open(os.path.join(out, 'modes', 'frequencies.csv')))}
reader = vtk.vtkXMLMultiBlockDataReader()
reader.SetFileName(os.path.join(out, 'modes', 'modes.vtm'))
reader.Update()
mb = reader.GetOutput()
assert mb.GetNumberOfBlocks() == 2
for b, name in enumerate(['beam1', 'beam2']):
    assert mb.GetMetaData(b).Get(vtk.vtkCompositeDataSet.NAME()) == name
    grid = mb.GetBlock(b)
    for j, f in modes.items():
        assert grid.GetPointData().GetArray('mode_%d' % j) is not None, j
        assert grid.GetFieldData().GetArray('mode_%d_frequency_hz' % j).GetValue(0) == f, j
print('OK', checked)
)PY";

TEST(ParaviewFiles, VtkReadsTheSweepPointAndEnvelopeCollectionsWithTheRecoveredValues) {
  const fs::path dir = fresh_dir("paraview");
  const fs::path c = write_case(
      dir, "case",
      small_joint_case(0.5, 20, R"(recovery: {points: all, method: direct, fields: [displacement, stress], nodes: [200, 550]}
output: {vtu: true, plots: false}
)"));
  ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / "out").string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  ASSERT_EQ(run("modes -q " + c.string() + " -o " + (dir / "out").string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  std::ofstream(dir / "check.py") << kVtkCheck;
  EXPECT_EQ(shell("/usr/bin/python3 " + (dir / "check.py").string() + " " + (dir / "out").string(),
                  dir / "python.log"),
            0)
      << slurp(dir / "python.log");
  EXPECT_NE(slurp(dir / "python.log").find("OK 54"), std::string::npos) << slurp(dir / "python.log");
  // ParaView groups numbered names into series: the only numbers left in names are point numbers.
  EXPECT_FALSE(fs::exists(dir / "out" / "recovery_p4_beam1.vtu"));
  EXPECT_TRUE(fs::exists(dir / "out" / "recovery" / "beam2" / "p4.vtu"));
}

}  // namespace
