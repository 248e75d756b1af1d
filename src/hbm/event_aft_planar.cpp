// The event AFT for FrictionContact3D with general (non-collinear) tangential motion
// (aft.h, AftMethod::kEvent). Continuous law, θ = Ωt, u_t(θ) = u0 + C φ(θ), N(θ) = N0 + kn (w −
// g0):
//   stick (ref, 2-vector):  τ = ref + kt u_t(θ); leaves when g = (μN)² − |τ|² < 0 (→ slip) or
//                           N < 0 (→ open);
//   slip (angle φ):         τ = μN e(φ), e = (cos φ, sin φ), e⊥ = (−sin φ, cos φ). From
//                           τ' = kt (u_t' − λ e), λ ≥ 0 the slip rate, and |τ| = μN:
//                             φ' = kt e⊥·u_t' / (μN),   λ = e·u_t' − μN'/kt;
//                           leaves when λ < 0 (→ stick, ref = μN e − kt u_t) or N < 0 (→ open);
//   open:                   τ = N = 0; touchdown (N > 0) → stick from τ = 0 if kt|u_t'| ≤ μN',
//                           else slip along u_t'.
// The direction ODE is integrated by Gauss–Legendre collocation (kStages stages, order 2·kStages,
// A-stable: the ODE is stiff where N is small), with the Fourier integrals and the variational
// equations carried by the same method (their quadrature are the collocation nodes), so the
// forces and the Jacobian are the exact derivative pair of one discrete map. Events of φ
// (λ = 0) are located by Newton on the length of the step that ends on them, started from the
// zero along the step's collocation polynomial.
// Cost (what was measured to matter, docs/performance.md): the signals at a phase are computed
// once per phase (at() keeps the last; a step keeps its stage nodes' for the slip rate, the
// acceptance and the integrals); the stage values start from the last step's polynomial; the
// lift-off scans are skipped when a bound shows N > 0 throughout; a warm start (aft.h) replaces
// the virgin march.
// Jacobian (why the event-time terms vanish, and lift-off): see aft.h.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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
constexpr int kStages = 8;  // collocation stages: order 16 at the step ends
// Step control: an embedded estimate h |Σ (b_j − b̂_j) φ'_j| (b̂: the interpolatory rule on the
// first s − 1 nodes, O(h^s)) weighted by N/N_scale (the force is μN e: an error of the direction
// where N is small costs that little). The method's own error is O(h^{2s+1}): this bound on the
// pessimistic estimate puts it near round-off.
constexpr double kStepTolerance = 1e-9;
// As event_aft.cpp: a switching function counts as negative below −kSwitchTolerance · scale.
constexpr double kSwitchTolerance = 1e-12;
// The periodic cycle: start angle φ_s closed to this many radians by Newton.
constexpr double kClosureTolerance = 1e-13;
// ... or, once Newton stops gaining (|r| > kClosureStall |r_prev|), to this many: the march's
// return angle is reproducible only to its own error (the step sequence changes with φ_s), which
// was measured at 6e-12..2e-11 rad on gross-slip cycles (P' = 0, so Newton's first step already
// lands on the fixed point and then alternates on that noise; kClosureTolerance alone failed them
// and sent them to the sampled method, a jump in the residual). An angle error δ moves the force
// by μN δ.
constexpr double kClosureNoise = 1e-9;
constexpr double kClosureStall = 0.5;
constexpr int kMaxClosureIterations = 40;
constexpr int kMaxStageIterations = 20;
// The stage values' starting point extrapolates the last step's collocation polynomial by at most
// this many of its lengths (further, a degree-s polynomial is no better than a constant).
constexpr double kMaxExtrapolation = 1.5;

enum class Mode { kStick, kSlip, kOpen };

struct Collocation {
  std::array<double, kStages> c{}, b{}, bhat{};
  std::array<std::array<double, kStages>, kStages> A{};
  std::array<double, kStages + 1> dense{};  // the collocation polynomial's nodes: 0, c_0..c_{s−1}
  std::array<double, kStages + 1> bary{};   // their barycentric weights 1/Π_{m≠j}(x_j − x_m)
};

double lagrange(const double* nodes, int n, int j, double t) {
  double v = 1.0;
  for (int m = 0; m < n; ++m) {
    if (m != j) v *= (t - nodes[m]) / (nodes[j] - nodes[m]);
  }
  return v;
}

// Gauss collocation on [0, 1]: c the Gauss nodes, b the weights, A_ij = ∫_0^{c_i} ℓ_j (Gauss
// quadrature of the degree s − 1 Lagrange basis: exact), b̂ the interpolatory rule on c_0..c_{s−2}.
const Collocation& collocation() {
  static const Collocation col = [] {
    Collocation k;
    const auto& [x, w] = gauss_legendre(kStages);
    for (int i = 0; i < kStages; ++i) {
      k.c[i] = 0.5 * (1 + x[i]);
      k.b[i] = 0.5 * w[i];
    }
    for (int i = 0; i < kStages; ++i) {
      for (int j = 0; j < kStages; ++j) {
        double a = 0;
        for (int m = 0; m < kStages; ++m) {
          a += 0.5 * w[m] * lagrange(k.c.data(), kStages, j, k.c[i] * 0.5 * (1 + x[m]));
        }
        k.A[i][j] = k.c[i] * a;
      }
    }
    k.dense[0] = 0.0;
    for (int j = 0; j < kStages; ++j) k.dense[j + 1] = k.c[j];
    for (int j = 0; j <= kStages; ++j) {
      double p = 1.0;
      for (int m = 0; m <= kStages; ++m) {
        if (m != j) p *= k.dense[j] - k.dense[m];
      }
      k.bary[j] = 1.0 / p;
    }
    for (int j = 0; j + 1 < kStages; ++j) {
      double a = 0;
      for (int m = 0; m < kStages; ++m) {
        a += 0.5 * w[m] * lagrange(k.c.data(), kStages - 1, j, 0.5 * (1 + x[m]));
      }
      k.bhat[j] = a;
    }
    return k;
  }();
  return col;
}

struct State {
  Mode mode = Mode::kStick;
  bool virgin = false;                            // stick from the virgin state (ref = 0)
  double phi = 0.0;                               // slip: direction of τ
  Eigen::RowVectorXd dphi;                        // slip: ∂φ/∂p (1 x np)
  Eigen::Vector2d ref = Eigen::Vector2d::Zero();  // stick: τ = ref + kt u_t(θ)
  Eigen::MatrixXd dref;                           // stick: ∂ref/∂p (2 x np)
};

struct Totals {
  Eigen::VectorXd F;  // 3 nc
  Eigen::MatrixXd J;  // 3 nc x np (if jac)
  double stick = 0, slip = 0, open = 0, energy = 0;
};

struct Sig {  // the signals at one θ
  Eigen::Vector2d u, u1, u2;
  double N, N1, N2;
};

struct StepResult {
  std::array<double, kStages> th{}, Phi{}, f{}, fphi{};
  double th0 = 0.0, phi = 0.0, h = 0.0;  // the step: from (θ0, φ) of length h
  double phi_end = 0.0, err = 0.0;
  int nonpositive = -1;  // a stage where N ≤ 0 (the step failed there), else −1
  Eigen::Matrix<double, kStages, kStages> Jm;
  std::array<Sig, kStages> sig;  // the signals at the stage nodes
  Eigen::MatrixXd B0, B1;        // the basis φ, φ' at the stage nodes (nc x kStages)

  // The collocation polynomial (through (0, φ) and (c_j, Φ_j)) at x·h, x in units of the step
  // (barycentric form).
  double dense(double x) const {
    const Collocation& k = collocation();
    double num = 0, den = 0;
    for (int m = 0; m <= kStages; ++m) {
      const double v = m == 0 ? phi : Phi[m - 1], d = x - k.dense[m];
      if (d == 0.0) return v;
      const double w = k.bary[m] / d;
      num += w * v;
      den += w;
    }
    return num / den;
  }
};

// Parameters p: the 3 nc coefficients (t1, t2, w) and, last, the start angle φ_s of the cycle
// (its column closes the periodicity). With full = false only that last column is carried.
class PlanarCycle {
 public:
  PlanarCycle(const HarmonicSet& set, int grid_samples, const FrictionContactParameters& p,
              const Eigen::VectorXd& c, const Eigen::Vector3d& offset)
      : set_(set),
        nc_(set.coefficient_count()),
        grid_(kTwoPi / grid_samples),
        kt_(p.mu > 0 ? p.kt : 0.0),
        kn_(p.kn),
        mu_(p.mu),
        b0_(nc_),
        b1_(nc_),
        b2_(nc_),
        norm_(nc_) {
    C_.resize(2, nc_);
    C_.row(0) = c.segment(0, nc_).transpose();
    C_.row(1) = c.segment(nc_, nc_).transpose();
    cw_ = c.segment(2 * nc_, nc_);
    u0_ = offset.head<2>();
    nc0_ = p.normal_preload + p.kn * (offset[2] - p.gap);
    for (int q = 0; q < set.size(); ++q) {
      const int o = set.offset(q);
      if (set.harmonics()[q] == 0) {
        norm_[o] = 1 / kTwoPi;
      } else {
        norm_[o] = norm_[o + 1] = 1 / kPi;
      }
    }
    max_k_ = std::max(1, set.max_harmonic());
    n_scale_ = std::abs(nc0_) + kn_ * cw_.lpNorm<1>() + std::numeric_limits<double>::min();
    u_scale_ = u0_.lpNorm<1>() + C_.cwiseAbs().sum();
    // N(θ) ≥ nc0 + kn (a_0 − Σ_k |(a_k, b_k)|): when that is positive the contact never opens and
    // the scans for lift-off are skipped (their answer is known).
    double n_min = nc0_;
    for (int q = 0; q < set.size(); ++q) {
      const int o = set.offset(q);
      n_min += set.harmonics()[q] == 0 ? kn_ * cw_[o] : -kn_ * std::hypot(cw_[o], cw_[o + 1]);
    }
    always_closed_ = n_min > 0;
    h_max_ = std::min(0.5 * kStages * grid_, kPi / max_k_);
    exit_grid_ = std::min(grid_, kPi / (4 * max_k_));
    max_events_ = 8 * grid_samples + 100;
    grid_samples_ = grid_samples;
  }

  int np() const { return np_; }
  bool frictionless() const { return mu_ == 0.0; }

  // Basis φ, φ', φ'' at θ into b0_, b1_, b2_ and the signals.
  Sig at(double th) {
    if (th == last_th_) return last_sig_;  // callers ask for a value and its derivative in turn
    for (int q = 0; q < set_.size(); ++q) {
      const int k = set_.harmonics()[q], o = set_.offset(q);
      if (k == 0) {
        b0_[o] = 1.0;
        b1_[o] = b2_[o] = 0.0;
        continue;
      }
      const double cs = std::cos(k * th), sn = std::sin(k * th);
      b0_[o] = cs;
      b0_[o + 1] = sn;
      b1_[o] = -k * sn;
      b1_[o + 1] = k * cs;
      b2_[o] = -k * k * cs;
      b2_[o + 1] = -k * k * sn;
    }
    Sig s;
    s.u = u0_ + C_ * b0_;
    s.u1 = C_ * b1_;
    s.u2 = C_ * b2_;
    s.N = nc0_ + kn_ * cw_.dot(b0_);
    s.N1 = kn_ * cw_.dot(b1_);
    s.N2 = kn_ * cw_.dot(b2_);
    last_th_ = th;
    last_sig_ = s;
    return s;
  }

  // The periodic cycle and its integrals. warm: nullptr, or a start to try first (warm.arguments
  // == args: the call that found it had these arguments), updated to this cycle's. False when it
  // could not be closed (the caller falls back to the sampled AFT).
  bool run(bool jac, Totals& tot, int& periods, Eigen::Matrix3Xd* samples, AftWarmStart* warm,
           const Eigen::VectorXd& args) {
    using Kind = AftWarmStart::Kind;
    if (warm && warm->kind != Kind::kNone && warm->arguments.size() == args.size() &&
        run_warm(jac, tot, periods, samples, *warm, args)) {
      warm->arguments = args;
      return true;
    }
    AftWarmStart found;
    const bool ok = run_cold(jac, tot, periods, samples, found);
    if (warm) {
      *warm = ok ? found : AftWarmStart{};
      if (ok) warm->arguments = args;
    }
    return ok;
  }

 private:
  // From the start of an earlier cycle: a phase in separation closes at once (the state after it
  // does not depend on the history); a phase in slip with the angle found there is closed by
  // Newton on the angle (close_slip), or taken as closed when the arguments are the same (the
  // call before found it so; with the sensitivities now). False when the start does not apply
  // (not in separation, not slipping, or the cycle does not close from it).
  bool run_warm(bool jac, Totals& tot, int& periods, Eigen::Matrix3Xd* samples, AftWarmStart& w,
                const Eigen::VectorXd& args) {
    full_ = false;
    np_ = 1;
    const double ts = w.theta;
    if (w.kind == AftWarmStart::Kind::kOpen) {
      if (!(normal(ts, 0) < -kSwitchTolerance * n_scale_)) return false;
      State so;
      so.mode = Mode::kOpen;
      periods = 1;
      return final_march(so, ts, jac, tot, samples);
    }
    if (frictionless() || !(normal(ts, 0) > 0) || !(slip_rate(ts, w.phi) > 0)) return false;
    if ((jac || samples) && w.arguments == args) {
      State ss;
      ss.mode = Mode::kSlip;
      ss.phi = w.phi;
      periods = 1;
      return final_march(ss, ts, jac, tot, samples);
    }
    double phi_s = w.phi;
    periods = 0;
    if (!close_slip(ts, phi_s, jac, tot, periods, samples)) return false;
    w.phi = phi_s;
    return true;
  }

  // From the virgin state at θ = 0: two periods, then the cycle's start from the segments of the
  // second (found: that start, for the next call's warm start).
  bool run_cold(bool jac, Totals& tot, int& periods, Eigen::Matrix3Xd* samples,
                AftWarmStart& found) {
    // Start: θ = 0 from the virgin state.
    full_ = false;
    np_ = 1;
    State st = virgin_start();
    std::vector<Seg> rec;
    if (!march(st, 0.0, kTwoPi, nullptr, &rec)) return false;
    bool ever_left_virgin = !(st.mode == Mode::kStick && st.virgin);
    rec.clear();
    if (!march(st, kTwoPi, 2 * kTwoPi, nullptr, &rec)) return false;
    ever_left_virgin = ever_left_virgin || !(st.mode == Mode::kStick && st.virgin);
    const Seg* open = nullptr;
    const Seg* slip = nullptr;
    for (const Seg& s : rec) {
      if (s.mode == Mode::kOpen && (!open || s.b - s.a > open->b - open->a)) open = &s;
      if (s.mode == Mode::kSlip && (!slip || s.b - s.a > slip->b - slip->a)) slip = &s;
    }
    periods = 2;
    if (open) {  // the state after an open segment does not depend on the history: closed
      const double ts = 0.5 * (open->a + open->b);
      State so;
      so.mode = Mode::kOpen;
      found.kind = AftWarmStart::Kind::kOpen;
      found.theta = ts;
      ++periods;
      return final_march(so, ts, jac, tot, samples);
    }
    if (!slip) {
      if (ever_left_virgin) return stuck_after_transient(jac, tot, periods, samples);
      State sv;
      sv.mode = Mode::kStick;
      sv.virgin = true;
      periods = 2;
      return final_march(sv, 0.0, jac, tot, samples);
    }
    // Mid-way in the longest slip segment of the next period, then Newton on the start angle.
    double ts = 0.5 * (slip->a + slip->b) + kTwoPi;
    if (!march(st, 2 * kTwoPi, ts, nullptr, nullptr) || st.mode != Mode::kSlip) return false;
    // The angle modulo 2π (a gross-slip cycle winds it up over the transient periods).
    double phi_s = st.phi - kTwoPi * std::round(st.phi / kTwoPi);
    if (!close_slip(ts, phi_s, jac, tot, periods, samples)) return false;
    found.kind = AftWarmStart::Kind::kSlip;
    found.theta = ts;
    found.phi = phi_s;
    return true;
  }

  // Newton on the start angle φ_s at θ_s (in slip) until the period map returns it, then the
  // integrals (from the last march, or one more with the sensitivities). Adds the periods marched.
  bool close_slip(double ts, double& phi_s, bool jac, Totals& tot, int& periods,
                  Eigen::Matrix3Xd* samples) {
    full_ = false;
    np_ = 1;
    double r_prev = std::numeric_limits<double>::infinity();
    Totals t1;
    for (int it = 0;; ++it) {
      if (it >= kMaxClosureIterations) return false;
      State ss;
      ss.mode = Mode::kSlip;
      ss.phi = phi_s;
      ss.dphi.setOnes(1);
      t1 = Totals{};
      t1.F.setZero(3 * nc_);
      if (!march(ss, ts, ts + kTwoPi, jac ? nullptr : &t1, nullptr) || ss.mode != Mode::kSlip) {
        return false;
      }
      ++periods;
      const double d = ss.phi - phi_s;
      const double r = d - kTwoPi * std::round(d / kTwoPi);
      if (std::abs(r) <= kClosureTolerance * std::max(1.0, std::abs(phi_s))) break;
      if (std::abs(r) <= kClosureNoise && std::abs(r) > kClosureStall * r_prev) break;
      r_prev = std::abs(r);
      const double g = 1.0 - ss.dphi[0];
      phi_s += std::abs(g) > 1e-3 ? r / g : r;
    }
    if (!jac && !samples) {
      tot = std::move(t1);
      finish(tot);
      return true;
    }
    State ss;
    ss.mode = Mode::kSlip;
    ss.phi = phi_s;
    ++periods;
    return final_march(ss, ts, jac, tot, samples);
  }
  struct Seg {
    double a, b;
    Mode mode;
  };

  void finish(Totals& t) const {
    t.stick /= kTwoPi;
    t.slip /= kTwoPi;
    t.open /= kTwoPi;
    if (frictionless()) {  // τ = 0 throughout: contact is free sliding
      t.slip += t.stick;
      t.stick = 0.0;
    }
  }

  // The state at θ = 0 from the virgin law (τ = kt u_t(0), clipped to μN), with its
  // sensitivities (np_ parameters).
  State virgin_start() {
    State st;
    const Sig s0 = at(0.0);
    if (s0.N <= 0) {
      st.mode = Mode::kOpen;
    } else if ((kt_ * s0.u).norm() > mu_ * s0.N && !frictionless()) {
      st.mode = Mode::kSlip;
      st.phi = std::atan2(s0.u[1], s0.u[0]);
      st.dphi.setZero(np_);
      // ∂φ = e⊥·∂u_t(0)/|u_t(0)|.
      if (full_) {
        const Eigen::Vector2d ep(-std::sin(st.phi), std::cos(st.phi));
        const double a = s0.u.norm();
        for (int r = 0; r < 2; ++r) st.dphi.segment(r * nc_, nc_) += ep[r] / a * b0_.transpose();
      }
    } else {
      st.mode = Mode::kStick;
      st.virgin = true;
      st.dref.setZero(2, np_);
    }
    return st;
  }

  // A cycle stuck throughout after slipping in the transient: the stuck periodic cycles form a
  // family (any anchor with |τ| ≤ μN all along), and the law's own history from the virgin state
  // at θ = 0 picks one, as the sampled march does. The transient is marched again carrying the
  // sensitivities (the anchor depends on c through every event of the transient; the event-time
  // terms are those of the regular march, aft.h), then one period accumulates.
  bool stuck_after_transient(bool jac, Totals& tot, int& periods, Eigen::Matrix3Xd* samples) {
    full_ = jac;
    np_ = jac ? 3 * nc_ + 1 : 1;
    State st = virgin_start();
    if (!march(st, 0.0, 2 * kTwoPi, nullptr, nullptr) || st.mode != Mode::kStick) return false;
    tot = Totals{};
    tot.F.setZero(3 * nc_);
    if (jac) tot.J.setZero(3 * nc_, np_);
    samples_ = samples;
    if (samples_) samples_->setZero(3, grid_samples_);
    const bool ok = march(st, 2 * kTwoPi, 3 * kTwoPi, &tot, nullptr);
    samples_ = nullptr;
    if (!ok || st.mode != Mode::kStick) return false;
    if (jac) tot.J = tot.J.leftCols(3 * nc_).eval();
    finish(tot);
    periods = 3;
    return true;
  }

  // One period from θ_s with the integrals (and the Jacobian: all parameters carried).
  bool final_march(State st, double ts, bool jac, Totals& tot, Eigen::Matrix3Xd* samples) {
    full_ = jac;
    np_ = jac ? 3 * nc_ + 1 : 1;
    if (st.mode == Mode::kSlip) {
      st.dphi.setZero(np_);
      st.dphi[np_ - 1] = 1.0;
    }
    st.dref.setZero(2, np_);
    tot = Totals{};
    tot.F.setZero(3 * nc_);
    if (jac) tot.J.setZero(3 * nc_, np_);
    samples_ = samples;
    if (samples_) samples_->setZero(3, grid_samples_);
    const bool ok = march(st, ts, ts + kTwoPi, &tot, nullptr);
    samples_ = nullptr;
    if (!ok) return false;
    if (jac) {
      // Periodicity of the start angle: φ_s = P(φ_s, c) ⇒ dφ_s/dc = P_c / (1 − P_φ).
      Eigen::MatrixXd J = tot.J.leftCols(3 * nc_);
      if (st.mode == Mode::kSlip) {
        const double g = 1.0 - st.dphi[np_ - 1];
        if (std::abs(g) < 1e-12) return false;
        J.noalias() += tot.J.col(np_ - 1) * (st.dphi.head(3 * nc_) / g);
      }
      tot.J = std::move(J);
    }
    finish(tot);
    return true;
  }

  // Adds v (1 x nc) times s into row r's coefficient block blk of a 2 x np sensitivity.
  void add_block(Eigen::MatrixXd& d, int r, int blk, double s, const Eigen::VectorXd& v) const {
    if (full_) d.block(r, blk * nc_, 1, nc_) += s * v.transpose();
  }

  // First θ in (a, b] where fun < −tol (fun(θ, q): derivative q = 0, 1, 2; event_roots.h). The
  // grid is the N-point one, refined to π/(4 H_max): the stick function (μN)² − |τ|² has degree
  // 2 H_max, and the check of one interior minimum per interval needs a few points per period of
  // its highest harmonic.
  template <class F>
  std::optional<double> first_exit(const F& fun, double tol, double a, double b) {
    return event_roots::first_exit(fun, tol, exit_grid_, a, b);
  }

  // The first lift-off in (a, b] (first_exit of N).
  std::optional<double> first_opening(double a, double b) {
    if (always_closed_) return std::nullopt;
    return first_exit([&](double t, int q) { return normal(t, q); }, kSwitchTolerance * n_scale_, a,
                      b);
  }

  double normal(double th, int q) {
    const Sig s = at(th);
    return q == 0 ? s.N : q == 1 ? s.N1 : s.N2;
  }

  // Marches st from θ = a to b. tot: accumulate the integrals (nullptr: only the state). rec:
  // the segments. False when the march failed (too many events, a step that cannot be solved).
  bool march(State& st, double a, double b, Totals* tot, std::vector<Seg>* rec) {
    double th = a;
    int events = 0;
    const double n_tol = kSwitchTolerance * n_scale_;
    while (th < b) {
      if (++events > max_events_) return false;
      double te = b;
      Mode next = st.mode;
      switch (st.mode) {
        case Mode::kOpen: {
          const auto e = first_exit([&](double t, int q) { return -normal(t, q); }, n_tol, th, b);
          if (e) te = *e;
          if (tot) tot->open += te - th;
          if (tot) fill_samples(st, th, te);
          if (rec) rec->push_back({th, te, st.mode});
          if (!e) return true;
          touchdown(st, te);
          th = te;
          continue;
        }
        case Mode::kStick: {
          const double g_scale =
              std::pow(mu_ * n_scale_ + kt_ * u_scale_, 2) + std::numeric_limits<double>::min();
          auto g = [&](double t, int q) {
            const Sig s = at(t);
            const Eigen::Vector2d tau = st.ref + kt_ * s.u;
            const double m2 = mu_ * mu_;
            if (q == 0) return m2 * s.N * s.N - tau.squaredNorm();
            if (q == 1) return 2 * m2 * s.N * s.N1 - 2 * kt_ * tau.dot(s.u1);
            return 2 * m2 * (s.N1 * s.N1 + s.N * s.N2) -
                   2 * kt_ * (kt_ * s.u1.squaredNorm() + tau.dot(s.u2));
          };
          std::optional<double> e1;
          if (!frictionless()) e1 = first_exit(g, kSwitchTolerance * g_scale, th, b);
          const auto e2 = first_opening(th, e1 ? *e1 : b);
          if (e2) {
            te = *e2;
            next = Mode::kOpen;
          } else if (e1) {
            te = *e1;
            next = Mode::kSlip;
          }
          if (tot) accumulate_stick(st, th, te, *tot);
          if (rec) rec->push_back({th, te, st.mode});
          if (next == Mode::kStick) return true;
          if (next == Mode::kOpen) {
            st = State{};
            st.mode = Mode::kOpen;
          } else {
            stick_to_slip(st, te);
          }
          th = te;
          continue;
        }
        case Mode::kSlip: {
          const auto e = first_opening(th, b);
          const double end = e ? *e : b;
          bool to_stick = false, lifted = false;
          const double stop = integrate_slip(st, th, end, tot, to_stick, lifted);
          if (stop < 0) return false;
          if (rec) rec->push_back({th, stop, st.mode});
          th = stop;
          if (to_stick) {
            slip_to_stick(st, th);
          } else if (e || lifted) {
            st = State{};
            st.mode = Mode::kOpen;
          } else {
            return true;
          }
          continue;
        }
      }
    }
    return true;
  }

  void touchdown(State& st, double te) {
    const Sig s = at(te);
    // ∂θ_a = −kn φ(θ_a)ᵀ ∂c_w / N'(θ_a): the touchdown moves with the normal motion.
    Eigen::RowVectorXd dth = Eigen::RowVectorXd::Zero(np_);
    if (full_ && s.N1 > 0) dth.segment(2 * nc_, nc_) = -kn_ / s.N1 * b0_.transpose();
    State n;
    if (kt_ * s.u1.norm() <= mu_ * s.N1 || frictionless()) {
      // Stick from τ = 0: ref = −kt u_t(θ_a); ∂ref = −kt (φ(θ_a)ᵀ ∂c_t + u_t'(θ_a) ∂θ_a).
      n.mode = Mode::kStick;
      n.ref = -kt_ * s.u;
      n.dref.setZero(2, np_);
      for (int r = 0; r < 2; ++r) {
        add_block(n.dref, r, r, -kt_, b0_);
        n.dref.row(r) -= kt_ * s.u1[r] * dth;
      }
    } else {
      // Slip along u_t'(θ_a): φ(θ_a) = arg u_t'(θ_a). At a fixed θ > θ_a the start moving by
      // ∂θ_a changes φ by ∂[arg u_t'(θ_a)] − φ'(θ_a+) ∂θ_a, with ∂[arg u_t'(θ_a)] =
      // e⊥·(φ'(θ_a)ᵀ ∂c_t + u_t'' ∂θ_a)/|u_t'| and the regular solution's start rate (φ' =
      // kt e⊥·u_t'/(μN) expanded to first order in θ − θ_a, e⊥·u_t' and N both vanishing):
      //   φ'(θ_a+) = kt e⊥·u_t'' / (μN' + kt |u_t'|).
      n.mode = Mode::kSlip;
      n.phi = std::atan2(s.u1[1], s.u1[0]);
      const Eigen::Vector2d ep(-std::sin(n.phi), std::cos(n.phi));
      const double a = s.u1.norm();
      const double rate = kt_ * ep.dot(s.u2) / (mu_ * s.N1 + kt_ * a);
      n.dphi = (ep.dot(s.u2) / a - rate) * dth;
      if (full_) {
        for (int r = 0; r < 2; ++r) n.dphi.segment(r * nc_, nc_) += ep[r] / a * b1_.transpose();
      }
    }
    st = std::move(n);
  }

  // Stick → slip at θ_e: φ = arg τ, ∂φ = e⊥·∂τ/|τ|. The event time's term is (φ'_stick −
  // φ'_slip) ∂θ_e = 0: in stick τ' = kt u_t', so the angle turns at kt e⊥·u_t'/|τ| = φ'_slip.
  void stick_to_slip(State& st, double te) {
    const Sig s = at(te);
    const Eigen::Vector2d tau = st.ref + kt_ * s.u;
    Eigen::MatrixXd dtau = st.dref;
    for (int r = 0; r < 2; ++r) add_block(dtau, r, r, kt_, b0_);
    State n;
    n.mode = Mode::kSlip;
    n.phi = std::atan2(tau[1], tau[0]);
    const Eigen::Vector2d ep(-std::sin(n.phi), std::cos(n.phi));
    n.dphi = (ep.transpose() * dtau) / tau.norm();
    st = std::move(n);
  }

  // Slip → stick at θ_a: ref = μN e − kt u_t. The event time's term is d/dθ(μN e − kt u_t) =
  // μN' e + kt (I − e eᵀ) u_t' − kt u_t' = −kt λ e = 0 (λ = 0 there).
  void slip_to_stick(State& st, double ta) {
    const Sig s = at(ta);
    const Eigen::Vector2d e(std::cos(st.phi), std::sin(st.phi)), ep(-e[1], e[0]);
    State n;
    n.mode = Mode::kStick;
    n.ref = mu_ * s.N * e - kt_ * s.u;
    n.dref = (mu_ * s.N * ep) * st.dphi;
    for (int r = 0; r < 2; ++r) {
      add_block(n.dref, r, 2, mu_ * kn_ * e[r], b0_);
      add_block(n.dref, r, r, -kt_, b0_);
    }
    st = std::move(n);
  }

  void accumulate_stick(const State& st, double a, double b, Totals& tot) {
    const double len = b - a;
    if (len <= 0) return;
    tot.stick += len;
    fill_samples(st, a, b);
    const int nq = static_cast<int>(std::ceil(0.75 * max_k_ * len + 10));
    const auto& [xg, wg] = gauss_legendre(nq);
    Eigen::MatrixXd M;
    Eigen::VectorXd v;
    if (full_) {
      M.setZero(nc_, nc_);
      v.setZero(nc_);
    }
    for (int g = 0; g < nq; ++g) {
      const double th = 0.5 * (a + b) + 0.5 * len * xg[g], w = 0.5 * len * wg[g];
      const Sig s = at(th);
      const Eigen::VectorXd psi = b0_.cwiseProduct(norm_);
      const Eigen::Vector2d tau = st.ref + kt_ * s.u;
      tot.F.segment(0, nc_) += (w * tau[0]) * psi;
      tot.F.segment(nc_, nc_) += (w * tau[1]) * psi;
      tot.F.segment(2 * nc_, nc_) += (w * s.N) * psi;
      tot.energy += w * tau.dot(s.u1);
      if (full_) {
        M.noalias() += (w * psi) * b0_.transpose();
        v += w * psi;
      }
    }
    if (!full_) return;
    for (int r = 0; r < 2; ++r) {
      tot.J.block(r * nc_, 0, nc_, np_).noalias() += v * st.dref.row(r);
      tot.J.block(r * nc_, r * nc_, nc_, nc_) += kt_ * M;
    }
    tot.J.block(2 * nc_, 2 * nc_, nc_, nc_) += kn_ * M;
  }

  // Samples on the grid θ_j = j·2π/N in [a, b) of a stick or open segment.
  void fill_samples(const State& st, double a, double b) {
    if (!samples_) return;
    for (long j = static_cast<long>(std::ceil(a / grid_)); j * grid_ < b; ++j) {
      const double th = j * grid_;
      const int col = static_cast<int>(((j % grid_samples_) + grid_samples_) % grid_samples_);
      if (st.mode == Mode::kOpen) {
        samples_->col(col).setZero();
        continue;
      }
      const Sig s = at(th);
      const Eigen::Vector2d tau = st.ref + kt_ * s.u;
      samples_->col(col) << tau[0], tau[1], s.N;
    }
  }

  // The slip ODE's right-hand side and its φ-derivative at (θ, φ) (s: the signals at θ).
  void rhs(const Sig& s, double phi, double& f, double& fphi) const {
    const Eigen::Vector2d e(std::cos(phi), std::sin(phi)), ep(-e[1], e[0]);
    const double mn = mu_ * s.N;
    f = kt_ * ep.dot(s.u1) / mn;
    fphi = -kt_ * e.dot(s.u1) / mn;
  }

  // One collocation step from (θ, φ) of length h. guess: the stage values' starting point (else
  // φ at every stage). False if the stage equations do not converge.
  bool solve_step(double th, double phi, double h, StepResult& r,
                  const std::array<double, kStages>* guess = nullptr) {
    const Collocation& k = collocation();
    r.nonpositive = -1;
    r.th0 = th;
    r.phi = phi;
    r.h = h;
    if (r.B0.rows() != nc_) {
      r.B0.resize(nc_, kStages);
      r.B1.resize(nc_, kStages);
    }
    for (int j = 0; j < kStages; ++j) {
      r.th[j] = th + k.c[j] * h;
      r.Phi[j] = guess ? (*guess)[j] : phi;
      r.sig[j] = at(r.th[j]);
      if (!(r.sig[j].N > 0)) {
        r.nonpositive = j;
        return false;
      }
      r.B0.col(j) = b0_;
      r.B1.col(j) = b1_;
    }
    const double tol = 8 * std::numeric_limits<double>::epsilon() * (1 + std::abs(phi));
    Eigen::Matrix<double, kStages, 1> res;
    Eigen::Matrix<double, kStages, kStages> Ah;
    for (int i = 0; i < kStages; ++i) {
      for (int j = 0; j < kStages; ++j) Ah(i, j) = h * k.A[i][j];
    }
    bool converged = false;
    for (int it = 0; it < kMaxStageIterations; ++it) {
      for (int j = 0; j < kStages; ++j) rhs(r.sig[j], r.Phi[j], r.f[j], r.fphi[j]);
      for (int i = 0; i < kStages; ++i) {
        double a = 0;
        for (int j = 0; j < kStages; ++j) a += Ah(i, j) * r.f[j];
        res[i] = r.Phi[i] - phi - a;
      }
      r.Jm = -Ah;
      for (int j = 0; j < kStages; ++j) r.Jm.col(j) *= r.fphi[j];
      r.Jm.diagonal().array() += 1.0;
      if (converged) break;
      const Eigen::Matrix<double, kStages, 1> d = r.Jm.partialPivLu().solve(res);
      if (!d.allFinite()) return false;
      for (int j = 0; j < kStages; ++j) r.Phi[j] -= d[j];
      converged = d.cwiseAbs().maxCoeff() <= tol;
    }
    if (!converged) return false;
    double sum = 0, est = 0;
    for (int j = 0; j < kStages; ++j) {
      sum += k.b[j] * r.f[j];
      est += (k.b[j] - k.bhat[j]) * r.f[j];
    }
    r.phi_end = phi + h * sum;
    const double n_mid = std::abs(r.sig[kStages / 2].N) / n_scale_;
    r.err = std::abs(h * est) * std::clamp(n_mid, 1e-6, 1.0);
    return std::isfinite(r.phi_end);
  }

  // The slip rate λ/|u_t| scale: e·u_t' − μN'/kt at (θ, φ) (s: the signals at θ), and its total
  // θ-derivative along the slip ODE.
  double slip_rate(const Sig& s, double phi, double* dth = nullptr) const {
    const Eigen::Vector2d e(std::cos(phi), std::sin(phi)), ep(-e[1], e[0]);
    if (dth) {
      double f, fphi;
      rhs(s, phi, f, fphi);
      *dth = ep.dot(s.u1) * f + e.dot(s.u2) - mu_ * s.N2 / kt_;
    }
    return e.dot(s.u1) - mu_ * s.N1 / kt_;
  }
  double slip_rate(double th, double phi, double* dth = nullptr) {
    return slip_rate(at(th), phi, dth);
  }

  // The length x in (0, neg] of the step from r's start that ends where the slip rate crosses
  // zero (r: an accepted step of length ≥ neg whose slip rate is negative at neg). Located by
  // Newton on the length of the step that ends there (each iterate a collocation step: the event
  // lies on the discrete solution), started from the zero along r's collocation polynomial (no
  // step solves; its error is the polynomial's, O(h^{s+1})). tmp receives the step of the root.
  // Returns −1 on failure.
  double slip_to_stick_step(double th, const StepResult& r, double neg, StepResult& tmp) {
    const double h = r.h, phi = r.phi;
    // The zero along the dense output.
    auto fd = [&](double x) { return slip_rate(th + x, r.dense(x / h)); };
    auto dfd = [&](double x) {
      double d = 0;
      slip_rate(th + x, r.dense(x / h), &d);
      return d;
    };
    const double x0 = event_roots::locate(fd, dfd, 0.0, neg);
    // Newton on the discrete solution; each iterate's step solved once (value and derivative).
    bool ok = true;
    double last_x = std::numeric_limits<double>::quiet_NaN(), last_f = 0, last_d = 0;
    auto eval = [&](double x) {
      if (x == last_x) return;
      last_x = x;
      std::array<double, kStages> guess;
      for (int j = 0; j < kStages; ++j) guess[j] = r.dense(collocation().c[j] * x / h);
      ok = ok && solve_step(th, phi, x, tmp, &guess);
      if (ok) last_f = slip_rate(th + x, tmp.phi_end, &last_d);
    };
    auto fun = [&](double x) {
      eval(x);
      return ok ? last_f : -1.0;
    };
    auto dfun = [&](double x) {
      eval(x);
      return ok ? last_d : 0.0;
    };
    const double step = event_roots::locate(fun, dfun, 0.0, neg, x0);
    eval(step);
    return ok ? step : -1.0;
  }

  // Integrates the slip from a towards end; stops at end, where the slip rate turns negative
  // (to_stick) or where N reaches 0 though it dipped below zero by less than the switching
  // tolerance (lifted: a grazing contact; the law's memory is lost there all the same). Updates st
  // (φ, ∂φ) and accumulates. Returns the θ reached, −1 on failure.
  double integrate_slip(State& st, double a, double end, Totals* tot, bool& to_stick,
                        bool& lifted) {
    const Collocation& k = collocation();
    const double lam_tol =
        kSwitchTolerance * (C_.cwiseAbs().sum() * max_k_ + mu_ * n_scale_ * max_k_ / kt_);
    double th = a, h = h_max_;
    StepResult r, tmp;
    bool have_prev = false;  // r holds the last solved step of this slip segment
    int steps = 0;
    while (th < end) {
      if (++steps > 1000 * grid_samples_) return -1;
      const bool last = h >= end - th;
      const double hs = last ? end - th : h;
      if (end - th <= 1e-13 * (1 + std::abs(th))) return end;  // what is left carries N ≈ 0
      // The stage values' starting point: the last step's collocation polynomial (the rejected
      // step from the same start, or the accepted one before, extrapolated by at most
      // kMaxExtrapolation of its length); else φ at every stage.
      std::array<double, kStages> guess;
      bool guessed = false;
      if (have_prev && th + hs - r.th0 <= (1 + kMaxExtrapolation) * r.h) {
        for (int j = 0; j < kStages; ++j) guess[j] = r.dense((th + k.c[j] * hs - r.th0) / r.h);
        guessed = true;
      }
      bool solved = solve_step(th, st.phi, hs, r, guessed ? &guess : nullptr);
      if (!solved && guessed && r.nonpositive < 0) solved = solve_step(th, st.phi, hs, r);
      have_prev = solved;
      if (!solved) {
        if (r.nonpositive >= 0) {
          if (!(normal(th, 0) > 0)) {
            lifted = true;
            return th;
          }
          end =
              event_roots::locate([&](double t) { return normal(t, 0); },
                                  [&](double t) { return normal(t, 1); }, th, r.th[r.nonpositive]);
          lifted = true;
          continue;
        }
        h = 0.25 * hs;
        if (h < 1e-14 * (1 + std::abs(th))) return -1;
        continue;
      }
      if (r.err > kStepTolerance) {
        h = hs * std::max(0.1, 0.9 * std::pow(kStepTolerance / r.err, 1.0 / kStages));
        continue;
      }
      // Slip → stick inside the step: the slip rate at the stage nodes and the end.
      double neg = -1;
      for (int j = 0; j < kStages && neg < 0; ++j) {
        if (slip_rate(r.sig[j], r.Phi[j]) < -lam_tol) neg = k.c[j] * hs;
      }
      if (neg < 0 && slip_rate(th + hs, r.phi_end) < -lam_tol) neg = hs;
      double step = hs;
      const StepResult* acc = &r;
      if (neg > 0) {
        step = slip_to_stick_step(th, r, neg, tmp);
        if (step < 0) return -1;
        acc = &tmp;
        to_stick = true;
      }
      accept_step(st, th, step, *acc, tot);
      th += step;
      if (to_stick) return th;
      if (last) break;
      h = hs *
          std::min(4.0, 0.9 * std::pow(kStepTolerance / std::max(r.err, 1e-300), 1.0 / kStages));
      h = std::min(h, h_max_);
    }
    return end;
  }

  // Accepts the step: the end angle, the variational equations of the collocation method
  // (dΦ = Jm⁻¹ (1 dφ_n + h A F_p), dφ_{n+1} = dφ_n + h Σ b_j (f_φ,j dΦ_j + F_p,j)) and the
  // integrals at the nodes (the Fourier integrals are the method's quadrature components).
  void accept_step(State& st, double th, double h, const StepResult& r, Totals* tot) {
    const Collocation& k = collocation();
    if (tot) tot->slip += h;
    Eigen::MatrixXd Fp;
    const bool sens = st.dphi.size() == np_;
    if (sens) Fp.setZero(kStages, np_);
    for (int j = 0; j < kStages; ++j) {
      const Sig& s = r.sig[j];
      const Eigen::Vector2d e(std::cos(r.Phi[j]), std::sin(r.Phi[j])), ep(-e[1], e[0]);
      if (sens && full_) {
        const double mn = mu_ * s.N;
        for (int q = 0; q < 2; ++q)
          Fp.block(j, q * nc_, 1, nc_) = kt_ * ep[q] / mn * r.B1.col(j).transpose();
        Fp.block(j, 2 * nc_, 1, nc_) = -r.f[j] * kn_ / s.N * r.B0.col(j).transpose();
      }
      if (!tot) continue;
      const double w = h * k.b[j];
      const Eigen::VectorXd psi = r.B0.col(j).cwiseProduct(norm_);
      const Eigen::Vector2d tau = mu_ * s.N * e;
      tot->F.segment(0, nc_) += (w * tau[0]) * psi;
      tot->F.segment(nc_, nc_) += (w * tau[1]) * psi;
      tot->F.segment(2 * nc_, nc_) += (w * s.N) * psi;
      tot->energy += w * tau.dot(s.u1);
    }
    Eigen::MatrixXd dPhi;
    if (sens) {
      Eigen::Matrix<double, kStages, kStages> Ah;
      for (int i = 0; i < kStages; ++i) {
        for (int j = 0; j < kStages; ++j) Ah(i, j) = h * k.A[i][j];
      }
      Eigen::MatrixXd rhs_m = Ah * Fp;
      rhs_m.rowwise() += st.dphi;
      dPhi = r.Jm.partialPivLu().solve(rhs_m);
      Eigen::RowVectorXd inc = Eigen::RowVectorXd::Zero(np_);
      for (int j = 0; j < kStages; ++j) inc += k.b[j] * (r.fphi[j] * dPhi.row(j) + Fp.row(j));
      st.dphi += h * inc;
    }
    if (tot && full_) {
      for (int j = 0; j < kStages; ++j) {
        const double w = h * k.b[j];
        const Sig& s = r.sig[j];
        const Eigen::Vector2d e(std::cos(r.Phi[j]), std::sin(r.Phi[j])), ep(-e[1], e[0]);
        const auto b0 = r.B0.col(j);
        const Eigen::VectorXd psi = b0.cwiseProduct(norm_);
        for (int q = 0; q < 2; ++q) {
          tot->J.block(q * nc_, 2 * nc_, nc_, nc_).noalias() +=
              (w * mu_ * kn_ * e[q] * psi) * b0.transpose();
          tot->J.block(q * nc_, 0, nc_, np_).noalias() +=
              (w * mu_ * s.N * ep[q] * psi) * dPhi.row(j);
        }
        tot->J.block(2 * nc_, 2 * nc_, nc_, nc_).noalias() += (w * kn_ * psi) * b0.transpose();
      }
    }
    if (samples_) {
      // Dense output: the collocation polynomial through (0, φ_n) and (c_j, Φ_j).
      std::array<double, kStages + 1> nodes{}, vals{};
      nodes[0] = 0.0;
      vals[0] = st.phi;
      for (int j = 0; j < kStages; ++j) {
        nodes[j + 1] = k.c[j];
        vals[j + 1] = r.Phi[j];
      }
      for (long j = static_cast<long>(std::ceil(th / grid_)); j * grid_ < th + h; ++j) {
        const double x = (j * grid_ - th) / h;
        double phi = 0;
        for (int m = 0; m <= kStages; ++m) {
          phi += vals[m] * lagrange(nodes.data(), kStages + 1, m, x);
        }
        const Sig s = at(j * grid_);
        const int col = static_cast<int>(((j % grid_samples_) + grid_samples_) % grid_samples_);
        samples_->col(col) << mu_ * s.N * std::cos(phi), mu_ * s.N * std::sin(phi), s.N;
      }
    }
    st.phi = r.phi_end;
  }

  const HarmonicSet& set_;
  int nc_;
  double grid_;
  double kt_, kn_, mu_;
  Eigen::Matrix<double, 2, Eigen::Dynamic> C_;
  Eigen::VectorXd cw_;
  Eigen::Vector2d u0_;
  double nc0_ = 0.0;
  Eigen::VectorXd b0_, b1_, b2_, norm_;
  double last_th_ = std::numeric_limits<double>::quiet_NaN();  // at(): the last θ and its signals
  Sig last_sig_;
  bool always_closed_ = false;  // N > 0 at every θ (a bound from the coefficients' moduli)
  int max_k_ = 1, max_events_ = 0, grid_samples_ = 0, np_ = 1;
  double n_scale_ = 1.0, u_scale_ = 0.0, h_max_ = 1.0, exit_grid_ = 1.0;
  bool full_ = false;
  Eigen::Matrix3Xd* samples_ = nullptr;
};

}  // namespace

bool Aft::evaluate_planar(const FrictionContact3D& contact, const Eigen::VectorXd& coefficients,
                          const Eigen::VectorXd& offset, Eigen::VectorXd& forces,
                          Eigen::MatrixXd* jacobian, AftSamples* samples, AftWarmStart* warm,
                          CycleStatistics& stats) const {
  const HarmonicSet& set = basis_.harmonics();
  const int nc = set.coefficient_count();
  const int n = basis_.time_samples();
  const Eigen::Vector3d off =
      offset.size() == 3 ? Eigen::Vector3d(offset) : Eigen::Vector3d::Zero();
  PlanarCycle cycle(set, n, contact.parameters(), coefficients, off);
  Totals tot;
  int periods = 0;
  Eigen::Matrix3Xd f;
  Eigen::VectorXd args;
  if (warm) {
    args.resize(coefficients.size() + 3);
    args << coefficients, off;
  }
  if (!cycle.run(jacobian != nullptr, tot, periods, samples ? &f : nullptr, warm, args))
    return false;
  if (!tot.F.allFinite() || (jacobian && !tot.J.allFinite())) return false;
  forces = tot.F;
  if (jacobian) *jacobian = tot.J;
  stats.stick_fraction = tot.stick;
  stats.slip_fraction = tot.slip;
  stats.separation_fraction = tot.open;
  stats.dissipated_energy = tot.energy;
  stats.periods = periods;
  if (samples) {
    samples->u.resize(3, n);
    for (int j = 0; j < n; ++j) {
      const Eigen::VectorXd phi = basis_.synthesis().row(j).transpose();
      for (int d = 0; d < 3; ++d)
        samples->u(d, j) = off[d] + coefficients.segment(d * nc, nc).dot(phi);
    }
    samples->f = f;
  }
  return true;
}

}  // namespace stickslip
