// The event method of Aft (aft.h, AftMethod::kEvent): the periodic cycle of the friction law
// for a trigonometric displacement, with every transition located in time and the Fourier
// integrals evaluated segment by segment.
//
// Scalar form. Jenkins1D: s = u, limit L = μN constant. FrictionContact3D with collinear
// tangential motion: s = e·u_t, N(θ) = N0 + kn (w(θ) − g0), L = μN. Between transitions:
//   stick (anchor θ_a, τ_a):  τ = τ_a + kt (s(θ) − s(θ_a)); leaves when μN − τ or μN + τ < 0;
//   slip σ = ±1:             τ = σ μN(θ); leaves when the slip rate σ kt s' − μN' < 0 (→ stick,
//                             anchor τ_a = σ μN(θ_a)) or N < 0 (→ open);
//   open:                    τ = N = 0; leaves when N > 0 (touchdown: stick from τ_a = 0 if
//                             kt |s'| ≤ μN', else slip in the direction of s').
// Every switching function is a trigonometric polynomial (plus a constant) in θ.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "contact/friction_contact.h"
#include "core/errors.h"
#include "core/types.h"
#include "hbm/aft.h"
#include "hbm/event_roots.h"
#include "hbm/gauss_legendre.h"

namespace stickslip {

namespace {

constexpr double kTwoPi = 2.0 * kPi;
// A switching function counts as negative below −kSwitchTolerance · (its scale): transitions that
// dip less than that (round-off of the cancellation in μN ∓ τ at a slip → stick point) are not
// transitions.
constexpr double kSwitchTolerance = 1e-12;
// Tangential motion is collinear when every harmonic vector (c_t1,i, c_t2,i) is within this
// fraction of the largest one from the line through e.
constexpr double kCollinearTolerance = 1e-9;
constexpr int kMaxCyclePeriods = 20;

// f(θ) = c0 + Σ coef_i φ_i^{(p)}(θ): a switching function or a signal (p = derivative order).
struct Trig {
  double c0 = 0.0;
  Eigen::VectorXd coef;
  int p = 0;
};

enum class Mode { kStick, kSlip, kOpen };
enum class Anchor { kVirgin, kSlipEnd, kTouchdown };

struct State {
  Mode mode = Mode::kStick;
  int sigma = 1;
  Anchor anchor = Anchor::kVirgin;
  double theta_a = 0.0, tau_a = 0.0;
};

struct Segment {
  double a, b;
  State state;
};

class EventCycle {
 public:
  // s, w: coefficient vectors of the tangential (e) and normal signals; s0, w0 their offsets.
  EventCycle(const HarmonicSet& set, int grid_samples, double kt, bool normal, double mu,
             double kn, double n_const, double limit)
      : set_(set), nc_(set.coefficient_count()), grid_(kTwoPi / grid_samples), kt_(kt),
        normal_(normal), mu_(mu), kn_(kn), phi_(set.coefficient_count()) {
    max_k_ = std::max(1, set.max_harmonic());
    n_const_ = n_const;
    limit_ = limit;
    max_events_ = 8 * grid_samples + 100;
  }

  void set_signals(const Eigen::VectorXd& cs, double s0, const Eigen::VectorXd& cw) {
    S_ = Trig{s0, cs, 0};
    if (normal_) {
      N_ = Trig{n_const_, kn_ * cw, 0};
      L_ = Trig{mu_ * N_.c0, mu_ * N_.coef, 0};
    } else {
      N_ = Trig{0.0, Eigen::VectorXd::Zero(nc_), 0};
      L_ = Trig{limit_, Eigen::VectorXd::Zero(nc_), 0};
    }
    frictionless_ = normal_ ? mu_ == 0.0 : limit_ <= 0.0;
  }

  // φ^{(p)}(θ) into out (size nc).
  void basis(double theta, int p, double* out) const {
    for (int q = 0; q < set_.size(); ++q) {
      const int k = set_.harmonics()[q];
      const int o = set_.offset(q);
      if (k == 0) {
        out[o] = p == 0 ? 1.0 : 0.0;
        continue;
      }
      const double arg = k * theta + p * (kPi / 2);  // d^p/dθ^p cos kθ = k^p cos(kθ + pπ/2)
      const double kp = p == 0 ? 1.0 : std::pow(static_cast<double>(k), p);
      out[o] = kp * std::cos(arg);
      out[o + 1] = kp * std::sin(arg);
    }
  }
  double value(const Trig& f, double theta, int q = 0) const {
    const int p = f.p + q;
    basis(theta, p, phi_.data());
    return (p == 0 ? f.c0 : 0.0) + f.coef.dot(phi_);
  }
  double scale(const Trig& f) const {
    return std::abs(f.c0) + f.coef.lpNorm<1>() * std::pow(static_cast<double>(max_k_), f.p) +
           std::numeric_limits<double>::min();
  }

  double stick_tau(const State& st, double theta) const {
    return st.tau_a + kt_ * (value(S_, theta) - value(S_, st.theta_a));
  }
  double tau(const State& st, double theta) const {
    switch (st.mode) {
      case Mode::kStick: return stick_tau(st, theta);
      case Mode::kSlip: return st.sigma * value(L_, theta);
      default: return 0.0;
    }
  }

  // The first θ in (a, b] where f < −tolerance, bracketed on the grid θ_k = k·2π/N
  // (event_roots.h).
  std::optional<double> first_exit(const Trig& f, double a, double b) const {
    return event_roots::first_exit([&](double t, int q) { return value(f, t, q); },
                                   kSwitchTolerance * scale(f), grid_, a, b);
  }

  // Marches from θ = a in state st to b (or to the first transition if stop_at_event; its time
  // in *event). Appends the segments to segs if given. Returns the state at the end.
  State march(State st, double a, double b, std::vector<Segment>* segs, bool stop_at_event,
              double* event) {
    double th = a;
    while (th < b) {
      std::optional<double> e1, e2;
      switch (st.mode) {
        case Mode::kStick: {
          const double ref = kt_ * value(S_, st.theta_a) - st.tau_a;
          const Trig gp{L_.c0 - kt_ * S_.c0 + ref, L_.coef - kt_ * S_.coef, 0};
          const Trig gm{L_.c0 + kt_ * S_.c0 - ref, L_.coef + kt_ * S_.coef, 0};
          e1 = first_exit(gp, th, b);
          e2 = first_exit(gm, th, e1 ? *e1 : b);
          break;
        }
        case Mode::kSlip: {
          if (!frictionless_) {
            const Trig rate{0.0, st.sigma * kt_ * S_.coef - L_.coef, 1};
            e1 = first_exit(rate, th, b);
          }
          if (normal_) e2 = first_exit(N_, th, e1 ? *e1 : b);
          break;
        }
        case Mode::kOpen: {
          const Trig closing{-N_.c0, -N_.coef, 0};
          e1 = first_exit(closing, th, b);
          break;
        }
      }
      if (!e1 && !e2) {
        if (segs) segs->push_back({th, b, st});
        return st;
      }
      const bool second = e2 && (!e1 || *e2 < *e1);
      const double te = second ? *e2 : *e1;
      if (segs) segs->push_back({th, te, st});
      st = transition(st, second, te);
      th = te;
      if (++events_ > max_events_) {
        failed_ = true;
        return st;
      }
      if (stop_at_event) {
        *event = te;
        return st;
      }
    }
    return st;
  }

  State transition(const State& st, bool second, double te) const {
    State n;
    switch (st.mode) {
      case Mode::kStick:
        n.mode = Mode::kSlip;
        n.sigma = second ? -1 : 1;
        break;
      case Mode::kSlip:
        if (second) {
          n.mode = Mode::kOpen;
        } else {
          n.mode = Mode::kStick;
          n.sigma = st.sigma;  // the direction of the slip that ended: τ_a = σ μN(θ_a)
          n.anchor = Anchor::kSlipEnd;
          n.theta_a = te;
          n.tau_a = st.sigma * value(L_, te);
        }
        break;
      case Mode::kOpen: {
        const double ds = value(S_, te, 1), dl = value(L_, te, 1);
        if (frictionless_) {
          n.mode = Mode::kSlip;
        } else if (kt_ * std::abs(ds) <= dl) {
          n.mode = Mode::kStick;
          n.anchor = Anchor::kTouchdown;
          n.theta_a = te;
          n.tau_a = 0.0;
        } else {
          n.mode = Mode::kSlip;
          n.sigma = ds >= 0 ? 1 : -1;
        }
        break;
      }
    }
    return n;
  }

  // The periodic cycle: segments covering [θ_s, θ_s + 2π). False if it could not be closed.
  bool cycle(std::vector<Segment>& segs, int& periods) {
    events_ = 0;
    failed_ = false;
    State st;
    double th_r = 0.0;
    const double n0 = value(N_, 0.0);
    if (normal_ && n0 <= 0) {
      st.mode = Mode::kOpen;
    } else if (frictionless_) {
      st.mode = Mode::kSlip;
    } else {
      const double t0 = kt_ * value(S_, 0.0), l0 = value(L_, 0.0);
      if (std::abs(t0) > l0) {
        st.mode = Mode::kSlip;
        st.sigma = t0 > 0 ? 1 : -1;
      } else {
        st.anchor = Anchor::kVirgin;  // τ = kt s(θ): from the virgin state (τ = 0 at s = 0)
        st.theta_a = 0.0;
        st.tau_a = t0;
        double ev = -1.0;
        const State next = march(st, 0.0, 2 * kTwoPi, nullptr, true, &ev);
        if (failed_) return false;
        if (ev < 0.0) {  // stuck over two periods: the stuck cycle from the virgin state
          segs.assign(1, Segment{0.0, kTwoPi, st});
          periods = 2;
          return true;
        }
        st = next;
        th_r = ev;
      }
    }
    // The state from θ_r on depends on θ_r only. Start the cycle mid-way in that segment, so
    // that its ends are not transitions.
    double th_next = th_r + kTwoPi;
    march(st, th_r, th_r + kTwoPi, nullptr, true, &th_next);
    if (failed_) return false;
    double th_s = 0.5 * (th_r + th_next);
    for (periods = 1; periods <= kMaxCyclePeriods; ++periods) {
      segs.clear();
      const State end = march(st, th_s, th_s + kTwoPi, &segs, false, nullptr);
      if (failed_) return false;
      const double force_scale = std::abs(L_.c0) + L_.coef.lpNorm<1>() +
                                 kt_ * (std::abs(S_.c0) + S_.coef.lpNorm<1>());
      bool closed = end.mode == st.mode;
      if (closed && st.mode == Mode::kSlip) closed = end.sigma == st.sigma;
      if (closed && st.mode == Mode::kStick) {
        closed = std::abs(stick_tau(end, th_s + kTwoPi) - stick_tau(st, th_s)) <=
                 1e-10 * force_scale;
      }
      if (closed) return true;
      st = end;
      th_s += kTwoPi;
    }
    return false;
  }

  const Trig& S() const { return S_; }
  const Trig& N() const { return N_; }
  const Trig& L() const { return L_; }
  double kt() const { return kt_; }
  double kn() const { return kn_; }
  double mu() const { return mu_; }
  bool normal() const { return normal_; }

 private:
  const HarmonicSet& set_;
  int nc_;
  double grid_;
  double kt_;
  bool normal_;
  double mu_, kn_, n_const_ = 0.0, limit_ = 0.0;
  bool frictionless_ = false;
  int max_k_ = 1;
  Trig S_, N_, L_;
  mutable Eigen::VectorXd phi_;
  int events_ = 0, max_events_ = 0;
  bool failed_ = false;
};

// Forces, Jacobian blocks and statistics of the closed cycle (scalar form).
struct CycleIntegrals {
  Eigen::VectorXd Fs, Fn;             // nc: tangential (along e) and normal force coefficients
  Eigen::MatrixXd Jss, Jsn, Jnn;      // ∂Fs/∂cs, ∂Fs/∂cw, ∂Fn/∂cw
  double stick = 0, slip = 0, open = 0, energy = 0;
};

void integrate(const EventCycle& cy, const HarmonicSet& set, const std::vector<Segment>& segs,
               bool jac, CycleIntegrals& out) {
  const int nc = set.coefficient_count();
  out.Fs.setZero(nc);
  out.Fn.setZero(nc);
  if (jac) {
    out.Jss.setZero(nc, nc);
    out.Jsn.setZero(nc, nc);
    out.Jnn.setZero(nc, nc);
  }
  Eigen::VectorXd norm(nc), phi(nc), psi(nc), v(nc), phia(nc);
  for (int q = 0; q < set.size(); ++q) {
    const int o = set.offset(q);
    if (set.harmonics()[q] == 0) {
      norm[o] = 1 / kTwoPi;
    } else {
      norm[o] = norm[o + 1] = 1 / kPi;
    }
  }
  Eigen::MatrixXd M(nc, nc);
  const double kt = cy.kt();
  for (const Segment& sg : segs) {
    const double len = sg.b - sg.a;
    if (len <= 0) continue;
    const State& st = sg.state;
    if (st.mode == Mode::kOpen) {
      out.open += len;
      continue;
    }
    (st.mode == Mode::kStick ? out.stick : out.slip) += len;
    const int nq = static_cast<int>(std::ceil(0.75 * set.max_harmonic() * len + 10));
    const auto& [xg, wg] = gauss_legendre(nq);
    if (jac) {
      M.setZero();
      v.setZero();
    }
    for (int g = 0; g < nq; ++g) {
      const double th = 0.5 * (sg.a + sg.b) + 0.5 * len * xg[g], w = 0.5 * len * wg[g];
      cy.basis(th, 0, phi.data());
      psi = phi.cwiseProduct(norm);
      const double tau = cy.tau(st, th);
      out.Fs += (w * tau) * psi;
      if (cy.normal()) out.Fn += (w * cy.value(cy.N(), th)) * psi;
      out.energy += w * tau * cy.value(cy.S(), th, 1);
      if (jac) {
        M.noalias() += (w * psi) * phi.transpose();
        v += w * psi;
      }
    }
    if (!jac) continue;
    if (cy.normal()) out.Jnn += cy.kn() * M;
    if (st.mode == Mode::kSlip) {
      if (cy.normal()) out.Jsn += (st.sigma * cy.mu() * cy.kn()) * M;
      continue;
    }
    out.Jss += kt * M;
    if (st.anchor == Anchor::kVirgin) continue;  // τ = kt s(θ)
    cy.basis(st.theta_a, 0, phia.data());
    out.Jss.noalias() -= (kt * v) * phia.transpose();
    if (st.anchor == Anchor::kSlipEnd) {
      if (cy.normal()) out.Jsn.noalias() += (st.sigma * cy.mu() * cy.kn() * v) * phia.transpose();
    } else {  // touchdown: θ_a moves with N, ∂θ_a = −kn φ(θ_a)ᵀ ∂c_w / N'(θ_a)
      const double dn = cy.value(cy.N(), st.theta_a, 1);
      if (dn > 0) {
        const double ds = cy.value(cy.S(), st.theta_a, 1);
        out.Jsn.noalias() += (kt * ds * cy.kn() / dn * v) * phia.transpose();
      }
    }
  }
  out.stick /= kTwoPi;
  out.slip /= kTwoPi;
  out.open /= kTwoPi;
}

// Index of the segment containing θ (mapped into the cycle's window).
const Segment& segment_at(const std::vector<Segment>& segs, double& theta) {
  const double start = segs.front().a;
  theta += kTwoPi * std::ceil((start - theta) / kTwoPi);
  if (theta >= start + kTwoPi) theta -= kTwoPi;
  for (const Segment& s : segs) {
    if (theta < s.b) return s;
  }
  return segs.back();
}

}  // namespace

bool Aft::evaluate_events(const NonlinearElement& element, const Eigen::VectorXd& coefficients,
                          const Eigen::VectorXd& offset, Eigen::VectorXd& forces,
                          Eigen::MatrixXd* jacobian, AftSamples* samples, AftWarmStart* warm,
                          CycleStatistics& stats) const {
  const HarmonicSet& set = basis_.harmonics();
  const int nc = set.coefficient_count();
  const int n = basis_.time_samples();
  const int m = element.dimension();
  STICKSLIP_VERIFY(coefficients.size() == m * nc, "Aft: coefficients must have m*nc entries");
  STICKSLIP_VERIFY(offset.size() == 0 || offset.size() == m, "Aft: offset must be empty or m");
  auto off = [&](int d) { return offset.size() == m ? offset[d] : 0.0; };
  const int i0 = set.has_static() ? set.offset(0) : -1;  // the a0 slot, if any

  if (const auto* jenkins = dynamic_cast<const Jenkins1D*>(&element)) {
    const JenkinsParameters& p = jenkins->parameters();
    EventCycle cy(set, n, p.kt, false, 0.0, 0.0, 0.0, p.mu * p.normal_load);
    cy.set_signals(coefficients, off(0), Eigen::VectorXd::Zero(nc));
    std::vector<Segment> segs;
    int periods = 0;
    if (!cy.cycle(segs, periods)) return false;
    CycleIntegrals ci;
    integrate(cy, set, segs, jacobian != nullptr, ci);
    forces = ci.Fs;
    if (jacobian) *jacobian = ci.Jss;
    stats.stick_fraction = ci.stick;
    stats.slip_fraction = ci.slip;
    stats.separation_fraction = 0.0;
    stats.dissipated_energy = ci.energy;
    stats.periods = periods;
    if (samples) {
      samples->u.resize(1, n);
      samples->f.resize(1, n);
      for (int j = 0; j < n; ++j) {
        double th = basis_.phase(j);
        const Segment& s = segment_at(segs, th);
        samples->u(0, j) = cy.value(cy.S(), th);
        samples->f(0, j) = cy.tau(s.state, th);
      }
    }
    return true;
  }

  const auto* contact = dynamic_cast<const FrictionContact3D*>(&element);
  if (contact == nullptr) return false;
  const FrictionContactParameters& p = contact->parameters();
  // Tangential direction e from the harmonic vectors (k ≥ 1); their spread off e decides.
  Eigen::Vector2d e(1.0, 0.0);
  double amp = 0.0, off_line = 0.0;
  for (int i = 0; i < nc; ++i) {
    if (i == i0) continue;
    const Eigen::Vector2d vi(coefficients[i], coefficients[nc + i]);
    if (vi.norm() > amp) {
      amp = vi.norm();
      e = vi / amp;
    }
  }
  Eigen::Vector2d mean(off(0), off(1));
  if (i0 >= 0) mean += Eigen::Vector2d(coefficients[i0], coefficients[nc + i0]);
  if (amp == 0.0 && mean.norm() > 0) e = mean / mean.norm();
  const Eigen::Vector2d eperp(-e[1], e[0]);
  for (int i = 0; i < nc; ++i) {
    if (i == i0) continue;
    off_line = std::max(off_line, std::abs(eperp.dot(
                                      Eigen::Vector2d(coefficients[i], coefficients[nc + i]))));
  }
  const bool planar = method_ == AftMethod::kEventPlanar;
  if (off_line > kCollinearTolerance * amp) {
    if (!planar) return false;
    return evaluate_planar(*contact, coefficients, offset, forces, jacobian, samples, warm, stats);
  }
  const bool perp_mean = std::abs(eperp.dot(mean)) > 1e-12 * (mean.norm() + amp);

  const Eigen::VectorXd ct1 = coefficients.segment(0, nc), ct2 = coefficients.segment(nc, nc);
  const Eigen::VectorXd cs = e[0] * ct1 + e[1] * ct2, cp = eperp[0] * ct1 + eperp[1] * ct2;
  const Eigen::VectorXd cw = coefficients.segment(2 * nc, nc);
  const double s0 = e[0] * off(0) + e[1] * off(1), p0 = eperp[0] * off(0) + eperp[1] * off(1);
  EventCycle cy(set, n, p.kt, true, p.mu, p.kn, p.normal_preload + p.kn * (off(2) - p.gap), 0.0);
  cy.set_signals(cs, s0, cw);
  std::vector<Segment> segs;
  int periods = 0;
  if (!cy.cycle(segs, periods)) return false;
  const bool virgin_stuck = segs.size() == 1 && segs[0].state.mode == Mode::kStick &&
                            segs[0].state.anchor == Anchor::kVirgin;
  const bool stuck = segs.size() == 1 && segs[0].state.mode == Mode::kStick;
  // A stuck cycle keeps a tangential force perpendicular to e from the mean offset (2D history):
  // not the scalar law's.
  if (stuck && perp_mean) {
    if (!planar) return false;
    return evaluate_planar(*contact, coefficients, offset, forces, jacobian, samples, warm, stats);
  }
  CycleIntegrals ci;
  integrate(cy, set, segs, jacobian != nullptr, ci);

  // Rotated frame (e, e⊥, n) → (t1, t2, n).
  Eigen::VectorXd Fp = Eigen::VectorXd::Zero(nc);
  if (virgin_stuck) {
    Fp = p.kt * cp;
    if (i0 >= 0) Fp[i0] += p.kt * p0;
  }
  forces.resize(3 * nc);
  forces.segment(0, nc) = e[0] * ci.Fs + eperp[0] * Fp;
  forces.segment(nc, nc) = e[1] * ci.Fs + eperp[1] * Fp;
  forces.segment(2 * nc, nc) = ci.Fn;
  // kEventPlanar: the Jacobian of a cycle that slips or lifts off is the planar method's
  // (event_aft_planar.cpp), exact also across the line (∂F_⊥/∂c_⊥: the slip direction turns off
  // e); its forces equal these to round-off. kEvent: ∂F_⊥/∂c_⊥ the sampled method's, below.
  bool planar_jacobian = false;
  if (jacobian && !virgin_stuck && planar) {
    Eigen::VectorXd Ftmp;
    CycleStatistics tmp;
    planar_jacobian =
        evaluate_planar(*contact, coefficients, offset, Ftmp, jacobian, nullptr, warm, tmp);
  }
  if (jacobian && !planar_jacobian) {
    Eigen::MatrixXd Jpp;
    if (virgin_stuck) {
      Jpp = p.kt * Eigen::MatrixXd::Identity(nc, nc);
    } else {
      // ∂F_⊥/∂c_⊥ the sampled method's, on the rotated coefficients (the law is isotropic in the
      // tangent plane): kEvent, and with kEventPlanar a stuck cycle whose anchor comes from an
      // earlier slip.
      Eigen::VectorXd rot(3 * nc), rot_offset, Ftmp;
      rot << cs, cp, cw;
      if (offset.size() == 3) rot_offset = Eigen::Vector3d(s0, p0, off(2));
      Eigen::MatrixXd Jtmp;
      evaluate_sampled(element, rot, rot_offset, Ftmp, &Jtmp, nullptr);
      Jpp = Jtmp.block(nc, nc, nc, nc);
    }
    Eigen::MatrixXd& J = *jacobian;
    J.setZero(3 * nc, 3 * nc);
    // J = Tᵀ J_rot T, T = [e1 I, e2 I, 0; −e2 I, e1 I, 0; 0, 0, I] (rows e, ⊥, n).
    const double R[2][2] = {{e[0], e[1]}, {eperp[0], eperp[1]}};  // R[r][a]: rotated r, axis a
    for (int a = 0; a < 2; ++a) {
      for (int b = 0; b < 2; ++b) {
        J.block(a * nc, b * nc, nc, nc) = R[0][a] * R[0][b] * ci.Jss + R[1][a] * R[1][b] * Jpp;
      }
      J.block(a * nc, 2 * nc, nc, nc) = R[0][a] * ci.Jsn;
    }
    J.block(2 * nc, 2 * nc, nc, nc) = ci.Jnn;
  }
  stats.stick_fraction = ci.stick;
  stats.slip_fraction = ci.slip;
  stats.separation_fraction = ci.open;
  stats.dissipated_energy = ci.energy;
  stats.periods = periods;
  if (samples) {
    samples->u.resize(3, n);
    samples->f.resize(3, n);
    for (int j = 0; j < n; ++j) {
      double th = basis_.phase(j);
      const Segment& s = segment_at(segs, th);
      const double sv = cy.value(cy.S(), th);
      const Eigen::VectorXd phi = basis_.synthesis().row(j).transpose();
      const double pv = p0 + cp.dot(phi);
      samples->u(0, j) = e[0] * sv + eperp[0] * pv;
      samples->u(1, j) = e[1] * sv + eperp[1] * pv;
      samples->u(2, j) = off(2) + cw.dot(phi);
      const double tau = cy.tau(s.state, th);
      const double tp = virgin_stuck ? p.kt * pv : 0.0;
      samples->f(0, j) = e[0] * tau + eperp[0] * tp;
      samples->f(1, j) = e[1] * tau + eperp[1] * tp;
      samples->f(2, j) = s.state.mode == Mode::kOpen ? 0.0 : cy.value(cy.N(), th);
    }
  }
  return true;
}

}  // namespace stickslip
