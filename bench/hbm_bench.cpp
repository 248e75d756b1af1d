// Harmonic balance benchmarks on a synthetic reference-size case (issue 4, item 7): two bodies of
// 50 nodes each (3 DOFs per node, 300 master DOFs, all 300 modes kept, like a Craig–Bampton model
// of the two beams), 30 node pairs in 3D friction contact (kt = 4.467e9, kn = 5.6309e9 N/m,
// μ = 0.5), H = 1, N = 64, 401 frequency points across a resonance, stepped sweep.
// The preload is chosen so that the pairs go from stick to partial slip through the resonance.
// Results and the command line: docs/performance.md, "Harmonic balance".
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "contact/friction_contact.h"
#include "continuation/newton.h"
#include "core/types.h"
#include "hbm/damped_modes.h"
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

// The same with the non-proportional damping path (LinearModel::modal_damping_matrix, here the
// same α M damping given as a dense 300 x 300 modal matrix; the two bodies are identical, so
// every damped mode is repeated). Argument: 0 = state-space expansion (the default), 1 = the
// impedance LU (per new Ω a complex LU of the modal impedance and 90 solves).
LinearModel damping_matrix_model(const Model& m, bool proportional) {
  if (proportional) {
    LinearModel linear = linear_model_from_matrices(m.K, m.M, 5.0, 0.0);
    linear.modal_damping_matrix = linear.modal_damping.asDiagonal();
    return linear;
  }
  // Non-proportional: C = 5 M + 2e-7 K₁, stiffness-proportional damping on body 1 only.
  const int half = static_cast<int>(m.K.rows()) / 2;
  Eigen::MatrixXd C = 5.0 * m.M;
  C.topLeftCorner(half, half) += 2e-7 * m.K.topLeftCorner(half, half);
  return linear_model_from_matrices(m.K, m.M, C);
}

const HarmonicBalanceSystem& damping_matrix_system(bool proportional, DampingMatrixMethod method) {
  static std::map<std::pair<bool, DampingMatrixMethod>, std::unique_ptr<HarmonicBalanceSystem>>
      systems;
  auto& system = systems[{proportional, method}];
  if (!system) {
    const Model m = build(150.0);
    HarmonicBalanceOptions options;
    options.harmonics = 1;
    options.time_samples = 64;
    options.damping_matrix_method = method;
    system = std::make_unique<HarmonicBalanceSystem>(damping_matrix_model(m, proportional), m.pairs,
                                                     m.excitation, options);
  }
  return *system;
}

void residual_new_frequency(benchmark::State& state, bool proportional) {
  const DampingMatrixMethod method =
      state.range(0) == 0 ? DampingMatrixMethod::kStateSpace : DampingMatrixMethod::kImpedanceLu;
  const HarmonicBalanceSystem& system = damping_matrix_system(proportional, method);
  const Case& c = reference_case();
  const Eigen::VectorXd x = c.system->linear_guess(c.omegas[200], true);
  Eigen::VectorXd R;
  int i = 0;
  for (auto _ : state) {
    system.evaluate(x, c.omegas[200 + (i++ % 2)], R, nullptr, nullptr);
    benchmark::DoNotOptimize(R.data());
  }
  state.counters["state_space"] = system.state_space_damping() ? 1 : 0;
}
void BM_ResidualNewFrequencyDampingMatrix(benchmark::State& state) {
  residual_new_frequency(state, true);
}
BENCHMARK(BM_ResidualNewFrequencyDampingMatrix)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
// The same with genuinely non-proportional damping (C = 5 M + 2e-7 K on body 1 only).
void BM_ResidualNewFrequencyNonProportional(benchmark::State& state) {
  residual_new_frequency(state, false);
}
BENCHMARK(BM_ResidualNewFrequencyNonProportional)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// The 401-point reference sweep with the damping matrix (C_m = 5 I, as above); 0 = state space,
// 1 = impedance LU. Includes building the system (and the expansion) once per run.
void BM_ReferenceSweepDampingMatrix(benchmark::State& state) {
  const Case& c = reference_case();
  const Model m = build(150.0);
  HarmonicBalanceOptions options;
  options.harmonics = 1;
  options.time_samples = 64;
  options.damping_matrix_method =
      state.range(0) == 0 ? DampingMatrixMethod::kStateSpace : DampingMatrixMethod::kImpedanceLu;
  FrequencyResponseOptions o;
  o.omegas = c.omegas;
  int converged = 0;
  for (auto _ : state) {
    const HarmonicBalanceSystem system(damping_matrix_model(m, true), m.pairs, m.excitation,
                                       options);
    const FrequencyResponse r = frequency_response(system, o);
    converged = 0;
    for (const FrequencyPoint& p : r.points) converged += p.converged;
  }
  state.counters["converged"] = converged;
}
BENCHMARK(BM_ReferenceSweepDampingMatrix)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// The one-off cost of the state-space expansion (damped_modal_expansion: dgeev of order 600,
// the bilinear products, clusters, two probe LUs) for nm = 300. Argument: 1 = C_m = 5 I (every
// eigenvalue repeated: 150 clusters), 0 = the non-proportional C above.
void BM_DampedModalExpansion(benchmark::State& state) {
  const Model m = build(150.0);
  const LinearModel linear = damping_matrix_model(m, state.range(0) == 1);
  const Eigen::VectorXd elastic = Eigen::VectorXd::Ones(linear.omega2.size());
  std::string failure;
  for (auto _ : state) {
    const auto d =
        damped_modal_expansion(linear.omega2, linear.modal_damping_matrix, elastic, failure);
    benchmark::DoNotOptimize(d.get());
    if (!d) state.SkipWithError(failure.c_str());
  }
}
BENCHMARK(BM_DampedModalExpansion)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

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

// ---------- Issue 4's large case: 300 pairs, H = 3, 100 points. ----------
// Two chains of 320 nodes (1920 DOFs), the lowest 1000 modes kept (α = 5 s⁻¹), the last 300
// nodes of each chain joined by 300 FrictionContact3D pairs (same parameters as above, N0 =
// 150 N), ±500 N tip excitation, H = 3, N = 32, uncoupled statics (nu = 900 rows x 6 = 5400
// unknowns), 100 points over ±1 % around the stuck resonance that moves the pairs tangentially
// (from the modes of the stuck structure), stepped sweep without the arc-length fallback.
// Above kStructuredSolverThreshold unknowns the structured solve is used.
constexpr int kLargeNodes = 320;
constexpr int kLargePairs = 300;
constexpr int kLargeModes = 1000;

struct LargeCase {
  std::unique_ptr<HarmonicBalanceSystem> system;
  std::vector<double> omegas;
};

LargeCase make_large_case() {
  const int n = 2 * kLargeNodes * 3;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n), M = Eigen::MatrixXd::Zero(n, n);
  const double k_chain[3] = {4e9, 2e9, 3e9}, mass = 0.05;
  for (int b = 0; b < 2; ++b) {
    for (int i = 0; i < kLargeNodes; ++i) {
      for (int d = 0; d < 3; ++d) {
        const int p = 3 * (b * kLargeNodes + i) + d;
        M(p, p) = mass * (1.0 + 0.001 * i);
        if (i == 0) K(p, p) += 10 * k_chain[d];
        if (i + 1 < kLargeNodes) {
          const double k = k_chain[d] * (1.0 + 0.02 * ((i * 7 + d) % 5));
          K(p, p) += k;
          K(p + 3, p + 3) += k;
          K(p, p + 3) -= k;
          K(p + 3, p) -= k;
        }
      }
    }
  }
  const FrictionContactParameters contact{
      .kt = 4.467e9, .kn = 5.6309e9, .mu = 0.5, .normal_preload = 150.0};
  auto element = std::make_shared<FrictionContact3D>(contact);
  std::vector<ContactPair> pairs;
  Eigen::MatrixXd Kstuck = K;
  const double kc[3] = {contact.kt, contact.kt, contact.kn};
  for (int q = 0; q < kLargePairs; ++q) {
    const int a = kLargeNodes - kLargePairs + q, b = kLargeNodes + a;
    pairs.push_back({.dofs_a = {3 * a, 3 * a + 1, 3 * a + 2},
                     .dofs_b = {3 * b, 3 * b + 1, 3 * b + 2},
                     .frame = Eigen::Matrix3d::Identity(),
                     .element = element});
    for (int d = 0; d < 3; ++d) {
      Kstuck(3 * a + d, 3 * a + d) += kc[d];
      Kstuck(3 * b + d, 3 * b + d) += kc[d];
      Kstuck(3 * a + d, 3 * b + d) -= kc[d];
      Kstuck(3 * b + d, 3 * a + d) -= kc[d];
    }
  }
  Excitation e;
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(n);
  f[3 * (kLargeNodes - 1)] = 500.0;
  f[3 * (2 * kLargeNodes - 1)] = -500.0;
  e.harmonics[1] = f;

  LinearModel full = linear_model_from_matrices(K, M, 5.0, 0.0);
  LinearModel model;
  model.omega2 = full.omega2.head(kLargeModes);
  model.Phi = full.Phi.leftCols(kLargeModes);
  model.modal_damping = full.modal_damping.head(kLargeModes);

  // The stuck structure's FRF of the x relative displacement of pair 0, from its own modes.
  const LinearModel stuck = linear_model_from_matrices(Kstuck, M, 5.0, 0.0);
  const int a0 = kLargeNodes - kLargePairs, b0 = kLargeNodes + a0;
  const Eigen::VectorXd psi = stuck.Phi.row(3 * a0) - stuck.Phi.row(3 * b0);
  const Eigen::VectorXcd q = stuck.Phi.transpose().cast<std::complex<double>>() * f;
  double best = 0, omega_peak = 0;
  for (double w = 100; w < 2e5; w *= 1.002) {
    std::complex<double> u = 0;
    for (Eigen::Index r = 0; r < psi.size(); ++r) {
      u +=
          psi[r] * q[r] / std::complex<double>(stuck.omega2[r] - w * w, w * stuck.modal_damping[r]);
    }
    if (std::abs(u) > best) {
      best = std::abs(u);
      omega_peak = w;
    }
  }
  HarmonicBalanceOptions options;
  options.harmonics = 3;
  options.time_samples = 32;
  LargeCase c;
  c.system = std::make_unique<HarmonicBalanceSystem>(model, pairs, e, options);
  for (int i = 0; i < 100; ++i) c.omegas.push_back(omega_peak * (0.99 + 0.02 * i / 99.0));
  return c;
}

const LargeCase& large_case() {
  static const LargeCase c = make_large_case();
  return c;
}

void BM_LargeSweep(benchmark::State& state) {
  const LargeCase& c = large_case();
  FrequencyResponseOptions o;
  o.omegas = c.omegas;
  if (state.range(0) < static_cast<int64_t>(o.omegas.size())) o.omegas.resize(state.range(0));
  o.sweep.jump_max_points = 0;  // no arc-length fallback (it needs the dense Jacobian)
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
  state.counters["unknowns"] = c.system->size();
  state.counters["points"] = static_cast<double>(o.omegas.size());
  state.counters["converged"] = converged;
  state.counters["newton_per_point"] = static_cast<double>(iterations) / o.omegas.size();
  state.counters["max_slip_fraction"] = slip;
  state.counters["last_gmres_iterations"] = c.system->last_gmres_iterations();
}
// The dense path's cost per Newton iteration on the large case: residual + dense dR/dx
// (5400 x 5400) and its LU, at the stuck guess of the middle frequency.
void BM_LargeDenseNewtonStep(benchmark::State& state) {
  const LargeCase& c = large_case();
  const double w = c.omegas[50];
  const Eigen::VectorXd x = c.system->linear_guess(w, true);
  Eigen::VectorXd R;
  Eigen::MatrixXd J;
  for (auto _ : state) {
    c.system->evaluate(x, w, R, &J, nullptr);
    Eigen::VectorXd dx = J.partialPivLu().solve(R);
    benchmark::DoNotOptimize(dx.data());
  }
}
BENCHMARK(BM_LargeDenseNewtonStep)->Unit(benchmark::kSecond)->Iterations(1);

// The structured path's pieces on the large case: building G_k and the preconditioner's LUs at
// a new Ω (alternating two frequencies), and one structured Newton step (AFT Jacobian + GMRES).
void BM_LargeOperatorNewFrequency(benchmark::State& state) {
  const LargeCase& c = large_case();
  const Eigen::VectorXd x = c.system->linear_guess(c.omegas[50], true);
  Eigen::VectorXd R, dx;
  int i = 0;
  for (auto _ : state) {
    const double w = c.omegas[50 + (i++ % 2)];
    c.system->evaluate(x, w, R, nullptr, nullptr);
    c.system->solve_jacobian(x, w, -R, dx);  // builds the preconditioner
    benchmark::DoNotOptimize(dx.data());
  }
}
BENCHMARK(BM_LargeOperatorNewFrequency)->Unit(benchmark::kMillisecond)->Iterations(4);

void BM_LargeStructuredNewtonStep(benchmark::State& state) {
  const LargeCase& c = large_case();
  const double w = c.omegas[50];
  Eigen::VectorXd x = c.system->linear_guess(w, true);
  // A slipping state: one Newton iteration from the stuck guess.
  NewtonOptions o;
  o.max_iterations = 1;
  solve_newton(*c.system, w, x, o);
  Eigen::VectorXd R, dx;
  c.system->evaluate(x, w, R, nullptr, nullptr);
  for (auto _ : state) {
    c.system->solve_jacobian(x, w, -R, dx);
    benchmark::DoNotOptimize(dx.data());
  }
  state.counters["gmres_iterations"] = c.system->last_gmres_iterations();
}
BENCHMARK(BM_LargeStructuredNewtonStep)->Unit(benchmark::kMillisecond)->Iterations(3);

BENCHMARK(BM_LargeSweep)->Arg(5)->Arg(100)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace stickslip

BENCHMARK_MAIN();
