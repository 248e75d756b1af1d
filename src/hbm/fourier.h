// Truncated real Fourier series over one period and its sampled (AFT) counterpart.
//
//   x(t) = a0 + Σ_{k ∈ S, k ≥ 1} (a_k cos kθ + b_k sin kθ),   θ = Ωt ∈ [0, 2π),
//   complex amplitude X_k = a_k − i b_k, so x(t) = Re Σ X_k e^{ikθ} (docs/conventions.md
//   convention).
//
// S is a HarmonicSet: an increasing list of non-negative harmonic numbers (e.g. 0..H, or the odd
// ones 1, 3, 5). Harmonic 0 may be absent.
//
// Real coefficient layout of ONE signal (one DOF), in the order of S:
//   harmonic 0 (if present) -> one coefficient [a0]; harmonic k ≥ 1 -> two [a_k, b_k].
//   E.g. S = 0..2: [a0, a1, b1, a2, b2]; S = {1, 3}: [a1, b1, a3, b3].
// A vector of several signals stores them one after the other (signal-major): coefficient c of
// signal s is at s * coefficient_count() + c.
//
// Sampling: N equally spaced instants θ_j = 2πj/N, j = 0..N−1, with N ≥ 2(2 H_max + 1).
//   samples = E · coefficients  (E = synthesis(), N x nc)
//   coefficients = P · samples  (P = analysis(), nc x N; the discrete Fourier projection:
//   a0 = Σx/N, a_k = 2Σx cos kθ_j /N, b_k = 2Σx sin kθ_j /N). P·E = I exactly (band-limited
//   signals round-trip to round-off); for other signals P gives the usual aliased DFT coefficients.
#pragma once

#include <complex>
#include <vector>

#include <Eigen/Core>

namespace stickslip {

class HarmonicSet {
 public:
  // 0..H (include_static) or 1..H. H ≥ 0; H = 0 only with include_static.
  static HarmonicSet up_to(int max_harmonic, bool include_static = true);
  // Any strictly increasing list of non-negative integers, not empty. Throws InvalidInput.
  explicit HarmonicSet(std::vector<int> harmonics);

  const std::vector<int>& harmonics() const { return harmonics_; }
  int size() const { return static_cast<int>(harmonics_.size()); }
  bool has_static() const { return !harmonics_.empty() && harmonics_.front() == 0; }
  int max_harmonic() const { return harmonics_.back(); }
  // Number of real coefficients per signal: 1 for harmonic 0, 2 for each k ≥ 1.
  int coefficient_count() const { return coefficient_count_; }
  // Index of a_k (the cos or constant coefficient) of the harmonic at `position` in the list;
  // b_k is at offset(position) + 1 for k ≥ 1.
  int offset(int position) const { return offsets_[position]; }
  // Position of harmonic k in the list, or −1 if absent.
  int position_of(int harmonic) const;
  // Smallest admissible number of time samples: 2 (2 H_max + 1).
  int min_time_samples() const { return 2 * (2 * max_harmonic() + 1); }

  // Complex amplitude X_k = a_k − i b_k (a0 for k = 0) of the harmonic at `position`.
  std::complex<double> complex_amplitude(const Eigen::Ref<const Eigen::VectorXd>& coefficients,
                                         int position) const;

 private:
  std::vector<int> harmonics_;
  std::vector<int> offsets_;
  int coefficient_count_ = 0;
};

class FourierBasis {
 public:
  // Throws InvalidInput unless time_samples ≥ harmonics.min_time_samples().
  FourierBasis(HarmonicSet harmonics, int time_samples);

  const HarmonicSet& harmonics() const { return harmonics_; }
  int time_samples() const { return static_cast<int>(synthesis_.rows()); }
  int coefficient_count() const { return harmonics_.coefficient_count(); }
  const Eigen::MatrixXd& synthesis() const { return synthesis_; }  // E, N x nc
  const Eigen::MatrixXd& analysis() const { return analysis_; }    // P, nc x N
  // D (nc x nc): coefficients of dx/dθ = D · coefficients of x (multiply by Ω for d/dt):
  //   a_k' = k b_k, b_k' = −k a_k, a0' = 0.
  Eigen::MatrixXd derivative() const;
  // θ_j = 2πj/N.
  double phase(int sample) const;

 private:
  HarmonicSet harmonics_;
  Eigen::MatrixXd synthesis_;
  Eigen::MatrixXd analysis_;
};

}  // namespace stickslip
