// Nonlinear modes by EPMC (hbm/nonlinear_mode.h) against independent references: the closed form
// of the one-harmonic describing function of a Jenkins element (stiffness and energy per cycle)
// and of a cubic spring (Duffing backbone), a free decay of the Jenkins oscillator integrated in
// time here (frequency and decay rate from successive peaks), central differences of the extended
// system's Jacobian, and the linear limit against the eigenvalues of the stuck assembly.
#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "../derivative_check.h"
#include "contact/friction_contact.h"
#include "contact/springs.h"
#include "continuation/newton.h"
#include "core/errors.h"
#include "hbm/harmonic_balance.h"
#include "hbm/nonlinear_mode.h"

namespace stickslip {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
constexpr double kPi = std::numbers::pi;

// One mass m on a spring k and a dashpot c to the ground, with `element` between the mass and the
// ground: modal coordinate q = √m x (mass-normalised mode φ = 1/√m).
struct Oscillator {
  double m = 2.0, k = 800.0, c = 0.4;
  LinearModel model() const {
    LinearModel l;
    l.omega2 = VectorXd::Constant(1, k / m);
    l.Phi = MatrixXd::Constant(1, 1, 1.0 / std::sqrt(m));
    l.modal_damping = VectorXd::Constant(1, c / m);
    return l;
  }
};

ContactPair grounded(ElementPtr element, int dof = 0) {
  return ContactPair{.dofs_a = {dof},
                     .dofs_b = {},
                     .frame = MatrixXd::Constant(1, 1, 1.0),
                     .element = std::move(element)};
}

std::vector<double> geometric(double from, double to, int n) {
  std::vector<double> v(n);
  for (int i = 0; i < n; ++i) v[i] = from * std::pow(to / from, i / (n - 1.0));
  return v;
}

// Relative accuracy of an EPMC point solved to Newton's tolerance 1e-10 (relative residual):
// the closed forms are exact for H = 1 (the event AFT integrates the Jenkins cycle exactly), so
// only the residual and round-off remain; 1e-8 leaves two decades for the conditioning.
constexpr double kClosedFormTolerance = 1e-8;

// Jenkins element (kt, slip force μN) at displacement amplitude a, x = a cos θ: for a ≤ a_s =
// μN/kt it sticks (k_eq = kt, no loss); beyond, with cos θ* = 1 − 2 a_s/a the angle where the
// force reverses from +μN to −μN, the fundamental's in-phase part (derived in the header of this
// test: ∫ f cos θ over the stick arc and the slip arc) is k_eq a with
//   k_eq = (kt/π) (θ* − sin(2θ*)/2),
// and the loop (a parallelogram of height 2μN and width 2(a − a_s)) dissipates E = 4μN (a − a_s).
// EPMC at H = 1 with x = a cos Ωt: cos balance Ω² = (k + k_eq)/m; sin balance, with the element's
// quadrature part −E/(πa): ξ = c/m + E/(π m Ω a²); D = ξ/(2Ω).
struct JenkinsReference {
  double omega, xi, energy;
};
JenkinsReference jenkins_reference(const Oscillator& o, double kt, double slip_force, double a) {
  const double as = slip_force / kt;
  double keq = kt, energy = 0.0;
  if (a > as) {
    const double theta = std::acos(1.0 - 2.0 * as / a);
    keq = kt / kPi * (theta - 0.5 * std::sin(2 * theta));
    energy = 4 * slip_force * (a - as);
  }
  const double omega = std::sqrt((o.k + keq) / o.m);
  return {omega, o.c / o.m + energy / (kPi * o.m * omega * a * a), energy};
}

TEST(NonlinearMode, JenkinsOscillatorAtOneHarmonicMatchesTheDescribingFunction) {
  const Oscillator o;
  const double kt = 1200.0, slip_force = 0.6;  // a_s = 5e-4 m
  HarmonicBalanceOptions hb;
  hb.harmonics = 1;
  const HarmonicBalanceSystem sys(o.model(),
                                  {grounded(std::make_shared<Jenkins1D>(JenkinsParameters{
                                      .kt = kt, .mu = 0.5, .normal_load = slip_force / 0.5}))},
                                  Excitation{}, hb);
  NonlinearModeOptions options;
  options.mode = 1;
  const std::vector<double> x_amplitudes =
      geometric(0.2 * slip_force / kt, 100 * slip_force / kt, 41);
  for (double a : x_amplitudes) options.amplitudes.push_back(std::sqrt(o.m) * a);
  options.newton.tolerance = 1e-10;
  const NonlinearModeResult r = nonlinear_mode(sys, options);
  ASSERT_EQ(r.points.size(), x_amplitudes.size());
  EXPECT_TRUE(r.completed) << r.message;
  EXPECT_NEAR(r.linear_omega, std::sqrt((o.k + kt) / o.m), 1e-12 * r.linear_omega);
  EXPECT_NEAR(r.linear_xi, o.c / o.m, 1e-14);
  for (size_t i = 0; i < r.points.size(); ++i) {
    const NonlinearModePoint& p = r.points[i];
    ASSERT_TRUE(p.converged) << "point " << i << ": " << p.message;
    const JenkinsReference ref = jenkins_reference(o, kt, slip_force, x_amplitudes[i]);
    EXPECT_NEAR(p.omega, ref.omega, kClosedFormTolerance * ref.omega) << "point " << i;
    EXPECT_NEAR(p.xi, ref.xi, kClosedFormTolerance * ref.xi) << "point " << i;
    EXPECT_NEAR(p.damping_ratio, ref.xi / (2 * ref.omega),
                kClosedFormTolerance * ref.xi / ref.omega)
        << "point " << i;
    // The mode's displacement is x_a cos Ωt: X_1 = x_a (real).
    ASSERT_EQ(p.master.rows(), 1);
    ASSERT_EQ(p.master.cols(), 2);
    EXPECT_NEAR(p.master(0, 1).real(), x_amplitudes[i], 1e-9 * x_amplitudes[i]);
    EXPECT_NEAR(p.master(0, 1).imag(), 0.0, 1e-9 * x_amplitudes[i]);
    EXPECT_NEAR(p.dissipated_energy, ref.energy, 1e-6 * (ref.energy + slip_force * x_amplitudes[i]))
        << "point " << i;
  }
}

TEST(NonlinearMode, DuffingBackboneAtOneHarmonic) {
  // m ẍ + c ẋ + (k + k1) x + k3 x³ = 0 (k in the structure, k1 + k3 x³ the element: the
  // condensed unknowns need an element that carries the mode's force, nonlinear_mode.h): at H = 1
  // with x = a cos Ωt (x³ has ¾a³ in cos Ωt) Ω² = (k + k1 + ¾ k3 a²)/m, and the sin balance leaves
  // ξ = c/m (a cubic spring dissipates nothing), D = c/(2mΩ).
  const Oscillator o{.m = 1.5, .k = 600.0, .c = 0.3};
  const double k1 = 400.0, k3 = 2e7;
  HarmonicBalanceOptions hb;
  hb.harmonics = 1;
  const HarmonicBalanceSystem sys(
      o.model(),
      {grounded(std::make_shared<CubicSpring>(CubicSpringParameters{.k1 = k1, .k3 = k3}))},
      Excitation{}, hb);
  NonlinearModeOptions options;
  const std::vector<double> x_amplitudes = geometric(1e-5, 1e-2, 31);
  for (double a : x_amplitudes) options.amplitudes.push_back(std::sqrt(o.m) * a);
  options.newton.tolerance = 1e-10;
  const NonlinearModeResult r = nonlinear_mode(sys, options);
  ASSERT_TRUE(r.completed) << r.message;
  for (size_t i = 0; i < r.points.size(); ++i) {
    const double a = x_amplitudes[i];
    const double omega = std::sqrt((o.k + k1 + 0.75 * k3 * a * a) / o.m);
    EXPECT_NEAR(r.points[i].omega, omega, kClosedFormTolerance * omega) << "point " << i;
    EXPECT_NEAR(r.points[i].xi, o.c / o.m, kClosedFormTolerance * o.c / o.m) << "point " << i;
    EXPECT_NEAR(r.points[i].damping_ratio, o.c / (2 * o.m * omega),
                kClosedFormTolerance * o.c / (o.m * omega));
  }
}

// Two masses in a chain with friction to the ground and between them, and a cubic spring: the
// extended Jacobian against central differences (every unknown, Ω, ξ) and the Taylor slope, with
// proportional and non-proportional damping, static uncoupled and coupled, at a state where the
// elements slip (a perturbed linear mode at a large amplitude, not a solution).
TEST(NonlinearMode, ExtendedJacobianMatchesCentralDifferences) {
  const MatrixXd K = (MatrixXd(2, 2) << 3000, -1000, -1000, 1000).finished();
  const MatrixXd M = (MatrixXd(2, 2) << 1.0, 0, 0, 0.5).finished();
  const MatrixXd C = (MatrixXd(2, 2) << 0.8, -0.3, -0.3, 0.5).finished();
  std::vector<ContactPair> pairs;
  pairs.push_back(grounded(
      std::make_shared<Jenkins1D>(JenkinsParameters{.kt = 2000, .mu = 0.5, .normal_load = 2.0})));
  pairs.push_back(ContactPair{.dofs_a = {0},
                              .dofs_b = {1},
                              .frame = MatrixXd::Constant(1, 1, 1.0),
                              .element = std::make_shared<Jenkins1D>(
                                  JenkinsParameters{.kt = 1500, .mu = 0.4, .normal_load = 1.0})});
  pairs.push_back(
      grounded(std::make_shared<CubicSpring>(CubicSpringParameters{.k1 = 100, .k3 = 1e6}), 1));
  Excitation static_load;
  static_load.harmonics[0] = Eigen::Vector2cd(0.3, -0.2);
  for (const bool dense : {false, true}) {
    for (const bool coupled : {false, true}) {
      SCOPED_TRACE(::testing::Message() << "dense damping " << dense << ", coupled " << coupled);
      HarmonicBalanceOptions hb;
      hb.harmonics = 3;
      hb.static_coupling = coupled ? StaticCoupling::kCoupled : StaticCoupling::kUncoupled;
      const LinearModel model =
          dense ? linear_model_from_matrices(K, M, C) : linear_model_from_matrices(K, M, 0.7, 1e-4);
      const HarmonicBalanceSystem sys(model, pairs, static_load, hb);
      const StuckModes modes = stuck_modes(sys);
      const NonlinearModeSystem nm(sys, modes.eta.col(1));
      VectorXd y = nm.linear_guess(0.01);
      const int n = sys.size();
      y.head(n) += testing::random_state(n, 2e-3, 7);
      y[n] *= 0.97;
      y[n + 1] += 0.3;
      const double lambda = std::log(0.012);
      VectorXd R, dRdl;
      MatrixXd J;
      nm.evaluate(y, lambda, R, &J, &dRdl);
      ASSERT_EQ(J.rows(), n + 2);
      ASSERT_EQ(J.cols(), n + 2);
      MatrixXd fd(n + 2, n + 2);
      for (int q = 0; q < n + 2; ++q) {
        const double h = q < n ? 1e-8 : 1e-6 * std::max(1.0, std::abs(y[q]));
        VectorXd yp = y, ym = y, Rp, Rm;
        yp[q] += h;
        ym[q] -= h;
        nm.evaluate(yp, lambda, Rp, nullptr, nullptr);
        nm.evaluate(ym, lambda, Rm, nullptr, nullptr);
        fd.col(q) = (Rp - Rm) / (2 * h);
      }
      // Central differences: O(h²) truncation and O(eps ||R|| / h) round-off, far below 1e-6.
      EXPECT_LE((fd - J).norm(), 1e-6 * J.norm());
      for (int q = n; q < n + 2; ++q) {
        EXPECT_LE((fd.col(q) - J.col(q)).norm(), 1e-6 * J.col(q).norm()) << "column " << q;
      }
      EXPECT_LE((fd.bottomRows(2) - J.bottomRows(2)).norm(), 1e-6 * J.bottomRows(2).norm());
      VectorXd dy(n + 2);
      for (int q = 0; q < n + 2; ++q) dy[q] = std::cos(1.0 + 2.7 * q);
      dy.head(n) *= 1e-3 / dy.head(n).norm();
      dy[n] *= 0.01 * y[n];
      testing::expect_taylor_slope(testing::taylor_remainder(nm, y, lambda, dy, 0.1));
    }
  }
}

// At a small amplitude every element is stuck: the mode is the stuck assembly's linear mode,
// Ω = its eigenfrequency from K + Σ k_t bbᵀ (solved here in physical coordinates), ξ = α for
// mass-proportional damping C = αM (every mode: ξ M = C), and the shape is the eigenvector.
TEST(NonlinearMode, SmallAmplitudeIsTheStuckLinearMode) {
  const MatrixXd K =
      (MatrixXd(3, 3) << 3000, -1000, 0, -1000, 2500, -1500, 0, -1500, 1500).finished();
  const MatrixXd M = Eigen::Vector3d(1.0, 0.5, 0.8).asDiagonal();
  const double alpha = 1.3, kt1 = 2000, kt2 = 900;
  std::vector<ContactPair> pairs;
  pairs.push_back(grounded(
      std::make_shared<Jenkins1D>(JenkinsParameters{.kt = kt1, .mu = 0.5, .normal_load = 2.0})));
  pairs.push_back(ContactPair{.dofs_a = {2},
                              .dofs_b = {1},
                              .frame = MatrixXd::Constant(1, 1, 1.0),
                              .element = std::make_shared<Jenkins1D>(
                                  JenkinsParameters{.kt = kt2, .mu = 0.4, .normal_load = 1.0})});
  HarmonicBalanceOptions hb;
  hb.harmonics = 3;
  const HarmonicBalanceSystem sys(linear_model_from_matrices(K, M, alpha, 0.0), pairs, Excitation{},
                                  hb);
  MatrixXd Ks = K;
  Ks(0, 0) += kt1;
  Ks(1, 1) += kt2;
  Ks(2, 2) += kt2;
  Ks(1, 2) -= kt2;
  Ks(2, 1) -= kt2;
  const Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> eig(Ks, M);
  for (int mode = 1; mode <= 3; ++mode) {
    NonlinearModeOptions options;
    options.mode = mode;
    options.amplitudes = {1e-6, 2e-6};
    options.newton.tolerance = 1e-12;
    const NonlinearModeResult r = nonlinear_mode(sys, options);
    ASSERT_TRUE(r.completed) << r.message;
    const double omega = std::sqrt(eig.eigenvalues()[mode - 1]);
    for (const NonlinearModePoint& p : r.points) {
      EXPECT_NEAR(p.omega, omega, 1e-9 * omega) << "mode " << mode;
      EXPECT_NEAR(p.xi, alpha, 1e-9 * alpha) << "mode " << mode;
      // X_1 = a φ (mass-normalised, sign free), the higher harmonics 0.
      const VectorXd phi = eig.eigenvectors().col(mode - 1);
      const VectorXd x1 = p.master.col(1).real();
      const double sign = x1.dot(M * phi) > 0 ? 1.0 : -1.0;
      EXPECT_LE((x1 - sign * p.amplitude * phi).norm(), 1e-8 * p.amplitude * phi.norm());
      EXPECT_LE(p.master.col(1).imag().norm(), 1e-8 * p.amplitude * phi.norm());
      EXPECT_LE(p.master.rightCols(2).norm(), 1e-8 * p.amplitude * phi.norm());
    }
  }
}

// Free decay of m ẍ + c ẋ + k x + f_J = 0 (Jenkins element, return mapping per step, RK4 with the
// element force frozen to the step's elastic predictor) against EPMC at H = 7. With slowly varying
// amplitude the energy balance over a cycle gives dE/dt = −ξ E, so the peaks decay as
// a_{n+1}/a_n = exp(−ξ T/2): ξ_decay = 2 ln(a_n/a_{n+1}) / T_n, Ω = 2π/T_n, compared at the peak
// displacement (the EPMC point's max_t x(t), interpolated in ln a). The slow-flow assumption is
// O(D) ≈ 1–2 % above 15 mm: tolerances 1e-3 on Ω and 3 % on ξ.
TEST(NonlinearMode, JenkinsFreeDecayMatchesSevenHarmonics) {
  const Oscillator o{.m = 1.0, .k = 1000.0, .c = 0.05};
  const double kt = 2000.0, slip_force = 0.5;  // a_s = 2.5e-4 m
  HarmonicBalanceOptions hb;
  hb.harmonics = 7;
  hb.time_samples = 256;
  const HarmonicBalanceSystem sys(o.model(),
                                  {grounded(std::make_shared<Jenkins1D>(JenkinsParameters{
                                      .kt = kt, .mu = 0.5, .normal_load = slip_force / 0.5}))},
                                  Excitation{}, hb);
  NonlinearModeOptions options;
  // From the stuck range (a_s = 2.5e-4 m), where the linear mode is the solution; √m = 1.
  for (double a : geometric(0.1e-3, 40e-3, 61)) options.amplitudes.push_back(a);
  options.newton.tolerance = 1e-10;
  const NonlinearModeResult r = nonlinear_mode(sys, options);
  ASSERT_TRUE(r.completed) << r.message;
  // Peak displacement of each EPMC point: max over a fine grid of x(t) = Re Σ X_k e^{ikθ}.
  std::vector<double> peak, omega, xi;
  for (const NonlinearModePoint& p : r.points) {
    double best = 0;
    for (int s = 0; s < 2000; ++s) {
      const double th = 2 * kPi * s / 2000;
      double x = p.master(0, 0).real();
      for (int j = 1; j < p.master.cols(); ++j)
        x += (p.master(0, j) * std::exp(std::complex<double>(0, r.harmonics[j] * th))).real();
      best = std::max(best, x);
    }
    peak.push_back(best);
    omega.push_back(p.omega);
    xi.push_back(p.xi);
  }
  auto interpolate = [&](const std::vector<double>& v, double a) {
    size_t i = 1;
    while (i + 1 < peak.size() && peak[i] < a) ++i;
    const double t =
        (std::log(a) - std::log(peak[i - 1])) / (std::log(peak[i]) - std::log(peak[i - 1]));
    return v[i - 1] + t * (v[i] - v[i - 1]);
  };
  // Time integration from x = 35 mm at rest with the element relaxed.
  const double w_stuck = std::sqrt((o.k + kt) / o.m), dt = 2 * kPi / w_stuck / 4000;
  double x = 35e-3, v = 0, f = 0, t = 0;
  auto element = [&](double f0, double x0, double x1) {
    return std::clamp(f0 + kt * (x1 - x0), -slip_force, slip_force);
  };
  std::vector<double> peak_t, peak_x;
  double x_prev2 = x, x_prev = x;
  int checked = 0;
  for (int step = 0; step < 4000 * 400 && peak_x.size() < 200; ++step) {
    const double x0 = x, f0 = f;
    auto acc = [&](double xs, double vs) {
      return -(o.c * vs + o.k * xs + element(f0, x0, xs)) / o.m;
    };
    const double k1x = v, k1v = acc(x, v);
    const double k2x = v + 0.5 * dt * k1v, k2v = acc(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v);
    const double k3x = v + 0.5 * dt * k2v, k3v = acc(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v);
    const double k4x = v + dt * k3v, k4v = acc(x + dt * k3x, v + dt * k3v);
    x += dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    f = element(f0, x0, x);
    t += dt;
    if (x_prev > x_prev2 && x_prev >= x && step > 1) {  // a maximum at t − dt: parabola
      const double d = 0.5 * (x_prev2 - x) / (x_prev2 - 2 * x_prev + x);
      peak_t.push_back(t - dt + d * dt);
      peak_x.push_back(x_prev - 0.25 * (x_prev2 - x) * d);
    }
    x_prev2 = x_prev;
    x_prev = x;
  }
  ASSERT_GE(peak_x.size(), 20u);
  for (size_t i = 1; i < peak_x.size(); ++i) {
    const double a = std::sqrt(peak_x[i] * peak_x[i - 1]);
    // Below ~15 mm D exceeds 2 % (12 % near 2 a_s): the slow flow no longer holds.
    if (a < 15e-3 || a > 0.95 * peak.back()) continue;
    const double T = peak_t[i] - peak_t[i - 1];
    const double omega_decay = 2 * kPi / T, xi_decay = 2 * std::log(peak_x[i - 1] / peak_x[i]) / T;
    EXPECT_NEAR(omega_decay, interpolate(omega, a), 1e-3 * omega_decay) << "a = " << a;
    EXPECT_NEAR(xi_decay, interpolate(xi, a), 0.03 * xi_decay) << "a = " << a;
    ++checked;
  }
  EXPECT_GE(checked, 5);
}

// The onset of slip estimated from the stuck mode (first_slip_amplitude): for the Jenkins
// oscillator the stuck limit a_s = μN/kt in displacement, √m a_s in modal amplitude; for a 3D
// friction contact whose stuck mode moves it along t1 and n (the structure couples x and z), the
// force along the mode f(c) = (kt c φ_x, 0, N0 + kn c φ_z) reaches |τ| = μN first on the side
// where N falls: a = μN0 / (kt |φ_x| + μ kn |φ_z|), φ the mass-normalised stuck mode (from
// Eigen's generalized eigen-solver here). And the EPMC itself: every pair sticks below the
// estimate. Above it a periodic cycle may still stick with a tangential offset τ₀ left by the
// slip (shakedown: the line τ = τ₀ + kt c φ_x fits between ±μ(N0 + kn c φ_z) at c = ±a while
// a kt |φ_x| ≤ μN0), so the EPMC is asked to slip only beyond a = min(μN0/(kt|φ_x|), N0/(kn|φ_z|)).
TEST(NonlinearMode, FirstSlipAmplitudeIsWhereTheStuckModeReachesTheCoulombLimit) {
  {
    const Oscillator o;
    const double kt = 1200.0, slip_force = 0.6;
    HarmonicBalanceOptions hb;
    const HarmonicBalanceSystem sys(o.model(),
                                    {grounded(std::make_shared<Jenkins1D>(JenkinsParameters{
                                        .kt = kt, .mu = 0.5, .normal_load = slip_force / 0.5}))},
                                    Excitation{}, hb);
    const double expected = std::sqrt(o.m) * slip_force / kt;
    EXPECT_NEAR(first_slip_amplitude(sys, VectorXd::Ones(1)), expected, 1e-12 * expected);
  }
  const double m = 0.7, kt = 3000, kn = 5000, mu = 0.4, n0 = 2.0;
  const MatrixXd K = (MatrixXd(3, 3) << 4000, 0, 1500, 0, 3000, 0, 1500, 0, 2500).finished();
  const MatrixXd M = MatrixXd::Identity(3, 3) * m;
  std::vector<ContactPair> pairs;
  pairs.push_back(
      ContactPair{.dofs_a = {0, 1, 2},
                  .dofs_b = {},
                  .frame = MatrixXd::Identity(3, 3),  // t1 = x, t2 = y, n = z
                  .element = std::make_shared<FrictionContact3D>(FrictionContactParameters{
                      .kt = kt, .kn = kn, .mu = mu, .normal_preload = n0})});
  // The preload pushes the node along −n (the force on A is −[τ; N]); a static load +N0 along z
  // balances it, so the static state is u = 0 with N = N0.
  Excitation statics;
  statics.harmonics[0] = Eigen::Vector3cd(0, 0, n0);
  HarmonicBalanceOptions hb;
  hb.static_newton.tolerance = 1e-13;
  const HarmonicBalanceSystem sys(linear_model_from_matrices(K, M, 0.5, 0.0), pairs, statics, hb);
  ASSERT_LE(sys.static_displacement().norm(), 1e-12);
  MatrixXd Ks = K;
  Ks.diagonal() += Eigen::Vector3d(kt, kt, kn);
  const Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> eig(Ks, M);
  const StuckModes modes = stuck_modes(sys);
  int checked = 0;
  for (int mode = 1; mode <= 3; ++mode) {
    const VectorXd phi = eig.eigenvectors().col(mode - 1);  // φᵀMφ = 1
    if (std::abs(phi[0]) < 1e-6) continue;                  // the y mode: t2 only
    const double expected = mu * n0 / (kt * std::abs(phi[0]) + mu * kn * std::abs(phi[2]));
    const VectorXd eta = modes.eta.col(mode - 1);
    EXPECT_NEAR(first_slip_amplitude(sys, eta), expected, 1e-9 * expected) << "mode " << mode;
    NonlinearModeOptions options;
    options.mode = mode;
    const double shakedown =
        std::min(mu * n0 / (kt * std::abs(phi[0])), n0 / (kn * std::abs(phi[2])));
    options.amplitudes = {0.5 * expected, 0.98 * expected, 1.05 * shakedown};
    options.newton.tolerance = 1e-11;
    const NonlinearModeResult r = nonlinear_mode(sys, options);
    ASSERT_TRUE(r.completed) << r.message;
    EXPECT_NEAR(r.first_slip_amplitude, expected, 1e-9 * expected);
    EXPECT_EQ(r.points[0].pairs_slipping, 0.0) << "mode " << mode;
    EXPECT_EQ(r.points[1].pairs_slipping, 0.0) << "mode " << mode;
    EXPECT_EQ(r.points[2].pairs_slipping, 1.0) << "mode " << mode;
    EXPECT_GT(r.points[2].mean_slip_fraction, 0.0);
    EXPECT_EQ(r.points[2].pairs_separating, 0.0);
    ++checked;
  }
  EXPECT_EQ(checked, 2);
}

// The stuck modes after a static loading path that moved a friction spring's anchor (the model of
// StaticContact.TwoContactsClosingInSequenceFollowTheLoadPath, hand calculation there): one node on
// ground springs k_s, masses m_x, m_y, m_z, two friction contacts with gaps g1 < g2 pressed in
// sequence by a static load (Q along x, P along z). Along the path both end stuck with τ1 = kt (x −
// a1), τ2 = kt (x − a2) < μN2, their springs anchored at a1, a2; a fresh spring at the final x
// would carry kt x > μN2 (contact 2 slipping). Reference: both stuck, so the stuck assembly is
// K = diag(k_s + 2kt, k_s + 2kt, k_s + 2kn) with M = diag(m): ω² in closed form, and the first slip
// of the x mode (unit modal amplitude moves the node by 1/√m_x along x) is where contact 2's
// τ2 + c kt/√m_x reaches μN2, of the y mode where √(τ2² + (c kt/√m_y)²) does.
TEST(NonlinearMode, StuckModesAfterAStaticPathAreThoseOfTheAnchoredSprings) {
  const double ks = 1.0e6, kt = 1.0e6, kn = 1.0e6, mu = 0.5, P = 1000.0, Q = 300.0;
  const double g1 = 1.5e-4, g2 = 3.2e-4, alpha = 2.0;
  const Eigen::Vector3d mass(1.0, 2.0, 4.0);
  const double l1 = g1 * ks / P, a1 = l1 * Q / ks;
  const double l2 = (g2 * (ks + kn) - kn * g1) / P, a2 = (l2 * Q + kt * a1) / (ks + kt);
  const double x = (Q + kt * (a1 + a2)) / (ks + 2 * kt), z = (P + kn * (g1 + g2)) / (ks + 2 * kn);
  const double tau2 = kt * (x - a2), N2 = kn * (z - g2);
  ASSERT_LT(tau2, mu * N2);
  ASSERT_GT(kt * x, mu * N2);  // a fresh spring at x would slip
  // Stuck: ascending z, y, x.
  const std::vector<double> omega2 = {(ks + 2 * kn) / mass[2], (ks + 2 * kt) / mass[1],
                                      (ks + 2 * kt) / mass[0]};
  const double slip_x = (mu * N2 - tau2) * std::sqrt(mass[0]) / kt;
  const double slip_y = std::sqrt(mu * mu * N2 * N2 - tau2 * tau2) * std::sqrt(mass[1]) / kt;
  for (const StaticCoupling coupling : {StaticCoupling::kUncoupled, StaticCoupling::kCoupled}) {
    for (const int increments : {0, 3}) {
      SCOPED_TRACE(::testing::Message() << "increments " << increments << ", coupled "
                                        << (coupling == StaticCoupling::kCoupled));
      std::vector<ContactPair> pairs;
      for (const double g : {g1, g2}) {
        pairs.push_back({.dofs_a = {0, 1, 2},
                         .dofs_b = {},
                         .frame = MatrixXd::Identity(3, 3),
                         .element = std::make_shared<FrictionContact3D>(
                             FrictionContactParameters{kt, kn, mu, 0.0, g})});
      }
      Excitation e;
      e.harmonics[0] = Eigen::Vector3cd(Q, 0, P);
      HarmonicBalanceOptions opt;
      opt.time_samples = 16;
      opt.static_coupling = coupling;
      opt.static_increments = increments;
      const HarmonicBalanceSystem sys(
          linear_model_from_matrices(ks * MatrixXd::Identity(3, 3), MatrixXd(mass.asDiagonal()),
                                     alpha, 0.0),
          pairs, e, opt);
      ASSERT_TRUE(sys.static_summary().converged()) << sys.static_summary().message;
      const StuckModes modes = stuck_modes(sys);
      ASSERT_EQ(modes.omega2.size(), 3);
      for (int j = 0; j < 3; ++j) {
        EXPECT_NEAR(modes.omega2[j], omega2[j], 1e-12 * omega2[j]) << "mode " << j + 1;
      }
      EXPECT_NEAR(first_slip_amplitude(sys, modes.eta.col(2)), slip_x, 1e-9 * slip_x);
      EXPECT_NEAR(first_slip_amplitude(sys, modes.eta.col(1)), slip_y, 1e-9 * slip_y);
      // The nonlinear mode's linear limit: the x mode, stuck, damped by α.
      NonlinearModeOptions options;
      options.mode = 3;
      options.amplitudes = {1e-3 * slip_x, 0.5 * slip_x};
      options.newton.tolerance = 1e-11;
      const NonlinearModeResult r = nonlinear_mode(sys, options);
      ASSERT_TRUE(r.completed) << r.message;
      for (const NonlinearModePoint& p : r.points) {
        EXPECT_NEAR(p.omega, std::sqrt(omega2[2]), 1e-9 * std::sqrt(omega2[2]));
        EXPECT_NEAR(p.xi, alpha, 1e-9 * alpha);
        EXPECT_EQ(p.pairs_slipping, 0.0);
      }
    }
  }
}

// Single nonlinear mode theory on the Jenkins oscillator at H = 1. Reference: with the closed
// forms ω(x), ξ(x) of the describing function (jenkins_reference) and ψ = 1/√m, q = √m x, the
// SNMT equation is (k + k_eq(x) − mΩ² + i m ξ(x) Ω) X = F for |X| = x: its roots Ω are found here
// by bisection of |Z|² x² − F² on [0, ω] and [ω, 10ω], and X = F / Z.
// Against the forced harmonic balance (H = 1): the describing function gives, for the same x,
//   HB:   (k + k_eq − mΩ² + i (cΩ + e)) X = F,           e = E/(π x²) (friction: rate independent)
//   SNMT: (k + k_eq − mΩ² + i (cΩ + e Ω/ω)) X = F        (m ξ = c + e/ω: the loss taken at ω)
// so the predicted point is the forced response to ρF, ρ = |Z_HB| / |Z_SNMT|, and |ρ − 1| ≤
// |1 − Ω/ω| (the imaginary parts differ by a factor between 1 and Ω/ω, the real parts agree).
// Exactly at the backbone, Ω = ω(x), ρ = 1: the prediction is the forced response.
TEST(NonlinearMode, ForcedResponsePredictionOfTheJenkinsOscillator) {
  const Oscillator o;
  const double kt = 1200.0, slip_force = 0.6, as = slip_force / kt;
  const auto element = std::make_shared<Jenkins1D>(
      JenkinsParameters{.kt = kt, .mu = 0.5, .normal_load = slip_force / 0.5});
  HarmonicBalanceOptions hb;
  hb.harmonics = 1;
  const HarmonicBalanceSystem free_sys(o.model(), {grounded(element)}, Excitation{}, hb);
  const std::vector<double> x_amplitudes = geometric(0.2 * as, 100 * as, 41);
  NonlinearModeOptions options;
  for (double a : x_amplitudes) options.amplitudes.push_back(std::sqrt(o.m) * a);
  options.newton.tolerance = 1e-12;
  const NonlinearModeResult mode = nonlinear_mode(free_sys, options);
  ASSERT_TRUE(mode.completed) << mode.message;
  // The force that puts the 30th amplitude (slipping, x = 24 a_s) on the backbone: |Z(ω)| x = F
  // with Z(ω) = i m ξ ω.
  const int backbone = 30;
  const double xb = x_amplitudes[backbone];
  const JenkinsReference rb = jenkins_reference(o, kt, slip_force, xb);
  const double F = o.m * rb.xi * rb.omega * xb;
  const std::vector<ForcedResponsePrediction> prediction =
      predict_forced_response(mode, Eigen::VectorXcd::Constant(1, F));
  ASSERT_FALSE(prediction.empty());

  using Complex = std::complex<double>;
  auto snmt_impedance = [&](double x, double omega) {
    const JenkinsReference r = jenkins_reference(o, kt, slip_force, x);
    return Complex(o.m * (r.omega * r.omega - omega * omega), o.m * r.xi * omega);
  };
  auto bisect = [](auto g, double lo, double hi) {
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      ((g(lo) < 0) == (g(mid) < 0) ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  };
  // Where each amplitude has roots: two when g(ω) ≤ 0 < g(0), one (above ω) when g(0) ≤ 0 too
  // (the stuck amplitudes here, whose static deflection F/(k + kt) is larger), none above the peak.
  size_t expected = 0;
  for (double x : x_amplitudes) {
    const JenkinsReference r = jenkins_reference(o, kt, slip_force, x);
    auto g = [&](double w) { return std::norm(snmt_impedance(x, w)) * x * x - F * F; };
    if (g(r.omega * (1 - 1e-6)) < 0) expected += g(0.0) > 0 ? 2 : 1;
  }
  EXPECT_EQ(prediction.size(), expected);
  int below = 0, above = 0;
  bool previous_above = false;
  for (const ForcedResponsePrediction& p : prediction) {
    SCOPED_TRACE(::testing::Message() << "point " << p.point << (p.above ? " above" : " below"));
    EXPECT_TRUE(!previous_above || p.above) << "the roots below come first";
    previous_above = p.above;
    const double x = x_amplitudes[p.point];
    const JenkinsReference r = jenkins_reference(o, kt, slip_force, x);
    auto g = [&](double w) { return std::norm(snmt_impedance(x, w)) * x * x - F * F; };
    // Just below ω, g < 0 between the roots (at the backbone point g(ω) = 0 is the root above).
    const double inside = r.omega * (1 - 1e-6);
    ASSERT_LT(g(inside), 0.0);  // the amplitude is below the peak
    if (!p.above) {
      ASSERT_GT(g(0.0), 0.0);
    }
    const double omega = p.above ? bisect(g, inside, 10 * r.omega) : bisect(g, 0.0, inside);
    EXPECT_NEAR(p.omega, omega, 1e-9 * omega);
    const Complex X = F / snmt_impedance(x, omega);
    ASSERT_EQ(p.master.cols(), 2);
    EXPECT_NEAR(std::abs(p.master(0, 1) - X), 0.0, 1e-9 * x);
    (p.above ? above : below) += 1;
  }
  EXPECT_GE(below, 10);
  EXPECT_GE(above, 20);

  // The forced harmonic balance at the predicted frequencies, with the force scaled by ρ.
  int at_backbone = 0;
  for (const ForcedResponsePrediction& p : prediction) {
    SCOPED_TRACE(::testing::Message() << "point " << p.point << (p.above ? " above" : " below"));
    const double x = x_amplitudes[p.point];
    const JenkinsReference r = jenkins_reference(o, kt, slip_force, x);
    const double e = r.energy / (kPi * x * x);
    const Complex z_hb(o.m * r.omega * r.omega - o.m * p.omega * p.omega,
                       o.c * p.omega + e);  // k + k_eq = m ω²
    const double rho = std::abs(z_hb) / std::abs(snmt_impedance(x, p.omega));
    EXPECT_LE(std::abs(rho - 1), std::abs(1 - p.omega / r.omega) + 1e-12);
    Excitation ex;
    ex.harmonics[1] = Eigen::VectorXcd::Constant(1, rho * F);
    const HarmonicBalanceSystem forced(o.model(), {grounded(element)}, ex, hb);
    VectorXd u(2);
    u << p.master(0, 1).real(), -p.master(0, 1).imag();  // X = a − i b
    NewtonOptions newton;
    newton.tolerance = 1e-12;
    const NewtonSummary s = solve_newton(forced, p.omega, u, newton);
    ASSERT_TRUE(s.converged()) << s.message;
    // Newton to 1e-12 and the event AFT exact at H = 1: 1e-8 covers the conditioning.
    EXPECT_NEAR(std::hypot(u[0], u[1]), x, 1e-8 * x);
    if (p.point == backbone && p.above) {
      EXPECT_NEAR(p.omega, r.omega, 1e-10 * r.omega);
      EXPECT_NEAR(rho, 1.0, 1e-10);
      ++at_backbone;
    }
  }
  EXPECT_EQ(at_backbone, 1);
}

// A linear 2-DOF chain (a Jenkins element that never slips to the ground at DOF 0: μN = 1e9 N)
// with well-separated modes and C = αM: the nonlinear mode is the linear mode r (ω_r, ξ = α,
// ψ = φ_r), so the prediction is the single-mode FRF X = φ_r φ_rᵀF / (ω_r² − Ω² + iαΩ) at the
// roots of |ω_r² − Ω² + iαΩ| q = |φ_rᵀF|, and what the full FRF (K_s − Ω²M + iΩαM)⁻¹F adds is
// exactly the other mode's term. Modes in closed form: λ from det(K_s − λM) = 0, φ ∝ [−k₁₂,
// k₁₁ − λ m₁], mass-normalised.
TEST(NonlinearMode, ForcedResponsePredictionOfALinearModeIsItsModalFrf) {
  const double m1 = 1.0, m2 = 0.3, k1 = 2000, k2 = 6000, kt = 500, alpha = 0.8;
  MatrixXd K(2, 2);
  K << k1 + k2, -k2, -k2, k2;
  const MatrixXd M = Eigen::Vector2d(m1, m2).asDiagonal();
  const HarmonicBalanceSystem sys(linear_model_from_matrices(K, M, alpha, 0.0),
                                  {grounded(std::make_shared<Jenkins1D>(
                                      JenkinsParameters{.kt = kt, .mu = 0.5, .normal_load = 2e9}))},
                                  Excitation{}, HarmonicBalanceOptions{});
  const double k11 = k1 + k2 + kt, k12 = -k2, k22 = k2;
  const double b = k11 * m2 + k22 * m1, c = k11 * k22 - k12 * k12, d = m1 * m2;
  const double lambda[2] = {(b - std::sqrt(b * b - 4 * d * c)) / (2 * d),
                            (b + std::sqrt(b * b - 4 * d * c)) / (2 * d)};
  ASSERT_GT(lambda[1], 10 * lambda[0]);  // well separated
  Eigen::Vector2d phi[2];
  for (int r = 0; r < 2; ++r) {
    phi[r] = Eigen::Vector2d(-k12, k11 - lambda[r] * m1);
    // Mass-normalised (M = diag(m1, m2); written out: GCC 12 -O1 calls Eigen's product temporary
    // in phi.dot(M * phi) a use after free, a false positive that -Werror turns into an error).
    phi[r] /= std::sqrt(m1 * phi[r](0) * phi[r](0) + m2 * phi[r](1) * phi[r](1));
  }
  const Eigen::Vector2cd F(std::complex<double>(3.0, 1.0), std::complex<double>(-2.0, 0.5));
  using Complex = std::complex<double>;
  for (int r = 0; r < 2; ++r) {
    SCOPED_TRACE(::testing::Message() << "mode " << r + 1);
    const double w = std::sqrt(lambda[r]);
    const double peak = std::abs(phi[r].cast<Complex>().dot(F)) / (alpha * w);  // q at Ω ≈ ω
    NonlinearModeOptions options;
    options.mode = r + 1;
    options.amplitudes = geometric(0.05 * peak, 0.95 * peak, 15);
    options.newton.tolerance = 1e-12;
    const NonlinearModeResult mode = nonlinear_mode(sys, options);
    ASSERT_TRUE(mode.completed) << mode.message;
    const std::vector<ForcedResponsePrediction> prediction = predict_forced_response(mode, F);
    ASSERT_EQ(prediction.size(), 30u);  // both roots at every amplitude below the peak
    for (const ForcedResponsePrediction& p : prediction) {
      const double W = p.omega;
      const Complex modal = phi[r].cast<Complex>().dot(F) / Complex(lambda[r] - W * W, alpha * W);
      EXPECT_NEAR(std::abs(modal), options.amplitudes[p.point], 1e-9 * peak);
      const Eigen::Vector2cd X = phi[r].cast<Complex>() * modal;
      EXPECT_LE((p.master.col(1) - X).norm(), 1e-9 * X.norm()) << "point " << p.point;
      const Eigen::Matrix2cd Z =
          (K + kt * Eigen::Vector2d(1, 0) * Eigen::RowVector2d(1, 0) - W * W * M).cast<Complex>() +
          Complex(0, W * alpha) * M.cast<Complex>();
      const Eigen::Vector2cd full = Z.lu().solve(F);
      const int s = 1 - r;
      const Eigen::Vector2cd other = phi[s].cast<Complex>() * phi[s].cast<Complex>().dot(F) /
                                     Complex(lambda[s] - W * W, alpha * W);
      EXPECT_LE((full - X - other).norm(), 1e-9 * full.norm()) << "point " << p.point;
    }
  }
}

// Without a force on the mode (ψᴴF = 0) there is no forced response to predict.
TEST(NonlinearMode, ForcedResponsePredictionWithoutModalForceIsEmpty) {
  const Oscillator o;
  const HarmonicBalanceSystem sys(o.model(),
                                  {grounded(std::make_shared<Jenkins1D>(JenkinsParameters{
                                      .kt = 100, .mu = 0.5, .normal_load = 1.0}))},
                                  Excitation{}, HarmonicBalanceOptions{});
  NonlinearModeOptions options;
  options.amplitudes = {1e-3, 1e-2};
  const NonlinearModeResult mode = nonlinear_mode(sys, options);
  ASSERT_TRUE(mode.completed);
  EXPECT_TRUE(predict_forced_response(mode, Eigen::VectorXcd::Zero(1)).empty());
}

TEST(NonlinearMode, BadOptionsAreRefused) {
  const Oscillator o;
  HarmonicBalanceOptions hb;
  const HarmonicBalanceSystem sys(o.model(),
                                  {grounded(std::make_shared<Jenkins1D>(JenkinsParameters{
                                      .kt = 100, .mu = 0.5, .normal_load = 1.0}))},
                                  Excitation{}, hb);
  NonlinearModeOptions options;
  options.amplitudes = {1e-3, 1e-2};
  options.mode = 0;
  EXPECT_THROW(nonlinear_mode(sys, options), InvalidInput);
  options.mode = 2;  // one mode only
  EXPECT_THROW(nonlinear_mode(sys, options), InvalidInput);
  options.mode = 1;
  options.amplitudes = {1e-2, 1e-3};
  EXPECT_THROW(nonlinear_mode(sys, options), InvalidInput);
  options.amplitudes = {0.0, 1e-3};
  EXPECT_THROW(nonlinear_mode(sys, options), InvalidInput);
  options.amplitudes = {};
  EXPECT_THROW(nonlinear_mode(sys, options), InvalidInput);
  hb.harmonic_list = {3};
  const HarmonicBalanceSystem odd(o.model(), sys.pairs(), Excitation{}, hb);
  options.amplitudes = {1e-3};
  EXPECT_THROW(nonlinear_mode(odd, options), InvalidInput);
}

}  // namespace
}  // namespace stickslip
