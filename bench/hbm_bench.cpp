// Harmonic balance benchmarks on a synthetic reference-size case (issue 4, item 7): two bodies of
// 50 nodes each (3 DOFs per node, 300 master DOFs, all 300 modes kept, like a Craig–Bampton model
// of the two beams), 30 node pairs in 3D friction contact (kt = 4.467e9, kn = 5.6309e9 N/m,
// μ = 0.5), H = 1, N = 64, 401 frequency points across a resonance, stepped sweep.
// The preload is chosen so that the pairs go from stick to partial slip through the resonance.
// Results and the command line: docs/performance.md, "Harmonic balance".
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include <Eigen/Dense>

#include "contact/friction_contact.h"
#include "core/types.h"
#include "hbm/frequency_response.h"
#include "hbm/harmonic_balance.h"

namespace stickslip {
namespace {

constexpr int kNodesPerBody = 50;
constexpr int kPairs = 30;

// Body b: a chain of nodes with springs between neighbours (all directions), node 0 clamped by
// ground springs, unit-ish masses; contact nodes are the last kPairs nodes of each chain.
struct Model {
  Eigen::MatrixXd K, M;
  std::vector<ContactPair> pairs;
  Excitation excitation;
};

Model build(double preload) {
  const int n = 2 * kNodesPerBody * 3;
  Model m;
  m.K = Eigen::MatrixXd::Zero(n, n);
  m.M = Eigen::MatrixXd::Zero(n, n);
  const double k_chain[3] = {4e9, 2e9, 3e9}, mass = 0.05;
  for (int b = 0; b < 2; ++b) {
    for (int i = 0; i < kNodesPerBody; ++i) {
      const int node = b * kNodesPerBody + i;
      for (int d = 0; d < 3; ++d) {
        const int p = 3 * node + d;
        m.M(p, p) = mass * (1.0 + 0.01 * i);
        if (i == 0) m.K(p, p) += 10 * k_chain[d];
        if (i + 1 < kNodesPerBody) {
          const int q = p + 3;
          const double k = k_chain[d] * (1.0 + 0.02 * ((i * 7 + d) % 5));
          m.K(p, p) += k;
          m.K(q, q) += k;
          m.K(p, q) -= k;
          m.K(q, p) -= k;
        }
      }
    }
  }
  const FrictionContactParameters contact{
      .kt = 4.467e9, .kn = 5.6309e9, .mu = 0.5, .normal_preload = preload};
  auto element = std::make_shared<FrictionContact3D>(contact);
  for (int p = 0; p < kPairs; ++p) {
    const int a = kNodesPerBody - kPairs + p, b = kNodesPerBody + a;
    ContactPair pair;
    pair.dofs_a = {3 * a, 3 * a + 1, 3 * a + 2};
    pair.dofs_b = {3 * b, 3 * b + 1, 3 * b + 2};
    pair.frame = Eigen::Matrix3d::Identity();  // t1 = x, t2 = y, n = z
    pair.element = element;
    m.pairs.push_back(pair);
  }
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(n);
  f[3 * (kNodesPerBody - 1) + 0] = 50.0;       // tip of body 1, +x
  f[3 * (2 * kNodesPerBody - 1) + 0] = -50.0;  // tip of body 2, −x
  m.excitation.harmonics[1] = f;
  return m;
}

struct Case {
  std::unique_ptr<HarmonicBalanceSystem> system;
  std::vector<double> omegas;
};

Case make_case() {
  const Model m = build(150.0);
  const LinearModel linear = linear_model_from_matrices(m.K, m.M, 5.0, 0.0);
  HarmonicBalanceOptions options;
  options.harmonics = 1;
  options.time_samples = 64;
  Case c;
  c.system = std::make_unique<HarmonicBalanceSystem>(linear, m.pairs, m.excitation, options);
  // Sweep ±0.5 % around the first stuck mode that moves the pairs tangentially against each
  // other: the stuck-linear peak of the x relative displacement of pair 0.
  double best = 0, omega_peak = 0;
  for (double w = 100; w < 2e5; w *= 1.002) {
    const double amp = std::abs(c.system->linear_guess(w, true)[1]);
    if (amp > best) {
      best = amp;
      omega_peak = w;
    }
  }
  for (int i = 0; i <= 400; ++i) c.omegas.push_back(omega_peak * (0.99 + 0.02 * i / 400.0));
  return c;
}

const Case& reference_case() {
  static const Case c = make_case();
  return c;
}

void BM_ReferenceSweep(benchmark::State& state) {
  const Case& c = reference_case();
  FrequencyResponseOptions o;
  o.omegas = c.omegas;
  int iterations = 0, converged = 0;
  double slip = 0;
  for (auto _ : state) {
    const FrequencyResponse r = frequency_response(*c.system, o);
    iterations = converged = 0;
    slip = 0;
    for (const FrequencyPoint& p : r.points) {
      iterations += p.iterations;
      converged += p.converged;
      for (const PairResponse& pr : p.pairs) slip = std::max(slip, pr.cycle.slip_fraction);
    }
  }
  state.counters["points"] = static_cast<double>(c.omegas.size());
  state.counters["converged"] = converged;
  state.counters["newton_per_point"] = static_cast<double>(iterations) / c.omegas.size();
  state.counters["max_slip_fraction"] = slip;
}
BENCHMARK(BM_ReferenceSweep)->Unit(benchmark::kMillisecond)->Iterations(3);

// One residual + Jacobian evaluation (AFT of 30 pairs, receptance, 𝔾·J) at a slipping state.
void BM_EvaluateWithJacobian(benchmark::State& state) {
  const Case& c = reference_case();
  const double w = c.omegas[200];
  const Eigen::VectorXd x = c.system->linear_guess(w, true);
  Eigen::VectorXd R;
  Eigen::MatrixXd J;
  for (auto _ : state) {
    c.system->evaluate(x, w, R, &J, nullptr);
    benchmark::DoNotOptimize(J.data());
  }
}
BENCHMARK(BM_EvaluateWithJacobian)->Unit(benchmark::kMicrosecond);

// Residual only, alternating two frequencies: the cost of building 𝔾(Ω) and u_lin(Ω) (the
// receptance from the modes) plus one AFT pass.
void BM_ResidualNewFrequency(benchmark::State& state) {
  const Case& c = reference_case();
  const Eigen::VectorXd x = c.system->linear_guess(c.omegas[200], true);
  Eigen::VectorXd R;
  int i = 0;
  for (auto _ : state) {
    c.system->evaluate(x, c.omegas[200 + (i++ % 2)], R, nullptr, nullptr);
    benchmark::DoNotOptimize(R.data());
  }
}
BENCHMARK(BM_ResidualNewFrequency)->Unit(benchmark::kMicrosecond);

// The AFT alone (forces and cycle statistics of 30 pairs, no Jacobian).
void BM_ContactForces(benchmark::State& state) {
  const Case& c = reference_case();
  const double w = c.omegas[200];
  const Eigen::VectorXd x = c.system->linear_guess(w, true);
  Eigen::VectorXd F;
  std::vector<CycleStatistics> stats;
  for (auto _ : state) {
    c.system->contact_forces(x, F, &stats);
    benchmark::DoNotOptimize(F.data());
  }
  double periods = 0;
  for (const CycleStatistics& s : stats) periods += s.periods;
  state.counters["mean_periods"] = periods / static_cast<double>(stats.size());
}
BENCHMARK(BM_ContactForces)->Unit(benchmark::kMicrosecond);

// The dense LU of one Newton step (n = 90 rows x 2 coefficients = 180 unknowns).
void BM_DenseLu(benchmark::State& state) {
  const Case& c = reference_case();
  const double w = c.omegas[200];
  const Eigen::VectorXd x = c.system->linear_guess(w, true);
  Eigen::VectorXd R;
  Eigen::MatrixXd J;
  c.system->evaluate(x, w, R, &J, nullptr);
  for (auto _ : state) {
    Eigen::VectorXd dx = J.partialPivLu().solve(R);
    benchmark::DoNotOptimize(dx.data());
  }
}
BENCHMARK(BM_DenseLu)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace stickslip

BENCHMARK_MAIN();
