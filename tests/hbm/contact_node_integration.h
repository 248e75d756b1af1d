// One 3D contact node on the ground (issue 18, issue 25): the model and an independent RK4 time
// integration marched to its periodic steady state, shared by the hbm tests that need it.
#pragma once

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>

#include <Eigen/Dense>

#include "contact/friction_contact.h"
#include "continuation/newton.h"
#include "core/types.h"
#include "hbm/frequency_response.h"
#include "hbm/harmonic_balance.h"

namespace stickslip::testing {

// Unit mass, unit ground springs and modal damping c in x, y, z; the contact to the ground below
// (t1 = e_x, t2 = −e_y, n = −e_z: the approach is w = −z) with N0 = 1, kn = 8, kt = 4, μ = 0.5.
// A static force −e_z of 1 N presses the node down: with it the static state is w = 0, N = N0.
struct Node {
  double k = 1.0, c = 0.05;
  FrictionContactParameters contact{.kt = 4.0, .kn = 8.0, .mu = 0.5, .normal_preload = 1.0};
  Eigen::Matrix3d R = (Eigen::Matrix3d() << 1, 0, 0, 0, -1, 0, 0, 0, -1).finished();
};

struct Case {
  std::string name;
  double omega;                // rad/s
  Eigen::Vector3d static_load; // N, global
  Eigen::Vector3d load;        // N, F cos Ωt, global
  Eigen::Vector3d load_sin = Eigen::Vector3d::Zero();  // N, + F_s sin Ωt (elliptical forcing)
};

// The last period of an RK4 integration (fixed step, contact state updated once per step: the
// stick predictor from the step's start, radially returned to μN, τ = 0 when open), from rest.
struct ReferenceCycle {
  using Complex = std::complex<double>;
  Eigen::Vector3cd X0, X1;      // harmonics 0 and 1 of x (X_k = a_k − i b_k)
  double min_normal = 1e300;    // min over the period of N0 + kn w (≤ 0: lifted off)
  bool slips = false;           // the predictor exceeded μN somewhere in the period
  Eigen::Vector3d mean_force = Eigen::Vector3d::Zero();  // local (τ1, τ2, N), cycle mean
  double max_force = 0;         // max over the period of |(τ, N)|
  Eigen::Matrix3Xd x;           // x(t_j), t_j = (j + 1) T / steps, j = 0..steps − 1
};

inline ReferenceCycle integrate_node(const Node& n, const Case& c, int steps, double duration) {
  using Complex = std::complex<double>;
  const FrictionContactParameters& p = n.contact;
  const double T = 2 * kPi / c.omega, dt = T / steps;
  const int periods = static_cast<int>(std::ceil(duration / T));
  Eigen::Vector3d x = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
  Eigen::Vector2d tau = Eigen::Vector2d::Zero(), ut_ref = Eigen::Vector2d::Zero();
  bool slipped = false;
  // Local force (τ1, τ2, N) on the ground at displacement xs, from the step's start state.
  auto local_force = [&](const Eigen::Vector3d& xs) {
    const Eigen::Vector3d u = n.R * xs;
    const double N = std::max(0.0, p.normal_preload + p.kn * u[2]);
    Eigen::Vector2d t = Eigen::Vector2d::Zero();
    slipped = false;
    if (N > 0) {
      t = tau + p.kt * (u.head<2>() - ut_ref);
      if (t.norm() > p.mu * N) {
        t *= p.mu * N / t.norm();
        slipped = true;
      }
    }
    return Eigen::Vector3d(t[0], t[1], N);
  };
  auto acc = [&](double ts, const Eigen::Vector3d& xs, const Eigen::Vector3d& vs) {
    // Force on the node (A) = −Rᵀ f.
    return Eigen::Vector3d(c.static_load + c.load * std::cos(c.omega * ts) +
                           c.load_sin * std::sin(c.omega * ts) - n.c * vs - n.k * xs -
                           n.R.transpose() * local_force(xs));
  };
  ReferenceCycle out;
  out.x.resize(3, steps);
  out.X0.setZero();
  out.X1.setZero();
  double t = 0;
  for (int per = 0; per < periods; ++per) {
    for (int s = 0; s < steps; ++s) {
      const Eigen::Vector3d k1x = v, k1v = acc(t, x, v);
      const Eigen::Vector3d k2x = v + 0.5 * dt * k1v,
                            k2v = acc(t + 0.5 * dt, x + 0.5 * dt * k1x, k2x);
      const Eigen::Vector3d k3x = v + 0.5 * dt * k2v,
                            k3v = acc(t + 0.5 * dt, x + 0.5 * dt * k2x, k3x);
      const Eigen::Vector3d k4x = v + dt * k3v, k4v = acc(t + dt, x + dt * k3x, k4x);
      x += dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
      v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
      t += dt;
      const Eigen::Vector3d f = local_force(x);
      tau = f.head<2>();
      ut_ref = (n.R * x).head<2>();
      if (per == periods - 1) {
        const double theta = 2 * kPi * (s + 1) / steps;
        out.x.col(s) = x;
        out.X0 += x.cast<Complex>() / steps;
        out.X1 += x.cast<Complex>() * (2.0 / steps) * Complex(std::cos(theta), -std::sin(theta));
        out.min_normal = std::min(out.min_normal, p.normal_preload + p.kn * (n.R * x)[2]);
        out.slips = out.slips || slipped;
        out.mean_force += f / steps;
        out.max_force = std::max(out.max_force, f.norm());
      }
    }
  }
  return out;
}

inline HarmonicBalanceSystem make_node(const Node& n, const Case& c, StaticCoupling coupling,
                                       int H, int samples,
                                       AftMethod aft = AftMethod::kEvent) {
  using Complex = std::complex<double>;
  LinearModel model{.omega2 = Eigen::Vector3d::Constant(n.k),
                    .Phi = Eigen::MatrixXd::Identity(3, 3),
                    .modal_damping = Eigen::VectorXd::Constant(3, n.c)};
  ContactPair pair{.dofs_a = {0, 1, 2},
                   .dofs_b = {},
                   .frame = n.R,
                   .element = std::make_shared<FrictionContact3D>(n.contact)};
  Excitation e;
  e.harmonics[0] = c.static_load.cast<Complex>();
  e.harmonics[1] = c.load.cast<Complex>() - Complex(0, 1) * c.load_sin.cast<Complex>();
  HarmonicBalanceOptions o;
  o.harmonics = H;
  o.time_samples = samples;
  o.aft = aft;
  o.static_coupling = coupling;
  o.static_newton.tolerance = 1e-12;
  return HarmonicBalanceSystem(model, {pair}, e, o);
}

// The harmonic-balance solution at Ω by Newton from the reference's own harmonics (its contact
// relative displacement u = R x projected on the unknowns' harmonics; uncoupled: without the
// mean, which is frozen). Where branches coexist (lift-off) this selects the reference's one;
// the solution itself is Newton's, to 1e-12 of the residual scale.
inline FrequencyPoint solve_point(const HarmonicBalanceSystem& sys, const Node& n, const Case& c,
                           const Eigen::Matrix3Xd& cycle) {
  const HarmonicSet& set = sys.unknown_harmonics();
  const int nc = set.coefficient_count(), steps = static_cast<int>(cycle.cols());
  const Eigen::Matrix3Xd u = n.R * cycle;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(sys.size());
  for (int r = 0; r < 3; ++r) {
    for (int pos = 0; pos < set.size(); ++pos) {
      const int k = set.harmonics()[pos], o = set.offset(pos);
      for (int j = 0; j < steps; ++j) {
        const double theta = 2 * kPi * k * (j + 1) / steps;
        if (k == 0) {
          x[r * nc + o] += u(r, j) / steps;
        } else {
          x[r * nc + o] += 2.0 * u(r, j) * std::cos(theta) / steps;
          x[r * nc + o + 1] += 2.0 * u(r, j) * std::sin(theta) / steps;
        }
      }
    }
  }
  NewtonOptions newton;
  newton.tolerance = 1e-12;
  newton.max_iterations = 60;
  const NewtonSummary s = solve_newton(sys, c.omega, x, newton);
  FrequencyPoint p = evaluate_point(sys, x, c.omega);
  p.converged = s.converged();
  p.message = s.message;
  return p;
}

}  // namespace stickslip::testing
