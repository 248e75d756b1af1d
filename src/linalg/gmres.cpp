#include "linalg/gmres.h"

#include <cmath>

#include <Eigen/Dense>

#include "core/errors.h"

namespace stickslip {

GmresSummary gmres(const LinearOperator& apply, const LinearOperator& precondition,
                   const Eigen::VectorXd& b, Eigen::VectorXd& x, const GmresOptions& options) {
  require(options.restart >= 1, "GmresOptions.restart", std::to_string(options.restart), ">= 1");
  require(options.max_iterations >= 1, "GmresOptions.max_iterations",
          std::to_string(options.max_iterations), ">= 1");
  const Eigen::Index n = b.size();
  GmresSummary summary;
  x.setZero(n);
  const double bnorm = b.norm();
  if (bnorm == 0) {
    summary.converged = true;
    return summary;
  }
  const double target = options.tolerance * bnorm;
  const int m = options.restart;
  Eigen::VectorXd r = b;
  Eigen::MatrixXd V(n, m + 1), H(m + 1, m);
  Eigen::VectorXd cs(m), sn(m), g(m + 1), w;
  while (true) {
    const double beta = r.norm();
    summary.relative_residual = beta / bnorm;
    if (!std::isfinite(beta)) return summary;
    if (beta <= target) {
      summary.converged = true;
      return summary;
    }
    if (summary.iterations >= options.max_iterations) return summary;
    H.setZero();
    g.setZero();
    g[0] = beta;
    V.col(0) = r / beta;
    int j = 0;
    while (j < m && summary.iterations < options.max_iterations) {
      w = apply(precondition(V.col(j)));
      ++summary.iterations;
      for (int i = 0; i <= j; ++i) {  // modified Gram–Schmidt
        H(i, j) = w.dot(V.col(i));
        w -= H(i, j) * V.col(i);
      }
      H(j + 1, j) = w.norm();
      if (H(j + 1, j) > 0) V.col(j + 1) = w / H(j + 1, j);
      for (int i = 0; i < j; ++i) {  // previous Givens rotations
        const double t = cs[i] * H(i, j) + sn[i] * H(i + 1, j);
        H(i + 1, j) = -sn[i] * H(i, j) + cs[i] * H(i + 1, j);
        H(i, j) = t;
      }
      const double d = std::hypot(H(j, j), H(j + 1, j));
      if (!(d > 0)) break;  // breakdown with a singular Hessenberg matrix
      cs[j] = H(j, j) / d;
      sn[j] = H(j + 1, j) / d;
      H(j, j) = d;
      H(j + 1, j) = 0;
      g[j + 1] = -sn[j] * g[j];
      g[j] *= cs[j];
      ++j;
      if (std::abs(g[j]) <= target) break;
    }
    if (j == 0) return summary;
    const Eigen::VectorXd y = H.topLeftCorner(j, j).triangularView<Eigen::Upper>().solve(g.head(j));
    x += precondition(V.leftCols(j) * y);
    r = b - apply(x);
  }
}

}  // namespace stickslip
