// The recovery of a cyclic sector read back by VTK itself (Debian python3-vtk9, not our writer),
// for the end-to-end tests of tests/cli/cyclic_*_cli_test.cpp: a Python script and its output.
// Arguments: sector_dir ring_dir N body ring_body — the sector run's folder and the whole ring's
// (annulus) run's, the sector body whose recovery/<body>_annulus is compared with the ring's
// recovery/<ring_body>.
#pragma once

#include <map>
#include <sstream>
#include <string>

namespace stickslip::cli_test {

// The recovery (item 5) read back by VTK itself (Debian python3-vtk9, not our writer): the
// sector's annulus file against the whole ring's own recovery, cell by cell (cells matched by
// centroid, their nodes by position: the ring's shroud faces have two coincident nodes, one per
// blade, told apart by their cells), every array at every node of every sector; the annulus's
// copies of one ring node (the sector boundaries) against each other; the sector's own file
// against the annulus's sector 0; the sector's reactions against the ring's at the same places.
// Prints "RESULT <what> <largest difference relative to the ring's largest value>".
inline const char* const kAnnulusCheck = R"PY(
import sys, os, csv
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy
sector_dir, ring_dir, N = sys.argv[1], sys.argv[2], int(sys.argv[3])
body, ring_body = sys.argv[4], sys.argv[5]
def read(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    assert g.GetNumberOfPoints() > 0 and g.GetNumberOfCells() > 0, path
    return g
def arrays(g):
    pd = g.GetPointData()
    return {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)).reshape(g.GetNumberOfPoints(), -1)
            for i in range(pd.GetNumberOfArrays())}
def cells(g):
    out = []
    for c in range(g.GetNumberOfCells()):
        ids = g.GetCell(c).GetPointIds()
        out.append([ids.GetId(i) for i in range(ids.GetNumberOfIds())])
    return out
def nearest(x, places):  # the row of `places` at x (within 1e-9 m)
    d = np.abs(places - x).max(axis=1)
    i = int(np.argmin(d))
    assert d[i] < 1e-9, (x, d[i])
    return i
def family(name):
    if name.startswith('displacement_h'): return 'displacement'
    if name.startswith('stress_h'): return 'stress'
    return 'envelope'
points = sorted(int(r['point']) for r in csv.DictReader(open(os.path.join(sector_dir, 'points.csv')))
                if r['converged'] == '1')
assert points
diff, scale, shared, own = {}, {}, 0, 0.0
for p in points:
    sec = read(os.path.join(sector_dir, 'recovery', body, 'p%d.vtu' % p))
    ann = read(os.path.join(sector_dir, 'recovery', body + '_annulus', 'p%d.vtu' % p))
    ring = read(os.path.join(ring_dir, 'recovery', ring_body, 'p%d.vtu' % p))
    n = sec.GetNumberOfPoints()
    assert ann.GetNumberOfPoints() == N * n, (ann.GetNumberOfPoints(), n)
    assert ann.GetNumberOfCells() == N * sec.GetNumberOfCells() == ring.GetNumberOfCells()
    A, R, S = arrays(ann), arrays(ring), arrays(sec)
    assert sorted(A['sector'][:, 0]) == sorted(j for j in range(N) for _ in range(n))
    ax = vtk_to_numpy(ann.GetPoints().GetData())
    rx = vtk_to_numpy(ring.GetPoints().GetData())
    ring_cells = cells(ring)
    centroids = np.array([rx[c].mean(axis=0) for c in ring_cells])
    match = {}
    for c in cells(ann):
        rc = ring_cells[nearest(ax[c].mean(axis=0), centroids)]
        for a in c:
            m = [r for r in rc if np.abs(rx[r] - ax[a]).max() < 1e-9]
            assert len(m) == 1, (a, m)
            assert match.setdefault(a, m[0]) == m[0]
    assert len(match) == N * n
    ai = np.array(sorted(match))
    ri = np.array([match[a] for a in ai])
    names = [k for k in R if k.startswith(('displacement_h', 'stress_h', 'von_mises', 'max_principal'))]
    assert len(names) > 4 and all(k in A and k in S for k in names), names
    copies = {}
    for a, r in match.items():
        copies.setdefault(r, []).append(a)
    for k in names:
        f = family(k)
        diff[f] = max(diff.get(f, 0.0), float(np.abs(A[k][ai] - R[k][ri]).max()))
        scale[f] = max(scale.get(f, 0.0), float(np.abs(R[k]).max()))
        for r, al in copies.items():
            if len(al) > 1:
                diff['boundary_' + f] = max(diff.get('boundary_' + f, 0.0),
                                            float(np.abs(A[k][al] - A[k][al[0]]).max()))
                scale['boundary_' + f] = scale[f]
        own = max(own, float(np.abs(A[k][:n] - S[k]).max()))
    shared = max(shared, sum(1 for al in copies.values() if len(al) > 1))
# Reactions at sector 0's clamped nodes against the ring's at the same places.
def node_places(g):
    return vtk_to_numpy(g.GetPointData().GetArray('node_id')), vtk_to_numpy(g.GetPoints().GetData())
def reactions(d, b):
    return {(r['point'], int(r['node']), r['axis'], r['harmonic']): complex(float(r['real_n']), float(r['imag_n']))
            for r in csv.DictReader(open(os.path.join(d, 'reactions.csv'))) if r['body'] == b}
s_ids, s_x = node_places(read(os.path.join(sector_dir, 'recovery', body, 'p%d.vtu' % points[0])))
r_ids, r_x = node_places(read(os.path.join(ring_dir, 'recovery', ring_body, 'p%d.vtu' % points[0])))
ring_id = {int(i): int(r_ids[nearest(s_x[j], r_x)]) for j, i in enumerate(s_ids)}
rs, rr = reactions(sector_dir, body), reactions(ring_dir, ring_body)
if rs:  # a body held by its clamps (a damper held only by contacts has none)
    diff['reaction'] = max(abs(v - rr[(pt, ring_id[node], ax, h)]) for (pt, node, ax, h), v in rs.items())
    scale['reaction'] = max(abs(v) for v in rr.values())
for f in sorted(diff):
    print('RESULT', f, diff[f] / scale[f] if scale[f] > 0 else diff[f])
print('RESULT own_sector', own)
print('RESULT shared_nodes', shared)
print('RESULT reaction_rows', len(rs))
)PY";

// RESULT lines of kAnnulusCheck's output.
inline std::map<std::string, double> results(const std::string& log) {
  std::map<std::string, double> out;
  std::istringstream in(log);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream l(line);
    std::string tag, what;
    double v = 0;
    if (l >> tag >> what >> v && tag == "RESULT") out[what] = v;
  }
  return out;
}

}  // namespace stickslip::cli_test
