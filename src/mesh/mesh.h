// A finite-element mesh as plain data: nodes, elements, node and element sets. Knows nothing of
// files (readers live in io/). Coordinates in m.
//
// Indices vs ids: every node and element has an internal 0-based *index* (its position in the
// arrays below) and an external *id* (the number in the file it came from; unique, positive).
// Connectivity and sets store indices. DOFs of node index i are 3i, 3i+1, 3i+2 (x, y, z).
//
// Element node order is CalculiX/Abaqus's (the .inp convention) for every type; readers of other
// formats (Gmsh) reorder to it.
#pragma once

#include <limits>
#include <map>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

namespace stickslip {

// Named after the CalculiX element that has the same topology and formulation.
enum class ElementType {
  kC3D8,    // 8-node hexahedron, full 2x2x2 integration
  kC3D8I,   // 8-node hexahedron with incompatible modes (Wilson–Taylor), 2x2x2
  kC3D20,   // 20-node hexahedron, 3x3x3 integration
  kC3D20R,  // 20-node hexahedron, reduced 2x2x2 integration
  kC3D4,    // 4-node tetrahedron
  kC3D10,   // 10-node tetrahedron
  kC3D8B,   // 8-node hexahedron, B-bar (mean dilatation), 2x2x2: ANSYS SOLID185, KEYOPT(2)=0;
            // not a CalculiX element (CalculiX's C3D8 is plain full integration)
  kC3D6,    // 6-node wedge (pentahedron)
  kC3D15,   // 15-node wedge
  kC3D5,    // 5-node pyramid: the collapsed 8-node brick (ANSYS SOLID185's pyramid), 2x2x2
  kC3D13,   // 13-node pyramid: the collapsed 20-node brick (CalculiX's C3D20 with a collapsed
            // face; ANSYS SOLID186's pyramid shape), 3x3x3; not a CalculiX type name
  kC3D8R,   // 8-node hexahedron, 1 point (uniform strain) + CalculiX's hourglass stiffness
};

int nodes_per_element(ElementType type);
const char* element_type_name(ElementType type);  // "C3D8", ...
// Parses a CalculiX/Abaqus type name (case-insensitive); false if not supported.
bool parse_element_type(const std::string& name, ElementType* type);

// A linear multi-point constraint between DOFs of a mesh (DOF 3·node index + direction):
//   Σ_k coefficients[k] · u(dofs[k]) = 0,
// as Abaqus/CalculiX *EQUATION: the first DOF is the dependent one (eliminated in favour of the
// others, fe/dof_map.h), coefficients[0] ≠ 0, no DOF twice. `origin` says where it was defined
// ("file:line"), for messages.
struct LinearConstraint {
  std::vector<int> dofs;
  std::vector<double> coefficients;
  std::string origin;
};

// A linear discrete spring (Abaqus/CalculiX SPRING1, SPRING2, SPRINGA) of stiffness k (N/m):
//   energy ½ k (d_aᵀ u_a − d_bᵀ u_b)²,  u_b = 0 for node_b = -1 (to the ground),
// d_a, d_b unit vectors: SPRING1 and SPRING2 along global axes, SPRINGA along the line from a to
// b in the undeformed mesh (d_a = d_b). Its stiffness is added to K in assembly (fe/assembly.h).
struct DiscreteSpring {
  int id = 0;       // element id in the file (shares the id space of elements)
  int node_a = 0;   // node index
  int node_b = -1;  // node index or -1
  Eigen::Vector3d direction_a = Eigen::Vector3d::UnitX(), direction_b = Eigen::Vector3d::UnitX();
  double stiffness = 0.0;  // N/m, >= 0
  std::string origin;      // "file:line"
};

// A point mass m (kg) on the three translations of a node (Abaqus/CalculiX MASS), added to M.
struct PointMass {
  int id = 0;    // element id in the file
  int node = 0;  // node index
  double mass = 0.0;
  std::string origin;
};

// A linear elastic isotropic material given in a mesh file (.inp: *MATERIAL with *ELASTIC and
// *DENSITY, assigned by *SOLID SECTION; .cdb: MPDATA by material number). Constants the file does
// not give are NaN; `problem` says why the material cannot be used ("" when it can be, if
// complete), e.g. anisotropic elasticity. SI units as IsotropicMaterial.
struct MeshMaterial {
  std::string name;
  double youngs_modulus = std::numeric_limits<double>::quiet_NaN();
  double poisson_ratio = std::numeric_limits<double>::quiet_NaN();
  double density = std::numeric_limits<double>::quiet_NaN();
  std::string origin;   // "file:line" where it is defined
  std::string problem;  // why it cannot be used, or ""
};

// One data line of a deck's *BOUNDARY: the displacements of `nodes` (indices) in directions
// first..last (0-based) held at zero. A line the program cannot apply as such (a non-zero value,
// rotational DOFs only, a TYPE= other than DISPLACEMENT) carries the reason in `unsupported`.
// The mesh only records them: a body applies them when its case file says so
// (bodies.B.supports: {from_mesh: true}, docs/case-file.md).
struct MeshBoundary {
  std::vector<int> nodes;
  int first = 0, last = 2;
  std::string unsupported;  // empty: applicable
  std::string origin;       // "file:line"
};

struct Mesh {
  // --- nodes ---
  Eigen::Matrix3Xd coordinates;  // 3 x num_nodes, m
  std::vector<int> node_ids;     // external id of each node index

  // --- elements (compressed rows) ---
  std::vector<ElementType> element_types;
  std::vector<int> element_ids;       // external id of each element index
  std::vector<int> element_offsets{0};  // size num_elements + 1
  std::vector<int> connectivity;      // node indices, CalculiX local order

  // --- sets (sorted, unique indices) ---
  std::map<std::string, std::vector<int>> node_sets;
  std::map<std::string, std::vector<int>> element_sets;

  // --- linear constraints between DOFs (*EQUATION), in file order ---
  std::vector<LinearConstraint> equations;
  // --- zero displacements of the deck (*BOUNDARY), in file order; applied only on request ---
  std::vector<MeshBoundary> boundaries;

  // --- materials of the file: element_material is empty (none assigned) or holds, per element,
  //     an index into materials or -1 (no material assigned to that element) ---
  std::vector<MeshMaterial> materials;
  std::vector<int> element_material;

  // --- discrete springs and point masses (not elements: no stresses, not in element sets) ---
  std::vector<DiscreteSpring> springs;
  std::vector<PointMass> point_masses;

  int num_nodes() const { return static_cast<int>(node_ids.size()); }
  int num_elements() const { return static_cast<int>(element_types.size()); }
  int num_dofs() const { return 3 * num_nodes(); }
  std::span<const int> element_nodes(int e) const {
    return {connectivity.data() + element_offsets[e],
            static_cast<size_t>(element_offsets[e + 1] - element_offsets[e])};
  }

  // Appends a node / element; returns its index. Node indices in `nodes` must exist.
  int add_node(int id, const Eigen::Vector3d& x);
  int add_element(int id, ElementType type, std::span<const int> nodes);
};

// Map external node id -> node index, for lookups by id (e.g. from a case file).
std::unordered_map<int, int> node_index_by_id(const Mesh& mesh);

// Checks the internal consistency of a mesh (sizes, index ranges, unique ids, sets in range);
// throws InvalidInput naming the first problem. Readers call it before returning a mesh.
void check_mesh(const Mesh& mesh);

}  // namespace stickslip
