// Mesh utilities on plain Mesh data (no files): sub-meshes of element sets, node selection by
// geometry, coincident node matching between two node sets, and appending meshes.
//
// All node/element arguments and results are 0-based *indices* (see mesh.h), sorted and unique
// where they are sets. Coordinates and tolerances in m. Geometric input errors (a missing set, a
// node without a coincident partner) throw InvalidInput naming the set/node id and the rule.
#pragma once

#include <functional>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"

namespace stickslip {

// A part of a mesh with the maps back to the parent: node index i of `mesh` is node index
// node_parent[i] of the parent, element e is element_parent[e]. External ids are kept.
struct SubMesh {
  Mesh mesh;
  std::vector<int> node_parent;     // new node index -> parent node index (increasing)
  std::vector<int> element_parent;  // new element index -> parent element index (increasing)
};

// Sub-mesh made of `elements` (parent indices, any order, duplicates ignored) and the nodes they
// use, in increasing parent order. Node and element sets are restricted to what is kept; sets
// that become empty are dropped. Equations are kept when all their nodes are kept and dropped
// when none is; one that ties kept nodes to dropped ones throws InvalidInput naming its origin.
SubMesh extract_submesh(const Mesh& mesh, std::span<const int> elements);
// Same for the element set `element_set` (e.g. one body); InvalidInput if it does not exist.
SubMesh extract_element_set(const Mesh& mesh, const std::string& element_set);

// Sorted unique node indices used by `elements`.
std::vector<int> nodes_of_elements(const Mesh& mesh, std::span<const int> elements);

using NodePredicate = std::function<bool(const Eigen::Vector3d&)>;
// Sorted node indices whose coordinates satisfy `predicate`: among all nodes, or among
// `candidates` only.
std::vector<int> select_nodes(const Mesh& mesh, const NodePredicate& predicate);
std::vector<int> select_nodes(const Mesh& mesh, std::span<const int> candidates,
                              const NodePredicate& predicate);
// Nodes at distance <= tolerance from the plane through `point` with normal `normal` (any
// length > 0): |n̂·(x − point)| <= tolerance.
std::vector<int> nodes_on_plane(const Mesh& mesh, const Eigen::Vector3d& point,
                                const Eigen::Vector3d& normal, double tolerance);
// Nodes inside the axis-aligned box [lower − tol, upper + tol] (componentwise).
std::vector<int> nodes_in_box(const Mesh& mesh, const Eigen::Vector3d& lower,
                              const Eigen::Vector3d& upper, double tolerance);

// The node (among all, or among `candidates`) nearest to `x`; ties go to the lowest index.
// InvalidInput if there is no candidate or the nearest one is farther than max_distance.
int nearest_node(const Mesh& mesh, const Eigen::Vector3d& x,
                 double max_distance = std::numeric_limits<double>::infinity());
int nearest_node(const Mesh& mesh, std::span<const int> candidates, const Eigen::Vector3d& x,
                 double max_distance = std::numeric_limits<double>::infinity());

// The node / element set `name`; InvalidInput naming it and the sets that exist if missing.
const std::vector<int>& find_node_set(const Mesh& mesh, const std::string& name);
const std::vector<int>& find_element_set(const Mesh& mesh, const std::string& name);

// Pairs every node of `nodes_a` (indices into mesh_a) with the one node of `nodes_b` (indices
// into mesh_b) at distance <= tolerance. Returns (a, b) index pairs in the order of nodes_a.
// Throws InvalidInput (naming the node id and its coordinates) if a node of A has no partner,
// more than one partner within tolerance, or if two nodes of A share one node of B.
// Nodes of B left unmatched are allowed (B may be the larger set).
std::vector<std::pair<int, int>> match_coincident_nodes(const Mesh& mesh_a,
                                                        std::span<const int> nodes_a,
                                                        const Mesh& mesh_b,
                                                        std::span<const int> nodes_b,
                                                        double tolerance);

// Appends `part` to `mesh`: its node ids are shifted by node_id_offset and its element ids by
// element_id_offset; its sets are merged into `mesh`'s by name (union), its equations appended. Returns the index of
// the first appended node and element. Throws InvalidInput if ids collide.
struct AppendedRange {
  int first_node = 0;
  int first_element = 0;
};
AppendedRange append_mesh(Mesh& mesh, const Mesh& part, int node_id_offset = 0,
                          int element_id_offset = 0);

// A structured box of nx x ny x nz 8-node hexahedra of `type` (C3D8 or C3D8I) over
// [0, size.x] x [0, size.y] x [0, size.z] (m). Node (i, j, k), 0 <= i <= nx, ..., has index
// i + (nx + 1)(j + (ny + 1) k), coordinates (size.x i / nx, size.y j / ny, size.z k / nz) and id
// index + 1; element (i, j, k) has index i + nx (j + ny k), id index + 1. No sets. The arrays are
// filled directly, so millions of nodes are cheap (Mesh::add_node grows one column at a time).
// InvalidInput for a non-positive count or size, or a type that is not an 8-node hexahedron.
Mesh structured_hex_box(int nx, int ny, int nz, const Eigen::Vector3d& size, ElementType type);

}  // namespace stickslip
