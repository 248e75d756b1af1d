#include "io/two_beam_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>

#include "core/errors.h"
#include "io/gmsh_mesh.h"
#include "io/gmsh_plugin.h"
#include "mesh/mesh_tools.h"

namespace stickslip {
namespace {

// Geometric tolerance relative to the model size: coordinates come from Gmsh's transfinite
// interpolation, exact to a few ulps; 1e-9 of the size is far below any element size.
constexpr double kRelativeGeometryTolerance = 1e-9;

using Box = GmshBox;

bool is_quadratic(ElementType t) { return t == ElementType::kC3D20 || t == ElementType::kC3D20R; }

// Meshes one beam (its boxes, in global coordinates) in a fresh Gmsh model (of the caller's
// GmshSession) and converts it.
Mesh mesh_beam(const std::vector<Box>& boxes, const TwoBeamOptions& o, double tolerance,
               const std::string& name) {
  const std::string source = "two-beam model (" + name + ")";
  GmshReadOptions read;
  if (is_quadratic(o.element_type)) {
    read.hexahedron20 = o.element_type;
  } else {
    read.hexahedron8 = o.element_type;
  }
  Mesh mesh = gmsh_plugin(source).mesh_boxes(boxes, is_quadratic(o.element_type), tolerance, name,
                                             source, read);
  // Renumber 1..n in index order.
  for (int i = 0; i < mesh.num_nodes(); ++i) mesh.node_ids[i] = i + 1;
  for (int e = 0; e < mesh.num_elements(); ++e) mesh.element_ids[e] = e + 1;
  mesh.node_sets.clear();
  mesh.element_sets.clear();
  return mesh;
}

std::string str(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

int node_at(const Mesh& mesh, const Eigen::Vector3d& x, double tolerance, const char* what) {
  const std::vector<int> found = nodes_in_box(mesh, x, x, tolerance);
  STICKSLIP_VERIFY(found.size() == 1, std::string("two-beam model: no unique node for ") + what);
  return found[0];
}

}  // namespace

void validate(const TwoBeamOptions& o) {
  auto positive = [](double v, const char* field) {
    require(std::isfinite(v) && v > 0.0, std::string("TwoBeamOptions::") + field, str(v),
            "must be a positive length in m");
  };
  positive(o.beam_length, "beam_length");
  positive(o.width, "width");
  positive(o.thickness, "thickness");
  positive(o.end_length, "end_length");
  require(o.element_type == ElementType::kC3D8 || o.element_type == ElementType::kC3D8I ||
              o.element_type == ElementType::kC3D20 || o.element_type == ElementType::kC3D20R,
          "TwoBeamOptions::element_type", element_type_name(o.element_type),
          "must be a hexahedron (C3D8, C3D8I, C3D20, C3D20R)");
  if (o.thesis_coarse) return;
  constexpr int kMaxDivisions = 10000;
  auto count = [&](int v, const std::string& field) {
    require(v >= 1 && v <= kMaxDivisions, "TwoBeamOptions::" + field, std::to_string(v),
            "must be in 1.." + std::to_string(kMaxDivisions));
  };
  const auto check = [&](const BlockDivisions& box, const BlockDivisions& end_block,
                         const std::string& prefix) {
    count(box.x, (prefix + "box.x").c_str());
    count(box.y, (prefix + "box.y").c_str());
    count(box.z, (prefix + "box.z").c_str());
    count(end_block.x, (prefix + "end_block.x").c_str());
    count(end_block.y, (prefix + "end_block.y").c_str());
    count(end_block.z, (prefix + "end_block.z").c_str());
    require(
        end_block.y == box.y, "TwoBeamOptions::" + prefix + "end_block.y",
        std::to_string(end_block.y),
        "must equal " + prefix + "box.y = " + std::to_string(box.y) + " (conforming interface)");
    require(end_block.z < box.z, "TwoBeamOptions::" + prefix + "end_block.z",
            std::to_string(end_block.z),
            "must be less than " + prefix + "box.z = " + std::to_string(box.z) +
                " (end_block.z layers of the large box lie below mid-thickness, the rest above)");
  };
  check(o.box, o.end_block, "");
  if (o.beam2_box || o.beam2_end_block)
    check(o.beam2_box.value_or(o.box), o.beam2_end_block.value_or(o.end_block), "beam2_");
}

TwoBeamModel make_two_beam_model(const TwoBeamOptions& o) {
  validate(o);
  const double L = o.beam_length, W = o.width, T = o.thickness, e = o.end_length;
  const bool butt = o.arrangement == TwoBeamOptions::Arrangement::kButt;
  const double tolerance = kRelativeGeometryTolerance * std::max({L, W, T, e});

  // Each beam's boxes in beam 1's place; beam 2's are their images under the arrangement's map.
  const auto boxes = [&](const BlockDivisions& box, const BlockDivisions& end_block) {
    std::vector<Box> beam;
    if (o.thesis_coarse) {
      beam.push_back({{0, 0, 0}, {L, W, T}, {7, 5, 1}});
      beam.push_back({{L, 0, 0}, {L + e, W, T / 2}, {4, 5, 4}});
    } else {
      const int below = end_block.z, above = box.z - end_block.z;
      beam.push_back({{0, 0, 0}, {L, W, T / 2}, {box.x, box.y, below}});
      beam.push_back({{0, 0, T / 2}, {L, W, T}, {box.x, box.y, above}});
      beam.push_back({{L, 0, 0}, {L + e, W, T / 2}, {end_block.x, box.y, below}});
    }
    return beam;
  };
  const std::vector<Box> beam1 = boxes(o.box, o.end_block);
  auto image = [&](const Eigen::Vector3d& x) -> Eigen::Vector3d {
    if (butt) return {2 * (L + e) - x.x(), x.y(), x.z()};
    return {2 * L + e - x.x(), x.y(), T - x.z()};
  };
  std::vector<Box> beam2;
  for (const Box& b : boxes(o.beam2_box.value_or(o.box), o.beam2_end_block.value_or(o.end_block))) {
    const Eigen::Vector3d a = image(b.lower), c = image(b.upper);
    beam2.push_back({a.cwiseMin(c), a.cwiseMax(c), b.divisions});
  }
  // The contact faces match node for node when beam 2's divisions of them are beam 1's.
  const BlockDivisions b2 = o.beam2_box.value_or(o.box),
                       e2 = o.beam2_end_block.value_or(o.end_block);
  const bool matching = o.thesis_coarse ||
                        (b2.y == o.box.y && (butt ? e2.z == o.end_block.z : e2.x == o.end_block.x));

  Mesh m1, m2;
  {
    GmshSession session;
    m1 = mesh_beam(beam1, o, tolerance, "BEAM1");
    m2 = mesh_beam(beam2, o, tolerance, "BEAM2");
  }

  // Sets of each beam, in its own indices.
  const double x_far2 = butt ? 2 * L + 2 * e : 2 * L + e;
  std::vector<int> contact1, contact2;
  if (butt) {
    contact1 = nodes_on_plane(m1, {L + e, 0, 0}, Eigen::Vector3d::UnitX(), tolerance);
    contact2 = nodes_on_plane(m2, {L + e, 0, 0}, Eigen::Vector3d::UnitX(), tolerance);
  } else {
    contact1 = nodes_in_box(m1, {L, 0, T / 2}, {L + e, W, T / 2}, tolerance);
    contact2 = nodes_in_box(m2, {L, 0, T / 2}, {L + e, W, T / 2}, tolerance);
  }
  STICKSLIP_VERIFY(
      !contact1.empty() && !contact2.empty() && (!matching || contact1.size() == contact2.size()),
      "two-beam model: contact faces do not match");
  std::vector<std::pair<int, int>> pairs;
  if (matching) pairs = match_coincident_nodes(m1, contact1, m2, contact2, tolerance);

  const Eigen::Vector3d force1(L, 0, T);
  const int f1 = node_at(m1, force1, tolerance, "FORCE1");
  const int f2 = node_at(m2, image(force1), tolerance, "FORCE2");

  auto all = [](int n) {
    std::vector<int> v(n);
    for (int i = 0; i < n; ++i) v[i] = i;
    return v;
  };
  m1.node_sets["BEAM1"] = all(m1.num_nodes());
  m1.element_sets["BEAM1"] = all(m1.num_elements());
  m1.node_sets["CLAMP1"] = nodes_on_plane(m1, {0, 0, 0}, Eigen::Vector3d::UnitX(), tolerance);
  m1.node_sets["CONTACT1"] = contact1;
  m1.node_sets["FORCE1"] = {f1};
  m2.node_sets["BEAM2"] = all(m2.num_nodes());
  m2.element_sets["BEAM2"] = all(m2.num_elements());
  m2.node_sets["CLAMP2"] = nodes_on_plane(m2, {x_far2, 0, 0}, Eigen::Vector3d::UnitX(), tolerance);
  m2.node_sets["CONTACT2"] = contact2;
  m2.node_sets["FORCE2"] = {f2};

  TwoBeamModel model;
  model.mesh = std::move(m1);
  const AppendedRange r =
      append_mesh(model.mesh, m2, model.mesh.num_nodes(), model.mesh.num_elements());
  for (const auto& [a, b] : pairs) model.contact_pairs.emplace_back(a, b + r.first_node);
  std::sort(model.contact_pairs.begin(), model.contact_pairs.end());
  model.contact_normal = butt ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ();
  model.force_node_1 = f1;
  model.force_node_2 = f2 + r.first_node;
  return model;
}

}  // namespace stickslip
