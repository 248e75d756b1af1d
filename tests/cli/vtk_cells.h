// Our .vtu files read back by VTK itself (Debian's python3-vtk9, an implementation we did not
// write), for the tests of the node order of each cell type: per cell its VTK type and the volume
// VTK computes (vtkCellSizeFilter: negative for a cell ordered the wrong way round), and for the
// cells of one type the positions VTK's own shape functions give to chosen parametric points
// (vtkCell::EvaluateLocation). The tests compare them with the mesh's elements as our readers and
// fe/element.h see them.
#pragma once

#include <array>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "cli_test_support.h"
#include "mesh/mesh.h"

namespace stickslip::cli_test {

inline bool vtk_available() {
  return fs::exists("/usr/bin/python3") &&
         std::system("/usr/bin/python3 -c 'import vtk' 2>/dev/null") == 0;
}

struct VtkCell {
  int element_id = 0;  // the cell data `element_id`
  int type = 0;        // vtkCellType.h
  double volume = 0.0;
};
struct VtkPoint {
  int element_id = 0;
  int k = 0;  // index of the parametric point
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
};
struct VtkCells {
  std::vector<VtkCell> cells;
  std::vector<VtkPoint> points;
};

// VTK reads `vtu`; parametric points (r, s, t) are mapped in every cell of type `located_type`
// (0: every cell). Scratch files in `dir`. ADD_FAILURE (empty result) when python fails.
inline VtkCells read_with_vtk(const fs::path& vtu, const fs::path& dir,
                              const std::vector<std::array<double, 3>>& parametric,
                              int located_type = 0) {
  std::ofstream(dir / "vtk_cells.py") << R"PY(
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
located = int(sys.argv[3])
pcoords = [[float(v) for v in p.split(',')] for p in sys.argv[4:]]
with open(sys.argv[2], 'w') as out:
    for c in range(grid.GetNumberOfCells()):
        cell = grid.GetCell(c)
        eid = int(ids.GetValue(c))
        out.write('cell %d %d %r\n' % (eid, cell.GetCellType(), volume.GetValue(c)))
        if located != 0 and cell.GetCellType() != located:
            continue
        for k, p in enumerate(pcoords):
            x = [0.0, 0.0, 0.0]
            w = [0.0] * cell.GetNumberOfPoints()
            cell.EvaluateLocation(vtk.reference(0), p, x, w)
            out.write('point %d %d %r %r %r\n' % (eid, k, x[0], x[1], x[2]))
)PY";
  std::ostringstream command;
  command.precision(17);
  command << "/usr/bin/python3 '" << (dir / "vtk_cells.py").string() << "' '" << vtu.string()
          << "' '" << (dir / "vtk_cells.txt").string() << "' " << located_type;
  for (const auto& p : parametric) command << " " << p[0] << "," << p[1] << "," << p[2];
  VtkCells out;
  if (shell(command.str(), dir / "vtk_cells.log") != 0) {
    ADD_FAILURE() << slurp(dir / "vtk_cells.log");
    return out;
  }
  std::ifstream in(dir / "vtk_cells.txt");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string kind, a, b, c;
    if (!(s >> kind)) continue;
    if (kind == "cell") {
      VtkCell cell;
      s >> cell.element_id >> cell.type >> a;
      cell.volume = std::strtod(a.c_str(), nullptr);
      out.cells.push_back(cell);
    } else {
      VtkPoint point;
      s >> point.element_id >> point.k >> a >> b >> c;
      point.x = {std::strtod(a.c_str(), nullptr), std::strtod(b.c_str(), nullptr),
                 std::strtod(c.c_str(), nullptr)};
      out.points.push_back(point);
    }
  }
  return out;
}

// The coordinates of element e's nodes (3 x nodes).
inline Eigen::Matrix3Xd element_coordinates(const Mesh& mesh, int e) {
  const auto nodes = mesh.element_nodes(e);
  Eigen::Matrix3Xd X(3, nodes.size());
  for (size_t a = 0; a < nodes.size(); ++a) X.col(a) = mesh.coordinates.col(nodes[a]);
  return X;
}

}  // namespace stickslip::cli_test
