#include "contact/friction_contact.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "core/errors.h"

namespace stickslip {

namespace {

void require_finite_at_least(double value, double min, bool strict, const std::string& field) {
  const bool ok = std::isfinite(value) && (strict ? value > min : value >= min);
  require(ok, field, std::to_string(value),
          std::string(strict ? "> " : ">= ") + std::to_string(min) + " and finite");
}

void check_inputs(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp,
                  const Eigen::MatrixXd* df_dp, int m) {
  STICKSLIP_VERIFY(u.rows() == m && u.cols() >= 1, "element march: u must be m x N");
  STICKSLIP_VERIFY((du_dp == nullptr) == (df_dp == nullptr),
                   "element march: du_dp and df_dp both set or both null");
  STICKSLIP_VERIFY(du_dp == nullptr || du_dp->rows() == m * u.cols(),
                   "element march: du_dp must have m*N rows");
}

}  // namespace

void validate(const FrictionContactParameters& p) {
  require_finite_at_least(p.kt, 0.0, true, "FrictionContactParameters.kt");
  require_finite_at_least(p.kn, 0.0, true, "FrictionContactParameters.kn");
  require_finite_at_least(p.mu, 0.0, false, "FrictionContactParameters.mu");
  require_finite_at_least(p.normal_preload, 0.0, false, "FrictionContactParameters.normal_preload");
  require_finite_at_least(p.gap, 0.0, false, "FrictionContactParameters.gap");
}

void validate(const JenkinsParameters& p) {
  require_finite_at_least(p.kt, 0.0, true, "JenkinsParameters.kt");
  require_finite_at_least(p.mu, 0.0, false, "JenkinsParameters.mu");
  require_finite_at_least(p.normal_load, 0.0, false, "JenkinsParameters.normal_load");
}

FrictionContact3D::FrictionContact3D(FrictionContactParameters parameters, MarchOptions march)
    : parameters_(parameters), march_(march) {
  validate(parameters_);
  validate(march_);
}

CycleStatistics FrictionContact3D::march(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp,
                                         Eigen::MatrixXd& f, Eigen::MatrixXd* df_dp) const {
  check_inputs(u, du_dp, df_dp, 3);
  const int n = static_cast<int>(u.cols());
  const bool jac = du_dp != nullptr;
  const int np = jac ? static_cast<int>(du_dp->cols()) : 0;
  const double kt = parameters_.kt, kn = parameters_.kn, mu = parameters_.mu;
  const double n0 = parameters_.normal_preload, g0 = parameters_.gap;

  f.resize(3, n);
  if (jac) df_dp->resize(3 * n, np);

  // State: τ, u_t,prev and their derivatives. Virgin state: τ = 0 at u_t = 0.
  Eigen::Vector2d tau = Eigen::Vector2d::Zero();
  Eigen::Vector2d ut_prev = Eigen::Vector2d::Zero();
  // ∂τ/∂p as 2 x np (column q = ∂τ/∂p_q). The derivative updates below are written as plain
  // loops over q: no temporaries in the time march.
  Eigen::MatrixXd dtau = Eigen::MatrixXd::Zero(2, np);
  int prev = -1;  // sample holding u_t,prev (−1: the virgin state, independent of p)
  const double* du = jac ? du_dp->data() : nullptr;
  double* df = jac ? df_dp->data() : nullptr;
  const Eigen::Index ld = 3 * n;  // leading dimension of du_dp, df_dp (column-major)

  CycleStatistics stats;
  stats.converged = false;
  int stick = 0, slip = 0, separation = 0;
  for (int period = 1; period <= march_.max_periods; ++period) {
    const Eigen::Vector2d tau_start = tau;
    stick = slip = separation = 0;
    double force_scale = 0.0;
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector2d ut = u.col(j).head<2>();
      const double normal = n0 + kn * (u(2, j) - g0);
      if (normal <= 0.0) {  // separation: no force, the tangential spring is released
        ++separation;
        tau.setZero();
        f.col(j).setZero();
        if (jac) {
          dtau.setZero();
          for (int q = 0; q < np; ++q) {
            for (int r = 0; r < 3; ++r) df[3 * j + r + q * ld] = 0.0;
          }
        }
      } else {
        const Eigen::Vector2d tau_pred = tau + kt * (ut - ut_prev);
        const double limit = mu * normal;
        const double norm_pred = tau_pred.norm();
        const bool sticks = norm_pred <= limit;
        Eigen::Vector2d e = Eigen::Vector2d::Zero();
        if (sticks) {
          ++stick;
          tau = tau_pred;
        } else {  // slip: radial return onto the circle |τ| = μN
          ++slip;
          e = tau_pred / norm_pred;
          tau = limit * e;
        }
        f(0, j) = tau[0];
        f(1, j) = tau[1];
        f(2, j) = normal;
        if (jac) {
          // Stick:  ∂τ = ∂τ_pred = ∂τ_prev + kt (∂u_t − ∂u_t,prev).
          // Slip:   ∂τ = μ e ∂N + (μN/|τ_pred|) (I − e eᵀ) ∂τ_pred,  ∂N = kn ∂w.
          const double a = sticks ? 0.0 : limit / norm_pred;
          const double p00 = 1 - e[0] * e[0], p01 = -e[0] * e[1], p11 = 1 - e[1] * e[1];
          for (int q = 0; q < np; ++q) {
            const double* duq = du + q * ld;
            double* dfq = df + q * ld;
            double d0 = dtau(0, q) + kt * duq[3 * j];
            double d1 = dtau(1, q) + kt * duq[3 * j + 1];
            if (prev >= 0) {
              d0 -= kt * duq[3 * prev];
              d1 -= kt * duq[3 * prev + 1];
            }
            const double dn = kn * duq[3 * j + 2];
            if (!sticks) {
              const double s0 = mu * e[0] * dn + a * (p00 * d0 + p01 * d1);
              const double s1 = mu * e[1] * dn + a * (p01 * d0 + p11 * d1);
              d0 = s0;
              d1 = s1;
            }
            dtau(0, q) = d0;
            dtau(1, q) = d1;
            dfq[3 * j] = d0;
            dfq[3 * j + 1] = d1;
            dfq[3 * j + 2] = dn;
          }
        }
      }
      ut_prev = ut;
      prev = j;
      force_scale = std::max(force_scale, f.col(j).head<2>().cwiseAbs().maxCoeff());
    }
    stats.periods = period;
    // The state (τ, u_t,prev) repeats: u_t,prev is the last sample from period 2 on.
    if (period >= 2 && (tau - tau_start).cwiseAbs().maxCoeff() <= march_.tolerance * force_scale) {
      stats.converged = true;
      break;
    }
  }
  stats.stick_fraction = static_cast<double>(stick) / n;
  stats.slip_fraction = static_cast<double>(slip) / n;
  stats.separation_fraction = static_cast<double>(separation) / n;
  double energy = 0.0;
  for (int j = 0; j < n; ++j) {
    const int i = (j + n - 1) % n;
    energy +=
        0.5 *
        (f.col(j).head<2>() + f.col(i).head<2>()).dot(u.col(j).head<2>() - u.col(i).head<2>());
  }
  stats.dissipated_energy = energy;
  return stats;
}

Jenkins1D::Jenkins1D(JenkinsParameters parameters, MarchOptions march)
    : parameters_(parameters), march_(march) {
  validate(parameters_);
  validate(march_);
}

CycleStatistics Jenkins1D::march(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp,
                                 Eigen::MatrixXd& f, Eigen::MatrixXd* df_dp) const {
  check_inputs(u, du_dp, df_dp, 1);
  const int n = static_cast<int>(u.cols());
  const bool jac = du_dp != nullptr;
  const int np = jac ? static_cast<int>(du_dp->cols()) : 0;
  const double kt = parameters_.kt;
  const double limit = parameters_.mu * parameters_.normal_load;

  f.resize(1, n);
  if (jac) df_dp->resize(n, np);
  double tau = 0.0, u_prev = 0.0;
  // Derivative rows kept as column vectors (GCC 12 warns spuriously on dynamic row vectors).
  Eigen::VectorXd dtau = Eigen::VectorXd::Zero(np);
  int prev = -1;  // sample holding u_prev (−1: the virgin state, u_prev = 0 independent of p)

  CycleStatistics stats;
  stats.converged = false;
  int stick = 0, slip = 0;
  for (int period = 1; period <= march_.max_periods; ++period) {
    const double tau_start = tau;
    stick = slip = 0;
    double force_scale = 0.0;
    for (int j = 0; j < n; ++j) {
      const double tau_pred = tau + kt * (u(0, j) - u_prev);
      if (std::abs(tau_pred) <= limit) {
        ++stick;
        tau = tau_pred;
        if (jac) {
          dtau += kt * du_dp->row(j).transpose();
          if (prev >= 0) dtau -= kt * du_dp->row(prev).transpose();
        }
      } else {
        ++slip;
        tau = tau_pred > 0.0 ? limit : -limit;
        if (jac) dtau.setZero();  // fixed normal load: the slip force does not depend on u
      }
      f(0, j) = tau;
      if (jac) df_dp->row(j) = dtau.transpose();
      u_prev = u(0, j);
      prev = j;
      force_scale = std::max(force_scale, std::abs(tau));
    }
    stats.periods = period;
    if (period >= 2 && std::abs(tau - tau_start) <= march_.tolerance * force_scale) {
      stats.converged = true;
      break;
    }
  }
  stats.stick_fraction = static_cast<double>(stick) / n;
  stats.slip_fraction = static_cast<double>(slip) / n;
  double energy = 0.0;
  for (int j = 0; j < n; ++j) {
    const int i = (j + n - 1) % n;
    energy += 0.5 * (f(0, j) + f(0, i)) * (u(0, j) - u(0, i));
  }
  stats.dissipated_energy = energy;
  return stats;
}

}  // namespace stickslip
