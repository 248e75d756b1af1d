// End-to-end: pyramids (C3D5, and the quadratic C3D13 below) in a mesh with hexahedra and
// tetrahedra.
//  - Frequencies through `stickslip modes` against CalculiX *FREQUENCY run by the test on the same
//    mesh. ccx has no pyramid element; C3D5 is by definition the 8-node brick with nodes 5-8
//    collapsed onto the apex (ANSYS SOLID185's pyramid), so ccx gets each pyramid as exactly that
//    C3D8 (nodes 5-8 = the apex): an exact reference, computed by ccx's own C3D8 code. (The same
//    pyramids split into two tetrahedra would not be one: the brick's bilinear term differs from a
//    piecewise linear field.) With `mass_rule: calculix` both integrate the mass with 2x2x2
//    points, so the frequencies agree to ccx's 7 printed digits.
//  - The mesh's volume: the sum of element_volume over bricks, pyramids and tetrahedra equals the
//    bar's (an affine image of a box: det A · lx ly lz).
//  - VTK (Debian's python3-vtk9) reads the VTU stickslip writes: pyramids as VTK_PYRAMID (14) with
//    VTK's volume = ours, and VTK's own pyramid shape functions (vtkCell::EvaluateLocation) map
//    parametric points where ours do.
#include <gtest/gtest.h>

#include "../required_tool.h"
#include "cli_test_support.h"
#include "fe/element.h"
#include "io/inp_reader.h"
#include "pyramid_decks.h"
#include "vtk_cells.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <Eigen/LU>

namespace {

using namespace stickslip::cli_test;
using stickslip::ElementType;

// The skewed bar: det A = 0.865 > 0 (not a mirror), no two columns parallel.
constexpr double kA[3][3] = {{1.0, 0.3, -0.2}, {0.1, 1.1, 0.25}, {-0.15, 0.2, 0.9}};
constexpr double kLx = 0.2, kLy = 0.03, kLz = 0.02;

std::string mixed_bar(int nx, int ny, int nz, bool pyramids_as_c3d8) {
  return mixed_pyramid_bar_inp(nx, ny, nz, kLx, kLy, kLz, kA, 2, nx - 3, pyramids_as_c3d8);
}

int count_type(const stickslip::Mesh& mesh, ElementType type) {
  int n = 0;
  for (ElementType t : mesh.element_types) n += t == type ? 1 : 0;
  return n;
}

// Writes our deck (bar.inp) and ccx's (job.inp: `ccx_mesh` plus steel and *FREQUENCY), runs
// `stickslip modes` with ccx's mass rule and ccx, and returns the largest relative frequency
// difference over the first `modes` (each checked to ccx's printed 7 digits).
double modes_against_calculix(const fs::path& dir, const std::string& our_mesh,
                              const std::string& ccx_mesh, int modes) {
  std::ofstream(dir / "bar.inp") << our_mesh;
  std::ofstream(dir / "job.inp")
      << ccx_mesh
      << "*MATERIAL, NAME=STEEL\n*ELASTIC\n2e11, 0.3\n*DENSITY\n7800\n"
         "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*STEP\n*FREQUENCY\n"
      << modes << "\n*BOUNDARY\nFIX, 1, 3\n*END STEP\n";
  const std::string plain = tip_spring_bar_case((dir / "bar.inp").string());
  const std::string body = "clamp: FIX,";
  const size_t at = plain.find(body);
  EXPECT_NE(at, std::string::npos);
  if (at == std::string::npos) return 1.0;
  const std::string yaml =
      plain.substr(0, at) + "clamp: FIX, mass_rule: calculix," + plain.substr(at + body.size());
  run_stage("modes", write_case(dir, "bar", yaml), dir / "out");
  const auto rows = read_csv(dir / "out" / "modes" / "frequencies.csv");
  EXPECT_GE(static_cast<int>(rows.size()), modes);
  const std::vector<double> lambda = ccx_job_eigenvalues(dir);
  EXPECT_EQ(static_cast<int>(lambda.size()), modes) << slurp(dir / "ccx.log");
  if (static_cast<int>(rows.size()) < modes || static_cast<int>(lambda.size()) != modes) return 1.0;
  // Same K and M; ccx prints 7 significant digits (eigenvalue to 5e-8, frequency half of it).
  constexpr double kPrintedDigits = 1e-6;
  return expect_frequencies_match(rows, lambda, modes, kPrintedDigits);
}

TEST(PyramidCli, MixedBrickPyramidTetBarModesMatchCalculixWithPyramidsAsCollapsedBricks) {
  constexpr int kModes = 8;
  const fs::path dir = fresh_dir("pyramid_ccx");
  {
    std::ofstream(dir / "probe.inp") << mixed_bar(8, 2, 2, false);
    const stickslip::Mesh mesh = stickslip::read_inp((dir / "probe.inp").string());
    ASSERT_GT(count_type(mesh, ElementType::kC3D5), 20);
    ASSERT_GT(count_type(mesh, ElementType::kC3D4), 10);
    ASSERT_GT(count_type(mesh, ElementType::kC3D8), 10);
  }
  const double worst =
      modes_against_calculix(dir, mixed_bar(8, 2, 2, false), mixed_bar(8, 2, 2, true), kModes);
  std::printf(
      "[ CalculiX ] brick/pyramid/tet bar 8x2x2 cells: max relative frequency "
      "difference %.2e\n",
      worst);
  RecordProperty("max_relative_frequency_difference_to_ccx", std::to_string(worst));
  fs::remove_all(dir);
}

TEST(PyramidCli, VolumesOfBricksPyramidsAndTetrahedraAddUpToTheBar) {
  const fs::path dir = fresh_dir("pyramid_volume");
  std::ofstream(dir / "bar.inp") << mixed_bar(6, 2, 3, false);
  const stickslip::Mesh mesh = stickslip::read_inp((dir / "bar.inp").string());
  ASSERT_GT(count_type(mesh, ElementType::kC3D5), 20);
  double volume = 0.0;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto nodes = mesh.element_nodes(e);
    Eigen::Matrix3Xd X(3, nodes.size());
    for (size_t a = 0; a < nodes.size(); ++a) X.col(a) = mesh.coordinates.col(nodes[a]);
    volume += stickslip::element_volume(mesh.element_types[e], X);
  }
  Eigen::Matrix3d A;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) A(i, j) = kA[i][j];
  const double exact = A.determinant() * kLx * kLy * kLz;
  // The deck's coordinates carry 12 significant digits.
  constexpr double kDeckDigits = 1e-10;
  EXPECT_NEAR(volume, exact, kDeckDigits * exact);
  fs::remove_all(dir);
}

// Parametric points (r, s, t) of VTK's pyramid (vtkPyramid: base points 0-3 at (r, s) = (0, 0),
// (1, 0), (1, 1), (0, 1) with t = 0, apex 4 at t = 1), none on a symmetry of the pyramid.
const std::vector<std::array<double, 3>> kParametric = {
    {0.2, 0.5, 0.3}, {0.1, 0.15, 0.9}, {0.6, 0.25, 0.05}, {0.7, 0.8, 0.4}};

TEST(PyramidCli, VtkReadsPyramidsWithTheMeshsVolumesAndGeometry) {
  STICKSLIP_REQUIRE_TOOL(vtk_available(), "/usr/bin/python3 with VTK (python3-vtk9)");
  const fs::path dir = fresh_dir("pyramid_vtk");
  std::ofstream(dir / "bar.inp") << mixed_bar(6, 1, 1, false);
  run_stage("modes", write_case(dir, "bar", tip_spring_bar_case((dir / "bar.inp").string())),
            dir / "out");
  const fs::path vtu = dir / "out" / "modes" / "bar" / "shapes.vtu";
  ASSERT_TRUE(fs::exists(vtu));
  constexpr int kVtkPyramid = 14;  // vtkCellType.h
  const VtkCells vtk = read_with_vtk(vtu, dir, kParametric, kVtkPyramid);

  const stickslip::Mesh mesh = stickslip::read_inp((dir / "bar.inp").string());
  std::map<int, int> element_of_id;
  for (int e = 0; e < mesh.num_elements(); ++e) element_of_id[mesh.element_ids[e]] = e;
  // VTK_HEXAHEDRON, VTK_PYRAMID, VTK_TETRA (vtkCellType.h).
  const std::map<ElementType, int> vtk_types = {
      {ElementType::kC3D8, 12}, {ElementType::kC3D5, kVtkPyramid}, {ElementType::kC3D4, 10}};
  // Volumes and positions are sums of O(1) products of coordinates of size ~0.1 m (digits as in
  // the deck, 17 in the VTU): round-off is ~1e-16 of the element's size.
  constexpr double kRoundOff = 1e-12;
  for (const VtkCell& cell : vtk.cells) {
    ASSERT_TRUE(element_of_id.count(cell.element_id)) << cell.element_id;
    const int e = element_of_id.at(cell.element_id);
    const ElementType type = mesh.element_types[e];
    const Eigen::Matrix3Xd X = element_coordinates(mesh, e);
    const double size = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm();
    EXPECT_EQ(cell.type, vtk_types.at(type)) << "element " << cell.element_id;
    const double ours = stickslip::element_volume(type, X);
    EXPECT_GT(ours, 0.0);
    EXPECT_NEAR(cell.volume, ours, kRoundOff * std::pow(size, 3)) << "element " << cell.element_id;
  }
  for (const VtkPoint& point : vtk.points) {
    ASSERT_TRUE(element_of_id.count(point.element_id)) << point.element_id;
    const int e = element_of_id.at(point.element_id);
    ASSERT_EQ(mesh.element_types[e], ElementType::kC3D5) << "element " << point.element_id;
    ASSERT_TRUE(point.k >= 0 && point.k < 4);
    const Eigen::Matrix3Xd X = element_coordinates(mesh, e);
    const double size = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm();
    // VTK's (r, s, t) in [0, 1]^3 is our (xi, eta, zeta) in [-1, 1]^3.
    const auto& r = kParametric[point.k];
    const Eigen::Vector3d xi(2 * r[0] - 1, 2 * r[1] - 1, 2 * r[2] - 1);
    Eigen::VectorXd N;
    Eigen::Matrix3Xd dN;
    stickslip::shape_functions(ElementType::kC3D5, xi, N, dN);
    const Eigen::Vector3d ours = X * N;
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(point.x(d), ours(d), kRoundOff * size)
          << "element " << point.element_id << " parametric point " << point.k << " direction "
          << d;
    }
  }
  EXPECT_EQ(static_cast<int>(vtk.cells.size()), mesh.num_elements());
  EXPECT_EQ(static_cast<int>(vtk.points.size()), 4 * count_type(mesh, ElementType::kC3D5));
  EXPECT_GT(vtk.points.size(), 0u);
  fs::remove_all(dir);
}

std::string quadratic_bar(int nx, int ny, int nz, bool pyramids_as_c3d20) {
  return mixed_quadratic_pyramid_bar_inp(nx, ny, nz, kLx, kLy, kLz, kA, 2, nx - 3,
                                         pyramids_as_c3d20);
}

// The quadratic bar (C3D20 + C3D13 + C3D10) through `stickslip modes` against ccx *FREQUENCY on
// the same mesh with each pyramid written as the C3D20 it is (nodes 5-8 and 13-16 on the apex):
// the same shape functions and 3x3x3 rule, ccx's own C3D20 code.
TEST(PyramidCli, MixedQuadraticBarModesMatchCalculixWithPyramidsAsCollapsedC3D20) {
  constexpr int kModes = 8;
  const fs::path dir = fresh_dir("pyramid13_ccx");
  {
    std::ofstream(dir / "probe.inp") << quadratic_bar(6, 2, 2, false);
    const stickslip::Mesh mesh = stickslip::read_inp((dir / "probe.inp").string());
    ASSERT_GT(count_type(mesh, ElementType::kC3D13), 10);
    ASSERT_GT(count_type(mesh, ElementType::kC3D10), 5);
    ASSERT_GT(count_type(mesh, ElementType::kC3D20), 10);
  }
  const double worst = modes_against_calculix(dir, quadratic_bar(6, 2, 2, false),
                                              quadratic_bar(6, 2, 2, true), kModes);
  std::printf(
      "[ CalculiX ] quadratic brick/pyramid/tet bar 6x2x2 cells: max relative frequency "
      "difference %.2e\n",
      worst);
  RecordProperty("max_relative_frequency_difference_to_ccx", std::to_string(worst));
  fs::remove_all(dir);
}

TEST(PyramidCli, VolumesOfQuadraticBricksPyramidsAndTetrahedraAddUpToTheBar) {
  const fs::path dir = fresh_dir("pyramid13_volume");
  std::ofstream(dir / "bar.inp") << quadratic_bar(6, 2, 3, false);
  const stickslip::Mesh mesh = stickslip::read_inp((dir / "bar.inp").string());
  ASSERT_GT(count_type(mesh, ElementType::kC3D13), 20);
  double volume = 0.0;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    volume += stickslip::element_volume(mesh.element_types[e], element_coordinates(mesh, e));
  }
  Eigen::Matrix3d A;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) A(i, j) = kA[i][j];
  const double exact = A.determinant() * kLx * kLy * kLz;
  constexpr double kDeckDigits = 1e-10;  // the deck's coordinates carry 12 significant digits
  EXPECT_NEAR(volume, exact, kDeckDigits * exact);
  fs::remove_all(dir);
}

// VTK reads the 13-node pyramids as VTK_QUADRATIC_PYRAMID (27). VTK's quadratic pyramid has its
// own interpolation (not the collapsed brick's), but on straight edges with mid-edge nodes at
// their midpoints both reproduce the linear pyramid's map, so positions of parametric points
// agree only if every node is where VTK expects it; volumes too.
TEST(PyramidCli, VtkReadsQuadraticPyramidsWithTheMeshsVolumesAndGeometry) {
  STICKSLIP_REQUIRE_TOOL(vtk_available(), "/usr/bin/python3 with VTK (python3-vtk9)");
  const fs::path dir = fresh_dir("pyramid13_vtk");
  std::ofstream(dir / "bar.inp") << quadratic_bar(6, 1, 1, false);
  const std::string yaml = tip_spring_bar_case((dir / "bar.inp").string());
  run_stage("modes", write_case(dir, "bar", yaml), dir / "out");
  const fs::path vtu = dir / "out" / "modes" / "bar" / "shapes.vtu";
  ASSERT_TRUE(fs::exists(vtu));
  constexpr int kVtkQuadraticPyramid = 27;  // vtkCellType.h
  const VtkCells vtk = read_with_vtk(vtu, dir, kParametric, kVtkQuadraticPyramid);

  const stickslip::Mesh mesh = stickslip::read_inp((dir / "bar.inp").string());
  std::map<int, int> element_of_id;
  for (int e = 0; e < mesh.num_elements(); ++e) element_of_id[mesh.element_ids[e]] = e;
  // VTK_QUADRATIC_HEXAHEDRON, VTK_QUADRATIC_PYRAMID, VTK_QUADRATIC_TETRA (vtkCellType.h).
  const std::map<ElementType, int> vtk_types = {{ElementType::kC3D20, 25},
                                                {ElementType::kC3D13, kVtkQuadraticPyramid},
                                                {ElementType::kC3D10, 24}};
  constexpr double kRoundOff = 1e-12;
  for (const VtkCell& cell : vtk.cells) {
    ASSERT_TRUE(element_of_id.count(cell.element_id)) << cell.element_id;
    const int e = element_of_id.at(cell.element_id);
    const ElementType type = mesh.element_types[e];
    const Eigen::Matrix3Xd X = element_coordinates(mesh, e);
    const double size = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm();
    EXPECT_EQ(cell.type, vtk_types.at(type)) << "element " << cell.element_id;
    const double ours = stickslip::element_volume(type, X);
    EXPECT_GT(ours, 0.0);
    EXPECT_NEAR(cell.volume, ours, kRoundOff * std::pow(size, 3)) << "element " << cell.element_id;
  }
  for (const VtkPoint& point : vtk.points) {
    ASSERT_TRUE(element_of_id.count(point.element_id)) << point.element_id;
    const int e = element_of_id.at(point.element_id);
    ASSERT_EQ(mesh.element_types[e], ElementType::kC3D13) << "element " << point.element_id;
    ASSERT_TRUE(point.k >= 0 && point.k < 4);
    const Eigen::Matrix3Xd X = element_coordinates(mesh, e);
    const double size = (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm();
    const auto& r = kParametric[point.k];
    const Eigen::Vector3d xi(2 * r[0] - 1, 2 * r[1] - 1, 2 * r[2] - 1);
    Eigen::VectorXd N;
    Eigen::Matrix3Xd dN;
    stickslip::shape_functions(ElementType::kC3D13, xi, N, dN);
    const Eigen::Vector3d ours = X * N;
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(point.x(d), ours(d), kRoundOff * size)
          << "element " << point.element_id << " parametric point " << point.k << " direction "
          << d;
    }
  }
  EXPECT_EQ(static_cast<int>(vtk.cells.size()), mesh.num_elements());
  EXPECT_EQ(static_cast<int>(vtk.points.size()), 4 * count_type(mesh, ElementType::kC3D13));
  EXPECT_GT(vtk.points.size(), 0u);
  fs::remove_all(dir);
}

}  // namespace
