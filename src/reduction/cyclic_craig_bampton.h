// Craig–Bampton reduction of one cyclic sector for one nodal diameter h (issue 13, item 2;
// docs/cyclic.md says why the reduced model is per nodal diameter).
//
// Input: the sector's Hermitian pair of nodal diameter h on its independent DOFs u_I (n of them:
// the high boundary eliminated by u_high = e^{i2πh/N} R u_low, clamped DOFs removed), K_h = A + iB,
// M_h = C + iD, given in the real form fe/cyclic.h's cyclic_sector_problem returns:
//   doubled (0 < h < N/2):  [A −B; B A], [C −D; D C]   (2n square, real symmetric),
//   not doubled (h = 0, N/2): A, C                      (n square; B = D = 0).
// Boundary (master) DOFs b: indices into u_I (a master must be independent: not clamped, not on the
// high boundary; a node of the low boundary is fine), unique, any order.
//
//   u_I = T_h q,  q = [u_b; η]:  u_b = I u_b,  u_i = Φ_c u_b + Φ_n η,
//   Φ_c = −K_ii⁻¹ K_ib (complex constraint modes),
//   K_ii Φ_n = M_ii Φ_n Ω², Φ_nᴴ M_ii Φ_n = I (the num_modes lowest fixed-interface modes),
//   K_r = T_hᴴ K_h T_h,  M_r = T_hᴴ M_h T_h   (Hermitian, n_b + n_modes square; real when h = 0 or
//   N/2). K_r = [K_bb + K_bi Φ_c, 0; 0, Ω²] and Guyan (num_modes = 0) is exact for static loads on
//   the masters; with every interior mode kept T_h is square and K_r, M_r have K_h's eigenvalues.
//
// The physical meaning of q's boundary part: the complex amplitude, in sector 0, of the field of
// nodal diameter h (the field in sector j is R^j u e^{i2πhj/N}). For the conjugate diameter N − h
// use conj(K_r), conj(M_r), conj(T_h).
//
// How: the real form is reduced by craig_bampton (reduction/craig_bampton.h: floating interiors
// included) with the boundary {b, n + b} and twice the modes; its constraint modes (x; y) give
// Φ_c = x + iy, and its fixed-interface modes, which come in pairs (x; y), (−y; x) of one complex
// mode, span the complex modes: a Rayleigh–Ritz step in that span (M-orthonormal basis of rank
// num_modes, Hermitian eigen-solve) gives each complex mode once. A span of another rank (a pair
// split by the eigen-solve) is reported in the summary, never a silently wrong basis.
//
// Cost: the real form's Craig–Bampton (a Cholesky of 2n_i rows, 2n_b constraint modes, 2 num_modes
// eigenpairs), the Ritz step (dense 2 num_modes square) and the complex products T_hᴴ K_h T_h
// (sparse n x n times dense n x (n_b + num_modes)). Bad input throws InvalidInput.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>

#include "core/types.h"
#include "reduction/craig_bampton.h"

namespace stickslip {

struct CyclicReducedSector {
  int nodal_diameter = 0;
  Eigen::MatrixXcd K, M;             // Hermitian, n_b + n_modes square, boundary DOFs first
  std::vector<int> boundary;         // reduced DOF k < n_b is u_I index boundary[k]
  Eigen::VectorXd mode_eigenvalues;  // Ω² of the kept fixed-interface modes, ascending, (rad/s)²
  Eigen::MatrixXcd T;                // n x (n_b + n_modes): u_I = T q (options.keep_basis)
  CraigBamptonSummary summary;       // of the real form's reduction, or the Ritz step's failure
  int num_boundary() const { return static_cast<int>(boundary.size()); }
};

// options.num_modes: complex fixed-interface modes kept (≤ the interior DOFs n − n_b).
CyclicReducedSector cyclic_craig_bampton(const SparseMatrix& K, const SparseMatrix& M, bool doubled,
                                         int nodal_diameter, std::span<const int> boundary,
                                         const CraigBamptonOptions& options);

}  // namespace stickslip
