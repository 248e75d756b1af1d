// Stress cycles and envelopes against closed forms: uniaxial (signed von Mises = σ(t)),
// out-of-phase biaxial, pure shear; point functions against hand values.
#include "recovery/stress_envelope.h"

#include <cmath>
#include <complex>
#include <vector>

#include <gtest/gtest.h>

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
  ComplexStressMatrix imaginary_mean = S;
  imaginary_mean(0, 0) = Complex(1e6, 1e6);
  const std::vector<ComplexStressMatrix> bad{imaginary_mean};
  EXPECT_THROW(stress_envelope(bad, std::vector<int>{0}), InvalidInput);
  const std::vector<ComplexStressMatrix> mismatched{S, ComplexStressMatrix::Zero(6, 3)};
  EXPECT_THROW(stress_envelope(mismatched, std::vector<int>{0, 1}), InvalidInput);
}

}  // namespace
}  // namespace stickslip
