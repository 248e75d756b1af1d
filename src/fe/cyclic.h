// Cyclic symmetry of one sector of N (issue 13, item 1: the linear modal analysis per nodal
// diameter; the reduction and the forced response build on it).
//
// The sector's "low" boundary, rotated by +2π/N about the axis (right-handed about
// axis_direction), lands on its "high" boundary: sector j + 1 is sector j rotated by 2π/N. A field
// of nodal diameter h (0 ≤ h ≤ N/2) repeats from sector to sector with the phase φ = 2πh/N, so the
// high boundary of the sector carries the low boundary's displacement rotated and phase-shifted:
//   u_high = e^{iφ} R u_low,   R the rotation by 2π/N.
// With u = T_h u_I (u_I: every DOF that is not on the high boundary; T_h complex: identity on
// them, e^{iφ} R on the low partners' columns for the high rows) the sector's matrices become the
// Hermitian K_h = T_hᴴ K T_h, M_h = T_hᴴ M T_h. Written with K_h = A + iB (A symmetric, B
// antisymmetric), the real symmetric problem of twice the size
//   [A  −B] [x]     [C  −D] [x]
//   [B   A] [y] = λ [D   C] [y],   M_h = C + iD,
// has every eigenvalue of the Hermitian one twice ((x, y) and (−y, x)): these are the two standing
// waves (or travelling waves) of the ring's double modes. For h = 0 and h = N/2 (N even) T_h is real
// and the problem keeps its size (single modes of the ring).
//
// Clamped DOFs (DofMap-style list of full DOFs) are removed from u_I; a high DOF may be clamped
// only when its low partner's rotated DOFs are clamped too (else InvalidInput): the constraint then
// holds whatever h.
#pragma once

#include <complex>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/types.h"
#include "mesh/mesh.h"

namespace stickslip {

struct CyclicSymmetry {
  int sectors = 0;                         // N ≥ 2
  Eigen::Vector3d axis_point{0, 0, 0};     // m
  Eigen::Vector3d axis_direction{0, 0, 1};  // any length > 0
  // Rotation by +2π/N about axis_direction (the map from sector j to sector j + 1).
  Eigen::Matrix3d rotation() const;
};
void validate(const CyclicSymmetry& symmetry);  // InvalidInput naming the field

// (low, high) node index pairs: each node of `low` with the node of `high` within `tolerance` (m)
// of its image under the rotation. InvalidInput naming the node id, its image and the nearest
// high node with its distance when a low node has no partner, or two low nodes share one; the
// counts of low and high must be equal.
std::vector<std::pair<int, int>> match_cyclic_boundaries(const Mesh& mesh, std::span<const int> low,
                                                         std::span<const int> high,
                                                         const CyclicSymmetry& symmetry,
                                                         double tolerance);

struct CyclicSectorProblem {
  int nodal_diameter = 0;
  bool doubled = false;          // true for 0 < h < N/2: K, M are the real 2n form above
  SparseMatrix K, M;             // real symmetric, n or 2n square
  std::vector<int> independent;  // full DOFs of u_I, increasing (n of them)
  // Index in u_I of a full DOF; -1 when it is clamped or on the high boundary.
  int independent_index(int full_dof) const;
  // Full complex displacement of the sector (3·num_nodes) from a solution of K, M (size n or 2n).
  Eigen::VectorXcd expand(const Eigen::VectorXd& solution) const;

  ComplexSparseMatrix T;  // full DOFs x n: u = T u_I
};

// The problem of nodal diameter h (0 ≤ h ≤ N/2) for the sector's full K and M (3·num_nodes
// square), its boundary pairs (match_cyclic_boundaries) and clamped full DOFs.
CyclicSectorProblem cyclic_sector_problem(const SparseMatrix& K, const SparseMatrix& M,
                                          std::span<const std::pair<int, int>> boundary_pairs,
                                          std::span<const int> clamped_dofs,
                                          const CyclicSymmetry& symmetry, int nodal_diameter);

}  // namespace stickslip
