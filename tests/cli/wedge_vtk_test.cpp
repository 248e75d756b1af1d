// End-to-end: the node order of wedges in the VTU files stickslip writes, checked by VTK itself
// (Debian's python3-vtk9, an implementation we did not write). A skewed box meshed with C3D6 or
// C3D15 wedges goes through `stickslip modes`; VTK reads modes/bar/shapes.vtu and reports, per
// cell, its type, its signed volume (vtkCellSizeFilter: negative for a cell whose first triangle
// is ordered the wrong way round) and the positions of parametric points mapped by its own shape
// functions (vtkCell::EvaluateLocation). Reference: the mesh's own elements, read from the deck by
// our .inp reader — volumes from element_volume, positions from shape_functions at the same
// points. The box is an affine image of a cube, so every wedge is affine: VTK's volume (a sum
// over tetrahedra) is exact, and a wrong correspondence of nodes moves the mapped points.
#include <gtest/gtest.h>

#include "../required_tool.h"
#include "cli_test_support.h"
#include "fe/element.h"
#include "io/inp_reader.h"
#include "wedge_decks.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>

namespace {

using namespace stickslip::cli_test;
using stickslip::ElementType;

// Volumes and positions are sums of O(1) products of coordinates of size ~0.1 m (17 digits in the
// deck and in the VTU): round-off is ~1e-16 of the element's size.
constexpr double kRoundOff = 1e-12;

bool vtk_available() {
  return fs::exists("/usr/bin/python3") &&
         std::system("/usr/bin/python3 -c 'import vtk' 2>/dev/null") == 0;
}

// Parametric points (r, s, t) of VTK's wedge (vtkWedge / vtkQuadraticWedge: points 0, 1, 2 at
// (r, s) = (0, 0), (1, 0), (0, 1) with t = 0, points 3-5 above them at t = 1), none of them on a
// symmetry of the wedge, so that two different node correspondences map them to different places.
constexpr double kParametric[4][3] = {
    {0.2, 0.5, 0.3}, {0.1, 0.15, 0.9}, {0.6, 0.25, 0.05}, {0.3, 0.3, 0.7}};

constexpr const char* kVtkCheck = R"PY(
import sys
import vtk
reader = vtk.vtkXMLUnstructuredGridReader()
reader.SetFileName(sys.argv[1])
reader.Update()
grid = reader.GetOutput()
sizes = vtk.vtkCellSizeFilter()
sizes.SetInputData(grid)
sizes.Update()
volume = sizes.GetOutput().GetCellData().GetArray('Volume')
ids = grid.GetCellData().GetArray('element_id')
pcoords = [[float(v) for v in p.split(',')] for p in sys.argv[3:]]
with open(sys.argv[2], 'w') as out:
    for c in range(grid.GetNumberOfCells()):
        cell = grid.GetCell(c)
        eid = int(ids.GetValue(c))
        out.write('cell %d %d %r\n' % (eid, cell.GetCellType(), volume.GetValue(c)))
        for k, p in enumerate(pcoords):
            x = [0.0, 0.0, 0.0]
            w = [0.0] * cell.GetNumberOfPoints()
            cell.EvaluateLocation(vtk.reference(0), p, x, w)
            out.write('point %d %d %r %r %r\n' % (eid, k, x[0], x[1], x[2]))
)PY";

// The skewed box: det A = 0.865 > 0 (not a mirror), no two columns parallel.
std::string skewed_wedge_box(int nx, int ny, int nz, bool quadratic) {
  constexpr double A[3][3] = {{1.0, 0.3, -0.2}, {0.1, 1.1, 0.25}, {-0.15, 0.2, 0.9}};
  return wedge_box_inp(nx, ny, nz, 0.2, 0.04, 0.03, A, quadratic);
}

void check_wedges_in_vtk(bool quadratic) {
  STICKSLIP_REQUIRE_TOOL(vtk_available(), "/usr/bin/python3 with VTK (python3-vtk9)");
  const fs::path dir = fresh_dir(quadratic ? "wedge_vtk15" : "wedge_vtk6");
  std::ofstream(dir / "bar.inp") << skewed_wedge_box(3, 2, 1, quadratic);
  run_stage("modes", write_case(dir, "bar", tip_spring_bar_case((dir / "bar.inp").string())),
            dir / "out");
  const fs::path vtu = dir / "out" / "modes" / "bar" / "shapes.vtu";
  ASSERT_TRUE(fs::exists(vtu));
  std::ofstream(dir / "check.py") << kVtkCheck;
  std::string command = "/usr/bin/python3 " + (dir / "check.py").string() + " " + vtu.string() +
                        " " + (dir / "vtk.txt").string();
  for (const auto& p : kParametric) {
    std::ostringstream s;
    s.precision(17);
    s << " " << p[0] << "," << p[1] << "," << p[2];
    command += s.str();
  }
  ASSERT_EQ(shell(command, dir / "python.log"), 0) << slurp(dir / "python.log");

  const stickslip::Mesh mesh = stickslip::read_inp((dir / "bar.inp").string());
  std::map<int, int> element_of_id;
  for (int e = 0; e < mesh.num_elements(); ++e) element_of_id[mesh.element_ids[e]] = e;
  const ElementType type = quadratic ? ElementType::kC3D15 : ElementType::kC3D6;
  const int vtk_type = quadratic ? 26 : 13;  // VTK_QUADRATIC_WEDGE, VTK_WEDGE (vtkCellType.h)
  std::ifstream in(dir / "vtk.txt");
  std::string line;
  int cells = 0, points = 0;
  const auto coordinates = [&](int e) {
    const auto nodes = mesh.element_nodes(e);
    Eigen::Matrix3Xd X(3, nodes.size());
    for (size_t a = 0; a < nodes.size(); ++a) X.col(a) = mesh.coordinates.col(nodes[a]);
    return X;
  };
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string kind;
    int id = 0;
    s >> kind >> id;
    ASSERT_TRUE(element_of_id.count(id)) << line;
    const Eigen::Matrix3Xd X = coordinates(element_of_id.at(id));
    const double size = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm();
    if (kind == "cell") {
      int cell_type = 0;
      std::string volume;
      s >> cell_type >> volume;
      EXPECT_EQ(cell_type, vtk_type) << line;
      const double ours = stickslip::element_volume(type, X);
      EXPECT_GT(ours, 0.0);
      EXPECT_NEAR(std::strtod(volume.c_str(), nullptr), ours, kRoundOff * std::pow(size, 3))
          << "element " << id;
      ++cells;
    } else {
      ASSERT_EQ(kind, "point") << line;
      int k = 0;
      std::string x[3];
      s >> k >> x[0] >> x[1] >> x[2];
      ASSERT_TRUE(k >= 0 && k < 4) << line;
      // VTK's wedge point 1 (r = 1) is our node 3 (eta = 1), its point 2 (s = 1) our node 2
      // (xi = 1): the writer swaps them so that VTK's first triangle turns the other way
      // (io/vtu_writer.cpp). Our zeta runs over [-1, 1], VTK's t over [0, 1].
      const Eigen::Vector3d xi(kParametric[k][1], kParametric[k][0], 2 * kParametric[k][2] - 1);
      Eigen::VectorXd N;
      Eigen::Matrix3Xd dN;
      stickslip::shape_functions(type, xi, N, dN);
      const Eigen::Vector3d ours = X * N;
      for (int d = 0; d < 3; ++d) {
        EXPECT_NEAR(std::strtod(x[d].c_str(), nullptr), ours(d), kRoundOff * size)
            << "element " << id << " parametric point " << k << " direction " << d;
      }
      ++points;
    }
  }
  EXPECT_EQ(cells, mesh.num_elements());
  EXPECT_EQ(points, 4 * mesh.num_elements());
  EXPECT_EQ(cells, 12);
  fs::remove_all(dir);
}

TEST(WedgeVtk, VtkReadsLinearWedgesWithTheMeshsVolumesAndGeometry) { check_wedges_in_vtk(false); }

TEST(WedgeVtk, VtkReadsQuadraticWedgesWithTheMeshsVolumesAndGeometry) { check_wedges_in_vtk(true); }

}  // namespace
