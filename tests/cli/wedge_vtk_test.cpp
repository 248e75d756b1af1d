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
#include "vtk_cells.h"
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

// Parametric points (r, s, t) of VTK's wedge (vtkWedge / vtkQuadraticWedge: points 0, 1, 2 at
// (r, s) = (0, 0), (1, 0), (0, 1) with t = 0, points 3-5 above them at t = 1), none of them on a
// symmetry of the wedge, so that two different node correspondences map them to different places.
const std::vector<std::array<double, 3>> kParametric = {
    {0.2, 0.5, 0.3}, {0.1, 0.15, 0.9}, {0.6, 0.25, 0.05}, {0.3, 0.3, 0.7}};

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
  const VtkCells vtk = read_with_vtk(vtu, dir, kParametric);

  const stickslip::Mesh mesh = stickslip::read_inp((dir / "bar.inp").string());
  std::map<int, int> element_of_id;
  for (int e = 0; e < mesh.num_elements(); ++e) element_of_id[mesh.element_ids[e]] = e;
  const ElementType type = quadratic ? ElementType::kC3D15 : ElementType::kC3D6;
  const int vtk_type = quadratic ? 26 : 13;  // VTK_QUADRATIC_WEDGE, VTK_WEDGE (vtkCellType.h)
  const auto element = [&](int id) {
    EXPECT_TRUE(element_of_id.count(id)) << id;
    return element_coordinates(mesh, element_of_id.count(id) ? element_of_id.at(id) : 0);
  };
  for (const VtkCell& cell : vtk.cells) {
    const Eigen::Matrix3Xd X = element(cell.element_id);
    const double size = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm();
    EXPECT_EQ(cell.type, vtk_type) << "element " << cell.element_id;
    const double ours = stickslip::element_volume(type, X);
    EXPECT_GT(ours, 0.0);
    EXPECT_NEAR(cell.volume, ours, kRoundOff * std::pow(size, 3)) << "element " << cell.element_id;
  }
  for (const VtkPoint& point : vtk.points) {
    ASSERT_TRUE(point.k >= 0 && point.k < 4);
    const Eigen::Matrix3Xd X = element(point.element_id);
    const double size = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm();
    // VTK's wedge point 1 (r = 1) is our node 3 (eta = 1), its point 2 (s = 1) our node 2
    // (xi = 1): the writer swaps them so that VTK's first triangle turns the other way
    // (io/vtu_writer.cpp). Our zeta runs over [-1, 1], VTK's t over [0, 1].
    const auto& r = kParametric[point.k];
    const Eigen::Vector3d xi(r[1], r[0], 2 * r[2] - 1);
    Eigen::VectorXd N;
    Eigen::Matrix3Xd dN;
    stickslip::shape_functions(type, xi, N, dN);
    const Eigen::Vector3d ours = X * N;
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(point.x(d), ours(d), kRoundOff * size)
          << "element " << point.element_id << " parametric point " << point.k << " direction "
          << d;
    }
  }
  EXPECT_EQ(static_cast<int>(vtk.cells.size()), mesh.num_elements());
  EXPECT_EQ(static_cast<int>(vtk.points.size()), 4 * mesh.num_elements());
  EXPECT_EQ(vtk.cells.size(), 12u);
  fs::remove_all(dir);
}

TEST(WedgeVtk, VtkReadsLinearWedgesWithTheMeshsVolumesAndGeometry) { check_wedges_in_vtk(false); }

TEST(WedgeVtk, VtkReadsQuadraticWedgesWithTheMeshsVolumesAndGeometry) { check_wedges_in_vtk(true); }

}  // namespace
