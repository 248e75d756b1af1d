#include "io/gmsh_mesh.h"

#include <gmsh.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>

#include <Eigen/Geometry>

#include "core/errors.h"
#include "fe/element.h"

namespace stickslip {
namespace {

// Coordinates written by Gmsh to an ASCII .msh carry 16 significant digits.
constexpr double kCoordinateTolerance = 1e-14;
// Mid-edge positions and volumes are sums of a few products of O(1) coordinates.
constexpr double kGeometryTolerance = 1e-12;

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("stickslip_gmsh_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

// CalculiX edges of the mid-edge nodes (CalculiX User's Manual, C3D20 and C3D10).
const int kHex20Edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
const int kTet10Edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};

Eigen::Vector3d node(const Mesh& m, int e, int local) {
  return m.coordinates.col(m.element_nodes(e)[local]);
}

double tet_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  const Eigen::Vector3d& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

// Signed volume from the corner nodes: exact for tetrahedra and for hexahedra with planar
// faces that are parallelepipeds (the structured boxes used here); positive for CalculiX's
// orientation (bottom face counter-clockwise seen from the top; tet nodes 1-2-3 counter-
// clockwise seen from node 4).
double corner_volume(const Mesh& m, int e) {
  auto x = [&](int i) { return node(m, e, i); };
  const ElementType t = m.element_types[e];
  if (t == ElementType::kC3D4 || t == ElementType::kC3D10)
    return tet_volume(x(0), x(1), x(2), x(3));
  // Six tetrahedra around the diagonal 0-6.
  return tet_volume(x(0), x(1), x(2), x(6)) + tet_volume(x(0), x(2), x(3), x(6)) +
         tet_volume(x(0), x(3), x(7), x(6)) + tet_volume(x(0), x(7), x(4), x(6)) +
         tet_volume(x(0), x(4), x(5), x(6)) + tet_volume(x(0), x(5), x(1), x(6));
}

void expect_midpoints_on_calculix_edges(const Mesh& m) {
  for (int e = 0; e < m.num_elements(); ++e) {
    const bool hex =
        m.element_types[e] == ElementType::kC3D20 || m.element_types[e] == ElementType::kC3D20R;
    const bool tet = m.element_types[e] == ElementType::kC3D10;
    ASSERT_TRUE(hex || tet);
    const int first = hex ? 8 : 4;
    const int count = hex ? 12 : 6;
    for (int k = 0; k < count; ++k) {
      const int* edge = hex ? kHex20Edges[k] : kTet10Edges[k];
      const Eigen::Vector3d mid = 0.5 * (node(m, e, edge[0]) + node(m, e, edge[1]));
      ASSERT_LT((node(m, e, first + k) - mid).norm(), kGeometryTolerance)
          << "element " << m.element_ids[e] << " mid-edge node " << first + k;
    }
  }
}

// Box [0, a] x [0, b] x [0, c] in the geo kernel; returns the volume tag. Surface x = 0 and the
// volume get physical groups "XMIN" and "SOLID".
int make_box(double a, double b, double c) {
  namespace geo = gmsh::model::geo;
  const int p[8] = {geo::addPoint(0, 0, 0), geo::addPoint(a, 0, 0), geo::addPoint(a, b, 0),
                    geo::addPoint(0, b, 0), geo::addPoint(0, 0, c), geo::addPoint(a, 0, c),
                    geo::addPoint(a, b, c), geo::addPoint(0, b, c)};
  std::map<std::pair<int, int>, int> lines;
  auto line = [&](int i, int j) {
    const auto key = std::make_pair(std::min(p[i], p[j]), std::max(p[i], p[j]));
    if (!lines.count(key)) lines[key] = geo::addLine(key.first, key.second);
    return p[i] < p[j] ? lines[key] : -lines[key];
  };
  auto face = [&](int i, int j, int k, int l) {
    return geo::addPlaneSurface(
        {geo::addCurveLoop({line(i, j), line(j, k), line(k, l), line(l, i)})});
  };
  const int xmin = face(0, 3, 7, 4);
  const std::vector<int> faces = {
      face(0, 1, 2, 3), face(4, 5, 6, 7), face(0, 1, 5, 4), face(3, 2, 6, 7), xmin,
      face(1, 2, 6, 5)};
  const int volume = geo::addVolume({geo::addSurfaceLoop(faces)});
  geo::synchronize();
  gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, {xmin}), "XMIN");
  gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, {volume}), "SOLID");
  return volume;
}

struct GmshNodes {
  std::vector<std::size_t> tags;
  std::vector<double> coords;
};

GmshNodes all_nodes() {
  GmshNodes n;
  std::vector<double> param;
  gmsh::model::mesh::getNodes(n.tags, n.coords, param, -1, -1, false, false);
  return n;
}

void expect_same_nodes(const Mesh& m, const GmshNodes& g) {
  ASSERT_EQ(static_cast<size_t>(m.num_nodes()), g.tags.size());
  const auto index = node_index_by_id(m);
  for (size_t i = 0; i < g.tags.size(); ++i) {
    const int n = index.at(static_cast<int>(g.tags[i]));
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(m.coordinates(d, n), g.coords[3 * i + d], kCoordinateTolerance);
    }
  }
}

TEST(GmshMesh, StructuredHex20BoxRoundTripsThroughMshWithCalculixNodeOrder) {
  const double a = 2.0, b = 1.0, c = 0.5;
  const int nx = 3, ny = 2, nz = 2;
  const std::string path = temp_path("hex20.msh");
  GmshNodes generated;
  {
    GmshSession session;
    gmsh::model::add("hex20");
    make_box(a, b, c);
    for (const auto& [dim, tag] : [] {
           gmsh::vectorpair v;
           gmsh::model::getEntities(v, 1);
           return v;
         }()) {
      std::vector<double> lo(3), hi(3);
      gmsh::model::getBoundingBox(dim, tag, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
      const int n = hi[0] - lo[0] > 1e-9 ? nx : (hi[1] - lo[1] > 1e-9 ? ny : nz);
      gmsh::model::mesh::setTransfiniteCurve(tag, n + 1);
    }
    gmsh::vectorpair surfaces, volumes;
    gmsh::model::getEntities(surfaces, 2);
    gmsh::model::getEntities(volumes, 3);
    for (const auto& [dim, tag] : surfaces) {
      gmsh::model::mesh::setTransfiniteSurface(tag);
      gmsh::model::mesh::setRecombine(dim, tag);
    }
    gmsh::model::mesh::setTransfiniteVolume(volumes[0].second);
    gmsh::option::setNumber("Mesh.SecondOrderIncomplete", 1);
    gmsh::model::mesh::generate(3);
    gmsh::model::mesh::setOrder(2);
    generated = all_nodes();
    gmsh::write(path);
    gmsh::model::remove();
  }
  const Mesh m =
      read_gmsh(path, {.hexahedron8 = ElementType::kC3D8I, .hexahedron20 = ElementType::kC3D20R});
  std::filesystem::remove(path);

  ASSERT_EQ(m.num_elements(), nx * ny * nz);
  for (ElementType t : m.element_types) EXPECT_EQ(t, ElementType::kC3D20R);
  // Serendipity grid: vertices plus one node per grid edge.
  const int vertices = (nx + 1) * (ny + 1) * (nz + 1);
  const int edges = nx * (ny + 1) * (nz + 1) + (nx + 1) * ny * (nz + 1) + (nx + 1) * (ny + 1) * nz;
  EXPECT_EQ(m.num_nodes(), vertices + edges);
  expect_same_nodes(m, generated);
  expect_midpoints_on_calculix_edges(m);
  double volume = 0.0;
  for (int e = 0; e < m.num_elements(); ++e) {
    const double v = corner_volume(m, e);
    EXPECT_GT(v, 0.0) << "inverted element " << m.element_ids[e];
    volume += v;
  }
  EXPECT_NEAR(volume, a * b * c, kGeometryTolerance);

  // Physical groups: the x = 0 face (its grid: (ny+1)(nz+1) vertices + ny(nz+1) + (ny+1)nz edges).
  const auto& xmin = m.node_sets.at("XMIN");
  EXPECT_EQ(static_cast<int>(xmin.size()), (ny + 1) * (nz + 1) + ny * (nz + 1) + (ny + 1) * nz);
  for (int n : xmin) EXPECT_EQ(m.coordinates(0, n), 0.0);
  EXPECT_EQ(static_cast<int>(m.element_sets.at("SOLID").size()), m.num_elements());
  EXPECT_EQ(static_cast<int>(m.node_sets.at("SOLID").size()), m.num_nodes());
}

TEST(GmshMesh, UnstructuredTet10BoxHasMidNodesOnCalculixEdgesAndTheRightVolume) {
  const double a = 1.0, b = 0.7, c = 0.4;
  const std::string path = temp_path("tet10.msh");
  GmshNodes generated;
  {
    GmshSession session;
    gmsh::model::add("tet10");
    make_box(a, b, c);
    gmsh::option::setNumber("Mesh.MeshSizeMax", 0.25);
    gmsh::option::setNumber("Mesh.SecondOrderIncomplete", 0);
    gmsh::model::mesh::generate(3);
    gmsh::model::mesh::setOrder(2);
    generated = all_nodes();
    gmsh::option::setNumber("Mesh.Binary", 1);  // binary .msh: exact coordinates
    gmsh::write(path);
    gmsh::option::setNumber("Mesh.Binary", 0);
    gmsh::model::remove();
  }
  const Mesh m = read_gmsh(path);
  std::filesystem::remove(path);
  ASSERT_GT(m.num_elements(), 20);
  for (ElementType t : m.element_types) ASSERT_EQ(t, ElementType::kC3D10);
  expect_same_nodes(m, generated);
  expect_midpoints_on_calculix_edges(m);
  double volume = 0.0;
  for (int e = 0; e < m.num_elements(); ++e) {
    const double v = corner_volume(m, e);
    EXPECT_GT(v, 0.0) << "inverted element " << m.element_ids[e];
    volume += v;
  }
  EXPECT_NEAR(volume, a * b * c, kGeometryTolerance);
}

TEST(GmshMesh, PermutationMapsGmshReferenceNodesOntoCalculixEdges) {
  // Independent of any mesh: Gmsh's own reference coordinates of its 20-node hexahedron and
  // 10-node tetrahedron, permuted, must put each mid-edge node at the midpoint of its CalculiX
  // edge.
  GmshSession session;
  for (int type : {17, 11, 18}) {
    std::string name;
    int dim, order, num_nodes, primary;
    std::vector<double> local;
    gmsh::model::mesh::getElementProperties(type, name, dim, order, num_nodes, local, primary);
    const int* perm = gmsh_to_calculix_order(type);
    ASSERT_NE(perm, nullptr);
    auto ref = [&](int calculix_local) {
      const int g = perm[calculix_local];
      return Eigen::Vector3d(local[3 * g], local[3 * g + 1], local[3 * g + 2]);
    };
    const bool hex = type == 17, prism = type == 18;
    // CalculiX C3D15: mid-edge nodes 7-15 on 1-2, 2-3, 3-1, 4-5, 5-6, 6-4, 1-4, 2-5, 3-6.
    constexpr int kPrism15Edges[9][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5},
                                         {5, 3}, {0, 3}, {1, 4}, {2, 5}};
    for (int k = 0; k < (hex ? 12 : prism ? 9 : 6); ++k) {
      const int* edge = hex ? kHex20Edges[k] : prism ? kPrism15Edges[k] : kTet10Edges[k];
      const int first_mid = hex ? 8 : prism ? 6 : 4;
      EXPECT_LT((ref(first_mid + k) - 0.5 * (ref(edge[0]) + ref(edge[1]))).norm(), 1e-15)
          << name << " edge " << k;
    }
    if (prism) {
      // Corners: CalculiX's natural triangle (0,0), (1,0), (0,1) at zeta = -1, then +1, which
      // Gmsh's reference prism uses too (u, v, w).
      const double corners[6][3] = {{0, 0, -1}, {1, 0, -1}, {0, 1, -1},
                                    {0, 0, 1},  {1, 0, 1},  {0, 1, 1}};
      for (int a = 0; a < 6; ++a) {
        EXPECT_EQ(ref(a), Eigen::Vector3d(corners[a][0], corners[a][1], corners[a][2])) << a;
      }
    }
    // And the permutation is a permutation.
    std::vector<int> p(perm, perm + num_nodes);
    std::sort(p.begin(), p.end());
    for (int i = 0; i < num_nodes; ++i) EXPECT_EQ(p[i], i);
  }
}

TEST(GmshMesh, ReadsPrismsAsC3D6PyramidsAsC3D5AndRejects14NodePyramidsNamingThem) {
  const std::string path = temp_path("prism.msh");
  {
    GmshSession session;
    gmsh::model::add("prism");
    const int v = gmsh::model::addDiscreteEntity(3);
    gmsh::model::mesh::addNodes(3, v, {1, 2, 3, 4, 5, 6},
                                {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1});
    gmsh::model::mesh::addElementsByType(v, 6, {1}, {1, 2, 3, 4, 5, 6});
    gmsh::write(path);
    gmsh::model::remove();
  }
  const Mesh prism = read_gmsh(path);
  ASSERT_EQ(prism.num_elements(), 1);
  EXPECT_EQ(prism.element_types[0], ElementType::kC3D6);
  const auto nodes = prism.element_nodes(0);
  for (int a = 0; a < 6; ++a) EXPECT_EQ(prism.node_ids[nodes[a]], a + 1);
  {
    GmshSession session;
    gmsh::model::add("pyramid");
    const int v = gmsh::model::addDiscreteEntity(3);
    gmsh::model::mesh::addNodes(3, v, {1, 2, 3, 4, 5},
                                {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0.5, 1});
    gmsh::model::mesh::addElementsByType(v, 7, {1}, {1, 2, 3, 4, 5});
    gmsh::write(path);
    gmsh::model::remove();
  }
  const Mesh pyramid = read_gmsh(path);
  ASSERT_EQ(pyramid.num_elements(), 1);
  EXPECT_EQ(pyramid.element_types[0], ElementType::kC3D5);
  const auto pyramid_nodes = pyramid.element_nodes(0);
  for (int a = 0; a < 5; ++a) EXPECT_EQ(pyramid.node_ids[pyramid_nodes[a]], a + 1);
  {
    GmshSession session;
    gmsh::model::add("pyramid14");
    const int v = gmsh::model::addDiscreteEntity(3);
    std::vector<std::size_t> tags;
    std::vector<double> xyz;
    for (int i = 0; i < 14; ++i) {
      tags.push_back(static_cast<std::size_t>(i + 1));
      for (double c : {0.1 * i, 0.2 * (i % 3), 0.3 * (i % 5)}) xyz.push_back(c);
    }
    gmsh::model::mesh::addNodes(3, v, tags, xyz);
    gmsh::model::mesh::addElementsByType(v, 14, {1}, tags);
    gmsh::write(path);
    gmsh::model::remove();
  }
  try {
    read_gmsh(path);
    FAIL() << "a 14-node pyramid was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, path);
    EXPECT_NE(e.message().find("Pyramid"), std::string::npos) << e.message();
  }
  std::filesystem::remove(path);
}

// Gmsh's own reference pyramid (getElementProperties): base corners 0-3 at w = 0 and apex 4 at
// (0, 0, 1), in the order of C3D5's natural nodes (base at zeta = -1, apex at (0, 0, 1)), so the
// reader keeps Gmsh's node order.
TEST(GmshMesh, GmshReferencePyramidHasC3D5sNodeOrder) {
  GmshSession session;
  std::string name;
  int dim = 0, order = 0, num_nodes = 0, primary = 0;
  std::vector<double> local;
  gmsh::model::mesh::getElementProperties(7, name, dim, order, num_nodes, local, primary);
  ASSERT_EQ(num_nodes, 5);
  const Eigen::Matrix3Xd ours = natural_node_coordinates(ElementType::kC3D5);
  const int* perm = gmsh_to_calculix_order(7);
  ASSERT_NE(perm, nullptr);
  for (int a = 0; a < 5; ++a) {
    const int g = perm[a];
    const Eigen::Vector3d gmsh(local[3 * g], local[3 * g + 1], local[3 * g + 2]);
    // Gmsh's w in [0, 1] is our zeta in [-1, 1] on the base; both put the apex at (0, 0, 1).
    const Eigen::Vector3d mapped(gmsh(0), gmsh(1), a < 4 ? 2 * gmsh(2) - 1 : gmsh(2));
    EXPECT_EQ(mapped, Eigen::Vector3d(ours.col(a))) << "node " << a;
  }
}

// Gmsh's own reference 13-node pyramid (type 19): its nodes, permuted by the reader's order, sit
// where C3D13's natural nodes do once Gmsh's pyramid (base corners (±1, ±1, 0), apex (0, 0, 1))
// is mapped onto the collapsed brick: ξ = u / (1 − w), η = v / (1 − w), ζ = 2w − 1 (the apex
// anywhere on ζ = 1; ours is at (0, 0, 1)). A mesh of one such pyramid reads as C3D13 with the
// element's volume.
TEST(GmshMesh, GmshReference13NodePyramidHasC3D13sNodeOrderAndReadsAsC3D13) {
  const std::string path = temp_path("pyramid13.msh");
  {
    GmshSession session;
    std::string name;
    int dim = 0, order = 0, num_nodes = 0, primary = 0;
    std::vector<double> local;
    gmsh::model::mesh::getElementProperties(19, name, dim, order, num_nodes, local, primary);
    ASSERT_EQ(num_nodes, 13);
    const Eigen::Matrix3Xd ours = natural_node_coordinates(ElementType::kC3D13);
    const int* perm = gmsh_to_calculix_order(19);
    ASSERT_NE(perm, nullptr);
    for (int a = 0; a < 13; ++a) {
      const int g = perm[a];
      const double u = local[3 * g], v = local[3 * g + 1], w = local[3 * g + 2];
      const Eigen::Vector3d mapped = w == 1.0
                                         ? Eigen::Vector3d(0, 0, 1)
                                         : Eigen::Vector3d(u / (1 - w), v / (1 - w), 2 * w - 1);
      EXPECT_LT((mapped - ours.col(a)).norm(), 1e-15) << "node " << a;
    }
    // The reference pyramid itself, scaled by 0.1 m, as a mesh in Gmsh's order.
    gmsh::model::add("pyramid13");
    const int e = gmsh::model::addDiscreteEntity(3);
    std::vector<std::size_t> tags;
    std::vector<double> xyz;
    for (int i = 0; i < 13; ++i) {
      tags.push_back(static_cast<std::size_t>(i + 1));
      for (int d = 0; d < 3; ++d) xyz.push_back(0.1 * local[static_cast<size_t>(3 * i + d)]);
    }
    gmsh::model::mesh::addNodes(3, e, tags, xyz);
    gmsh::model::mesh::addElementsByType(e, 19, {1}, tags);
    gmsh::write(path);
    gmsh::model::remove();
  }
  const Mesh pyramid = read_gmsh(path);
  ASSERT_EQ(pyramid.num_elements(), 1);
  EXPECT_EQ(pyramid.element_types[0], ElementType::kC3D13);
  // Base 0.2 m x 0.2 m, height 0.1 m: V = 0.2² · 0.1 / 3.
  Eigen::Matrix3Xd X(3, 13);
  const auto nodes = pyramid.element_nodes(0);
  for (int a = 0; a < 13; ++a) X.col(a) = pyramid.coordinates.col(nodes[a]);
  EXPECT_NEAR(element_volume(ElementType::kC3D13, X), 0.04 * 0.1 / 3, 1e-15);
  std::filesystem::remove(path);
}

TEST(GmshMesh, WarnsAboutElementsAndGroupNodesItDoesNotUse) {
  // One hexahedron in a physical volume; a triangle on a surface entity without a physical group
  // (used for nothing); a physical point whose node is on no 3D element (left out of its set).
  const std::string path = temp_path("unused.msh");
  {
    GmshSession session;
    gmsh::model::add("unused");
    const int v = gmsh::model::addDiscreteEntity(3);
    gmsh::model::mesh::addNodes(3, v, {1, 2, 3, 4, 5, 6, 7, 8},
                                {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,
                                 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1});
    gmsh::model::mesh::addElementsByType(v, 5, {1}, {1, 2, 3, 4, 5, 6, 7, 8});
    gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, {v}), "SOLID");
    const int s = gmsh::model::addDiscreteEntity(2);
    gmsh::model::mesh::addElementsByType(s, 2, {2}, {1, 2, 3});
    const int p = gmsh::model::addDiscreteEntity(0);
    gmsh::model::mesh::addNodes(0, p, {9}, {5, 5, 5});
    gmsh::model::mesh::addElementsByType(p, 15, {3}, {9});
    gmsh::model::setPhysicalName(0, gmsh::model::addPhysicalGroup(0, {p}), "LOOSE");
    gmsh::option::setNumber("Mesh.SaveAll", 1);
    gmsh::write(path);
    gmsh::option::setNumber("Mesh.SaveAll", 0);
    gmsh::model::remove();
  }
  std::vector<std::string> warnings;
  const Mesh m = read_gmsh(path, {}, &warnings);
  std::filesystem::remove(path);
  EXPECT_EQ(m.num_elements(), 1);
  EXPECT_TRUE(m.node_sets.at("LOOSE").empty());
  ASSERT_EQ(warnings.size(), 2u);
  std::string all = warnings[0] + "\n" + warnings[1];
  EXPECT_NE(all.find("physical group LOOSE: 1 of its 1 nodes are on no 3D element"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("1 Triangle 3 (MSH type 2) (dimension 2) belong to no physical group"),
            std::string::npos)
      << all;
  for (const std::string& w : warnings) EXPECT_EQ(w.rfind(path + ": ", 0), 0u) << w;
}

TEST(GmshMesh, BadOrMissingFilesAreInvalidInputNamingTheFile) {
  const std::string path = temp_path("garbage.msh");
  {
    std::ofstream out(path);
    out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n3 1 0 2\nnot a number\n";
  }
  try {
    read_gmsh(path);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, path);
  }
  std::filesystem::remove(path);
  try {
    read_gmsh(path);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, path);
    EXPECT_NE(e.message().find("cannot open"), std::string::npos);
  }
  GmshReadOptions bad;
  bad.hexahedron8 = ElementType::kC3D4;
  EXPECT_THROW(validate(bad), InvalidInput);
}

}  // namespace
}  // namespace stickslip
