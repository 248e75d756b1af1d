#include "linalg/floating_factor.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/errors.h"

namespace stickslip {
namespace {

// The shift σ = −kFloatingShift · trace(K)/trace(M) of the factor A = K − σM: the trace ratio is a
// mean eigenvalue, so cond(A) ~ 1e10 (the rigid pivots ~ 1e-10 of the others, far above the
// round-off of the elimination, ~1e-16), while |σ| stays far below the first elastic eigenvalue of
// any body whose spectrum spans less than ten decades: the refinement gains a factor |σ|/λ per
// step on every eigenvalue λ not kept.
constexpr double kFloatingShift = 1e-10;
// A mode is rigid (a null vector of K) when its eigenvalue is below kRigidFraction·|σ|
// (shift-invert Lanczos: the rigid eigenvalues come out at ~1e-10 |σ|) or, from the dense
// eigen-solve, below kDenseRigidFraction·λ_max (its round-off is a few eps·λ_max).
constexpr double kRigidFraction = 1e-3;
constexpr double kDenseRigidFraction = 1e-11;
// A body has at most six rigid modes per connected piece: the first eigen-solve asks for the kept
// modes plus six; more are asked for when all of those are rigid.
constexpr int kRigidGuess = 6;
// Vectors per block Lanczos step: a block finds an eigenvalue of multiplicity up to its size (the
// six rigid modes share one eigenvalue of the shifted operator).
constexpr int kRigidBlock = 8;
// solve() refines until the part of the residual outside the kept modes is below
// kRefinementTolerance of ‖b‖ (Frobenius), in at most kMaxRefinementSteps steps.
constexpr double kRefinementTolerance = 1e-13;
constexpr int kMaxRefinementSteps = 60;
// factor_gives_back's relative tolerance.
constexpr double kFactorCheck = 1e-6;

}  // namespace

bool factor_gives_back(const SparseCholesky& factor, const SparseMatrix& A) {
  const int n = static_cast<int>(A.rows());
  if (!factor.ok() || factor.size() != n) return false;
  Eigen::VectorXd v(n);
  unsigned state = 12345u;  // a fixed linear congruential sequence: deterministic runs
  for (int i = 0; i < n; ++i) {
    state = state * 1664525u + 1013904223u;
    v(i) = 0.5 + static_cast<double>(state >> 8) / static_cast<double>(1u << 24);
  }
  const Eigen::VectorXd b = A * v;
  Eigen::VectorXd x(n);
  factor.solve(b.data(), x.data());
  const double error = (x - v).norm();
  return std::isfinite(error) && error <= kFactorCheck * v.norm();
}

bool FloatingFactor::compute(const SparseMatrix& K, const SparseMatrix& M,
                             const FloatingFactorOptions& options) {
  *this = FloatingFactor();
  const int n = static_cast<int>(K.rows());
  if (K.cols() != n || M.rows() != n || M.cols() != n) {
    throw InvalidInput("FloatingFactor: K and M must be square and of one size");
  }
  require(options.num_elastic_modes >= 0, "FloatingFactorOptions::num_elastic_modes",
          std::to_string(options.num_elastic_modes), "num_elastic_modes >= 0");
  double trace_k = 0.0, trace_m = 0.0;
  for (int i = 0; i < n; ++i) {
    trace_k += K.coeff(i, i);
    trace_m += M.coeff(i, i);
  }
  if (!(trace_k > 0.0) || !(trace_m > 0.0)) {
    factor_failed_ = true;
    message_ = "trace(K) = " + std::to_string(trace_k) + ", trace(M) = " + std::to_string(trace_m) +
               ": K must be positive semi-definite and M positive definite";
    return false;
  }
  shift_ = -kFloatingShift * trace_k / trace_m;
  if (!factor_.factorize(SparseMatrix(K - shift_ * M))) {
    factor_failed_ = true;
    message_ = "Cholesky factorisation of K − σM (σ = " + std::to_string(shift_) +
               ") failed: " + factor_.message() +
               ". K must be symmetric positive semi-definite and M positive definite.";
    return false;
  }
  // The eigen-solve: Lanczos over the shifted factor, or dense when (nearly) every mode is
  // wanted; asked again with more modes while all of those asked for are rigid.
  const int num_modes = options.num_elastic_modes;
  ModalResult modes;
  int ask = std::min(num_modes + kRigidGuess, n);
  for (;;) {
    double threshold = 0.0;
    if (ask >= n - 1 || ask > n / 2) {
      modes = dense_modes(K, M);
      ask = n;
      if (modes.summary.ok() && n > 0)
        threshold = kDenseRigidFraction * std::abs(modes.eigenvalues(n - 1));
    } else {
      ModalOptions modal = options.modal;
      modal.num_modes = ask;
      modal.shift = shift_;
      modal.block_size = std::max(modal.block_size, kRigidBlock);
      modes = solve_modes(factor_, M, modal);
      threshold = kRigidFraction * std::abs(shift_);
    }
    modal_ = modes.summary;
    if (!modes.summary.ok()) {
      message_ = "eigen-solve failed: " + modes.summary.message;
      return false;
    }
    num_rigid_ = 0;
    while (num_rigid_ < modes.eigenvalues.size() && modes.eigenvalues(num_rigid_) <= threshold)
      ++num_rigid_;
    if (ask == n || (num_rigid_ < ask && num_rigid_ + num_modes <= ask)) break;
    ask = std::min(num_rigid_ + num_modes + kRigidGuess, n);
  }
  const int kept = std::min(num_rigid_ + num_modes, n);
  eigenvalues_ = modes.eigenvalues.head(kept);
  eigenvalues_.head(num_rigid_).setZero();  // null vectors of K: the rest is round-off
  modes_ = modes.modes.leftCols(kept);
  M_modes_ = M * modes_;
  K_ = K;
  ok_ = true;
  return true;
}

Eigen::MatrixXd FloatingFactor::solve(const Eigen::MatrixXd& B,
                                      FloatingSolveSummary* summary) const {
  if (!ok_) throw InvalidInput("FloatingFactor::solve: setup failed: " + message_);
  if (B.rows() != K_.rows()) {
    throw InvalidInput("FloatingFactor::solve: right-hand side has " + std::to_string(B.rows()) +
                       " rows, K has " + std::to_string(K_.rows()));
  }
  FloatingSolveSummary out;
  const Eigen::Index kept = modes_.cols(), elastic = kept - num_rigid_;
  const double norm_b = B.norm();
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(B.rows(), B.cols());
  Eigen::MatrixXd R = B;
  for (;; ++out.steps) {
    const Eigen::MatrixXd C = modes_.transpose() * R;  // kept-mode components of the residual
    X.noalias() += modes_.rightCols(elastic) *
                   (eigenvalues_.tail(elastic).cwiseInverse().asDiagonal() * C.bottomRows(elastic));
    const Eigen::MatrixXd R_d = R - M_modes_ * C;
    out.residual = norm_b > 0.0 ? R_d.norm() / norm_b : 0.0;
    if (R_d.norm() <= kRefinementTolerance * norm_b) break;
    if (out.steps == kMaxRefinementSteps) {
      out.converged = false;
      break;
    }
    X += factor_.solve(R_d);
    // The factor amplifies the round-off of R_d along the rigid modes by 1/|σ| (eps λ/|σ| ~ 1e-6
    // relative): removed, as any rigid part of X may be (K Φ_0 = 0).
    X.noalias() -= modes_.leftCols(num_rigid_) * (M_modes_.leftCols(num_rigid_).transpose() * X);
    R = B - K_ * X;
  }
  if (summary != nullptr) *summary = out;
  return X;
}

}  // namespace stickslip
