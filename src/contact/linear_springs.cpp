#include "contact/linear_springs.h"

#include <cmath>
#include <string>
#include <utility>

#include "core/errors.h"

namespace stickslip {

LinearSprings::LinearSprings(Eigen::VectorXd k) : k_(std::move(k)) {
  if (k_.size() < 1) throw InvalidInput("linear_springs: at least one stiffness is needed");
  for (Eigen::Index d = 0; d < k_.size(); ++d) {
    if (!std::isfinite(k_(d)) || k_(d) < 0) {
      throw InvalidInput("linear_springs: stiffness " + std::to_string(d) +
                         " must be finite and >= 0");
    }
  }
}

CycleStatistics LinearSprings::march(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp,
                                     Eigen::MatrixXd& f, Eigen::MatrixXd* df_dp) const {
  const Eigen::Index m = k_.size(), n = u.cols();
  if (u.rows() != m || (du_dp == nullptr) != (df_dp == nullptr) ||
      (du_dp && du_dp->rows() != m * n)) {
    throw InvalidInput("linear_springs: u must have " + std::to_string(m) +
                       " rows and du_dp (m·N rows) and df_dp must be given together");
  }
  f = k_.asDiagonal() * u;
  if (df_dp) {
    df_dp->resize(du_dp->rows(), du_dp->cols());
    for (Eigen::Index j = 0; j < n; ++j) {
      for (Eigen::Index d = 0; d < m; ++d) df_dp->row(j * m + d) = k_(d) * du_dp->row(j * m + d);
    }
  }
  CycleStatistics stats;
  stats.stick_fraction = 1.0;
  stats.periods = 1;
  return stats;
}

ElementPtr make_linear_springs(const Eigen::VectorXd& k) {
  return std::make_shared<LinearSprings>(k);
}

}  // namespace stickslip
