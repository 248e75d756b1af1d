// Stress cycles and envelopes against closed forms: uniaxial (signed von Mises = σ(t)),
// out-of-phase biaxial, pure shear; point functions against hand values and Eigen's iterative
// eigen-solver; the refined envelope against brute-force dense sampling of the period.
#include "recovery/stress_envelope.h"

#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "core/errors.h"
#include "core/types.h"

namespace stickslip {
namespace {

using Complex = std::complex<double>;
using Voigt = Eigen::Matrix<double, 6, 1>;
// Closed forms evaluated in double precision at sampled instants that hit the extremes exactly.
constexpr double kRoundOff = 1e-12;

TEST(StressEnvelope, PointFunctionsMatchHandValues) {
  Voigt uniaxial;
  uniaxial << -120e6, 0, 0, 0, 0, 0;
  EXPECT_NEAR(von_mises_stress(uniaxial), 120e6, kRoundOff * 120e6);
  EXPECT_NEAR(signed_von_mises_stress(uniaxial), -120e6, kRoundOff * 120e6);
  Voigt shear;
  shear << 0, 0, 0, 0, 0, 50e6;  // τ_yz
  EXPECT_NEAR(von_mises_stress(shear), std::sqrt(3.0) * 50e6, kRoundOff * 1e8);
  const Eigen::Vector3d p = principal_stresses(shear);
  EXPECT_NEAR(p(0), 50e6, kRoundOff * 1e8);
  EXPECT_NEAR(p(1), 0.0, kRoundOff * 1e8);
  EXPECT_NEAR(p(2), -50e6, kRoundOff * 1e8);
  Voigt hydro;
  hydro << 7e6, 7e6, 7e6, 0, 0, 0;
  EXPECT_NEAR(von_mises_stress(hydro), 0.0, 1e-6);
  // A general tensor: von Mises from the principal stresses.
  Voigt g;
  g << 10e6, -20e6, 5e6, 8e6, -3e6, 12e6;
  const Eigen::Vector3d q = principal_stresses(g);
  const double vm_p =
      std::sqrt(0.5 * ((q(0) - q(1)) * (q(0) - q(1)) + (q(1) - q(2)) * (q(1) - q(2)) +
                       (q(2) - q(0)) * (q(2) - q(0))));
  EXPECT_NEAR(von_mises_stress(g), vm_p, 1e-9 * vm_p);
  EXPECT_NEAR(q.sum(), g(0) + g(1) + g(2), 1e-6);
}

// σ_xx(t) = σ_m + σ_a cos(Ωt + φ) at every node (one node per case), one or two harmonics:
// signed von Mises = σ_xx(t), so max von Mises = |σ_m| + σ_a, alternating σ_a, mean σ_m,
// max principal max(σ_m + σ_a, 0), static |σ_m|.
TEST(StressEnvelope, UniaxialCycleGivesClosedForms) {
  const int N = 64;
  const double phi = 2.0 * kPi * 5.0 / N;  // peaks land on samples
  const std::vector<std::pair<double, double>> cases{
      {80e6, 100e6}, {-30e6, 50e6}, {0.0, 70e6}, {150e6, 20e6}};
  ComplexStressMatrix S0 = ComplexStressMatrix::Zero(6, 4), S1 = S0;
  for (int n = 0; n < 4; ++n) {
    const auto [mean, amp] = cases[n];
    S0(0, n) = mean;
    // σ_a cos(θ + φ) = a cos θ + b sin θ with a = σ_a cos φ, b = −σ_a sin φ; X = a − i b.
    S1(0, n) = Complex(amp * std::cos(phi), amp * std::sin(phi));
  }
  const std::vector<ComplexStressMatrix> S{S0, S1};
  const std::vector<int> H{0, 1};
  const StressEnvelope env = stress_envelope(S, H, {.time_samples = N});
  for (int n = 0; n < 4; ++n) {
    const auto [mean, amp] = cases[n];
    const double tol = kRoundOff * (std::abs(mean) + amp);
    EXPECT_NEAR(env.von_mises_max(n), std::abs(mean) + amp, tol) << n;
    EXPECT_NEAR(env.von_mises_alternating(n), amp, tol) << n;
    EXPECT_NEAR(env.von_mises_mean(n), mean, tol) << n;
    EXPECT_NEAR(env.max_principal_max(n), std::max(mean + amp, 0.0), tol) << n;
    EXPECT_NEAR(env.von_mises_static(n), std::abs(mean), tol) << n;
  }
  // The time history follows σ_m + σ_a cos(2π j/N + φ).
  const auto history = stress_time_history(S, H, N);
  ASSERT_EQ(history.size(), static_cast<size_t>(N));
  for (int j = 0; j < N; ++j) {
    const double expected = cases[0].first + cases[0].second * std::cos(2 * kPi * j / N + phi);
    EXPECT_NEAR(history[j](0, 0), expected, kRoundOff * 2e8);
  }
}

// Second harmonic only: σ_xx = σ_a cos 2Ωt, every quantity as for one harmonic, mean 0.
TEST(StressEnvelope, HigherHarmonicAlone) {
  ComplexStressMatrix S2 = ComplexStressMatrix::Zero(6, 1);
  S2(1, 0) = Complex(0.0, -60e6);  // a = 0, b = 60 MPa: 60 sin 2Ωt
  const std::vector<ComplexStressMatrix> S{S2};
  const std::vector<int> H{2};
  const StressEnvelope env = stress_envelope(S, H, {.time_samples = 16});
  EXPECT_NEAR(env.von_mises_max(0), 60e6, kRoundOff * 6e7);
  EXPECT_NEAR(env.von_mises_alternating(0), 60e6, kRoundOff * 6e7);
  EXPECT_NEAR(env.von_mises_mean(0), 0.0, kRoundOff * 6e7);
  EXPECT_EQ(env.von_mises_static(0), 0.0);
}

// σ_xx = A cos Ωt, σ_yy = A sin Ωt: σ_vm² = A² (1 − sin 2Ωt / 2), so max σ_vm = A √1.5 and
// min A √0.5; σ_1 = A max(cos, sin) over the cycle peaks at A.
TEST(StressEnvelope, OutOfPhaseBiaxialCycle) {
  const double A = 90e6;
  ComplexStressMatrix S1 = ComplexStressMatrix::Zero(6, 1);
  S1(0, 0) = A;                 // A cos
  S1(1, 0) = Complex(0.0, -A);  // A sin (b = A, X = −i A)
  const std::vector<ComplexStressMatrix> S{S1};
  const std::vector<int> H{1};
  const StressEnvelope env = stress_envelope(S, H, {.time_samples = 64});
  EXPECT_NEAR(env.von_mises_max(0), A * std::sqrt(1.5), kRoundOff * A);
  EXPECT_NEAR(env.max_principal_max(0), A, kRoundOff * A);
  // Signed von Mises: the peaks of σ_vm (2Ωt = −π/2 mod 2π) are ties |σ_1| = |σ_3| = A/√2 where
  // the sign flips; on either side the cycle is tensile- or compressive-dominated, so the
  // signed range is ±A √1.5 in the limit. The samples next to the tie (Δt = T/64) lose
  // 1 − sqrt(1 − (1 − cos(π/16))/3) ≈ 0.3% of it.
  constexpr double kSamplingLoss = 0.005;
  EXPECT_NEAR(env.von_mises_alternating(0), A * std::sqrt(1.5), kSamplingLoss * A);
  EXPECT_NEAR(env.von_mises_mean(0), 0.0, kSamplingLoss * A);
}

// Independent references: Eigen's iterative (QR) symmetric eigen-solver, descending.
Eigen::Vector3d reference_principal(const Voigt& s) {
  Eigen::Matrix3d t;
  t << s(0), s(3), s(4), s(3), s(1), s(5), s(4), s(5), s(2);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(t, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d e = solver.eigenvalues();
  return {e(2), e(1), e(0)};
}

Voigt random_voigt(std::mt19937& rng, double scale) {
  std::normal_distribution<double> normal(0.0, scale);
  Voigt s;
  for (int i = 0; i < 6; ++i) s(i) = normal(rng);
  return s;
}

TEST(StressEnvelope, ClosedFormPrincipalStressesMatchIterativeEigenSolver) {
  std::mt19937 rng(7);
  std::vector<Voigt> cases;
  for (int i = 0; i < 2000; ++i) cases.push_back(random_voigt(rng, 1e8));
  // Degenerate ones: uniaxial (double root 0), hydrostatic (triple), pure shear, a double root
  // with a large mean, an almost-double root, and zero.
  Voigt v;
  v << 3e8, 0, 0, 0, 0, 0;
  cases.push_back(v);
  v << -5e7, -5e7, -5e7, 0, 0, 0;
  cases.push_back(v);
  v << 0, 0, 0, 4e7, 0, 0;
  cases.push_back(v);
  v << 1e9, 1e9, 1e9 + 2e6, 0, 0, 0;
  cases.push_back(v);
  v << 1e8, 1e8 * (1 + 1e-9), -2e7, 0, 0, 1e3;
  cases.push_back(v);
  cases.push_back(Voigt::Zero());
  for (const Voigt& s : cases) {
    const Eigen::Vector3d p = principal_stresses(s);
    const Eigen::Vector3d r = reference_principal(s);
    const double scale = std::max(s.norm(), 1.0);
    // From the invariants (round-off eps relative) the eigenvalues near a double root move like
    // the square root of that perturbation: up to ~sqrt(eps) = 1.5e-8 of the norm.
    constexpr double kClosedForm = 3e-8;
    EXPECT_NEAR(p(0), r(0), kClosedForm * scale) << s.transpose();
    EXPECT_NEAR(p(1), r(1), kClosedForm * scale) << s.transpose();
    EXPECT_NEAR(p(2), r(2), kClosedForm * scale) << s.transpose();
    // The sign of the signed von Mises stress: sign(σ_1 + σ_3) from the reference eigenvalues,
    // away from ties (where either sign is right up to round-off).
    if (std::abs(r(0) + r(2)) > 1e-9 * scale && von_mises_stress(s) > 1e-9 * scale) {
      EXPECT_EQ(signed_von_mises_stress(s) >= 0.0, r(0) + r(2) > 0.0) << s.transpose();
    }
  }
}

// Brute force: σ(θ) = Re Σ S_k e^{ikθ} (complex arithmetic) at M instants, von Mises from the
// principal stresses of the iterative eigen-solver, sign of σ_1 + σ_3 for the signed value.
struct DenseEnvelope {
  double vm_max = 0, p_max = -1e300, svm_max = -1e300, svm_min = 1e300;
  double shortest_sign_run = 2 * kPi;  // shortest interval of one sign of σ_svm, radians
};
DenseEnvelope dense_envelope(const std::vector<ComplexStressMatrix>& S, const std::vector<int>& k,
                             int node, int M) {
  DenseEnvelope d;
  std::vector<char> positive(static_cast<size_t>(M));
  for (int j = 0; j < M; ++j) {
    const double theta = 2.0 * kPi * j / M;
    Voigt s = Voigt::Zero();
    for (size_t h = 0; h < S.size(); ++h) {
      s += (S[h].col(node) * std::exp(Complex(0.0, k[h] * theta))).real();
    }
    const Eigen::Vector3d p = reference_principal(s);
    const double vm =
        std::sqrt(0.5 * ((p(0) - p(1)) * (p(0) - p(1)) + (p(1) - p(2)) * (p(1) - p(2)) +
                         (p(2) - p(0)) * (p(2) - p(0))));
    const double svm = p(0) + p(2) >= 0.0 ? vm : -vm;
    d.vm_max = std::max(d.vm_max, vm);
    d.p_max = std::max(d.p_max, p(0));
    d.svm_max = std::max(d.svm_max, svm);
    d.svm_min = std::min(d.svm_min, svm);
    positive[static_cast<size_t>(j)] = svm >= 0.0;
  }
  int start = 0;  // a sign change, so that runs are counted whole (cyclically)
  while (start < M && positive[static_cast<size_t>(start)] ==
                          positive[static_cast<size_t>((start + M - 1) % M)]) {
    ++start;
  }
  if (start < M) {
    int run = 0;
    for (int i = 0; i < M; ++i) {
      const int j = (start + i) % M;
      if (i > 0 &&
          positive[static_cast<size_t>(j)] != positive[static_cast<size_t>((j + M - 1) % M)]) {
        d.shortest_sign_run = std::min(d.shortest_sign_run, 2 * kPi * run / M);
        run = 0;
      }
      ++run;
    }
    d.shortest_sign_run = std::min(d.shortest_sign_run, 2 * kPi * run / M);
  }
  return d;
}

// Random multi-harmonic cycles (seeded; harmonics 0..H with decaying amplitudes): the refined
// envelope (automatic, small N) against dense sampling with M instants. Dense sampling itself
// falls short of a smooth peak by at most H² (2π/M)² / 8 of the amplitude (Bernstein), and of a
// supremum at a jump of σ_svm by at most |dσ_vm/dθ| 2π/M <= H (2π/M) of it. The sign of σ_svm
// is known at the samples, so an interval of one sign shorter than the sample spacing (a
// near-tie |σ_1| ≈ |σ_3| that flips the sign briefly) can be missed, as by any sampling: the
// signed extremes are compared where the dense sign intervals are all longer than that.
TEST(StressEnvelope, RefinedEnvelopeMatchesDenseSamplingOfThePeriod) {
  std::mt19937 rng(2026);
  constexpr int kNodes = 40, kDense = 20000;
  for (const int H : {1, 3}) {
    std::vector<int> k;
    std::vector<ComplexStressMatrix> S;
    for (int h = 0; h <= H; ++h) {
      k.push_back(h);
      ComplexStressMatrix Sh(6, kNodes);
      for (int n = 0; n < kNodes; ++n) {
        const double scale = 1e8 / (1 + h);
        const Voigt re = random_voigt(rng, scale), im = random_voigt(rng, scale);
        Sh.col(n).real() = re;
        Sh.col(n).imag() = h == 0 ? Voigt::Zero() : im;
      }
      S.push_back(Sh);
    }
    const StressEnvelope env = stress_envelope(S, k);
    const StressEnvelope coarse = stress_envelope(S, k, {.refine = false});
    const double smooth = H * H * std::pow(2 * kPi / kDense, 2) / 8.0 + 1e-12;
    const double jump = H * 2 * kPi / kDense;
    double worst_gain = 0.0;  // how much refining moved a maximum, relative
    int short_runs = 0;
    for (int n = 0; n < kNodes; ++n) {
      double amp = 0.0;
      for (const auto& Sh : S) amp += Sh.col(n).norm();
      const DenseEnvelope d = dense_envelope(S, k, n, kDense);
      // Never below the dense maxima by more than their own shortfall, never above them.
      EXPECT_NEAR(env.von_mises_max(n), d.vm_max, 2 * smooth * amp) << "H " << H << " node " << n;
      EXPECT_NEAR(env.max_principal_max(n), d.p_max, 2 * smooth * amp)
          << "H " << H << " node " << n;
      worst_gain = std::max(worst_gain, (env.von_mises_max(n) - coarse.von_mises_max(n)) / amp);
      EXPECT_GE(env.von_mises_max(n), coarse.von_mises_max(n));
      EXPECT_GE(env.max_principal_max(n), coarse.max_principal_max(n));
      if (d.shortest_sign_run < 2 * kPi / envelope_time_samples({}, H)) {
        ++short_runs;
        continue;
      }
      const double svm_max = env.von_mises_mean(n) + env.von_mises_alternating(n);
      const double svm_min = env.von_mises_mean(n) - env.von_mises_alternating(n);
      EXPECT_GE(svm_max, d.svm_max - 2 * smooth * amp) << n;
      EXPECT_LE(svm_max, d.svm_max + jump * amp) << n;
      EXPECT_LE(svm_min, d.svm_min + 2 * smooth * amp) << n;
      EXPECT_GE(svm_min, d.svm_min - jump * amp) << n;
    }
    EXPECT_LT(short_runs, kNodes / 4) << "H " << H;  // the signed check ran on most nodes
    // The coarse samples alone do miss peaks by a visible amount (the refinement is needed).
    EXPECT_GT(worst_gain, 1e-5) << "H " << H;
  }
}

// Without refinement the envelope is the maximum over the N samples exactly: the pruned
// closed-form principal stresses and the polynomial sign test against the sampled references.
TEST(StressEnvelope, UnrefinedEnvelopeIsTheMaximumOverTheSamples) {
  std::mt19937 rng(99);
  constexpr int kNodes = 50, N = 24;
  std::vector<int> k{0, 1, 2};
  std::vector<ComplexStressMatrix> S;
  for (int h : k) {
    ComplexStressMatrix Sh(6, kNodes);
    for (int n = 0; n < kNodes; ++n) {
      Sh.col(n).real() = random_voigt(rng, 1e8);
      Sh.col(n).imag() = h == 0 ? Voigt::Zero() : random_voigt(rng, 1e8);
    }
    S.push_back(Sh);
  }
  const StressEnvelope env = stress_envelope(S, k, {.time_samples = N, .refine = false});
  for (int n = 0; n < kNodes; ++n) {
    const DenseEnvelope d = dense_envelope(S, k, n, N);
    const double scale = 1e8;
    EXPECT_NEAR(env.von_mises_max(n), d.vm_max, kRoundOff * 10 * scale);
    EXPECT_NEAR(env.max_principal_max(n), d.p_max, kRoundOff * 10 * scale);
    EXPECT_NEAR(env.von_mises_mean(n) + env.von_mises_alternating(n), d.svm_max,
                kRoundOff * 10 * scale);
    EXPECT_NEAR(env.von_mises_mean(n) - env.von_mises_alternating(n), d.svm_min,
                kRoundOff * 10 * scale);
  }
}

// A uniaxial cycle whose peak falls between samples: the refined maxima are exact.
TEST(StressEnvelope, RefinementFindsPeaksBetweenSamples) {
  const double mean = 40e6, amp = 100e6, phi = 0.123;  // no sample at the peaks
  ComplexStressMatrix S0 = ComplexStressMatrix::Zero(6, 1), S1 = S0;
  S0(0, 0) = mean;
  S1(0, 0) = Complex(amp * std::cos(phi), amp * std::sin(phi));
  const std::vector<ComplexStressMatrix> S{S0, S1};
  const std::vector<int> H{0, 1};
  const StressEnvelope env = stress_envelope(S, H, {.time_samples = 6});
  const double tol = kRoundOff * (mean + amp);
  EXPECT_NEAR(env.von_mises_max(0), mean + amp, tol);
  EXPECT_NEAR(env.max_principal_max(0), mean + amp, 1e-9 * (mean + amp));
  EXPECT_NEAR(env.von_mises_alternating(0), amp, tol);
  EXPECT_NEAR(env.von_mises_mean(0), mean, tol);
  const StressEnvelope coarse = stress_envelope(S, H, {.time_samples = 6, .refine = false});
  EXPECT_LT(coarse.von_mises_max(0), mean + amp - 1e-3 * amp);
}

TEST(StressEnvelope, BadInputThrows) {
  const ComplexStressMatrix S = ComplexStressMatrix::Zero(6, 2);
  const std::vector<ComplexStressMatrix> one{S};
  EXPECT_THROW(stress_envelope(one, std::vector<int>{0, 1}), InvalidInput);
  const std::vector<ComplexStressMatrix> two{S, S};
  EXPECT_THROW(stress_envelope(two, std::vector<int>{1, 1}), InvalidInput);
  EXPECT_THROW(stress_envelope(one, std::vector<int>{-1}), InvalidInput);
  // Too few samples for harmonic 3: N >= 2 (2·3 + 1) = 14.
  EXPECT_THROW(stress_envelope(one, std::vector<int>{3}, {.time_samples = 13}), InvalidInput);
  EXPECT_NO_THROW(stress_envelope(one, std::vector<int>{3}, {.time_samples = 14}));
  EXPECT_THROW(stress_envelope(one, std::vector<int>{3}, {.num_threads = -1}), InvalidInput);
  ComplexStressMatrix imaginary_mean = S;
  imaginary_mean(0, 0) = Complex(1e6, 1e6);
  const std::vector<ComplexStressMatrix> bad{imaginary_mean};
  EXPECT_THROW(stress_envelope(bad, std::vector<int>{0}), InvalidInput);
  const std::vector<ComplexStressMatrix> mismatched{S, ComplexStressMatrix::Zero(6, 3)};
  EXPECT_THROW(stress_envelope(mismatched, std::vector<int>{0, 1}), InvalidInput);
}

}  // namespace
}  // namespace stickslip
