#include "mesh/mesh_tools.h"

#include <gtest/gtest.h>

#include "core/errors.h"

namespace stickslip {
namespace {

// A row of n unit cubes (C3D8) along x: nodes on the grid x = 0..n, y, z in {0, 1}. Node ids
// 100 + index, element ids 10 + index. Element set LEFT = first half, RIGHT = second half.
Mesh cube_row(int n, double x0 = 0.0) {
  Mesh m;
  for (int i = 0; i <= n; ++i) {
    for (int k = 0; k < 4; ++k) {
      const double y = (k == 1 || k == 2) ? 1.0 : 0.0;
      const double z = k >= 2 ? 1.0 : 0.0;
      m.add_node(100 + m.num_nodes(), {x0 + i, y, z});
    }
  }
  // node index of (i, corner k) with k: 0 (y0 z0), 1 (y1 z0), 2 (y1 z1), 3 (y0 z1)
  auto at = [](int i, int k) { return 4 * i + k; };
  for (int i = 0; i < n; ++i) {
    // CalculiX order: bottom face (z = 0) counter-clockwise seen from +z, then top face.
    const int nodes[8] = {at(i, 0), at(i + 1, 0), at(i + 1, 1), at(i, 1),
                          at(i, 3), at(i + 1, 3), at(i + 1, 2), at(i, 2)};
    m.add_element(10 + i, ElementType::kC3D8, nodes);
    m.element_sets[i < n / 2 ? "LEFT" : "RIGHT"].push_back(i);
  }
  m.node_sets["X0"] = {0, 1, 2, 3};
  return m;
}

TEST(ExtractSubmesh, KeepsIdsRestrictsSetsAndMapsBack) {
  const Mesh m = cube_row(4);
  const SubMesh sub = extract_element_set(m, "RIGHT");
  EXPECT_EQ(sub.mesh.num_elements(), 2);
  EXPECT_EQ(sub.mesh.num_nodes(), 12);  // 3 node layers x 4
  EXPECT_NO_THROW(check_mesh(sub.mesh));
  ASSERT_EQ(static_cast<int>(sub.node_parent.size()), 12);
  for (int i = 0; i < sub.mesh.num_nodes(); ++i) {
    const int p = sub.node_parent[i];
    EXPECT_EQ(sub.mesh.node_ids[i], m.node_ids[p]);
    EXPECT_EQ(sub.mesh.coordinates.col(i), m.coordinates.col(p));
  }
  for (int e = 0; e < sub.mesh.num_elements(); ++e) {
    const int p = sub.element_parent[e];
    EXPECT_EQ(sub.mesh.element_ids[e], m.element_ids[p]);
    const auto a = sub.mesh.element_nodes(e);
    const auto b = m.element_nodes(p);
    for (size_t k = 0; k < a.size(); ++k) EXPECT_EQ(sub.node_parent[a[k]], b[k]);
  }
  EXPECT_EQ(sub.mesh.element_sets.count("LEFT"), 0u);  // empty after restriction: dropped
  EXPECT_EQ(sub.mesh.element_sets.at("RIGHT"), (std::vector<int>{0, 1}));
  EXPECT_EQ(sub.mesh.node_sets.count("X0"), 0u);
  EXPECT_THROW(extract_element_set(m, "MISSING"), InvalidInput);
}

TEST(SelectNodes, PlaneAndBox) {
  const Mesh m = cube_row(3);
  const auto plane = nodes_on_plane(m, {2.0, 0, 0}, {2.0, 0, 0}, 1e-12);
  EXPECT_EQ(plane, (std::vector<int>{8, 9, 10, 11}));
  const auto top = nodes_on_plane(m, {0, 0, 1}, {0, 0, 1}, 1e-12);
  EXPECT_EQ(top.size(), 8u);
  for (int n : top) EXPECT_EQ(m.coordinates(2, n), 1.0);
  const auto box = nodes_in_box(m, {0.5, -1, -1}, {1.5, 2, 0.5}, 1e-12);
  EXPECT_EQ(box, (std::vector<int>{4, 5}));
  const auto some = select_nodes(m, std::vector<int>{11, 0, 5},
                                 [](const Eigen::Vector3d& x) { return x.y() > 0.5; });
  EXPECT_EQ(some, (std::vector<int>{5}));
}

TEST(MatchCoincidentNodes, PairsEveryNodeOfAWithExactlyOneOfB) {
  const Mesh a = cube_row(2);
  Mesh b = cube_row(2, 2.0);       // starts where a ends: a's x = 2 face meets b's x = 0 face
  b.coordinates.array() += 1e-10;  // within tolerance
  const auto a_face = nodes_on_plane(a, {2, 0, 0}, {1, 0, 0}, 1e-9);
  const auto b_face = nodes_on_plane(b, {2, 0, 0}, {1, 0, 0}, 1e-9);
  // Reverse B's order to make sure the pairing is by position, not by order.
  const std::vector<int> b_rev(b_face.rbegin(), b_face.rend());
  const auto pairs = match_coincident_nodes(a, a_face, b, b_rev, 1e-9);
  ASSERT_EQ(pairs.size(), 4u);
  for (const auto& [i, j] : pairs) {
    EXPECT_LT((a.coordinates.col(i) - b.coordinates.col(j)).norm(), 1e-9);
  }
  // A node of A without a partner.
  std::vector<int> a_more = a_face;
  a_more.push_back(0);
  EXPECT_THROW(match_coincident_nodes(a, a_more, b, b_face, 1e-9), InvalidInput);
  // Two candidates within the tolerance (the tolerance spans a whole element).
  const std::vector<int> all_b = nodes_of_elements(b, std::vector<int>{0, 1});
  EXPECT_THROW(match_coincident_nodes(a, a_face, b, all_b, 1.5), InvalidInput);
  // Two nodes of A sharing one of B.
  Mesh twin = a;
  twin.coordinates.col(a_face[1]) = twin.coordinates.col(a_face[0]);
  EXPECT_THROW(match_coincident_nodes(twin, a_face, b, b_face, 1e-9), InvalidInput);
}

TEST(NearestNode, FindsTheClosestAndRejectsFarOnes) {
  const Mesh m = cube_row(3);
  EXPECT_EQ(nearest_node(m, {2.1, 0.9, 0.05}), 9);
  EXPECT_EQ(nearest_node(m, std::vector<int>{0, 1, 2, 3}, {2.1, 0.9, 0.05}), 1);
  EXPECT_EQ(nearest_node(m, {2.1, 0.9, 0.05}, 0.2), 9);
  EXPECT_THROW(nearest_node(m, {2.5, 0.5, 0.5}, 0.1), InvalidInput);
  EXPECT_THROW(nearest_node(m, std::vector<int>{}, {0, 0, 0}), InvalidInput);
}

TEST(FindSet, NamesTheMissingSetAndTheKnownOnes) {
  const Mesh m = cube_row(2);
  EXPECT_EQ(find_node_set(m, "X0").size(), 4u);
  EXPECT_EQ(find_element_set(m, "LEFT"), std::vector<int>{0});
  try {
    find_element_set(m, "MIDDLE");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("'MIDDLE'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("known: LEFT, RIGHT"), std::string::npos) << e.what();
  }
}

TEST(AppendMesh, ShiftsIdsAndIndicesAndMergesSets) {
  Mesh m = cube_row(2);
  const Mesh part = cube_row(1, 5.0);
  const AppendedRange r = append_mesh(m, part, 1000, 1000);
  EXPECT_EQ(r.first_node, 12);
  EXPECT_EQ(r.first_element, 2);
  EXPECT_EQ(m.num_nodes(), 20);
  EXPECT_EQ(m.num_elements(), 3);
  EXPECT_EQ(m.node_ids[12], 1100);
  EXPECT_EQ(m.element_ids[2], 1010);
  EXPECT_EQ(m.element_nodes(2)[0], 12);
  EXPECT_EQ(m.node_sets.at("X0"), (std::vector<int>{0, 1, 2, 3, 12, 13, 14, 15}));
  Mesh clash = cube_row(1);
  EXPECT_THROW(append_mesh(clash, cube_row(1)), InvalidInput);  // same ids
}

TEST(StructuredHexBox, CountsCoordinatesAndCalculixNodeOrder) {
  const Mesh m = structured_hex_box(3, 2, 4, Eigen::Vector3d(0.3, 0.2, 0.4), ElementType::kC3D8I);
  EXPECT_NO_THROW(check_mesh(m));
  EXPECT_EQ(m.num_nodes(), 4 * 3 * 5);
  EXPECT_EQ(m.num_elements(), 3 * 2 * 4);
  EXPECT_TRUE(m.coordinates.col(m.num_nodes() - 1).isApprox(Eigen::Vector3d(0.3, 0.2, 0.4)));
  // Every element: its first four nodes are the bottom face counter-clockwise seen from +z,
  // the last four the same face one layer up (CalculiX's order), with edges of 0.1 m.
  for (int e = 0; e < m.num_elements(); ++e) {
    const auto n = m.element_nodes(e);
    const Eigen::Vector3d x0 = m.coordinates.col(n[0]);
    EXPECT_TRUE((m.coordinates.col(n[1]) - x0).isApprox(Eigen::Vector3d(0.1, 0, 0)));
    EXPECT_TRUE((m.coordinates.col(n[3]) - x0).isApprox(Eigen::Vector3d(0, 0.1, 0)));
    for (int a = 0; a < 4; ++a) {
      EXPECT_TRUE((m.coordinates.col(n[a + 4]) - m.coordinates.col(n[a]))
                      .isApprox(Eigen::Vector3d(0, 0, 0.1)));
    }
  }
  EXPECT_THROW(structured_hex_box(0, 1, 1, Eigen::Vector3d::Ones(), ElementType::kC3D8),
               InvalidInput);
  EXPECT_THROW(structured_hex_box(1, 1, 1, Eigen::Vector3d::Ones(), ElementType::kC3D10),
               InvalidInput);
}

}  // namespace
}  // namespace stickslip
