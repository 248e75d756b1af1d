#include "hbm/nonlinear_mode.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "core/errors.h"
#include "core/format.h"

namespace stickslip {

namespace {
using Complex = std::complex<double>;
constexpr Complex kI{0.0, 1.0};
// A mode whose contact motion ||Ψη|| is below this share of the largest contact motion of a unit
// modal coordinate (max_r ||Ψ_r||) does not move the contacts: its nonlinear mode is the linear one
// and the condensed unknowns cannot carry it (the amplitude equation would be 0 = a).
constexpr double kNoContactMotion = 1e-10;
}  // namespace

void validate(const NonlinearModeOptions& options) {
  if (options.mode < 1) {
    throw InvalidInput("NonlinearModeOptions.mode = " + std::to_string(options.mode) +
                       ": must be >= 1 (modes are numbered from 1)");
  }
  if (options.amplitudes.empty()) {
    throw InvalidInput("NonlinearModeOptions.amplitudes: empty, expected at least one amplitude");
  }
  for (size_t i = 0; i < options.amplitudes.size(); ++i) {
    const double a = options.amplitudes[i];
    if (!(std::isfinite(a) && a > 0)) {
      throw InvalidInput("NonlinearModeOptions.amplitudes[" + std::to_string(i) +
                         "] = " + format_number(a) + ": must be finite and > 0");
    }
    if (i > 0 && !(a > options.amplitudes[i - 1])) {
      throw InvalidInput("NonlinearModeOptions.amplitudes[" + std::to_string(i) +
                         "] = " + format_number(a) + ": the amplitudes must increase strictly");
    }
  }
  validate(options.newton, "NonlinearModeOptions.newton.");
  if (options.max_step_halvings < 0) {
    throw InvalidInput("NonlinearModeOptions.max_step_halvings = " +
                       std::to_string(options.max_step_halvings) + ": must be >= 0");
  }
}

StuckModes stuck_modes(const HarmonicBalanceSystem& system) {
  const LinearModel& model = system.linear_model();
  const Eigen::MatrixXd& Psi = system.contact_modes();
  const int nu = system.contact_rows();
  // Element tangents at the static state: the AFT Jacobian of a constant signal (harmonic 0 only)
  // maps the constant of one row to the constant of the others.
  const Aft tangent_aft(FourierBasis(HarmonicSet({0}), 2));
  Eigen::VectorXd u0 = system.static_displacement();
  if (u0.size() != nu) u0 = Eigen::VectorXd::Zero(nu);
  Eigen::MatrixXd Kt = Eigen::MatrixXd::Zero(nu, nu);
  Eigen::VectorXd fp;
  Eigen::MatrixXd jp;
  for (size_t p = 0; p < system.pairs().size(); ++p) {
    const int m = system.pairs()[p].element->dimension(), r = system.pair_row(static_cast<int>(p));
    tangent_aft.evaluate(*system.pairs()[p].element, u0.segment(r, m), Eigen::VectorXd(), fp, &jp);
    Kt.block(r, r, m, m) = jp;
  }
  Eigen::MatrixXd K = Psi.transpose() * (0.5 * (Kt + Kt.transpose())) * Psi;
  K.diagonal() += model.omega2;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (K + K.transpose()));
  STICKSLIP_VERIFY(eig.info() == Eigen::Success, "stuck_modes: the eigen-solver failed");
  StuckModes out{eig.eigenvalues(), eig.eigenvectors()};
  for (Eigen::Index j = 0; j < out.eta.cols(); ++j) {
    Eigen::Index i = 0;
    out.eta.col(j).cwiseAbs().maxCoeff(&i);
    if (out.eta(i, j) < 0) out.eta.col(j) *= -1.0;
  }
  return out;
}

NonlinearModeSystem::NonlinearModeSystem(const HarmonicBalanceSystem& system, Eigen::VectorXd eta)
    : system_(system), eta_(std::move(eta)) {
  if (system.travelling_wave()) {
    throw InvalidInput("NonlinearModeSystem: a travelling-wave (cyclic) system is not supported");
  }
  const LinearModel& model = system.linear_model();
  n_ = system.size();
  rows_ = system.contact_rows();
  nc_ = system.unknown_harmonics().coefficient_count();
  nm_ = static_cast<int>(model.omega2.size());
  STICKSLIP_VERIFY(eta_.size() == nm_, "NonlinearModeSystem: η has the wrong size");
  dense_damping_ = model.modal_damping_matrix.size() > 0;
  const Eigen::VectorXd contact = system.contact_modes() * eta_;
  s_ = contact.norm();
  if (!(s_ > 0)) s_ = (model.Phi * eta_).norm();
  if (!(s_ > 0)) s_ = 1.0;
  // The linear mode's frequency and ξ: the Rayleigh quotients of the stuck stiffness and of the
  // damping (exact for the mode when the damping is proportional).
  const StuckModes modes = stuck_modes(system);
  Eigen::MatrixXd K =
      Eigen::MatrixXd(modes.eta * modes.omega2.asDiagonal() * modes.eta.transpose());
  omega_lin_ = std::sqrt(std::max(eta_.dot(K * eta_), 0.0));
  xi_lin_ = dense_damping_ ? eta_.dot(model.modal_damping_matrix * eta_)
                           : eta_.dot(model.modal_damping.cwiseProduct(eta_));
}

double NonlinearModeSystem::residual_scale_at(double lambda) const {
  const double dynamic = std::exp(lambda) * s_;
  return system_.unknown_harmonics().has_static() ? dynamic + system_.residual_scale() : dynamic;
}

void NonlinearModeSystem::flexibility(int k, double omega, double xi, const Eigen::MatrixXcd& rhs,
                                      Eigen::MatrixXcd* H_rhs, Eigen::MatrixXcd* dH_domega_rhs,
                                      Eigen::MatrixXcd* dH_dxi_rhs) const {
  const LinearModel& model = system_.linear_model();
  const double kw = k * omega;
  if (!dense_damping_) {
    // h_r = 1 / (ω_r² − (kΩ)² + i kΩ (c_r − ξ)); ∂h/∂Ω = −h² (−2k²Ω + i k (c_r − ξ)),
    // ∂h/∂ξ = −h² (−i kΩ).
    Eigen::VectorXcd h(nm_), dw(nm_), dx(nm_);
    for (int r = 0; r < nm_; ++r) {
      const double c = model.modal_damping[r] - xi;
      h[r] = 1.0 / Complex(model.omega2[r] - kw * kw, kw * c);
      dw[r] = -h[r] * h[r] * Complex(-2.0 * k * kw, k * c);
      dx[r] = h[r] * h[r] * kI * kw;
    }
    if (H_rhs) *H_rhs = h.asDiagonal() * rhs;
    if (dH_domega_rhs) *dH_domega_rhs = dw.asDiagonal() * rhs;
    if (dH_dxi_rhs) *dH_dxi_rhs = dx.asDiagonal() * rhs;
    return;
  }
  // Z = diag(ω²) − (kΩ)² I + i kΩ (C_m − ξ I); H = Z⁻¹, ∂H/∂Ω = −H (∂Z/∂Ω) H with
  // ∂Z/∂Ω = −2k²Ω I + i k (C_m − ξ I), ∂H/∂ξ = −H (−i kΩ I) H.
  Eigen::MatrixXcd C = model.modal_damping_matrix.cast<Complex>();
  C.diagonal().array() -= Complex(xi);
  Eigen::MatrixXcd Z = (kI * kw) * C;
  Z.diagonal() += (model.omega2.array() - kw * kw).matrix().cast<Complex>();
  const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(Z);
  const Eigen::MatrixXcd X = lu.solve(rhs);
  if (H_rhs) *H_rhs = X;
  if (dH_domega_rhs) {
    Eigen::MatrixXcd dZX = (kI * static_cast<double>(k)) * (C * X);
    dZX -= (2.0 * k * kw) * X;
    *dH_domega_rhs = -lu.solve(dZX);
  }
  if (dH_dxi_rhs) *dH_dxi_rhs = (kI * kw) * lu.solve(X);
}

void NonlinearModeSystem::forces(const Eigen::VectorXd& x, Eigen::VectorXd& F,
                                 Eigen::MatrixXd* J) const {
  if (J) *J = system_.force_jacobian(x);
  system_.contact_forces(x, F, nullptr);
}

void NonlinearModeSystem::evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd& R,
                                   Eigen::MatrixXd* dR_dy, Eigen::VectorXd* dR_dlambda) const {
  STICKSLIP_VERIFY(y.size() == size(), "NonlinearModeSystem: y has the wrong size");
  const Eigen::VectorXd x = y.head(n_);
  const double omega = y[n_], xi = y[n_ + 1], a = std::exp(lambda);
  const HarmonicSet& set = system_.unknown_harmonics();
  const Eigen::MatrixXd& Psi = system_.contact_modes();
  const Eigen::MatrixXcd PsiC = Psi.cast<Complex>();

  // Harmonic 0 (static: coupled): the system's own static rows, independent of Ω and ξ. Its
  // evaluate also leaves the element forces at x for contact_forces.
  Eigen::VectorXd Rsys;
  Eigen::MatrixXd Jsys;
  if (set.has_static()) system_.evaluate(x, omega, Rsys, dR_dy ? &Jsys : nullptr, nullptr);
  Eigen::VectorXd F;
  Eigen::MatrixXd J;
  forces(x, F, dR_dy ? &J : nullptr);

  R.setZero(size());
  if (dR_dy) dR_dy->setZero(size(), size());
  if (dR_dlambda) dR_dlambda->setZero(size());
  Eigen::MatrixXd Gbig;  // 𝔾 over the harmonics ≥ 1 (zero rows for harmonic 0)
  if (dR_dy) Gbig.setZero(n_, n_);
  Complex z = 0, dz_domega = 0, dz_dxi = 0;
  Eigen::VectorXcd v;  // Ψ H_1 η: z = −vᵀ F_1
  int offset1 = -1;
  for (int pos = 0; pos < set.size(); ++pos) {
    const int k = set.harmonics()[pos], o = set.offset(pos);
    if (k == 0) {
      for (int r = 0; r < rows_; ++r) R[r * nc_ + o] = Rsys[r * nc_ + o];
      if (dR_dy) {
        for (int r = 0; r < rows_; ++r) dR_dy->row(r * nc_ + o).head(n_) = Jsys.row(r * nc_ + o);
      }
      continue;
    }
    Eigen::VectorXcd Fk(rows_);
    for (int r = 0; r < rows_; ++r) Fk[r] = Complex(F[r * nc_ + o], -F[r * nc_ + o + 1]);
    const Eigen::MatrixXcd Y = PsiC.transpose() * Fk;  // Ψᵀ F_k (nm)
    Eigen::MatrixXcd HY, dHY_dw, dHY_dxi;
    flexibility(k, omega, xi, Y, &HY, dR_dy ? &dHY_dw : nullptr, dR_dy ? &dHY_dxi : nullptr);
    const Eigen::VectorXcd W = PsiC * HY;  // G_k F_k
    for (int r = 0; r < rows_; ++r) {
      R[r * nc_ + o] = x[r * nc_ + o] + W[r].real();
      R[r * nc_ + o + 1] = x[r * nc_ + o + 1] - W[r].imag();
    }
    if (k == 1) {
      offset1 = o;
      z = -eta_.cast<Complex>().dot(HY.col(0));  // dot conjugates its first argument: η is real
    }
    if (!dR_dy) continue;
    const Eigen::VectorXcd Ww = PsiC * dHY_dw, Wx = PsiC * dHY_dxi;
    for (int r = 0; r < rows_; ++r) {
      (*dR_dy)(r * nc_ + o, n_) = Ww[r].real();
      (*dR_dy)(r * nc_ + o + 1, n_) = -Ww[r].imag();
      (*dR_dy)(r * nc_ + o, n_ + 1) = Wx[r].real();
      (*dR_dy)(r * nc_ + o + 1, n_ + 1) = -Wx[r].imag();
    }
    if (k == 1) {
      dz_domega = -eta_.cast<Complex>().dot(dHY_dw.col(0));
      dz_dxi = -eta_.cast<Complex>().dot(dHY_dxi.col(0));
      Eigen::MatrixXcd Heta;
      flexibility(1, omega, xi, eta_.cast<Complex>(), &Heta, nullptr, nullptr);
      v = PsiC * Heta.col(0);
    }
    // G_k = Ψ H_k Ψᵀ, real split: (fa, fb) → (Re, −Im) of G_k (fa − i fb).
    Eigen::MatrixXcd HPt;
    flexibility(k, omega, xi, PsiC.transpose(), &HPt, nullptr, nullptr);
    Eigen::MatrixXcd G = PsiC * HPt;
    G = 0.5 * (G + G.transpose()).eval();
    for (int s = 0; s < rows_; ++s) {
      for (int r = 0; r < rows_; ++r) {
        const double gr = G(s, r).real(), gi = G(s, r).imag();
        Gbig(s * nc_ + o, r * nc_ + o) = gr;
        Gbig(s * nc_ + o, r * nc_ + o + 1) = gi;
        Gbig(s * nc_ + o + 1, r * nc_ + o) = -gi;
        Gbig(s * nc_ + o + 1, r * nc_ + o + 1) = gr;
      }
    }
  }
  STICKSLIP_VERIFY(offset1 >= 0, "NonlinearModeSystem: harmonic 1 is not solved");
  R[n_] = s_ * (z.real() - a);
  R[n_ + 1] = s_ * z.imag();
  if (dR_dlambda) (*dR_dlambda)[n_] = -s_ * a;
  if (!dR_dy) return;

  // dR/dx on the harmonics ≥ 1: I + 𝔾 J, J block-diagonal per pair.
  for (size_t p = 0; p < system_.pairs().size(); ++p) {
    const int w = system_.pairs()[p].element->dimension() * nc_;
    const int c = system_.pair_row(static_cast<int>(p)) * nc_;
    dR_dy->block(0, c, n_, w).noalias() += Gbig.middleCols(c, w) * J.block(c, c, w, w);
  }
  for (int pos = 0; pos < set.size(); ++pos) {
    const int k = set.harmonics()[pos], o = set.offset(pos);
    if (k == 0) continue;
    for (int r = 0; r < rows_; ++r) {
      (*dR_dy)(r * nc_ + o, r * nc_ + o) += 1.0;
      (*dR_dy)(r * nc_ + o + 1, r * nc_ + o + 1) += 1.0;
    }
  }
  // dz/dx = −Σ_r v_r (∂fa_r/∂x − i ∂fb_r/∂x).
  Eigen::RowVectorXcd dz_dx = Eigen::RowVectorXcd::Zero(n_);
  for (int r = 0; r < rows_; ++r) {
    dz_dx -= v[r] * (J.row(r * nc_ + offset1).cast<Complex>() -
                     kI * J.row(r * nc_ + offset1 + 1).cast<Complex>());
  }
  dR_dy->row(n_).head(n_) = s_ * dz_dx.real();
  dR_dy->row(n_ + 1).head(n_) = s_ * dz_dx.imag();
  (*dR_dy)(n_, n_) = s_ * dz_domega.real();
  (*dR_dy)(n_ + 1, n_) = s_ * dz_domega.imag();
  (*dR_dy)(n_, n_ + 1) = s_ * dz_dxi.real();
  (*dR_dy)(n_ + 1, n_ + 1) = s_ * dz_dxi.imag();
}

Eigen::VectorXd NonlinearModeSystem::linear_guess(double amplitude) const {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(size());
  const HarmonicSet& set = system_.unknown_harmonics();
  const Eigen::VectorXd u = amplitude * (system_.contact_modes() * eta_);
  const int o1 = set.offset(set.position_of(1));
  for (int r = 0; r < rows_; ++r) y[r * nc_ + o1] = u[r];
  if (set.has_static()) {  // the static state: the stuck linear solution's harmonic 0
    const Eigen::VectorXd stuck = system_.linear_guess(omega_lin_, true);
    const int o0 = set.offset(set.position_of(0));
    for (int r = 0; r < rows_; ++r) y[r * nc_ + o0] = stuck[r * nc_ + o0];
  }
  y[n_] = omega_lin_;
  y[n_ + 1] = xi_lin_;
  return y;
}

std::complex<double> NonlinearModeSystem::modal_amplitude(const Eigen::VectorXd& y) const {
  Eigen::VectorXd R;
  evaluate(y, 0.0, R, nullptr, nullptr);
  // R[n] = s (Re z − 1) at a = 1, R[n + 1] = s Im z.
  return {R[n_] / s_ + 1.0, R[n_ + 1] / s_};
}

Eigen::MatrixXcd NonlinearModeSystem::master_response(const Eigen::VectorXd& y) const {
  const Eigen::VectorXd x = y.head(n_);
  const double omega = y[n_], xi = y[n_ + 1];
  Eigen::VectorXd F;
  forces(x, F, nullptr);
  const Eigen::MatrixXcd Fc = system_.to_complex(F, system_.static_force());
  const Eigen::MatrixXcd Uc = system_.to_complex(x, system_.static_displacement());
  Eigen::MatrixXcd X = system_.master_response(Fc, omega, &Uc);  // harmonic 0 kept from here
  const std::vector<int>& hs = system_.output_harmonics();
  const LinearModel& model = system_.linear_model();
  for (size_t j = 0; j < hs.size(); ++j) {
    if (hs[j] == 0) continue;
    const Eigen::MatrixXcd Y = -(system_.contact_modes().transpose().cast<Complex>() * Fc.col(j));
    Eigen::MatrixXcd HY;
    flexibility(hs[j], omega, xi, Y, &HY, nullptr, nullptr);
    X.col(j) = model.Phi.cast<Complex>() * HY.col(0);
  }
  return X;
}

NonlinearModeResult nonlinear_mode(const HarmonicBalanceSystem& system,
                                   const NonlinearModeOptions& options) {
  validate(options);
  const HarmonicSet& set = system.unknown_harmonics();
  if (set.position_of(1) < 0) {
    throw InvalidInput(
        "nonlinear_mode: the harmonic balance must solve harmonic 1 (the mode's "
        "fundamental)");
  }
  if (system.pairs().empty()) {
    throw InvalidInput("nonlinear_mode: the model has no contact elements: its modes are linear");
  }
  const StuckModes modes = stuck_modes(system);
  const int nm = static_cast<int>(modes.omega2.size());
  if (options.mode > nm) {
    throw InvalidInput("NonlinearModeOptions.mode = " + std::to_string(options.mode) +
                       ": the model has only " + std::to_string(nm) + " modes");
  }
  const Eigen::VectorXd eta = modes.eta.col(options.mode - 1);
  double largest = 0.0;
  for (int r = 0; r < nm; ++r) largest = std::max(largest, system.contact_modes().col(r).norm());
  if (!((system.contact_modes() * eta).norm() > kNoContactMotion * largest)) {
    throw InvalidInput("NonlinearModeOptions.mode = " + std::to_string(options.mode) +
                       ": the mode does not move the contacts (its nonlinear mode is the linear "
                       "one, " +
                       format_number(std::sqrt(std::max(modes.omega2[options.mode - 1], 0.0))) +
                       " rad/s)");
  }
  const NonlinearModeSystem sys(system, eta);
  NonlinearModeResult result;
  result.mode = options.mode;
  result.linear_omega = sys.linear_omega();
  result.linear_xi = sys.linear_xi();
  result.harmonics = system.output_harmonics();

  std::vector<double> lambdas;
  for (double a : options.amplitudes) lambdas.push_back(std::log(a));
  SteppedSweepOptions sweep;
  sweep.newton = options.newton;
  sweep.max_step_halvings = options.max_step_halvings;
  sweep.secant_predictor = true;
  sweep.jump_max_points = 0;  // an amplitude-parametrised mode does not fold: no jumps to follow
  sweep.on_point = options.on_point;
  const ContinuationResult c =
      stepped_sweep(sys, sys.linear_guess(options.amplitudes.front()), lambdas, sweep);

  const int n = system.size();
  int failed = 0;
  for (const ContinuationPoint& p : c.points) {
    NonlinearModePoint q;
    q.amplitude = std::exp(p.lambda);
    q.unknowns = p.x;
    q.omega = p.x[n];
    q.xi = p.x[n + 1];
    q.damping_ratio = q.xi / (2 * q.omega);
    q.converged = p.newton.converged();
    q.iterations = p.newton.iterations;
    q.residual_norm = p.newton.residual_norm;
    q.residual_scale = sys.residual_scale_at(p.lambda);
    q.message = p.newton.message;
    if (q.converged) {
      q.master = sys.master_response(p.x);
      Eigen::VectorXd F;
      std::vector<CycleStatistics> stats;
      system.contact_forces(p.x.head(n), F, &stats);
      for (const CycleStatistics& s : stats) q.dissipated_energy += s.dissipated_energy;
    }
    failed += q.converged ? 0 : 1;
    result.points.push_back(std::move(q));
  }
  result.completed = failed == 0;
  result.message = failed == 0
                       ? "every amplitude converged"
                       : std::to_string(failed) + " of " + std::to_string(result.points.size()) +
                             " amplitudes did not converge";
  return result;
}

}  // namespace stickslip
