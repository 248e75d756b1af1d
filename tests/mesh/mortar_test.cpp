// Mortar coupling of two blocks meeting on a plane (mesh/mortar.h), against properties that hold
// exactly and are computed here independently of the coupling: node-to-node on conforming meshes,
// rigid motions and every linear field reproduced on non-matching and distorted meshes, a uniform
// pressure on A delivered to B as its consistent nodal forces (∫ N_k dA from surface_area.h, a
// different integration), the gap of separated blocks, and partial coverage reported.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>

#include "core/errors.h"
#include "mesh/mesh_tools.h"
#include "mesh/mortar.h"
#include "mesh/surface_area.h"

namespace stickslip {
namespace {

// Block A: [0, 1] x [0, 1] x [0, 0.2], its top face z = 0.2 the surface. Block B: [0, bx] x
// [0, 1] x [0.2 + gap, 0.5 + gap], its bottom face the surface.
struct Blocks {
  Mesh a, b;
  std::vector<ElementFace> faces_a, faces_b;
  std::vector<int> nodes_a, nodes_b;
};

Blocks blocks(int ax, int ay, int bx, int by, double gap = 0.0, double b_length = 1.0) {
  Blocks s;
  s.a = structured_hex_box(ax, ay, 1, {1.0, 1.0, 0.2}, ElementType::kC3D8);
  s.b = structured_hex_box(bx, by, 1, {b_length, 1.0, 0.3}, ElementType::kC3D8);
  s.b.coordinates.row(2).array() += 0.2 + gap;
  s.nodes_a = nodes_on_plane(s.a, {0, 0, 0.2}, {0, 0, 1}, 1e-9);
  s.nodes_b = nodes_on_plane(s.b, {0, 0, 0.2 + gap}, {0, 0, 1}, 1e-9);
  s.faces_a = faces_within(s.a, s.nodes_a);
  s.faces_b = faces_within(s.b, s.nodes_b);
  return s;
}

// Moves B's surface nodes inside the surface (not on its edges) by up to `amount` (m) in x and y:
// with amount well below the cell size the faces stay convex and flat, but are no longer
// parallelograms.
void distort_b(Blocks& s, double amount, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amount, amount);
  for (int node : s.nodes_b) {
    auto x = s.b.coordinates.col(node);
    if (x.x() > 1e-9 && x.x() < 1 - 1e-9) x.x() += u(rng);
    if (x.y() > 1e-9 && x.y() < 1 - 1e-9) x.y() += u(rng);
  }
}

double weighted(const MortarPoint& p, const Mesh& b, const std::function<double(const Eigen::Vector3d&)>& f) {
  double s = 0;
  for (size_t k = 0; k < p.nodes_b.size(); ++k) s += p.weights_b[k] * f(b.coordinates.col(p.nodes_b[k]));
  return s;
}

TEST(Mortar, ConformingMeshesGiveNodeToNodeWithTheConsistentNodalArea) {
  const Blocks s = blocks(3, 4, 3, 4);
  const MortarCoupling c = mortar_coupling(s.a, s.faces_a, s.b, s.faces_b);
  ASSERT_EQ(c.points.size(), s.nodes_a.size());
  EXPECT_TRUE(c.partial.empty());
  const std::vector<double> area = nodal_areas(s.a, s.nodes_a, NodalAreaRule::kConsistent);
  for (size_t i = 0; i < c.points.size(); ++i) {
    const MortarPoint& p = c.points[i];
    EXPECT_EQ(p.node_a, s.nodes_a[i]);
    EXPECT_NEAR(p.area, area[i], 1e-14);
    EXPECT_NEAR((p.normal - Eigen::Vector3d(0, 0, 1)).norm(), 0, 1e-14);
    // Node to node exactly: the coincident B node alone (the others' round-off dropped).
    ASSERT_EQ(p.nodes_b.size(), 1u) << "A node " << p.node_a;
    EXPECT_LT((s.b.coordinates.col(p.nodes_b[0]) - s.a.coordinates.col(p.node_a)).norm(), 1e-12);
    EXPECT_NEAR(p.weights_b[0], 1.0, 1e-14) << "A node " << p.node_a;
    EXPECT_NEAR(p.gap, 0, 1e-14);
  }
}

// Every linear field f(x) = f0 + g·x of B's nodes, weighted by Φ, gives f at the A node; with
// f = 1 that is the full coverage, with f = x, y, z the rigid translations and rotations.
void expect_linear_fields_reproduced(const Blocks& s, const MortarCoupling& c) {
  ASSERT_TRUE(c.partial.empty());
  const std::vector<std::pair<double, Eigen::Vector3d>> fields = {
      {1.0, {0, 0, 0}}, {0.0, {1, 0, 0}}, {0.0, {0, 1, 0}}, {0.0, {0, 0, 1}}, {0.3, {-0.7, 2.1, 0.4}}};
  for (const MortarPoint& p : c.points) {
    EXPECT_NEAR(p.coverage, 1.0, 1e-12);
    double sum = 0;
    for (double w : p.weights_b) sum += w;
    EXPECT_NEAR(sum, 1.0, 1e-12);
    for (const auto& [f0, g] : fields) {
      auto f = [&](const Eigen::Vector3d& x) { return f0 + g.dot(x); };
      EXPECT_NEAR(weighted(p, s.b, f), f(s.a.coordinates.col(p.node_a)), 1e-12)
          << "A node " << p.node_a << ", field " << f0 << " + " << g.transpose();
    }
  }
}

TEST(Mortar, NonMatchingMeshesReproduceEveryLinearField) {
  for (const auto& [bx, by] : {std::pair{4, 5}, std::pair{7, 2}, std::pair{2, 9}}) {
    SCOPED_TRACE(std::to_string(bx) + " x " + std::to_string(by));
    const Blocks s = blocks(3, 3, bx, by);
    expect_linear_fields_reproduced(s, mortar_coupling(s.a, s.faces_a, s.b, s.faces_b));
  }
}

TEST(Mortar, DistortedFacesOfBStillReproduceEveryLinearField) {
  // A's faces are parallelograms: ψ_i and x are polynomials over them, so the 7-point rule on the
  // overlap triangles is exact whatever B's (convex) faces look like.
  Blocks s = blocks(3, 3, 5, 4);
  distort_b(s, 0.06, 7);  // cells 0.2 x 0.25
  expect_linear_fields_reproduced(s, mortar_coupling(s.a, s.faces_a, s.b, s.faces_b));
}

TEST(Mortar, UniformPressureOnAReachesBAsItsConsistentNodalForces) {
  // p D_i on A's nodes, carried by Φᵀ, must be p ∫_B N_k dA on B's nodes (the patch test):
  // Σ_i Φ_ik D_i = the consistent nodal area of B's node k, from surface_area.h's own quadrature.
  for (const auto& [bx, by] : {std::pair{4, 5}, std::pair{7, 2}}) {
    SCOPED_TRACE(std::to_string(bx) + " x " + std::to_string(by));
    const Blocks s = blocks(3, 3, bx, by);
    const MortarCoupling c = mortar_coupling(s.a, s.faces_a, s.b, s.faces_b);
    std::map<int, double> delivered;
    double total = 0;
    for (const MortarPoint& p : c.points) {
      total += p.area;
      for (size_t k = 0; k < p.nodes_b.size(); ++k) delivered[p.nodes_b[k]] += p.weights_b[k] * p.area;
    }
    EXPECT_NEAR(total, 1.0, 1e-14);
    const std::vector<double> area_b = nodal_areas(s.b, s.nodes_b, NodalAreaRule::kConsistent);
    for (size_t k = 0; k < s.nodes_b.size(); ++k) {
      EXPECT_NEAR(delivered[s.nodes_b[k]], area_b[k], 1e-14) << "B node " << s.nodes_b[k];
    }
  }
}

TEST(Mortar, GapIsTheNormalDistanceOfTheSurfaces) {
  for (double gap : {1e-3, -2e-3}) {
    const Blocks s = blocks(3, 3, 4, 5, gap);
    const MortarCoupling c = mortar_coupling(s.a, s.faces_a, s.b, s.faces_b);
    ASSERT_TRUE(c.partial.empty());
    for (const MortarPoint& p : c.points) EXPECT_NEAR(p.gap, gap, 1e-14) << p.node_a;
  }
  // Beyond the search distance nothing couples: every point is reported, with no coverage.
  const Blocks far = blocks(3, 3, 4, 5, 0.5);
  const MortarCoupling c = mortar_coupling(far.a, far.faces_a, far.b, far.faces_b,
                                           {.search_distance = 0.1});
  EXPECT_EQ(c.partial.size(), far.nodes_a.size());
  for (const MortarPoint& p : c.points) {
    EXPECT_EQ(p.coverage, 0.0);
    EXPECT_TRUE(std::isnan(p.gap));
  }
}

TEST(Mortar, PointsWhoseFacesStickOutOfBAreReportedPartial) {
  // B covers x in [0, 0.5]. A's nodes at x = 0 have their faces in [0, 1/3]: covered. Those at
  // 1/3 and 2/3 have faces reaching past 0.5: partial, covered by the part of their hat function
  // N_i (in x; the y factor cancels) over x < 0.5: at 1/3 all but the triangle of height 1/2 over
  // [0.5, 2/3], i.e. 1 − (1/2 · 1/6 · 1/2) / (1/3) = 7/8; at 2/3 that triangle only, 1/8. At x = 1
  // nothing overlaps: coverage 0.
  const Blocks s = blocks(3, 3, 2, 3, 0.0, 0.5);
  const MortarCoupling c = mortar_coupling(s.a, s.faces_a, s.b, s.faces_b);
  for (const MortarPoint& p : c.points) {
    const double x = s.a.coordinates(0, p.node_a);
    const bool listed = std::find(c.partial.begin(), c.partial.end(), p.node_a) != c.partial.end();
    if (x < 1e-9) {
      EXPECT_NEAR(p.coverage, 1.0, 1e-12);
      EXPECT_FALSE(listed);
    } else {
      EXPECT_LT(p.coverage, 1.0 - 1e-6) << x;
      EXPECT_TRUE(listed) << x;
    }
    if (std::abs(x - 1.0 / 3) < 1e-9) {
      EXPECT_NEAR(p.coverage, 0.875, 1e-12);
    }
    if (std::abs(x - 2.0 / 3) < 1e-9) {
      EXPECT_NEAR(p.coverage, 0.125, 1e-12);
    }
    if (x > 0.9) {
      EXPECT_EQ(p.coverage, 0.0);
    }
  }
}

// The same box as `structured_hex_box` cut into tetrahedra (6 per hexahedron around its 0–6
// diagonal): its surfaces are made of 3-node triangles.
Mesh tet_box(int nx, int ny, const Eigen::Vector3d& size) {
  const Mesh hex = structured_hex_box(nx, ny, 1, size, ElementType::kC3D8);
  Mesh tet;
  tet.coordinates = hex.coordinates;
  tet.node_ids = hex.node_ids;
  constexpr int kTets[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                               {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
  int id = 1;
  for (int e = 0; e < hex.num_elements(); ++e) {
    const std::span<const int> v = hex.element_nodes(e);
    for (const auto& t : kTets) {
      const std::array<int, 4> nodes = {v[t[0]], v[t[1]], v[t[2]], v[t[3]]};
      tet.add_element(id++, ElementType::kC3D4, nodes);
    }
  }
  return tet;
}

TEST(Mortar, TriangleFacesAgainstQuadrilateralsPassTheSameChecks) {
  Blocks s = blocks(3, 3, 4, 5);
  s.a = tet_box(3, 3, {1.0, 1.0, 0.2});
  s.faces_a = faces_within(s.a, s.nodes_a);  // the same node indices: the hexahedra's nodes
  ASSERT_EQ(s.faces_a.size(), 18u);
  ASSERT_EQ(s.faces_a.front().nodes.size(), 3u);
  const MortarCoupling c = mortar_coupling(s.a, s.faces_a, s.b, s.faces_b);
  expect_linear_fields_reproduced(s, c);
  std::map<int, double> delivered;
  for (const MortarPoint& p : c.points) {
    for (size_t k = 0; k < p.nodes_b.size(); ++k) delivered[p.nodes_b[k]] += p.weights_b[k] * p.area;
  }
  const std::vector<double> area_b = nodal_areas(s.b, s.nodes_b, NodalAreaRule::kConsistent);
  for (size_t k = 0; k < s.nodes_b.size(); ++k) EXPECT_NEAR(delivered[s.nodes_b[k]], area_b[k], 1e-14);
}

TEST(Mortar, FacesOfOtherNodeCountsAreRefusedByName) {
  const Blocks s = blocks(2, 2, 2, 2);
  std::vector<ElementFace> five = {s.faces_a.front()};
  five.front().nodes.push_back(0);  // 5 nodes: no such face
  try {
    mortar_coupling(s.a, five, s.b, s.faces_b);
    FAIL() << "a 5-node face was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("5 nodes"), std::string::npos) << e.what();
  }
}

// The quadratic version of a mesh of C3D8 or C3D4: a node at the middle of every edge (shared
// between the elements of the edge), C3D20 or C3D10 in CalculiX's node order.
Mesh quadratic(const Mesh& linear) {
  Mesh out;
  out.coordinates = linear.coordinates;
  out.node_ids = linear.node_ids;
  std::map<std::pair<int, int>, int> middle;
  const auto mid = [&](int p, int q) {
    const std::pair<int, int> key{std::min(p, q), std::max(p, q)};
    const auto it = middle.find(key);
    if (it != middle.end()) return it->second;
    const Eigen::Vector3d x = 0.5 * (out.coordinates.col(p) + out.coordinates.col(q));
    const int index = out.add_node(out.num_nodes() + 1, x);
    middle.emplace(key, index);
    return index;
  };
  constexpr int kHexEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                    {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  constexpr int kTetEdges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  for (int e = 0; e < linear.num_elements(); ++e) {
    const std::span<const int> v = linear.element_nodes(e);
    std::vector<int> nodes(v.begin(), v.end());
    const bool hex = v.size() == 8;
    if (hex) {
      for (const auto& edge : kHexEdges) nodes.push_back(mid(v[edge[0]], v[edge[1]]));
    } else {
      for (const auto& edge : kTetEdges) nodes.push_back(mid(v[edge[0]], v[edge[1]]));
    }
    out.add_element(linear.element_ids[static_cast<size_t>(e)],
                    hex ? ElementType::kC3D20 : ElementType::kC3D10, nodes);
  }
  return out;
}

// Blocks of quadratic elements: A of C3D20 (or, `tets_a`, C3D10), B of C3D20; the surfaces are
// every node on the contact plane (corners and mid-edge nodes).
Blocks quadratic_blocks(int ax, int ay, int bx, int by, bool tets_a = false) {
  Blocks s = blocks(ax, ay, bx, by);
  s.a = quadratic(tets_a ? tet_box(ax, ay, {1.0, 1.0, 0.2}) : s.a);
  s.b = quadratic(s.b);
  s.nodes_a = nodes_on_plane(s.a, {0, 0, 0.2}, {0, 0, 1}, 1e-9);
  s.nodes_b = nodes_on_plane(s.b, {0, 0, 0.2}, {0, 0, 1}, 1e-9);
  s.faces_a = faces_within(s.a, s.nodes_a);
  s.faces_b = faces_within(s.b, s.nodes_b);
  return s;
}

// Σ_j a_ij f(x_Aj): the point's own position in the field f.
double point_value(const MortarPoint& p, const Mesh& a,
                   const std::function<double(const Eigen::Vector3d&)>& f) {
  if (p.nodes_a.empty()) return f(a.coordinates.col(p.node_a));
  double s = 0;
  for (size_t j = 0; j < p.nodes_a.size(); ++j) s += p.weights_a[j] * f(a.coordinates.col(p.nodes_a[j]));
  return s;
}

// Quadratic faces (8-node quadrilaterals, 6-node triangles) pass the checks of linear ones: every
// area positive, the areas summing to the surface's; Σ_k Φ_ik = Σ_j a_ij = 1; every linear field
// f: Σ_k Φ_ik f(x_Bk) = Σ_j a_ij f(x_Aj) = f(x_Ai) (flat faces, straight edges); a uniform
// pressure on A reaches B as B's consistent nodal forces ∫ N_k dA (negative at the 8-node
// corners: −A/12) and A's as A's, Σ_i a_ij D_i = ∫ N_j dA (surface_area.h's own quadrature).
TEST(Mortar, QuadraticFacesPassThePatchTest) {
  struct Case {
    int ax, ay, bx, by;
    bool tets_a;
  };
  for (const Case m : {Case{2, 2, 3, 3, false}, Case{3, 2, 2, 5, false}, Case{2, 2, 3, 2, true}}) {
    SCOPED_TRACE(std::to_string(m.ax) + " x " + std::to_string(m.ay) +
                 (m.tets_a ? " (C3D10)" : "") + " against " + std::to_string(m.bx) + " x " +
                 std::to_string(m.by));
    const Blocks s = quadratic_blocks(m.ax, m.ay, m.bx, m.by, m.tets_a);
    ASSERT_EQ(s.faces_a.front().nodes.size(), m.tets_a ? 6u : 8u);
    ASSERT_EQ(s.faces_b.front().nodes.size(), 8u);
    const MortarCoupling c = mortar_coupling(s.a, s.faces_a, s.b, s.faces_b);
    ASSERT_TRUE(c.partial.empty());
    ASSERT_EQ(c.points.size(), s.nodes_a.size());
    const std::vector<std::pair<double, Eigen::Vector3d>> fields = {
        {1.0, {0, 0, 0}}, {0.0, {1, 0, 0}}, {0.0, {0, 1, 0}}, {0.3, {-0.7, 2.1, 0.4}}};
    double total = 0;
    std::map<int, double> to_a, to_b;
    for (const MortarPoint& p : c.points) {
      EXPECT_GT(p.area, 0.0) << p.node_a;
      total += p.area;
      EXPECT_NEAR(p.coverage, 1.0, 1e-12);
      double sum_b = 0, sum_a = 0;
      for (double w : p.weights_b) sum_b += w;
      for (double w : p.weights_a) sum_a += w;
      EXPECT_NEAR(sum_b, 1.0, 1e-12) << p.node_a;
      if (!p.weights_a.empty()) {
        EXPECT_NEAR(sum_a, 1.0, 1e-12) << p.node_a;
      }
      EXPECT_NEAR(p.gap, 0.0, 1e-14) << p.node_a;
      for (const auto& [f0, g] : fields) {
        auto f = [&](const Eigen::Vector3d& x) { return f0 + g.dot(x); };
        EXPECT_NEAR(weighted(p, s.b, f), f(s.a.coordinates.col(p.node_a)), 1e-12) << p.node_a;
        EXPECT_NEAR(point_value(p, s.a, f), f(s.a.coordinates.col(p.node_a)), 1e-12) << p.node_a;
      }
      for (size_t k = 0; k < p.nodes_b.size(); ++k) to_b[p.nodes_b[k]] += p.weights_b[k] * p.area;
      if (p.nodes_a.empty()) to_a[p.node_a] += p.area;
      for (size_t j = 0; j < p.nodes_a.size(); ++j) to_a[p.nodes_a[j]] += p.weights_a[j] * p.area;
    }
    EXPECT_NEAR(total, 1.0, 1e-14);
    const std::vector<double> area_a = nodal_areas(s.a, s.nodes_a, NodalAreaRule::kConsistent);
    const std::vector<double> area_b = nodal_areas(s.b, s.nodes_b, NodalAreaRule::kConsistent);
    for (size_t k = 0; k < s.nodes_a.size(); ++k) EXPECT_NEAR(to_a[s.nodes_a[k]], area_a[k], 1e-14);
    for (size_t k = 0; k < s.nodes_b.size(); ++k) EXPECT_NEAR(to_b[s.nodes_b[k]], area_b[k], 1e-14);
  }
}

// On an 8-node rectangle of area A the transformed basis gives corners A/20 and mid-edge nodes
// A/5 (mesh/mortar.h); on conforming quadratic meshes Φ_ik = a_ik.
TEST(Mortar, ConformingQuadraticFacesTieEachPointToItsOwnCombination) {
  const Blocks s = quadratic_blocks(2, 2, 2, 2);
  const MortarCoupling c = mortar_coupling(s.a, s.faces_a, s.b, s.faces_b);
  const double A = 0.25;  // each face
  std::map<int, int> coincident;  // A node -> B node
  for (int i : s.nodes_a)
    for (int k : s.nodes_b)
      if ((s.a.coordinates.col(i) - s.b.coordinates.col(k)).norm() < 1e-12) coincident[i] = k;
  for (const MortarPoint& p : c.points) {
    // Faces around the node: 4 inside, 2 on an edge, 1 at a corner of the surface (corners);
    // 2 or 1 (mid-edge nodes).
    ASSERT_FALSE(p.nodes_a.empty());
    std::map<int, double> b;
    for (size_t k = 0; k < p.nodes_b.size(); ++k) b[p.nodes_b[k]] = p.weights_b[k];
    for (size_t j = 0; j < p.nodes_a.size(); ++j) {
      EXPECT_NEAR(b[coincident.at(p.nodes_a[j])], p.weights_a[j], 1e-12) << p.node_a;
      b.erase(coincident.at(p.nodes_a[j]));
    }
    EXPECT_TRUE(b.empty()) << p.node_a;  // no round-off partners: dropped below 1e-14
    const double face_share = p.area / (p.nodes_a.size() == 1 ? A / 20 : A / 5);
    EXPECT_NEAR(face_share, std::round(face_share), 1e-12) << p.node_a;
  }
}

TEST(Mortar, EmptySurfacesAreRefused) {
  const Blocks s = blocks(2, 2, 2, 2);
  EXPECT_THROW(mortar_coupling(s.a, {}, s.b, s.faces_b), InvalidInput);
  EXPECT_THROW(mortar_coupling(s.a, s.faces_a, s.b, {}), InvalidInput);
}

// Node-to-surface coupling (node_to_surface_coupling): each A node projected on B's faces, the
// weights B's shape functions there. On conforming meshes it is node-to-node; on non-matching
// (and distorted) faces it reproduces every linear field exactly (the isoparametric map does:
// Σ N_k x_Bk is the projection), yet a uniform pressure does not reach B as its consistent nodal
// forces (the patch test that only mortar passes, by 7-45 % here as in issue 23's measurements).
TEST(NodeToSurface, ConformingMeshesGiveNodeToNodeWithMortarsAreas) {
  const Blocks s = blocks(3, 4, 3, 4);
  const MortarCoupling c = node_to_surface_coupling(s.a, s.faces_a, s.b, s.faces_b);
  ASSERT_EQ(c.points.size(), s.nodes_a.size());
  EXPECT_TRUE(c.partial.empty());
  const std::vector<double> area = nodal_areas(s.a, s.nodes_a, NodalAreaRule::kConsistent);
  for (size_t i = 0; i < c.points.size(); ++i) {
    const MortarPoint& p = c.points[i];
    EXPECT_NEAR(p.area, area[i], 1e-14);
    ASSERT_EQ(p.nodes_b.size(), 1u) << "A node " << p.node_a;  // the others' round-off dropped
    EXPECT_NEAR((s.b.coordinates.col(p.nodes_b[0]) - s.a.coordinates.col(p.node_a)).norm(), 0, 1e-12);
    EXPECT_NEAR(p.weights_b[0], 1.0, 1e-12);
    EXPECT_NEAR(p.gap, 0, 1e-14);
    EXPECT_EQ(p.faces_b.size(), 1u);
  }
}

TEST(NodeToSurface, NonMatchingAndDistortedFacesReproduceEveryLinearField) {
  for (const auto& [bx, by] : {std::pair{4, 5}, std::pair{7, 2}}) {
    SCOPED_TRACE(std::to_string(bx) + " x " + std::to_string(by));
    Blocks s = blocks(3, 3, bx, by);
    expect_linear_fields_reproduced(s, node_to_surface_coupling(s.a, s.faces_a, s.b, s.faces_b));
    distort_b(s, 0.05, 11);
    expect_linear_fields_reproduced(s, node_to_surface_coupling(s.a, s.faces_a, s.b, s.faces_b));
  }
}

TEST(NodeToSurface, FailsThePatchTestThatMortarPasses) {
  const Blocks s = blocks(2, 2, 3, 3);
  const MortarCoupling c = node_to_surface_coupling(s.a, s.faces_a, s.b, s.faces_b);
  std::map<int, double> delivered;
  for (const MortarPoint& p : c.points)
    for (size_t k = 0; k < p.nodes_b.size(); ++k) delivered[p.nodes_b[k]] += p.weights_b[k] * p.area;
  const std::vector<double> area_b = nodal_areas(s.b, s.nodes_b, NodalAreaRule::kConsistent);
  double worst = 0;
  for (size_t k = 0; k < s.nodes_b.size(); ++k)
    worst = std::max(worst, std::abs(delivered[s.nodes_b[k]] - area_b[k]) / area_b[k]);
  // 2 x 2 against 3 x 3: B's nodes get shares of A's nodal areas by A's projections, not their
  // own areas: at a corner A's corner node (area 1/16) lands wholly on B's (area 1/36), +125 %.
  std::printf("[ measured ] node-to-surface, 2 x 2 on 3 x 3: largest error of B's nodal areas %.3f\n",
              worst);
  EXPECT_GT(worst, 0.05);
}

TEST(NodeToSurface, GapIsTheDistanceAlongTheNormalAndFarNodesAreReported) {
  for (double gap : {1e-3, -2e-3}) {
    const Blocks s = blocks(3, 3, 4, 5, gap);
    const MortarCoupling c = node_to_surface_coupling(s.a, s.faces_a, s.b, s.faces_b);
    ASSERT_TRUE(c.partial.empty());
    for (const MortarPoint& p : c.points) EXPECT_NEAR(p.gap, gap, 1e-14) << p.node_a;
  }
  // B covers x in [0, 0.5]: A's nodes at x = 2/3 and 1 project onto nothing.
  const Blocks half = blocks(3, 3, 2, 3, 0.0, 0.5);
  const MortarCoupling c = node_to_surface_coupling(half.a, half.faces_a, half.b, half.faces_b);
  int outside = 0;
  for (const MortarPoint& p : c.points) {
    const bool out = half.a.coordinates(0, p.node_a) > 0.5 + 1e-9;
    outside += out;
    EXPECT_EQ(p.coverage, out ? 0.0 : 1.0) << p.node_a;
    EXPECT_EQ(std::isnan(p.gap), out) << p.node_a;
  }
  EXPECT_EQ(static_cast<int>(c.partial.size()), outside);
  EXPECT_EQ(outside, 8);
}

// A curved quadratic surface: B's 8-node faces on z = 0.2 + c x² (serendipity faces hold x²
// exactly, so the surface is that parabola). Each A node (x, y, 0.2) projects along z at the gap
// c x² (closed form), and the weights give the projected point's position and any linear field
// there.
TEST(NodeToSurface, CurvedQuadraticFacesGiveTheGapOfTheirSurface) {
  constexpr double c = 0.05;
  Blocks s = quadratic_blocks(2, 2, 3, 3);
  for (int node : s.nodes_b) {
    auto x = s.b.coordinates.col(node);
    x.z() += c * x.x() * x.x();
  }
  const MortarCoupling cp = node_to_surface_coupling(s.a, s.faces_a, s.b, s.faces_b);
  ASSERT_TRUE(cp.partial.empty());
  for (const MortarPoint& p : cp.points) {
    const Eigen::Vector3d xa = s.a.coordinates.col(p.node_a);
    EXPECT_TRUE(p.nodes_a.empty());  // the point is the node itself
    EXPECT_NEAR(p.gap, c * xa.x() * xa.x(), 1e-12) << p.node_a;
    const Eigen::Vector3d target(xa.x(), xa.y(), 0.2 + c * xa.x() * xa.x());
    for (int d = 0; d < 3; ++d) {
      auto coordinate = [d](const Eigen::Vector3d& x) { return x(d); };
      EXPECT_NEAR(weighted(p, s.b, coordinate), target(d), 1e-12) << p.node_a << " axis " << d;
    }
  }
}

}  // namespace
}  // namespace stickslip
