// Regression for the reference-case regime: a small two-body joint with many preloaded 3D
// friction pairs, contacts much stiffer than the bodies, in partial slip (generic elliptical
// relative orbits, so the 2D circular limit matters), swept through a resonance from the stuck
// linear guess. Independent checks: every point converges in few Newton iterations with a
// recomputed residual below tolerance, and the energy per cycle balances: work of the excitation =
// viscous dissipation + friction work, with the friction work from the harmonics and, separately,
// from the sampled hysteresis loops.
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "contact/friction_contact.h"
#include "core/types.h"
#include "hbm/frequency_response.h"
#include "hbm/harmonic_balance.h"

namespace stickslip {
namespace {

using Complex = std::complex<double>;

// Two bodies, each a hub node (3 DOFs) on a ground spring with `pairs` contact nodes hung on it by
// random SPD 3x3 springs; contact node i of body A faces contact node i of body B. DOFs: hub A,
// contacts A, hub B, contacts B (3 per node). The hub of A is excited.
struct Joint {
  int pairs = 12;
  Eigen::MatrixXd K, M;
  double alpha = 20.0, beta = 1e-6;
  Eigen::Matrix3d R;  // contact frame rows t1, t2, n
  FrictionContactParameters contact{.kt = 2e7, .kn = 3e7, .mu = 0.5, .normal_preload = 10.0};
  int dofs() const { return 6 * (pairs + 1); }
  int node_a(int i) const { return 1 + i; }          // node index of contact i on A
  int node_b(int i) const { return pairs + 2 + i; }  // on B
  int hub_b() const { return pairs + 1; }
};

Joint make_joint() {
  Joint j;
  const int n = j.dofs();
  j.K = Eigen::MatrixXd::Zero(n, n);
  j.M = Eigen::MatrixXd::Identity(n, n) * 0.2;
  std::mt19937 rng(20261121);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  auto spring = [&](int a, int b, const Eigen::Matrix3d& k) {  // b < 0: ground
    j.K.block(3 * a, 3 * a, 3, 3) += k;
    if (b < 0) return;
    j.K.block(3 * b, 3 * b, 3, 3) += k;
    j.K.block(3 * a, 3 * b, 3, 3) -= k;
    j.K.block(3 * b, 3 * a, 3, 3) -= k;
  };
  auto random_spd = [&](double scale) {
    Eigen::Matrix3d a;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a(r, c) = uni(rng);
    return Eigen::Matrix3d(scale * (a * a.transpose() + 0.5 * Eigen::Matrix3d::Identity()));
  };
  spring(0, -1, random_spd(2e5));
  spring(j.hub_b(), -1, random_spd(2e5));
  for (int i = 0; i < j.pairs; ++i) {
    spring(j.node_a(i), 0, random_spd(1e5));
    spring(j.node_b(i), j.hub_b(), random_spd(1e5));
  }
  j.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  return j;
}

// Counts the evaluations of R (with or without the Jacobian) a solver makes.
class CountingSystem final : public ParametrizedSystem {
 public:
  explicit CountingSystem(const ParametrizedSystem& s) : s_(s) {}
  int size() const override { return s_.size(); }
  double residual_scale() const override { return s_.residual_scale(); }
  double residual_scale_at(double omega) const override { return s_.residual_scale_at(omega); }
  void evaluate(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd& R, Eigen::MatrixXd* J,
                Eigen::VectorXd* dR) const override {
    ++(J ? jacobians : residuals);
    s_.evaluate(x, lambda, R, J, dR);
  }
  mutable int residuals = 0;  // evaluations of R alone
  mutable int jacobians = 0;  // evaluations of R and dR/dx

 private:
  const ParametrizedSystem& s_;
};

std::vector<int> node_dofs(int node) { return {3 * node, 3 * node + 1, 3 * node + 2}; }

// The joint's harmonic balance system: the hub of A excited by `load` (harmonic 1), and the
// static preload load.
HarmonicBalanceSystem make_system(const Joint& j, const Eigen::Vector3cd& hub_load) {
  const int n = j.dofs();
  std::vector<ContactPair> pairs;
  Excitation e;
  Eigen::VectorXcd preload = Eigen::VectorXcd::Zero(n), load = Eigen::VectorXcd::Zero(n);
  for (int i = 0; i < j.pairs; ++i) {
    pairs.push_back({.dofs_a = node_dofs(j.node_a(i)),
                     .dofs_b = node_dofs(j.node_b(i)),
                     .frame = j.R,
                     .element = std::make_shared<FrictionContact3D>(j.contact)});
    // Static load pressing each pair together so that u = 0 carries N = N0 (as the pipeline does).
    const Eigen::Vector3d g = j.R.transpose() * Eigen::Vector3d(0, 0, j.contact.normal_preload);
    for (int d = 0; d < 3; ++d) {
      preload(3 * j.node_b(i) + d) -= g(d);
      preload(3 * j.node_a(i) + d) += g(d);
    }
  }
  load.head(3) = hub_load;
  e.harmonics[0] = preload;
  e.harmonics[1] = load;
  HarmonicBalanceOptions o;
  o.harmonics = 1;
  o.time_samples = 64;
  o.static_newton.tolerance = 1e-12;
  return HarmonicBalanceSystem(linear_model_from_matrices(j.K, j.M, j.alpha, j.beta), pairs, e, o);
}

// First natural frequency of the assembly with every contact stuck (kt, kt, kn springs).
double stuck_first_frequency(const Joint& j) {
  const int n = j.dofs();
  Eigen::MatrixXd Ks = j.K;
  for (int i = 0; i < j.pairs; ++i) {
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(3, n);
    b.middleCols(3 * j.node_a(i), 3) = j.R;
    b.middleCols(3 * j.node_b(i), 3) = -j.R;
    Ks +=
        b.transpose() * Eigen::Vector3d(j.contact.kt, j.contact.kt, j.contact.kn).asDiagonal() * b;
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(Ks, j.M, Eigen::EigenvaluesOnly);
  return std::sqrt(eig.eigenvalues()(0));
}

TEST(FrictionJoint, PartialSlipSweepConvergesAtEveryPointAndBalancesEnergy) {
  const Joint j = make_joint();
  // Amplitude chosen so that, across the sweep, most pairs slip over part of the cycle.
  const Eigen::Vector3cd hub_load(Complex(100.0, 0), Complex(62.5, 25.0), Complex(-37.5, 0));
  const HarmonicBalanceSystem system = make_system(j, hub_load);
  Eigen::VectorXcd load = Eigen::VectorXcd::Zero(j.dofs());
  load.head(3) = hub_load;
  ASSERT_TRUE(system.static_summary().converged());

  // Sweep through the first resonance of the stuck assembly.
  const double w1 = stuck_first_frequency(j);
  std::vector<double> omegas;
  for (int i = 0; i <= 60; ++i) omegas.push_back(w1 * (0.85 + 0.3 * i / 60.0));
  SteppedSweepOptions so;
  so.newton.tolerance = 1e-9;
  so.newton.max_iterations = 30;
  const CountingSystem counting(system);
  const ContinuationResult sweep =
      stepped_sweep(counting, system.linear_guess(omegas.front(), true), omegas, so);
  std::vector<FrequencyPoint> points;
  for (const ContinuationPoint& c : sweep.points) {
    EXPECT_EQ(c.step_halvings, 0) << "omega = " << c.lambda;
    EXPECT_FALSE(c.by_arclength) << "omega = " << c.lambda;
    points.push_back(evaluate_point(system, c.x, c.lambda));
    points.back().converged = c.newton.converged();
    points.back().iterations = c.newton.iterations;
    points.back().message = c.newton.message;
  }
  const Eigen::MatrixXd C = j.alpha * j.M + j.beta * j.K;
  int partial_slip_points = 0, total_iterations = 0, max_iterations = 0;
  for (const FrequencyPoint& p : points) {
    SCOPED_TRACE("omega = " + std::to_string(p.omega));
    EXPECT_TRUE(p.converged) << p.message;
    total_iterations += p.iterations;
    max_iterations = std::max(max_iterations, p.iterations);
    Eigen::VectorXd R;
    system.evaluate(p.unknowns, p.omega, R, nullptr, nullptr);
    EXPECT_LE(R.norm(), so.newton.tolerance * system.residual_scale_at(p.omega));

    int partial = 0;
    double friction_harmonic = 0, friction_loops = 0;
    for (const PairResponse& pr : p.pairs) {
      if (pr.cycle.slip_fraction > 0 && pr.cycle.stick_fraction > 0) ++partial;
      // ∮ f·du for harmonic 1 of u (u has no other dynamic harmonic): π Re(i F̄ᵀ U).
      friction_harmonic +=
          kPi * (Complex(0, 1) * pr.force_local.col(1).dot(pr.displacement_local.col(1))).real();
      friction_loops += pr.cycle.dissipated_energy;
    }
    if (partial >= j.pairs / 2) ++partial_slip_points;
    const Eigen::VectorXcd X = p.master.col(1);
    const double external = kPi * (Complex(0, 1) * load.dot(X)).real();
    const double viscous = kPi * p.omega * (X.adjoint() * C.cast<Complex>() * X)(0).real();
    // Balance of harmonic 1: exact up to the Newton tolerance.
    constexpr double kBalanceTolerance = 1e-6;
    EXPECT_NEAR(external, viscous + friction_harmonic, kBalanceTolerance * external);
    // The sampled loops (trapezoidal rule over N = 64 samples of the closed hysteresis cycle)
    // against the harmonic work: they differ by the O((2π/N)²) quadrature error and the work of
    // the force harmonics ≥ 2 on the sampled motion, both well below 2 %.
    constexpr double kLoopTolerance = 2e-2;
    EXPECT_NEAR(friction_loops, friction_harmonic,
                kLoopTolerance * std::max(friction_harmonic, 1e-3 * external));
  }
  // The regime the test is about: many pairs in partial slip over a good part of the sweep.
  EXPECT_GE(partial_slip_points, 10);
  // Few evaluations per point (Newton steps, line-search trials), no fallbacks: the step from
  // the previous point crosses few stick/slip kinks.
  const double n_points = static_cast<double>(points.size());
  std::printf("per point: %.2f Jacobians, %.2f residuals alone, %.2f iterations, max %d\n",
              counting.jacobians / n_points, counting.residuals / n_points,
              total_iterations / n_points, max_iterations);
  constexpr double kMeanJacobians = 6.5, kMeanResiduals = 10.5;
  EXPECT_LE(counting.jacobians / n_points, kMeanJacobians);
  EXPECT_LE(counting.residuals / n_points, kMeanResiduals);
  // Measured: 7.0 steps per point on average (Newton and chord steps), at most 18 (contacts 100
  // times stiffer than the bodies' springs, as in the reference case), 4.8 Jacobians and 8.2
  // residual-only evaluations per point (the full-step and chord trials and line-search points);
  // without chord steps 5.8 steps, 6.0 Jacobians, 6.1 residuals. The bounds leave a margin of
  // about 1.3.
  constexpr double kMeanIterations = 9.0;
  constexpr int kMaxIterations = 23;
  EXPECT_LE(static_cast<double>(total_iterations) / points.size(), kMeanIterations);
  EXPECT_LE(max_iterations, kMaxIterations);
}

TEST(FrictionJoint, FirstPointFarFromTheStuckGuessIsReachedByTheExcitationRamp) {
  // At the stuck resonance with a large load the joint slips grossly; the stuck linear guess is
  // far from the solution and Newton from it fails (checked: the test is about that case). The
  // first point must still be found (by the excitation ramp), without step halving or arc-length
  // in Ω, and satisfy R = 0 and the energy balance.
  const Joint j = make_joint();
  const Eigen::Vector3cd hub_load =
      30.0 * Eigen::Vector3cd(Complex(100.0, 0), Complex(62.5, 25.0), Complex(-37.5, 0));
  const HarmonicBalanceSystem system = make_system(j, hub_load);
  const double w1 = stuck_first_frequency(j);
  NewtonOptions newton;
  newton.tolerance = 1e-9;
  // A small budget: the direct solve from the stuck guess needs ~8 iterations, each 10 % step of
  // the ramp at most 5 (counting chord steps, NewtonOptions.reuse_jacobian; 4 without them).
  newton.max_iterations = 5;
  Eigen::VectorXd x = system.linear_guess(w1, true);
  const NewtonSummary direct = solve_newton(system, w1, x, newton);
  // Precondition: the direct attempt from the stuck guess fails within this Newton budget.
  ASSERT_FALSE(direct.converged()) << direct.message;
  FrequencyResponseOptions o;
  o.omegas = {w1};
  o.sweep.newton = newton;
  o.sweep.max_step_halvings = 0;
  o.sweep.jump_max_points = 0;
  const FrequencyResponse r = frequency_response(system, o);
  ASSERT_TRUE(r.completed) << r.message;
  Eigen::VectorXd R;
  system.evaluate(r.points[0].unknowns, w1, R, nullptr, nullptr);
  EXPECT_LE(R.norm(), newton.tolerance * system.residual_scale_at(w1));
  // Energy balance of harmonic 1 (as in the sweep test).
  Eigen::VectorXcd load = Eigen::VectorXcd::Zero(j.dofs());
  load.head(3) = hub_load;
  const Eigen::VectorXcd X = r.points[0].master.col(1);
  const Eigen::MatrixXd C = j.alpha * j.M + j.beta * j.K;
  double friction = 0;
  for (const PairResponse& pr : r.points[0].pairs) {
    friction +=
        kPi * (Complex(0, 1) * pr.force_local.col(1).dot(pr.displacement_local.col(1))).real();
  }
  const double external = kPi * (Complex(0, 1) * load.dot(X)).real();
  const double viscous = kPi * w1 * (X.adjoint() * C.cast<Complex>() * X)(0).real();
  EXPECT_NEAR(external, viscous + friction, 1e-6 * external);
}

}  // namespace
}  // namespace stickslip
