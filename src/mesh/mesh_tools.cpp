#include "mesh/mesh_tools.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/errors.h"
#include "core/format.h"

namespace stickslip {
namespace {

std::vector<int> sorted_unique(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

// Restricts a set of parent indices through an old->new map (-1 = dropped); result sorted.
std::vector<int> restrict_set(const std::vector<int>& set, const std::vector<int>& new_index) {
  std::vector<int> out;
  for (int i : set) {
    if (i >= 0 && i < static_cast<int>(new_index.size()) && new_index[i] >= 0) {
      out.push_back(new_index[i]);
    }
  }
  return sorted_unique(std::move(out));
}

std::string describe_node(const Mesh& mesh, int index) {
  std::ostringstream s;
  s.precision(9);
  const Eigen::Vector3d x = mesh.coordinates.col(index);
  s << "node " << mesh.node_ids[index] << " at (" << x.x() << ", " << x.y() << ", " << x.z() << ")";
  return s.str();
}

}  // namespace

std::vector<int> nodes_of_elements(const Mesh& mesh, std::span<const int> elements) {
  std::vector<int> nodes;
  for (int e : elements) {
    STICKSLIP_VERIFY(e >= 0 && e < mesh.num_elements(), "element index out of range");
    const auto en = mesh.element_nodes(e);
    nodes.insert(nodes.end(), en.begin(), en.end());
  }
  return sorted_unique(std::move(nodes));
}

SubMesh extract_submesh(const Mesh& mesh, std::span<const int> elements) {
  const std::vector<int> kept_elements = sorted_unique({elements.begin(), elements.end()});
  const std::vector<int> kept_nodes = nodes_of_elements(mesh, kept_elements);

  SubMesh sub;
  std::vector<int> new_node(mesh.num_nodes(), -1);
  sub.mesh.coordinates.resize(3, static_cast<Eigen::Index>(kept_nodes.size()));
  for (size_t i = 0; i < kept_nodes.size(); ++i) {
    const int p = kept_nodes[i];
    new_node[p] = static_cast<int>(i);
    sub.mesh.coordinates.col(static_cast<Eigen::Index>(i)) = mesh.coordinates.col(p);
    sub.mesh.node_ids.push_back(mesh.node_ids[p]);
  }
  sub.node_parent = kept_nodes;

  std::vector<int> new_element(mesh.num_elements(), -1);
  std::vector<int> local;
  for (int e : kept_elements) {
    local.clear();
    for (int n : mesh.element_nodes(e)) local.push_back(new_node[n]);
    new_element[e] = sub.mesh.add_element(mesh.element_ids[e], mesh.element_types[e], local);
  }
  sub.element_parent = kept_elements;
  if (!mesh.element_material.empty()) {
    sub.mesh.materials = mesh.materials;
    for (int e : kept_elements) sub.mesh.element_material.push_back(mesh.element_material[e]);
  }

  for (const auto& [name, set] : mesh.node_sets) {
    std::vector<int> r = restrict_set(set, new_node);
    if (!r.empty()) sub.mesh.node_sets.emplace(name, std::move(r));
  }
  for (const auto& [name, set] : mesh.element_sets) {
    std::vector<int> r = restrict_set(set, new_element);
    if (!r.empty()) sub.mesh.element_sets.emplace(name, std::move(r));
  }
  // Equations: kept when all their nodes are kept, dropped when none is (another part's); one
  // that ties kept nodes to others cannot be honoured by the part alone.
  for (const LinearConstraint& c : mesh.equations) {
    LinearConstraint kept{{}, c.coefficients, c.origin};
    int outside = -1;
    for (int dof : c.dofs) {
      const int n = new_node[dof / 3];
      if (n < 0) {
        outside = dof / 3;
      } else {
        kept.dofs.push_back(3 * n + dof % 3);
      }
    }
    if (kept.dofs.empty()) continue;
    if (outside >= 0) {
      throw InvalidInput("the equation" + (c.origin.empty() ? "" : " at " + c.origin) +
                         " ties nodes of this part to node " +
                         std::to_string(mesh.node_ids[outside]) +
                         ", which is on none of its elements (equations between bodies are not "
                         "supported)");
    }
    sub.mesh.equations.push_back(std::move(kept));
  }
  // Springs and point masses: kept when all their nodes are, dropped when none is.
  for (DiscreteSpring k : mesh.springs) {
    const int a = new_node[k.node_a], b = k.node_b < 0 ? -1 : new_node[k.node_b];
    const bool b_kept = k.node_b < 0 || b >= 0;
    if (a < 0 && !b_kept) continue;
    if (a < 0 || (k.node_b >= 0 && b < 0)) {
      throw InvalidInput("the spring " + std::to_string(k.id) +
                         (k.origin.empty() ? "" : " at " + k.origin) +
                         " joins this part to a node on none of its elements (springs between "
                         "bodies are contacts of the case file)");
    }
    k.node_a = a;
    k.node_b = b;
    sub.mesh.springs.push_back(std::move(k));
  }
  for (PointMass m : mesh.point_masses) {
    if (new_node[m.node] < 0) continue;
    m.node = new_node[m.node];
    sub.mesh.point_masses.push_back(std::move(m));
  }
  // Boundaries (*BOUNDARY): the part's own nodes of each line; lines on other parts only drop.
  for (const MeshBoundary& b : mesh.boundaries) {
    MeshBoundary kept = b;
    kept.nodes = restrict_set(b.nodes, new_node);
    if (!kept.nodes.empty()) sub.mesh.boundaries.push_back(std::move(kept));
  }
  return sub;
}

SubMesh extract_element_set(const Mesh& mesh, const std::string& element_set) {
  return extract_submesh(mesh, find_element_set(mesh, element_set));
}

std::vector<int> select_nodes(const Mesh& mesh, const NodePredicate& predicate) {
  std::vector<int> out;
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (predicate(mesh.coordinates.col(i))) out.push_back(i);
  }
  return out;
}

std::vector<int> select_nodes(const Mesh& mesh, std::span<const int> candidates,
                              const NodePredicate& predicate) {
  std::vector<int> out;
  for (int i : candidates) {
    STICKSLIP_VERIFY(i >= 0 && i < mesh.num_nodes(), "node index out of range");
    if (predicate(mesh.coordinates.col(i))) out.push_back(i);
  }
  return sorted_unique(std::move(out));
}

std::vector<int> nodes_on_plane(const Mesh& mesh, const Eigen::Vector3d& point,
                                const Eigen::Vector3d& normal, double tolerance) {
  const double length = normal.norm();
  STICKSLIP_VERIFY(length > 0.0, "plane normal must not be zero");
  const Eigen::Vector3d n = normal / length;
  return select_nodes(
      mesh, [&](const Eigen::Vector3d& x) { return std::abs(n.dot(x - point)) <= tolerance; });
}

std::vector<int> nodes_in_box(const Mesh& mesh, const Eigen::Vector3d& lower,
                              const Eigen::Vector3d& upper, double tolerance) {
  return select_nodes(mesh, [&](const Eigen::Vector3d& x) {
    return (x.array() >= lower.array() - tolerance).all() &&
           (x.array() <= upper.array() + tolerance).all();
  });
}

int nearest_node(const Mesh& mesh, const Eigen::Vector3d& x, double max_distance) {
  std::vector<int> all(mesh.num_nodes());
  for (int i = 0; i < mesh.num_nodes(); ++i) all[i] = i;
  return nearest_node(mesh, all, x, max_distance);
}

int nearest_node(const Mesh& mesh, std::span<const int> candidates, const Eigen::Vector3d& x,
                 double max_distance) {
  int best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int i : candidates) {
    STICKSLIP_VERIFY(i >= 0 && i < mesh.num_nodes(), "node index out of range");
    const double d = (mesh.coordinates.col(i) - x).norm();
    if (d < best_distance || (d == best_distance && i < best)) {
      best = i;
      best_distance = d;
    }
  }
  std::ostringstream where;
  where.precision(9);
  where << "(" << x.x() << ", " << x.y() << ", " << x.z() << ")";
  if (best < 0) throw InvalidInput("mesh: no candidate node near " + where.str());
  if (best_distance > max_distance) {
    throw InvalidInput("mesh: the node nearest to " + where.str() + " is " +
                       describe_node(mesh, best) + ", farther than " + format_number(max_distance) +
                       " m");
  }
  return best;
}

namespace {
const std::vector<int>& find_set(const std::map<std::string, std::vector<int>>& sets,
                                 const std::string& name, const char* kind) {
  const auto it = sets.find(name);
  if (it != sets.end()) return it->second;
  std::string known;
  for (const auto& [n, s] : sets) known += (known.empty() ? "" : ", ") + n;
  throw InvalidInput(std::string("mesh: no ") + kind + " set named '" + name + "' (" +
                     (known.empty() ? std::string("there are none") : "known: " + known) + ")");
}
}  // namespace

const std::vector<int>& find_node_set(const Mesh& mesh, const std::string& name) {
  return find_set(mesh.node_sets, name, "node");
}

const std::vector<int>& find_element_set(const Mesh& mesh, const std::string& name) {
  return find_set(mesh.element_sets, name, "element");
}

std::vector<std::pair<int, int>> match_coincident_nodes(const Mesh& mesh_a,
                                                        std::span<const int> nodes_a,
                                                        const Mesh& mesh_b,
                                                        std::span<const int> nodes_b,
                                                        double tolerance) {
  STICKSLIP_VERIFY(tolerance >= 0.0, "tolerance must be >= 0");
  // B sorted by x: the candidates of a node of A lie in an x window of width 2 tol.
  std::vector<std::pair<double, int>> b_by_x;
  b_by_x.reserve(nodes_b.size());
  for (int b : nodes_b) {
    STICKSLIP_VERIFY(b >= 0 && b < mesh_b.num_nodes(), "node index out of range");
    b_by_x.emplace_back(mesh_b.coordinates(0, b), b);
  }
  std::sort(b_by_x.begin(), b_by_x.end());

  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(nodes_a.size());
  std::vector<int> partner_of_b(mesh_b.num_nodes(), -1);
  for (int a : nodes_a) {
    STICKSLIP_VERIFY(a >= 0 && a < mesh_a.num_nodes(), "node index out of range");
    const Eigen::Vector3d xa = mesh_a.coordinates.col(a);
    auto it =
        std::lower_bound(b_by_x.begin(), b_by_x.end(), std::make_pair(xa.x() - tolerance, -1));
    int found = -1;
    int count = 0;
    for (; it != b_by_x.end() && it->first <= xa.x() + tolerance; ++it) {
      if ((mesh_b.coordinates.col(it->second) - xa).norm() <= tolerance) {
        found = it->second;
        ++count;
      }
    }
    if (count == 0) {
      throw InvalidInput("mesh: " + describe_node(mesh_a, a) +
                         " has no coincident node in the other set (tolerance " +
                         format_number(tolerance) + " m)");
    }
    if (count > 1) {
      throw InvalidInput("mesh: " + describe_node(mesh_a, a) + " has " + std::to_string(count) +
                         " nodes of the other set within the tolerance; must be exactly one");
    }
    if (partner_of_b[found] >= 0) {
      throw InvalidInput("mesh: " + describe_node(mesh_b, found) + " is the partner of both node " +
                         std::to_string(mesh_a.node_ids[partner_of_b[found]]) + " and node " +
                         std::to_string(mesh_a.node_ids[a]));
    }
    partner_of_b[found] = a;
    pairs.emplace_back(a, found);
  }
  return pairs;
}

AppendedRange append_mesh(Mesh& mesh, const Mesh& part, int node_id_offset, int element_id_offset) {
  AppendedRange range{mesh.num_nodes(), mesh.num_elements()};
  const int nn = mesh.num_nodes();
  mesh.coordinates.conservativeResize(3, nn + part.num_nodes());
  mesh.coordinates.rightCols(part.num_nodes()) = part.coordinates;
  for (int id : part.node_ids) mesh.node_ids.push_back(id + node_id_offset);
  std::vector<int> local;
  for (int e = 0; e < part.num_elements(); ++e) {
    local.clear();
    for (int n : part.element_nodes(e)) local.push_back(n + range.first_node);
    mesh.add_element(part.element_ids[e] + element_id_offset, part.element_types[e], local);
  }
  auto merge = [](std::map<std::string, std::vector<int>>& into,
                  const std::map<std::string, std::vector<int>>& from, int shift) {
    for (const auto& [name, set] : from) {
      std::vector<int>& target = into[name];
      for (int i : set) target.push_back(i + shift);
      target = sorted_unique(std::move(target));
    }
  };
  merge(mesh.node_sets, part.node_sets, range.first_node);
  merge(mesh.element_sets, part.element_sets, range.first_element);
  if (!mesh.element_material.empty() || !part.element_material.empty()) {
    mesh.element_material.resize(static_cast<size_t>(range.first_element), -1);
    const int shift = static_cast<int>(mesh.materials.size());
    mesh.materials.insert(mesh.materials.end(), part.materials.begin(), part.materials.end());
    for (int e = 0; e < part.num_elements(); ++e) {
      const int m = part.element_material.empty() ? -1 : part.element_material[e];
      mesh.element_material.push_back(m < 0 ? -1 : m + shift);
    }
  }
  for (LinearConstraint c : part.equations) {
    for (int& dof : c.dofs) dof += 3 * range.first_node;
    mesh.equations.push_back(std::move(c));
  }
  for (DiscreteSpring k : part.springs) {
    k.id += element_id_offset;
    k.node_a += range.first_node;
    if (k.node_b >= 0) k.node_b += range.first_node;
    mesh.springs.push_back(std::move(k));
  }
  for (PointMass m : part.point_masses) {
    m.id += element_id_offset;
    m.node += range.first_node;
    mesh.point_masses.push_back(std::move(m));
  }
  check_mesh(mesh);  // throws on colliding ids
  return range;
}

Mesh structured_hex_box(int nx, int ny, int nz, const Eigen::Vector3d& size, ElementType type) {
  if (nx < 1 || ny < 1 || nz < 1) {
    throw InvalidInput("structured_hex_box: element counts must be >= 1");
  }
  if (!(size.minCoeff() > 0.0)) throw InvalidInput("structured_hex_box: sizes must be > 0");
  if (nodes_per_element(type) != 8) {
    throw InvalidInput(std::string("structured_hex_box: ") + element_type_name(type) +
                       " is not an 8-node hexahedron");
  }
  const int px = nx + 1, py = ny + 1, pz = nz + 1;
  const auto node = [&](int i, int j, int k) { return i + px * (j + py * k); };
  Mesh mesh;
  const int num_nodes = px * py * pz;
  mesh.coordinates.resize(3, num_nodes);
  mesh.node_ids.resize(static_cast<size_t>(num_nodes));
  for (int k = 0; k < pz; ++k) {
    for (int j = 0; j < py; ++j) {
      for (int i = 0; i < px; ++i) {
        const int n = node(i, j, k);
        mesh.coordinates.col(n) << size(0) * i / nx, size(1) * j / ny, size(2) * k / nz;
        mesh.node_ids[static_cast<size_t>(n)] = n + 1;
      }
    }
  }
  const size_t num_elements = static_cast<size_t>(nx) * ny * nz;
  mesh.element_types.assign(num_elements, type);
  mesh.element_ids.resize(num_elements);
  mesh.element_offsets.resize(num_elements + 1);
  mesh.connectivity.resize(8 * num_elements);
  size_t e = 0;
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i, ++e) {
        const int nodes[8] = {node(i, j, k),
                              node(i + 1, j, k),
                              node(i + 1, j + 1, k),
                              node(i, j + 1, k),
                              node(i, j, k + 1),
                              node(i + 1, j, k + 1),
                              node(i + 1, j + 1, k + 1),
                              node(i, j + 1, k + 1)};
        std::copy(nodes, nodes + 8, mesh.connectivity.begin() + static_cast<std::ptrdiff_t>(8 * e));
        mesh.element_ids[e] = static_cast<int>(e) + 1;
        mesh.element_offsets[e + 1] = static_cast<int>(8 * (e + 1));
      }
    }
  }
  return mesh;
}

}  // namespace stickslip
