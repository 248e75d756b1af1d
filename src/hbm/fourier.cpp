#include "hbm/fourier.h"

#include <cmath>
#include <string>

#include "core/errors.h"
#include "core/types.h"

namespace stickslip {

namespace {

std::string list_to_string(const std::vector<int>& v) {
  std::string s = "[";
  for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::to_string(v[i]);
  return s + "]";
}

}  // namespace

HarmonicSet HarmonicSet::up_to(int max_harmonic, bool include_static) {
  require(max_harmonic >= (include_static ? 0 : 1), "HarmonicSet.max_harmonic",
          std::to_string(max_harmonic), include_static ? ">= 0" : ">= 1 without harmonic 0");
  std::vector<int> h;
  for (int k = include_static ? 0 : 1; k <= max_harmonic; ++k) h.push_back(k);
  return HarmonicSet(std::move(h));
}

HarmonicSet::HarmonicSet(std::vector<int> harmonics) : harmonics_(std::move(harmonics)) {
  require(!harmonics_.empty(), "HarmonicSet.harmonics", "[]", "not empty");
  for (size_t i = 0; i < harmonics_.size(); ++i) {
    if (harmonics_[i] >= 0 && (i == 0 || harmonics_[i] > harmonics_[i - 1])) continue;
    // (the list is formatted only here: formatting it for every entry is quadratic in its size)
    require(false, "HarmonicSet.harmonics", list_to_string(harmonics_),
            "strictly increasing non-negative integers");
  }
  for (int k : harmonics_) {
    offsets_.push_back(coefficient_count_);
    coefficient_count_ += (k == 0) ? 1 : 2;
  }
}

int HarmonicSet::position_of(int harmonic) const {
  for (int p = 0; p < size(); ++p) {
    if (harmonics_[p] == harmonic) return p;
  }
  return -1;
}

std::complex<double> HarmonicSet::complex_amplitude(
    const Eigen::Ref<const Eigen::VectorXd>& coefficients, int position) const {
  const int o = offsets_[position];
  if (harmonics_[position] == 0) return {coefficients[o], 0.0};
  return {coefficients[o], -coefficients[o + 1]};
}

FourierBasis::FourierBasis(HarmonicSet harmonics, int time_samples)
    : harmonics_(std::move(harmonics)) {
  require(time_samples >= harmonics_.min_time_samples(), "time_samples",
          std::to_string(time_samples),
          ">= 2(2 H_max + 1) = " + std::to_string(harmonics_.min_time_samples()));
  const int n = time_samples;
  const int nc = harmonics_.coefficient_count();
  synthesis_.resize(n, nc);
  analysis_.resize(nc, n);
  for (int p = 0; p < harmonics_.size(); ++p) {
    const int k = harmonics_.harmonics()[p];
    const int o = harmonics_.offset(p);
    for (int j = 0; j < n; ++j) {
      if (k == 0) {
        synthesis_(j, o) = 1.0;
        analysis_(o, j) = 1.0 / n;
        continue;
      }
      // Reduce k*j modulo n before the trigonometric call: exact phases for large products.
      const double theta = 2.0 * kPi * static_cast<double>((static_cast<long>(k) * j) % n) / n;
      const double c = std::cos(theta), s = std::sin(theta);
      synthesis_(j, o) = c;
      synthesis_(j, o + 1) = s;
      analysis_(o, j) = 2.0 * c / n;
      analysis_(o + 1, j) = 2.0 * s / n;
    }
  }
}

Eigen::MatrixXd FourierBasis::derivative() const {
  const int nc = harmonics_.coefficient_count();
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(nc, nc);
  for (int p = 0; p < harmonics_.size(); ++p) {
    const int k = harmonics_.harmonics()[p];
    if (k == 0) continue;
    const int o = harmonics_.offset(p);
    d(o, o + 1) = k;   // a_k' = k b_k
    d(o + 1, o) = -k;  // b_k' = −k a_k
  }
  return d;
}

double FourierBasis::phase(int sample) const { return 2.0 * kPi * sample / time_samples(); }

}  // namespace stickslip
