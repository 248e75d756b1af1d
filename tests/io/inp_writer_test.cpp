#include "io/inp_writer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <unistd.h>

#include "core/errors.h"
#include "fe/element.h"
#include "io/inp_reader.h"

namespace stickslip {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("stickslip_inp_writer_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

// A mesh with every element type, non-contiguous ids and coordinates that need all 17 digits.
// Each element is its reference element scaled by (1, 1e-3, 1e5), shifted and perturbed by 1 % of
// that scale: valid geometry (the reader refuses elements that cannot be integrated).
Mesh mixed_mesh() {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Vector3d scale(1.0, 1e-3, 1e5);
  Mesh m;
  int node_id = 1000, id = 5;
  double shift = 0.0;
  for (ElementType t : {ElementType::kC3D20R, ElementType::kC3D8, ElementType::kC3D4,
                        ElementType::kC3D10, ElementType::kC3D8I, ElementType::kC3D20}) {
    const Eigen::Matrix3Xd P = natural_node_coordinates(t);
    std::vector<int> nodes;
    for (Eigen::Index a = 0; a < P.cols(); ++a) {
      const Eigen::Vector3d jitter(u(rng), u(rng), u(rng));
      const Eigen::Vector3d x = (P.col(a) + 0.01 * jitter).cwiseProduct(scale) +
                                Eigen::Vector3d(shift, 0.0, 0.0);
      nodes.push_back(m.add_node(node_id, x));
      node_id -= 7;
    }
    m.add_element(id, t, nodes);
    id += 3;
    shift += 3.0;
  }
  m.node_sets["FIRST"] = {0, 1, 2};
  for (int i = 0; i < 40; i += 2) m.node_sets["MANY"].push_back(i);  // > 16: several lines
  m.element_sets["SOME"] = {1, 4};
  // 5 terms: two lines of *EQUATION data.
  m.equations.push_back({{3 * 2 + 1, 3 * 5, 3 * 7 + 2, 3 * 9 + 1, 3 * 11 + 2},
                         {1.0, -0.25, -0.25, -0.25, -0.12345678901234568},
                         ""});
  return m;
}

TEST(InpWriter, RoundTripReproducesTheMeshToThirteenDigitsInTwentyCharacterFields) {
  const Mesh m = mixed_mesh();
  const std::string path = temp_path("round_trip.inp");
  write_inp(path, m);
  const Mesh r = read_inp(path);
  std::filesystem::remove(path);

  EXPECT_EQ(r.node_ids, m.node_ids);
  // CalculiX reads 20 characters a number: coordinates are exact when their shortest text fits,
  // else rounded to 13 or more significant digits (relative error <= 5e-13).
  ASSERT_EQ(r.coordinates.cols(), m.coordinates.cols());
  int exact = 0;
  for (Eigen::Index i = 0; i < m.coordinates.size(); ++i) {
    const double a = m.coordinates.data()[i], b = r.coordinates.data()[i];
    EXPECT_LE(std::abs(a - b), 5e-13 * std::abs(a));
    exact += a == b;
  }
  EXPECT_GT(exact, 0);
  ASSERT_EQ(r.equations.size(), 1u);
  EXPECT_EQ(r.equations[0].dofs, m.equations[0].dofs);
  for (size_t k = 0; k < 5; ++k) {
    EXPECT_NEAR(r.equations[0].coefficients[k], m.equations[0].coefficients[k], 5e-13);
  }
  // Every field of the file fits 20 characters.
  write_inp(path, m);
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("**", 0) == 0) continue;
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) EXPECT_LE(field.size(), 21u) << line;  // + a blank
  }
  std::filesystem::remove(path);
  ASSERT_EQ(r.num_elements(), m.num_elements());
  // Elements come back grouped by type; compare by id.
  for (int e = 0; e < m.num_elements(); ++e) {
    const auto it = std::find(r.element_ids.begin(), r.element_ids.end(), m.element_ids[e]);
    ASSERT_NE(it, r.element_ids.end());
    const int re = static_cast<int>(it - r.element_ids.begin());
    EXPECT_EQ(r.element_types[re], m.element_types[e]);
    const auto a = m.element_nodes(e);
    const auto b = r.element_nodes(re);
    EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end()));
    // Sets refer to ids: translate.
    for (const auto& [name, set] : m.element_sets) {
      const bool in_m = std::binary_search(set.begin(), set.end(), e);
      const auto& rs = r.element_sets.at(name);
      EXPECT_EQ(in_m, std::binary_search(rs.begin(), rs.end(), re)) << name;
    }
  }
  EXPECT_EQ(r.node_sets, m.node_sets);  // node order is preserved, so indices agree
}

TEST(InpWriter, SpringsAndPointMassesRoundTrip) {
  Mesh m;
  m.add_node(1, {0, 0, 0});
  m.add_node(2, {1, 0, 0});
  m.add_node(3, {0, 1, 0});
  m.add_node(4, {0, 0, 1});
  m.add_element(1, ElementType::kC3D4, std::vector<int>{0, 1, 2, 3});
  DiscreteSpring ground{7, 3, -1, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), 1e3, ""};
  DiscreteSpring pair{8, 0, 1, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 2e3, ""};
  const Eigen::Vector3d axis = Eigen::Vector3d(-1, 1, 0).normalized();
  DiscreteSpring axial{9, 1, 2, axis, axis, 3e3, ""};
  m.springs = {ground, pair, axial};
  m.point_masses = {{10, 2, 4.0, ""}, {11, 3, 5.5, ""}};
  const std::string path = temp_path("springs.inp");
  write_inp(path, m);
  const Mesh r = read_inp(path);
  std::filesystem::remove(path);
  ASSERT_EQ(r.springs.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(r.springs[i].id, m.springs[i].id);
    EXPECT_EQ(r.springs[i].node_a, m.springs[i].node_a);
    EXPECT_EQ(r.springs[i].node_b, m.springs[i].node_b);
    EXPECT_EQ(r.springs[i].stiffness, m.springs[i].stiffness);
    EXPECT_LT((r.springs[i].direction_a - m.springs[i].direction_a).norm(), 1e-15);
    if (m.springs[i].node_b >= 0) {
      EXPECT_LT((r.springs[i].direction_b - m.springs[i].direction_b).norm(), 1e-15);
    }
  }
  ASSERT_EQ(r.point_masses.size(), 2u);
  EXPECT_EQ(r.point_masses[1].node, 3);
  EXPECT_EQ(r.point_masses[1].mass, 5.5);
}

TEST(InpWriter, LinesHoldAtMostSixteenEntries) {
  const Mesh m = mixed_mesh();
  std::ostringstream out;
  write_inp(out, m);
  std::istringstream in(out.str());
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '*') continue;
    const auto commas = std::count(line.begin(), line.end(), ',');
    const bool continued = line.back() == ',';
    EXPECT_LE(commas + (continued ? 0 : 1), 16) << line;
  }
}

TEST(InpWriter, RejectsSetNamesThatCannotBeWritten) {
  Mesh m = mixed_mesh();
  m.node_sets["A,B"] = {0};
  std::ostringstream out;
  EXPECT_THROW(write_inp(out, m), InvalidInput);
}

}  // namespace
}  // namespace stickslip
