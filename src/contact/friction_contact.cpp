#include "contact/friction_contact.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Dense>

#include "core/errors.h"
#include "core/format.h"

namespace stickslip {

namespace {

// The periodicity Newton inverts I − M, M = ∂P/∂τ_s the 2 x 2 Jacobian of the period map of the
// start state (entries O(1): products of radial-return contractions with factors in [0, 1]),
// only when |det(I − M)| > kPeriodMapSingular. The determinant vanishes as the cycle's slip does
// (M → I: a stuck cycle has no unique start state); M's entries carry round-off of about
// N·eps ≈ 1e-14 for the sample counts used (N of 32–256), so below that the determinant is noise
// and its inverse meaningless. Then a plain period is marched instead of the Newton step, and
// the start state's derivative is left at ∂P/∂p (the stuck cycle's).
constexpr double kPeriodMapSingular = 1e-14;

void require_finite_at_least(double value, double min, bool strict, const std::string& field) {
  const bool ok = std::isfinite(value) && (strict ? value > min : value >= min);
  require(ok, field, format_number(value),
          std::string(strict ? "> " : ">= ") + format_number(min) + " and finite");
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
  require(std::isfinite(p.gap), "FrictionContactParameters.gap", format_number(p.gap), "finite");
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

namespace {

// One period of the 3D friction law (header contract) from the start state τ (in/out: the end
// state on return). wrap: u_t,prev = u_t(t_{N−1}) (the periodic wrap), else the virgin u_t,prev =
// 0. M (optional): ∂τ_end/∂τ_start (2 x 2). dtau (optional, 2 x np, in/out) with du/df: the
// derivative of τ with respect to the parameters p on entry (of τ_start) and on exit (of τ_end);
// df receives ∂f(t_j)/∂p (column-major, leading dimension ld = 3N).
struct PeriodCounts {
  int stick = 0, slip = 0, separation = 0;
  double force_scale = 0.0;  // max_j |τ_i(t_j)|
};

PeriodCounts march_period(const FrictionContactParameters& prm, const Eigen::MatrixXd& u, bool wrap,
                          Eigen::Vector2d& tau, Eigen::Matrix2d* M, Eigen::MatrixXd* dtau,
                          const double* du, double* df, Eigen::Index ld, Eigen::MatrixXd& f) {
  const int n = static_cast<int>(u.cols());
  const int np = dtau ? static_cast<int>(dtau->cols()) : 0;
  const double kt = prm.kt, kn = prm.kn, mu = prm.mu;
  PeriodCounts counts;
  Eigen::Vector2d ut_prev =
      wrap ? Eigen::Vector2d(u.col(n - 1).head<2>()) : Eigen::Vector2d::Zero();
  int prev = wrap ? n - 1 : -1;  // sample holding u_t,prev (−1: virgin, independent of p)
  if (M) M->setIdentity();
  for (int j = 0; j < n; ++j) {
    const Eigen::Vector2d ut = u.col(j).head<2>();
    const double normal = prm.normal_preload + kn * (u(2, j) - prm.gap);
    if (normal <= 0.0) {  // separation: no force, the tangential spring is released
      ++counts.separation;
      tau.setZero();
      f.col(j).setZero();
      if (M) M->setZero();
      if (dtau) {
        dtau->setZero();
        for (int q = 0; q < np; ++q) {
          for (int r = 0; r < 3; ++r) df[3 * j + r + q * ld] = 0.0;
        }
      }
    } else {
      const Eigen::Vector2d tau_pred = tau + kt * (ut - ut_prev);
      const double limit = mu * normal;
      // |τ_pred| <= μN compared squared: no square root on the (common) stick path, whose march
      // is a chain of dependent samples.
      const bool sticks = tau_pred.squaredNorm() <= limit * limit;
      double norm_pred = 0.0;
      Eigen::Vector2d e = Eigen::Vector2d::Zero();
      if (sticks) {
        ++counts.stick;
        tau = tau_pred;
      } else {  // slip: radial return onto the circle |τ| = μN
        ++counts.slip;
        norm_pred = tau_pred.norm();
        e = tau_pred / norm_pred;
        tau = limit * e;
      }
      f(0, j) = tau[0];
      f(1, j) = tau[1];
      f(2, j) = normal;
      // Stick:  ∂τ = ∂τ_pred = ∂τ_prev + kt (∂u_t − ∂u_t,prev).
      // Slip:   ∂τ = μ e ∂N + (μN/|τ_pred|) (I − e eᵀ) ∂τ_pred,  ∂N = kn ∂w.
      const double a = sticks ? 0.0 : limit / norm_pred;
      const double p00 = 1 - e[0] * e[0], p01 = -e[0] * e[1], p11 = 1 - e[1] * e[1];
      if (M && !sticks) {
        Eigen::Matrix2d P;
        P << p00, p01, p01, p11;
        *M = (a * P) * (*M);
      }
      if (dtau) {
        Eigen::MatrixXd& dt = *dtau;
        for (int q = 0; q < np; ++q) {
          const double* duq = du + q * ld;
          double* dfq = df + q * ld;
          double d0 = dt(0, q) + kt * duq[3 * j];
          double d1 = dt(1, q) + kt * duq[3 * j + 1];
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
          dt(0, q) = d0;
          dt(1, q) = d1;
          dfq[3 * j] = d0;
          dfq[3 * j + 1] = d1;
          dfq[3 * j + 2] = dn;
        }
      }
    }
    ut_prev = ut;
    prev = j;
    counts.force_scale = std::max(counts.force_scale, f.col(j).head<2>().cwiseAbs().maxCoeff());
  }
  return counts;
}

}  // namespace

CycleStatistics FrictionContact3D::march(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp,
                                         Eigen::MatrixXd& f, Eigen::MatrixXd* df_dp) const {
  check_inputs(u, du_dp, df_dp, 3);
  const int n = static_cast<int>(u.cols());
  const bool jac = du_dp != nullptr;
  const int np = jac ? static_cast<int>(du_dp->cols()) : 0;
  f.resize(3, n);
  if (jac) df_dp->resize(3 * n, np);
  const double* du = jac ? du_dp->data() : nullptr;
  double* df = jac ? df_dp->data() : nullptr;
  const Eigen::Index ld = 3 * n;  // leading dimension of du_dp, df_dp (column-major)
  auto closed = [&](const Eigen::Vector2d& end, const Eigen::Vector2d& start, double scale) {
    return (end - start).cwiseAbs().maxCoeff() <= march_.tolerance * scale;
  };

  // Periods 1 and 2 from the virgin state (τ = 0 at u_t = 0), derivatives carried along. A cycle
  // that sticks throughout (or separates once) repeats after period 2; its mean tangential force
  // is the one reached from the virgin state (a stuck cycle is neutrally stable: any offset of τ
  // repeats, so the history fixes it).
  // The two periods are marched without derivatives first: only a cycle that closes here takes
  // its derivatives from them (marched again with derivatives, same forces); the others get theirs
  // from the periodicity condition below.
  // A period that sticks at every sample from the virgin state has τ(t_j) = kt u_t(t_j) (the stick
  // recursion telescopes), so the second period starts at τ = kt u_t(t_{N−1}) and its predictor
  // is again kt u_t(t_j) at every sample: it repeats the first exactly and is not marched.
  Eigen::Vector2d tau = Eigen::Vector2d::Zero();
  Eigen::MatrixXd dtau;
  if (jac) dtau.setZero(2, np);
  const PeriodCounts first =
      march_period(parameters_, u, false, tau, nullptr, nullptr, nullptr, nullptr, ld, f);
  Eigen::Vector2d tau_start = tau;
  PeriodCounts counts = first;
  Eigen::Matrix2d M;  // ∂τ_end/∂τ_start of period 2: the first Newton step below if it is needed
  if (first.stick != n) {
    counts = march_period(parameters_, u, true, tau, &M, nullptr, nullptr, nullptr, ld, f);
  }
  CycleStatistics stats;
  stats.periods = 2;
  stats.converged = first.stick == n || closed(tau, tau_start, counts.force_scale);
  if (stats.converged && jac && first.stick == n) {
    // Stuck at every sample of both periods: the stick recursion from the virgin state telescopes
    // to τ(t_j) = kt u_t(t_j), so ∂f = diag(kt, kt, kn) ∂u sample by sample.
    const double kt = parameters_.kt, kn = parameters_.kn;
    for (int q = 0; q < np; ++q) {
      const double* duq = du + q * ld;
      double* dfq = df + q * ld;
      for (int j = 0; j < n; ++j) {
        dfq[3 * j] = kt * duq[3 * j];
        dfq[3 * j + 1] = kt * duq[3 * j + 1];
        dfq[3 * j + 2] = kn * duq[3 * j + 2];
      }
    }
  } else if (stats.converged && jac) {
    tau.setZero();
    march_period(parameters_, u, false, tau, nullptr, &dtau, du, df, ld, f);
    counts = march_period(parameters_, u, true, tau, nullptr, &dtau, du, df, ld, f);
  }

  if (!stats.converged) {
    // Partial slip in 2D: plain marching contracts the start state τ_s only by the radial returns
    // (slowly when the slip is small against the stick range). Solve the periodicity condition
    // P(τ_s) = τ_s directly by Newton on the two components of τ_s, with M = ∂P/∂τ_s marched
    // alongside; a step that does not reduce |P(τ_s) − τ_s| is replaced by one plain period.
    // With slip in the cycle P is a contraction (products of a (I − e eᵀ), a < 1), so the fixed
    // point is unique and the same one marching converges to.
    // The first trial is the Newton step from period 2 (start tau_start, end tau, M).
    Eigen::Vector2d best_start = tau_start, best_end = tau;
    double best = (tau - tau_start).norm();
    const Eigen::Matrix2d A2 = Eigen::Matrix2d::Identity() - M;
    Eigen::Vector2d ts = std::abs(A2.determinant()) > kPeriodMapSingular
                             ? Eigen::Vector2d(tau_start + A2.inverse() * (tau - tau_start))
                             : tau;
    while (stats.periods < march_.max_periods) {
      Eigen::Vector2d te = ts;
      counts = march_period(parameters_, u, true, te, &M, nullptr, nullptr, nullptr, ld, f);
      ++stats.periods;
      const double res = (te - ts).norm();
      if (closed(te, ts, counts.force_scale)) {
        best_start = ts;
        best_end = te;
        stats.converged = true;
        break;
      }
      if (res < best) {
        best = res;
        best_start = ts;
        best_end = te;
        const Eigen::Matrix2d A = Eigen::Matrix2d::Identity() - M;
        const bool newton = std::abs(A.determinant()) > kPeriodMapSingular;
        ts = newton ? Eigen::Vector2d(ts + A.inverse() * (te - ts)) : te;
      } else {
        ts = best_end;  // the Newton step did not help: a plain period from the best state
        best = std::numeric_limits<double>::infinity();
      }
    }
    // The converged cycle starts at τ_s = best_start. Its exact derivative: τ_s = P(τ_s, p) gives
    // ∂τ_s/∂p = (I − M)⁻¹ ∂P/∂p (implicit function theorem; (I − M) is invertible when the cycle
    // slips). Pass 1 gives ∂P/∂p (τ_s held fixed) and M, pass 2 the cycle with the exact df.
    // Without derivatives a closed cycle is already in f (the last period marched started at
    // best_start); otherwise the cycle from best_start is marched once more.
    tau = best_start;
    if (jac) {
      dtau.setZero();
      march_period(parameters_, u, true, tau, &M, &dtau, du, df, ld, f);
      const Eigen::Matrix2d A = Eigen::Matrix2d::Identity() - M;
      if (std::abs(A.determinant()) > kPeriodMapSingular) dtau = A.inverse() * dtau;
      tau = best_start;
    }
    if (jac || !stats.converged) {
      counts = march_period(parameters_, u, true, tau, nullptr, jac ? &dtau : nullptr, du, df, ld,
                            f);
    }
  }
  stats.stick_fraction = static_cast<double>(counts.stick) / n;
  stats.slip_fraction = static_cast<double>(counts.slip) / n;
  stats.separation_fraction = static_cast<double>(counts.separation) / n;
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
