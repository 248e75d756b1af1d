#include "hbm/nonlinear_mode.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "contact/friction_contact.h"
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
// Where Newton fails at an amplitude even after the step halvings, the stepped sweep follows the
// branch by arc-length continuation (in the scaled unknowns of ScaledModeSystem and ln a) from the
// last solved amplitude until it reaches the requested one, with at most this many points
// (SteppedSweepOptions.jump_max_points). On the reference joint the mode leaves the stuck range
// abruptly when the last pairs stop sticking (1758 → 1350 Hz within 12 % of amplitude at 80 N per
// pair), through folds in amplitude (ScaledModeSystem): no step in ln a crosses them, the
// arc-length path goes round them. There the branch zigzags in amplitude (a fold every 10–20 arc
// points at 150 N) and the arc's step control, which bounds the tangent's turn per step, keeps the
// steps near 0.5 Hz: 200 points took the path from 1758 to 1708 Hz only, short of the next
// amplitude on a 200-point grid over 1e-7…1e-2 (2 amplitudes failed); 1000 reach it (200/200,
// 5.3 s against 6.0 s with the failures: docs/performance.md).
constexpr int kArcLengthPoints = 1000;
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

namespace {
// Each pair's force f_s (m) and tangent K_p (m x m) at the static state: the AFT of a constant
// signal (harmonic 0 only) maps the constant of one row to the constant of the others. The signal
// is the pair's motion as the harmonic balance's AFT sees it (HarmonicBalanceSystem::pair_offset):
// a friction element's spring anchored where the static loading path left it, so that a pair the
// path let slip and then stick again has its static τ0 and sticks (a fresh spring at u0 would give
// kt u0_t, possibly beyond μN: a slipping pair and the wrong tangent).
struct PairTangent {
  Eigen::VectorXd force;
  Eigen::MatrixXd stiffness;
};
std::vector<PairTangent> static_tangents(const HarmonicBalanceSystem& system) {
  const Aft tangent_aft(FourierBasis(HarmonicSet({0}), 2));
  // Coupled: the static state is the signal, pair_offset(p) = −(anchor, 0); uncoupled: the
  // offset holds u0 − (anchor, 0) and the signal's constant is 0.
  const bool coupled = system.unknown_harmonics().has_static();
  const Eigen::VectorXd& u0 = system.static_displacement();
  std::vector<PairTangent> out(system.pairs().size());
  for (size_t p = 0; p < system.pairs().size(); ++p) {
    const int m = system.pairs()[p].element->dimension(), r = system.pair_row(static_cast<int>(p));
    const Eigen::VectorXd signal = coupled && u0.size() == system.contact_rows()
                                       ? Eigen::VectorXd(u0.segment(r, m))
                                       : Eigen::VectorXd::Zero(m);
    tangent_aft.evaluate(*system.pairs()[p].element, signal,
                         system.pair_offset(static_cast<int>(p)), out[p].force, &out[p].stiffness);
  }
  return out;
}

// The smallest c > 0 with q(c) = A c² + 2 B c + C = 0 or q(−c) = 0 (+∞ without a real root).
double smallest_root_magnitude(double A, double B, double C) {
  double best = std::numeric_limits<double>::infinity();
  auto consider = [&best](double c) {
    if (std::isfinite(c)) best = std::min(best, std::abs(c));
  };
  const double scale = std::max({std::abs(A), std::abs(B), std::abs(C)});
  if (!(scale > 0)) return best;
  if (std::abs(A) <= 1e-14 * scale) {
    if (B != 0) consider(-C / (2 * B));
    return best;
  }
  const double disc = B * B - A * C;
  if (disc < 0) return best;
  const double q = -(B + std::copysign(std::sqrt(disc), B));  // no cancellation
  consider(q / A);
  if (q != 0) consider(C / q);
  return best;
}
}  // namespace

double first_slip_amplitude(const HarmonicBalanceSystem& system, const Eigen::VectorXd& eta) {
  const std::vector<PairTangent> tangents = static_tangents(system);
  const Eigen::VectorXd motion = system.contact_modes() * eta;
  double best = std::numeric_limits<double>::infinity();
  for (size_t p = 0; p < system.pairs().size(); ++p) {
    const NonlinearElement& element = *system.pairs()[p].element;
    const int m = element.dimension(), r = system.pair_row(static_cast<int>(p));
    const Eigen::VectorXd fs = tangents[p].force;
    const Eigen::VectorXd f1 = tangents[p].stiffness * motion.segment(r, m);
    if (const auto* contact = dynamic_cast<const FrictionContact3D*>(&element)) {
      const double mu = contact->parameters().mu;
      const Eigen::Vector2d ts = fs.head<2>(), t1 = f1.head<2>();
      const double ns = fs[2], n1 = f1[2];
      if (!(ns > 0)) return 0.0;  // open at rest
      // |τ_s + c τ_1|² − μ² (N_s + c N_1)² = 0, and N_s + c N_1 = 0 (lift-off).
      best = std::min(best, smallest_root_magnitude(t1.squaredNorm() - mu * mu * n1 * n1,
                                                    ts.dot(t1) - mu * mu * ns * n1,
                                                    ts.squaredNorm() - mu * mu * ns * ns));
      if (n1 != 0) best = std::min(best, std::abs(ns / n1));
    } else if (const auto* jenkins = dynamic_cast<const Jenkins1D*>(&element)) {
      const double limit = jenkins->parameters().mu * jenkins->parameters().normal_load;
      // τ_s + c τ_1 = ±μN.
      if (f1[0] != 0) {
        best = std::min(
            best, std::min(std::abs((limit - fs[0]) / f1[0]), std::abs((-limit - fs[0]) / f1[0])));
      }
    }
  }
  return best;
}

StuckModes stuck_modes(const HarmonicBalanceSystem& system) {
  const LinearModel& model = system.linear_model();
  const Eigen::MatrixXd& Psi = system.contact_modes();
  const int nu = system.contact_rows();
  const std::vector<PairTangent> tangents = static_tangents(system);
  Eigen::MatrixXd Kt = Eigen::MatrixXd::Zero(nu, nu);
  for (size_t p = 0; p < system.pairs().size(); ++p) {
    const int m = system.pairs()[p].element->dimension(), r = system.pair_row(static_cast<int>(p));
    Kt.block(r, r, m, m) = tangents[p].stiffness;
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
  // z = ηᵀ Q_1 (phase) and q = ||Q_1|| (amplitude), Q_1 = −H_1 Ψᵀ F_1; their derivatives in Ω, ξ.
  Complex z = 0, dz_domega = 0, dz_dxi = 0;
  double q = 0, dq_domega = 0, dq_dxi = 0;
  Eigen::VectorXcd v;  // Ψ H_1 η: dz = −vᵀ dF_1
  Eigen::VectorXcd w;  // Ψ H_1 conj(Q_1): Q_1ᴴ dQ_1 = −wᵀ dF_1 (H_1 symmetric)
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
      q = HY.col(0).norm();
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
      // q dq = Re(Q_1ᴴ dQ_1), Q_1 = −HY: Q_1ᴴ dQ_1 = HYᴴ d(HY).
      if (q > 0) {
        dq_domega = HY.col(0).dot(dHY_dw.col(0)).real() / q;
        dq_dxi = HY.col(0).dot(dHY_dxi.col(0)).real() / q;
      }
      Eigen::MatrixXcd Heta;
      Eigen::MatrixXcd rhs(nm_, 2);
      rhs.col(0) = eta_.cast<Complex>();
      rhs.col(1) = (-HY.col(0)).conjugate();
      flexibility(1, omega, xi, rhs, &Heta, nullptr, nullptr);
      v = PsiC * Heta.col(0);
      w = PsiC * Heta.col(1);
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
  R[n_] = s_ * (q - a);
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
  // dz/dx = −Σ_r v_r (∂fa_r/∂x − i ∂fb_r/∂x); q dq/dx = Re(−Σ_r w_r (∂fa_r/∂x − i ∂fb_r/∂x)).
  Eigen::RowVectorXcd dz_dx = Eigen::RowVectorXcd::Zero(n_);
  Eigen::RowVectorXcd qdq_dx = Eigen::RowVectorXcd::Zero(n_);
  for (int r = 0; r < rows_; ++r) {
    const Eigen::RowVectorXcd dF = J.row(r * nc_ + offset1).cast<Complex>() -
                                   kI * J.row(r * nc_ + offset1 + 1).cast<Complex>();
    dz_dx -= v[r] * dF;
    qdq_dx -= w[r] * dF;
  }
  if (q > 0) dR_dy->row(n_).head(n_) = (s_ / q) * qdq_dx.real();
  dR_dy->row(n_ + 1).head(n_) = s_ * dz_dx.imag();
  (*dR_dy)(n_, n_) = s_ * dq_domega;
  (*dR_dy)(n_ + 1, n_) = s_ * dz_domega.imag();
  (*dR_dy)(n_, n_ + 1) = s_ * dq_dxi;
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

double NonlinearModeSystem::modal_amplitude(const Eigen::VectorXd& y) const {
  Eigen::VectorXd R;
  evaluate(y, 0.0, R, nullptr, nullptr);
  return R[n_] / s_ + 1.0;  // R[n] = s (q − 1) at a = 1
}

Eigen::MatrixXcd NonlinearModeSystem::master_response(const Eigen::VectorXd& y,
                                                      double* modal_norm) const {
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
    if (hs[j] == 1 && modal_norm) *modal_norm = HY.col(0).norm();
  }
  return X;
}

namespace {
// The EPMC system in the unknowns the continuation works in: y = D(λ) w with
//   w = [U_k / (a s) for the harmonics k ≥ 1; U_0 / c_0; Ω / ω̃; ξ / ω̃]   (a = e^λ),
// dimensionless and of order 1 along the whole branch (U_k grows with a; c_0 the system's static
// scale). R(w, λ) is the system's R(D(λ) w, λ): the same equations and convergence test; dR/dw =
// dR/dy D, dR/dλ|_w = dR/dλ|_y + Σ_{k ≥ 1} dR/dU_k U_k. In y itself the columns of Ω and ξ are
// 1e-10 of the contact columns (m against rad/s, and ξ's sensitivity): the Jacobian's condition
// number was 1e15–1e16 on the reference joint, so the arc-length fallback of the stepped sweep —
// which scales all unknowns by one number, ||y|| — found "no tangent" at its first point and
// never started (in w: 1e6–4e7). It is needed: at 150, 80 and 50 N per pair the branch folds in
// amplitude where the joint goes from micro-slip to gross slip (the mass norm q of the
// fundamental peaks, e.g. at 1.80e-5 and 1757 Hz at 50 N, then falls while ξ grows), and a
// stepped sweep in a cannot pass a fold: Newton at a larger a stalled at q ≈ 1.80e-5 there.
class ScaledModeSystem final : public ParametrizedSystem {
 public:
  ScaledModeSystem(const NonlinearModeSystem& sys, const HarmonicBalanceSystem& system)
      : sys_(sys), n_(system.size()) {
    const HarmonicSet& set = system.unknown_harmonics();
    const int nc = set.coefficient_count();
    dynamic_ = Eigen::VectorXd::Ones(n_);
    if (set.has_static()) {
      const int o0 = set.offset(set.position_of(0));
      for (int r = 0; r < system.contact_rows(); ++r) dynamic_[r * nc + o0] = 0.0;
    }
    static_scale_ = system.residual_scale();
    omega_scale_ = sys.linear_omega() > 0 ? sys.linear_omega() : 1.0;
  }
  int size() const override { return n_ + 2; }
  double residual_scale() const override { return sys_.residual_scale(); }
  double residual_scale_at(double lambda) const override { return sys_.residual_scale_at(lambda); }

  // The diagonal of D(λ).
  Eigen::VectorXd scales(double lambda) const {
    Eigen::VectorXd d(n_ + 2);
    const double dynamic = std::exp(lambda) * sys_.scale();
    for (int i = 0; i < n_; ++i) d[i] = dynamic_[i] != 0 ? dynamic : static_scale_;
    d[n_] = d[n_ + 1] = omega_scale_;
    return d;
  }
  Eigen::VectorXd to_scaled(const Eigen::VectorXd& y, double lambda) const {
    return y.cwiseQuotient(scales(lambda));
  }
  Eigen::VectorXd from_scaled(const Eigen::VectorXd& w, double lambda) const {
    return w.cwiseProduct(scales(lambda));
  }

  void evaluate(const Eigen::VectorXd& w, double lambda, Eigen::VectorXd& R, Eigen::MatrixXd* dR_dw,
                Eigen::VectorXd* dR_dlambda) const override {
    const Eigen::VectorXd d = scales(lambda);
    const Eigen::VectorXd y = w.cwiseProduct(d);
    Eigen::MatrixXd J;
    sys_.evaluate(y, lambda, R, dR_dw || dR_dlambda ? &J : nullptr, dR_dlambda);
    if (dR_dlambda) {  // dU_k/dλ = U_k (k ≥ 1) at fixed w
      dR_dlambda->noalias() += J.leftCols(n_) * y.head(n_).cwiseProduct(dynamic_);
    }
    if (dR_dw) *dR_dw = J * d.asDiagonal();
  }

 private:
  const NonlinearModeSystem& sys_;
  int n_ = 0;
  Eigen::VectorXd dynamic_;  // 1 on the entries of harmonics ≥ 1, 0 on harmonic 0
  double static_scale_ = 1.0, omega_scale_ = 1.0;
};
}  // namespace

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
  result.first_slip_amplitude = first_slip_amplitude(system, eta);
  result.harmonics = system.output_harmonics();

  std::vector<double> lambdas;
  for (double a : options.amplitudes) lambdas.push_back(std::log(a));
  const ScaledModeSystem scaled(sys, system);
  SteppedSweepOptions sweep;
  sweep.newton = options.newton;
  sweep.max_step_halvings = options.max_step_halvings;
  sweep.secant_predictor = true;
  sweep.jump_max_points = kArcLengthPoints;
  if (options.on_point) {
    sweep.on_point = [&](const ContinuationProgress& p) {
      Eigen::VectorXd y;
      ContinuationProgress q = p;
      if (p.x) {
        y = scaled.from_scaled(*p.x, p.lambda);
        q.x = &y;
      }
      options.on_point(q);
    };
  }
  ContinuationResult c = stepped_sweep(
      scaled, scaled.to_scaled(sys.linear_guess(options.amplitudes.front()), lambdas.front()),
      lambdas, sweep);
  for (ContinuationPoint& p : c.points) p.x = scaled.from_scaled(p.x, p.lambda);

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
    q.message = p.failure.empty() ? p.newton.message : p.failure;
    if (q.converged) {
      q.master = sys.master_response(p.x, &q.modal_norm);
      Eigen::VectorXd F;
      std::vector<CycleStatistics> stats;
      system.contact_forces(p.x.head(n), F, &stats);
      for (const CycleStatistics& s : stats) {
        q.dissipated_energy += s.dissipated_energy;
        q.pairs_slipping += s.slip_fraction > 0 ? 1.0 : 0.0;
        q.pairs_separating += s.separation_fraction > 0 ? 1.0 : 0.0;
        q.mean_slip_fraction += s.slip_fraction;
      }
      const double pairs = std::max<double>(1.0, static_cast<double>(stats.size()));
      q.pairs_slipping /= pairs;
      q.pairs_separating /= pairs;
      q.mean_slip_fraction /= pairs;
    }
    failed += q.converged ? 0 : 1;
    result.points.push_back(std::move(q));
  }
  result.completed = failed == 0;
  result.message = failed == 0
                       ? "every amplitude converged"
                       : std::to_string(failed) + " of " + std::to_string(result.points.size()) +
                             " amplitudes did not converge";
  for (const NonlinearModePoint& q : result.points) {  // the first failure's reason
    if (q.converged) continue;
    std::ostringstream m;
    m << "; at amplitude " << q.amplitude << ": " << q.message;
    result.message += m.str();
    break;
  }
  return result;
}

std::vector<ForcedResponsePrediction> predict_forced_response(const NonlinearModeResult& mode,
                                                              const Eigen::VectorXcd& force) {
  const auto h1 = std::find(mode.harmonics.begin(), mode.harmonics.end(), 1);
  STICKSLIP_VERIFY(h1 != mode.harmonics.end(), "predict_forced_response: no harmonic 1");
  const int c1 = static_cast<int>(h1 - mode.harmonics.begin());
  std::vector<ForcedResponsePrediction> below, above;
  for (size_t i = 0; i < mode.points.size(); ++i) {
    const NonlinearModePoint& p = mode.points[i];
    if (!p.converged || !(p.modal_norm > 0) || p.master.rows() != force.size()) continue;
    const double q = p.modal_norm, w2 = p.omega * p.omega, xi = p.xi;
    // ψᴴF̂ = X_1ᴴ F̂ / q (dot conjugates its first argument).
    const Complex projected = p.master.col(c1).dot(force) / q;
    const double P = std::abs(projected) / q;
    const double centre = w2 - 0.5 * xi * xi;
    const double disc = P * P - xi * xi * w2 + 0.25 * xi * xi * xi * xi;
    if (!(disc >= 0) || !(P > 0)) continue;
    const double root = std::sqrt(disc);
    for (const bool upper : {false, true}) {
      const double s2 = upper ? centre + root : centre - root;
      if (!(s2 > 0)) continue;
      ForcedResponsePrediction r;
      r.point = static_cast<int>(i);
      r.above = upper;
      r.omega = std::sqrt(s2);
      // e^{iθ} = ψᴴF̂ / ((ω² − Ω² + i ξ Ω) q): of modulus 1 by the choice of Ω.
      r.phase = std::arg(projected / Complex(w2 - s2, xi * r.omega));
      r.master = p.master;
      for (size_t j = 0; j < mode.harmonics.size(); ++j) {
        r.master.col(j) *= std::polar(1.0, mode.harmonics[j] * r.phase);
      }
      (upper ? above : below).push_back(std::move(r));
    }
  }
  std::reverse(above.begin(), above.end());
  for (ForcedResponsePrediction& r : above) below.push_back(std::move(r));
  return below;
}

}  // namespace stickslip
