#include "linalg/dense_lu.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/errors.h"
#include "linalg/blas.h"
#include "linalg/blas_threads.h"

namespace stickslip {

bool DenseLu::compute(const Eigen::MatrixXd& A) {
  Eigen::MatrixXd copy = A;
  return factor(copy);
}

bool DenseLu::factor(Eigen::MatrixXd& A) {
  STICKSLIP_VERIFY(A.rows() == A.cols(), "DenseLu: the matrix must be square");
  ok_ = false;
  rcond_ = 0.0;
  const int n = static_cast<int>(A.rows());
  if (n == 0 || !A.allFinite()) return false;
  anorm_ = A.cwiseAbs().colwise().sum().maxCoeff();
  const ScopedBlasThreads single_thread(1);
  lu_.swap(A);
  A.resize(n, n);
  pivots_.resize(n);
  int info = 0;
  dgetrf_(&n, &n, lu_.data(), &n, pivots_.data(), &info);
  if (info != 0) return false;  // info > 0: exact zero pivot
  ok_ = true;
  rcond_ = -1.0;
  return true;
}

double DenseLu::rcond() const {
  if (!ok_) return 0.0;
  if (rcond_ < 0.0) {
    const ScopedBlasThreads single_thread(1);
    const double inverse_norm = inverse_norm_estimate();
    rcond_ = anorm_ > 0 && inverse_norm > 0 ? 1.0 / anorm_ / inverse_norm : 0.0;
  }
  return rcond_;
}

Eigen::VectorXd DenseLu::solve_with(char trans, const Eigen::VectorXd& b) const {
  Eigen::VectorXd x = b;
  const int n = static_cast<int>(lu_.rows()), nrhs = 1;
  int info = 0;
  dgetrs_(&trans, &n, &nrhs, lu_.data(), &n, pivots_.data(), x.data(), &n, &info);
  return x;
}

double DenseLu::inverse_norm_estimate() const {
  // Hager's method with Higham's refinements (LAPACK dlacn2, as Eigen's PartialPivLU::rcond):
  // ‖A⁻¹‖₁ >= ‖A⁻¹ v‖₁ / ‖v‖₁, maximised over v by a few steps of a subgradient ascent on the
  // unit 1-ball (solves with A and Aᵀ), plus Higham's alternating test vector.
  const Eigen::Index n = lu_.rows();
  if (n == 1) return 1.0 / std::abs(lu_(0, 0));
  constexpr int kMaxIterations = 5;
  Eigen::VectorXd v = solve_with('N', Eigen::VectorXd::Constant(n, 1.0 / n));
  double estimate = v.lpNorm<1>();
  auto signs = [](const Eigen::VectorXd& y) -> Eigen::VectorXd {  // ±1, LAPACK's sign(1, y_i)
    return (y.array() >= 0).select(Eigen::VectorXd::Ones(y.size()), -1.0);
  };
  Eigen::VectorXd sign = signs(v);
  Eigen::Index j = 0, previous = -1;
  Eigen::VectorXd z = solve_with('T', sign);
  for (int k = 0; k < kMaxIterations; ++k) {
    z.cwiseAbs().maxCoeff(&j);
    if (j == previous) break;
    v = solve_with('N', Eigen::VectorXd::Unit(n, j));
    const double next = v.lpNorm<1>();
    if (next <= estimate) break;
    estimate = next;
    const Eigen::VectorXd next_sign = signs(v);
    if (next_sign == sign) break;
    sign = next_sign;
    z = solve_with('T', sign);
    previous = j;
  }
  Eigen::VectorXd alternating(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    alternating[i] = (i % 2 == 0 ? 1.0 : -1.0) * (1.0 + static_cast<double>(i) / (n - 1));
  }
  const double alternate = 2.0 * solve_with('N', alternating).lpNorm<1>() / (3.0 * n);
  return std::max(estimate, alternate);
}

Eigen::VectorXd DenseLu::solve(const Eigen::VectorXd& b) const {
  STICKSLIP_VERIFY(ok_ && b.size() == lu_.rows(), "DenseLu::solve: no factorisation or wrong size");
  const ScopedBlasThreads single_thread(1);
  return solve_with('N', b);
}

bool ComplexDenseLu::compute(const Eigen::MatrixXcd& A) {
  STICKSLIP_VERIFY(A.rows() == A.cols(), "ComplexDenseLu: the matrix must be square");
  ok_ = false;
  const int n = static_cast<int>(A.rows());
  if (n == 0 || !A.allFinite()) return false;
  const ScopedBlasThreads single_thread(1);
  lu_ = A;
  pivots_.resize(n);
  int info = 0;
  zgetrf_(&n, &n, lu_.data(), &n, pivots_.data(), &info);
  ok_ = info == 0;  // info > 0: exact zero pivot
  return ok_;
}

Eigen::VectorXcd ComplexDenseLu::solve(const Eigen::VectorXcd& b) const {
  if (!ok_) {
    return Eigen::VectorXcd::Constant(b.size(), std::numeric_limits<double>::quiet_NaN());
  }
  Eigen::VectorXcd x = b;
  const int n = static_cast<int>(lu_.rows()), nrhs = 1;
  const char trans = 'N';
  int info = 0;
  const ScopedBlasThreads single_thread(1);
  zgetrs_(&trans, &n, &nrhs, lu_.data(), &n, pivots_.data(), x.data(), &n, &info);
  return x;
}

}  // namespace stickslip
