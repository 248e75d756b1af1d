// The damped modal flexibility of a non-proportionally damped linear model as a sum over its
// complex modes, computed once (HarmonicBalanceSystem's "state space" damping-matrix method), and
// the real split of Ψ H_k Ψᵀ from it. Kept apart from the harmonic balance proper, which only
// asks for the weights w(κ) and the Gram products.
#pragma once

#include <map>
#include <memory>
#include <string>

#include <Eigen/Core>

namespace stickslip {

// State-space expansion of the damped modal flexibility, k ≥ 1 (the derivation and when it is used:
// hbm/harmonic_balance.h, "state space"):
//   H(iκ) = (diag(ω²) − κ² I + iκ C_m)⁻¹ = X diag(w(κ)) Xᵀ
// over its entries e (the rigid modes plus 2 per elastic mode): first `rigid` rigid-body entries,
// w_e = 1/(−κ² + iκ c_e); then `real` real poles, then conjugate pairs (e, e + 1) with
// X.col(e + 1) = conj(X.col(e)), pole(e + 1) = conj(pole(e)); for poles
// w_e = f_e (−s_e) / (iκ − s_e) (f_e = 1 for the pairs, whose columns are normalised).
struct DampedModalExpansion {
  int rigid = 0, real = 0;
  Eigen::MatrixXcd X;             // nm x entries
  Eigen::VectorXcd pole, factor;  // s_e (1/s), f_e (rigid entries: unused)
  Eigen::VectorXd rigid_damping;  // c_e (1/s) of the rigid entries
  Eigen::VectorXcd weights(double kappa) const;                    // w_e(κ), κ = kΩ
  Eigen::VectorXcd weight_derivatives(int k, double omega) const;  // dw_e/dΩ at κ = kΩ
  // Filled by HarmonicBalanceSystem: P = Ψ X (nu x entries) and its real columns (entries of the
  // rigid and real blocks: Preal; pairs: U + iV), load k -> Xᵀ Φᵀ F_k.
  Eigen::MatrixXcd P;
  Eigen::MatrixXd Preal, U, V;
  std::map<int, Eigen::VectorXcd> load;
};
// The expansion of ω² (nm), C_m (nm x nm, symmetric PSD) with the elastic modes flagged (1) in
// `elastic`, or null with `failure` set (why it is not usable: then use the impedance LU).
// Cost: one real eigen-decomposition of order 2·ne, O(ne³).
std::shared_ptr<DampedModalExpansion> damped_modal_expansion(const Eigen::VectorXd& omega2,
                                                             const Eigen::MatrixXd& C_m,
                                                             const Eigen::VectorXd& elastic,
                                                             std::string& failure);

// Re G and Im G (nu x nu, full symmetric) of G = P diag(w) Pᵀ for the expansion d (its P, Preal,
// U, V filled) and weights w = d.weights(κ): a few BLAS dsyrk over ≈ 2·ne columns.
void damped_gram(const DampedModalExpansion& d, const Eigen::VectorXcd& w, Eigen::MatrixXd& gr,
                 Eigen::MatrixXd& gi);

}  // namespace stickslip
