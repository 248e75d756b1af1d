#include "contact/springs.h"

#include <cmath>
#include <string>

#include "core/errors.h"
#include "core/format.h"

namespace stickslip {

namespace {

void check_inputs(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp,
                  const Eigen::MatrixXd* df_dp) {
  STICKSLIP_VERIFY(u.rows() == 1 && u.cols() >= 1, "element march: u must be 1 x N");
  STICKSLIP_VERIFY((du_dp == nullptr) == (df_dp == nullptr),
                   "element march: du_dp and df_dp both set or both null");
  STICKSLIP_VERIFY(du_dp == nullptr || du_dp->rows() == u.cols(),
                   "element march: du_dp must have N rows");
}

}  // namespace

void validate(const UnilateralSpringParameters& p) {
  require(std::isfinite(p.k) && p.k > 0.0, "UnilateralSpringParameters.k", format_number(p.k),
          "> 0 and finite");
  require(std::isfinite(p.gap), "UnilateralSpringParameters.gap", format_number(p.gap), "finite");
  require(std::isfinite(p.preload) && p.preload >= 0.0, "UnilateralSpringParameters.preload",
          format_number(p.preload), ">= 0 and finite");
}

void validate(const CubicSpringParameters& p) {
  require(std::isfinite(p.k1), "CubicSpringParameters.k1", format_number(p.k1), "finite");
  require(std::isfinite(p.k3), "CubicSpringParameters.k3", format_number(p.k3), "finite");
}

UnilateralSpring::UnilateralSpring(UnilateralSpringParameters parameters)
    : parameters_(parameters) {
  validate(parameters_);
}

CycleStatistics UnilateralSpring::march(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp,
                                        Eigen::MatrixXd& f, Eigen::MatrixXd* df_dp) const {
  check_inputs(u, du_dp, df_dp);
  const int n = static_cast<int>(u.cols());
  f.resize(1, n);
  if (df_dp) df_dp->resize(n, du_dp->cols());
  int closed = 0;
  for (int j = 0; j < n; ++j) {
    const double force = parameters_.preload + parameters_.k * (u(0, j) - parameters_.gap);
    const bool is_closed = force > 0.0;
    closed += is_closed;
    f(0, j) = is_closed ? force : 0.0;
    if (df_dp) {
      if (is_closed) {
        df_dp->row(j) = parameters_.k * du_dp->row(j);
      } else {
        df_dp->row(j).setZero();
      }
    }
  }
  CycleStatistics stats;
  stats.stick_fraction = static_cast<double>(closed) / n;
  stats.separation_fraction = 1.0 - stats.stick_fraction;
  stats.periods = 1;
  return stats;
}

CubicSpring::CubicSpring(CubicSpringParameters parameters) : parameters_(parameters) {
  validate(parameters_);
}

CycleStatistics CubicSpring::march(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp,
                                   Eigen::MatrixXd& f, Eigen::MatrixXd* df_dp) const {
  check_inputs(u, du_dp, df_dp);
  const int n = static_cast<int>(u.cols());
  f.resize(1, n);
  if (df_dp) df_dp->resize(n, du_dp->cols());
  for (int j = 0; j < n; ++j) {
    const double x = u(0, j);
    f(0, j) = parameters_.k1 * x + parameters_.k3 * x * x * x;
    if (df_dp) df_dp->row(j) = (parameters_.k1 + 3.0 * parameters_.k3 * x * x) * du_dp->row(j);
  }
  CycleStatistics stats;
  stats.stick_fraction = 1.0;
  stats.periods = 1;
  return stats;
}

}  // namespace stickslip
