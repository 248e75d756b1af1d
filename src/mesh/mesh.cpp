#include "mesh/mesh.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <unordered_set>

#include "core/errors.h"

namespace stickslip {

namespace {
// A spring's direction must be a unit vector to 1e-12: the readers normalise what they read, so
// only round-off of that (≈ eps) is accepted; a direction given unnormalised is a caller's error.
constexpr double kUnitLengthTolerance = 1e-12;
}  // namespace

int nodes_per_element(ElementType type) {
  switch (type) {
    case ElementType::kC3D8:
    case ElementType::kC3D8I:
    case ElementType::kC3D8B:
    case ElementType::kC3D8R:
      return 8;
    case ElementType::kC3D20:
    case ElementType::kC3D20R:
      return 20;
    case ElementType::kC3D4:
      return 4;
    case ElementType::kC3D10:
      return 10;
    case ElementType::kC3D5:
      return 5;
    case ElementType::kC3D13:
      return 13;
    case ElementType::kC3D6:
      return 6;
    case ElementType::kC3D15:
      return 15;
  }
  return 0;
}

const char* element_type_name(ElementType type) {
  switch (type) {
    case ElementType::kC3D8: return "C3D8";
    case ElementType::kC3D8I: return "C3D8I";
    case ElementType::kC3D20: return "C3D20";
    case ElementType::kC3D20R: return "C3D20R";
    case ElementType::kC3D4: return "C3D4";
    case ElementType::kC3D10: return "C3D10";
    case ElementType::kC3D8B:
      return "C3D8B";
    case ElementType::kC3D5: return "C3D5";
    case ElementType::kC3D6: return "C3D6";
    case ElementType::kC3D15: return "C3D15";
    case ElementType::kC3D13:
      return "C3D13";
    case ElementType::kC3D8R:
      return "C3D8R";
  }
  return "?";
}

bool parse_element_type(const std::string& name, ElementType* type) {
  std::string u(name);
  std::transform(u.begin(), u.end(), u.begin(), [](unsigned char c) { return std::toupper(c); });
  static const std::pair<const char*, ElementType> kTable[] = {
      {"C3D8", ElementType::kC3D8},   {"C3D8I", ElementType::kC3D8I},
      {"C3D20", ElementType::kC3D20}, {"C3D20R", ElementType::kC3D20R},
      {"C3D4", ElementType::kC3D4},   {"C3D10", ElementType::kC3D10},
      {"C3D8B", ElementType::kC3D8B}, {"C3D6", ElementType::kC3D6},
      {"C3D15", ElementType::kC3D15}, {"C3D5", ElementType::kC3D5},
      {"C3D13", ElementType::kC3D13}, {"C3D8R", ElementType::kC3D8R}};
  for (const auto& [n, t] : kTable) {
    if (u == n) {
      *type = t;
      return true;
    }
  }
  return false;
}

int Mesh::add_node(int id, const Eigen::Vector3d& x) {
  const int index = num_nodes();
  coordinates.conservativeResize(3, index + 1);
  coordinates.col(index) = x;
  node_ids.push_back(id);
  return index;
}

int Mesh::add_element(int id, ElementType type, std::span<const int> nodes) {
  STICKSLIP_VERIFY(static_cast<int>(nodes.size()) == nodes_per_element(type),
                   "wrong node count for element type");
  const int index = num_elements();
  element_types.push_back(type);
  element_ids.push_back(id);
  connectivity.insert(connectivity.end(), nodes.begin(), nodes.end());
  element_offsets.push_back(static_cast<int>(connectivity.size()));
  return index;
}

std::unordered_map<int, int> node_index_by_id(const Mesh& mesh) {
  std::unordered_map<int, int> map;
  map.reserve(mesh.node_ids.size());
  for (int i = 0; i < mesh.num_nodes(); ++i) map.emplace(mesh.node_ids[i], i);
  return map;
}

void check_mesh(const Mesh& mesh) {
  const int nn = mesh.num_nodes();
  const int ne = mesh.num_elements();
  if (mesh.coordinates.cols() != nn) {
    throw InvalidInput("mesh: " + std::to_string(mesh.coordinates.cols()) +
                       " coordinate columns for " + std::to_string(nn) + " nodes");
  }
  if (static_cast<int>(mesh.element_ids.size()) != ne ||
      static_cast<int>(mesh.element_offsets.size()) != ne + 1 || mesh.element_offsets[0] != 0 ||
      mesh.element_offsets[ne] != static_cast<int>(mesh.connectivity.size())) {
    throw InvalidInput("mesh: inconsistent element arrays");
  }
  std::unordered_set<int> seen;
  for (int id : mesh.node_ids) {
    if (!seen.insert(id).second) throw InvalidInput("mesh: node id " + std::to_string(id) + " appears twice");
  }
  seen.clear();
  for (int e = 0; e < ne; ++e) {
    if (!seen.insert(mesh.element_ids[e]).second) {
      throw InvalidInput("mesh: element id " + std::to_string(mesh.element_ids[e]) +
                         " appears twice");
    }
    const auto nodes = mesh.element_nodes(e);
    if (static_cast<int>(nodes.size()) != nodes_per_element(mesh.element_types[e])) {
      throw InvalidInput("mesh: element " + std::to_string(mesh.element_ids[e]) + " of type " +
                         element_type_name(mesh.element_types[e]) + " has " +
                         std::to_string(nodes.size()) + " nodes");
    }
    for (int n : nodes) {
      if (n < 0 || n >= nn) {
        throw InvalidInput("mesh: element " + std::to_string(mesh.element_ids[e]) +
                           " refers to a node index out of range");
      }
    }
  }
  for (const auto& [name, set] : mesh.node_sets) {
    for (int n : set) {
      if (n < 0 || n >= nn) throw InvalidInput("mesh: node set " + name + " has an index out of range");
    }
  }
  for (const auto& [name, set] : mesh.element_sets) {
    for (int e : set) {
      if (e < 0 || e >= ne) throw InvalidInput("mesh: element set " + name + " has an index out of range");
    }
  }
  if (!mesh.element_material.empty()) {
    if (static_cast<int>(mesh.element_material.size()) != ne) {
      throw InvalidInput("mesh: element_material has " +
                         std::to_string(mesh.element_material.size()) + " entries for " +
                         std::to_string(ne) + " elements");
    }
    for (int m : mesh.element_material) {
      if (m < -1 || m >= static_cast<int>(mesh.materials.size())) {
        throw InvalidInput("mesh: an element's material index is out of range");
      }
    }
  }
  for (const DiscreteSpring& k : mesh.springs) {
    const std::string where =
        "mesh: spring " + std::to_string(k.id) + (k.origin.empty() ? "" : " at " + k.origin);
    if (!seen.insert(k.id).second) throw InvalidInput(where + ": its element id appears twice");
    if (k.node_a < 0 || k.node_a >= nn || k.node_b < -1 || k.node_b >= nn) {
      throw InvalidInput(where + " refers to a node index out of range");
    }
    if (!(k.stiffness >= 0.0) || !std::isfinite(k.stiffness) ||
        std::abs(k.direction_a.norm() - 1.0) > kUnitLengthTolerance ||
        std::abs(k.direction_b.norm() - 1.0) > kUnitLengthTolerance) {
      throw InvalidInput(where + ": stiffness must be finite and >= 0, directions unit vectors");
    }
  }
  for (const PointMass& m : mesh.point_masses) {
    const std::string where =
        "mesh: point mass " + std::to_string(m.id) + (m.origin.empty() ? "" : " at " + m.origin);
    if (!seen.insert(m.id).second) throw InvalidInput(where + ": its element id appears twice");
    if (m.node < 0 || m.node >= nn)
      throw InvalidInput(where + " refers to a node index out of range");
    if (!(m.mass >= 0.0) || !std::isfinite(m.mass))
      throw InvalidInput(where + ": mass must be finite and >= 0");
  }
  for (const LinearConstraint& c : mesh.equations) {
    const std::string where = "mesh: equation" + (c.origin.empty() ? "" : " at " + c.origin);
    if (c.dofs.empty() || c.dofs.size() != c.coefficients.size()) {
      throw InvalidInput(where + " has inconsistent term arrays");
    }
    if (!(c.coefficients[0] != 0.0) || !std::isfinite(c.coefficients[0])) {
      throw InvalidInput(where + ": the coefficient of its first (dependent) DOF must be finite and non-zero");
    }
    std::unordered_set<int> dofs;
    for (size_t k = 0; k < c.dofs.size(); ++k) {
      if (c.dofs[k] < 0 || c.dofs[k] >= 3 * nn) throw InvalidInput(where + " has a DOF out of range");
      if (!std::isfinite(c.coefficients[k])) throw InvalidInput(where + " has a coefficient that is not finite");
      if (!dofs.insert(c.dofs[k]).second) {
        throw InvalidInput(where + " names node " + std::to_string(mesh.node_ids[c.dofs[k] / 3]) +
                           " direction " + std::to_string(c.dofs[k] % 3 + 1) + " twice");
      }
    }
  }
}

}  // namespace stickslip
