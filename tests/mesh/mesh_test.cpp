#include "mesh/mesh.h"

#include <gtest/gtest.h>

#include "core/errors.h"

namespace stickslip {
namespace {

Mesh two_tets() {
  Mesh m;
  m.add_node(10, {0, 0, 0});
  m.add_node(11, {1, 0, 0});
  m.add_node(12, {0, 1, 0});
  m.add_node(13, {0, 0, 1});
  m.add_node(14, {1, 1, 1});
  const int a[] = {0, 1, 2, 3};
  const int b[] = {1, 2, 3, 4};
  m.add_element(1, ElementType::kC3D4, a);
  m.add_element(2, ElementType::kC3D4, b);
  return m;
}

TEST(Mesh, AddsNodesAndElementsWithIds) {
  const Mesh m = two_tets();
  EXPECT_EQ(m.num_nodes(), 5);
  EXPECT_EQ(m.num_elements(), 2);
  EXPECT_EQ(m.num_dofs(), 15);
  EXPECT_EQ(m.element_nodes(1)[3], 4);
  EXPECT_EQ(node_index_by_id(m).at(13), 3);
  EXPECT_NO_THROW(check_mesh(m));
}

TEST(Mesh, CheckRejectsDuplicateIdsAndBadSets) {
  Mesh m = two_tets();
  m.node_ids[4] = 10;
  EXPECT_THROW(check_mesh(m), InvalidInput);
  m = two_tets();
  m.node_sets["bad"] = {7};
  EXPECT_THROW(check_mesh(m), InvalidInput);
}

TEST(ElementType, NamesRoundTrip) {
  for (ElementType t : {ElementType::kC3D8, ElementType::kC3D8I, ElementType::kC3D20,
                        ElementType::kC3D20R, ElementType::kC3D4, ElementType::kC3D10}) {
    ElementType back;
    ASSERT_TRUE(parse_element_type(element_type_name(t), &back));
    EXPECT_EQ(back, t);
  }
  ElementType t;
  EXPECT_TRUE(parse_element_type("c3d20r", &t));
  EXPECT_EQ(t, ElementType::kC3D20R);
  EXPECT_FALSE(parse_element_type("S4R", &t));
}

}  // namespace
}  // namespace stickslip
