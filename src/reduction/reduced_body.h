// A body given by reduced linear matrices: what the nonlinear solver works on. Produced either by
// Craig–Bampton reduction in stickslip (reduction/craig_bampton.h) or read from files exported by
// another code (io/ansys_mapping.h: Harwell–Boeing matrices plus ANSYS's mapping file).
//
//   M_r q̈ + C_r q̇ + K_r q = f_r,   q = [x_b; η]  (boundary displacements, then modal coordinates)
//
// K_r, M_r: dense symmetric, size n_r x n_r, SI units (N/m, kg; modal rows in the units that make
// M_r's modal block dimensionless, i.e. mass-normalised modes). dofs[j] says what q_j is.
// C_r = α M_r + β K_r + Σ_{modal j} 2 ζ ω_j M_r(j,j) e_j e_jᵀ  (reduced_damping below): the
// Rayleigh part is exactly Tᵀ(αM + βK)T, the same damping as the full model; the optional modal
// ratio ζ damps each fixed-interface mode as a single-DOF oscillator (M_r(j,j) = 1 for
// mass-normalised modes). Plain data plus that one function; no file I/O.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace stickslip {

struct ReducedDof {
  enum class Kind {
    kPhysical,  // a displacement of a node in a direction (a boundary / master DOF)
    kModal,     // the amplitude of a fixed-interface (or other generalised) mode
  };
  Kind kind = Kind::kPhysical;

  // kPhysical. A body reduced in stickslip knows node *indices* (full_dof = 3 node_index + dir);
  // a body read from files knows external node *numbers* (node_id). Unknown fields stay -1.
  int node_index = -1;  // 0-based index in the body's mesh
  int node_id = -1;     // external node number (e.g. from an ANSYS mapping file)
  int direction = -1;   // 0 = x, 1 = y, 2 = z
  int full_dof = -1;    // DOF number in the full model, 3 node_index + direction

  // kModal.
  int mode = -1;              // 0-based number among the body's fixed-interface modes
  double frequency_hz = 0.0;  // its natural frequency with the boundary clamped, Hz
};

struct ReducedBody {
  Eigen::MatrixXd K;             // n_r x n_r, symmetric
  Eigen::MatrixXd M;             // n_r x n_r, symmetric positive definite
  std::vector<ReducedDof> dofs;  // size n_r: what each reduced DOF is

  int size() const { return static_cast<int>(dofs.size()); }
  int num_physical() const {
    int n = 0;
    for (const ReducedDof& d : dofs) n += d.kind == ReducedDof::Kind::kPhysical ? 1 : 0;
    return n;
  }
  int num_modal() const { return size() - num_physical(); }
};

struct ReducedDampingOptions {
  double alpha = 0.0;                // s⁻¹, mass-proportional (the thesis: 5)
  double beta = 0.0;                 // s, stiffness-proportional
  double modal_damping_ratio = 0.0;  // ζ on every modal DOF, added to the Rayleigh part
};
void validate(const ReducedDampingOptions& options);  // throws InvalidInput naming the field

// Sets node_id of every physical DOF that has a node_index from the mesh's external ids
// (node_ids[node_index], e.g. Mesh::node_ids), as writers of ANSYS mapping files need.
// Throws InvalidInput if a node_index is outside node_ids.
void assign_node_ids(ReducedBody& body, const std::vector<int>& node_ids);

// C_r (size n_r x n_r, N·s/m) for `body`; ω_j = 2π body.dofs[j].frequency_hz.
Eigen::MatrixXd reduced_damping(const ReducedBody& body, const ReducedDampingOptions& options);

}  // namespace stickslip
