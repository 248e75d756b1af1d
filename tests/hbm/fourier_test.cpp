#include "hbm/fourier.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/types.h"

namespace stickslip {
namespace {

// Independent evaluation of the series from its definition.
double series(const HarmonicSet& set, const Eigen::VectorXd& c, double theta) {
  double x = 0;
  for (int p = 0; p < set.size(); ++p) {
    const int k = set.harmonics()[p], o = set.offset(p);
    x += (k == 0) ? c[o] : c[o] * std::cos(k * theta) + c[o + 1] * std::sin(k * theta);
  }
  return x;
}

TEST(Fourier, LayoutIsA0ThenCosSinPairs) {
  const HarmonicSet full = HarmonicSet::up_to(2);
  EXPECT_EQ(full.coefficient_count(), 5);
  EXPECT_EQ(full.offset(0), 0);
  EXPECT_EQ(full.offset(1), 1);
  EXPECT_EQ(full.offset(2), 3);
  const HarmonicSet odd({1, 3, 5});
  EXPECT_FALSE(odd.has_static());
  EXPECT_EQ(odd.coefficient_count(), 6);
  EXPECT_EQ(odd.position_of(3), 1);
  EXPECT_EQ(odd.position_of(2), -1);
  EXPECT_EQ(odd.min_time_samples(), 22);
}

TEST(Fourier, RoundTripIsExactForBandLimitedSignals) {
  constexpr double kRoundOff = 1e-13;  // a few ulps times N
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> dist(-1, 1);
  for (const HarmonicSet& set :
       {HarmonicSet::up_to(5), HarmonicSet({1, 3, 5, 7}), HarmonicSet::up_to(3, false)}) {
    for (int n : {set.min_time_samples(), 64, 257}) {
      const FourierBasis basis(set, n);
      Eigen::VectorXd c(set.coefficient_count());
      for (int i = 0; i < c.size(); ++i) c[i] = dist(rng);
      const Eigen::VectorXd x = basis.synthesis() * c;
      for (int j = 0; j < n; ++j) EXPECT_NEAR(x[j], series(set, c, basis.phase(j)), kRoundOff);
      EXPECT_LT((basis.analysis() * x - c).cwiseAbs().maxCoeff(), kRoundOff);
    }
  }
}

TEST(Fourier, ComplexAmplitudeConvention) {
  // x = Re(X e^{iθ}) with X = a − i b  ⇔  x = a cos θ + b sin θ.
  const HarmonicSet set = HarmonicSet::up_to(1);
  Eigen::VectorXd c(3);
  c << 0.5, 2.0, -3.0;
  const std::complex<double> x1 = set.complex_amplitude(c, 1);
  EXPECT_EQ(x1, std::complex<double>(2.0, 3.0));
  for (double theta : {0.0, 0.7, 2.5}) {
    EXPECT_NEAR((x1 * std::exp(std::complex<double>(0, theta))).real() + 0.5, series(set, c, theta),
                1e-14);
  }
}

TEST(Fourier, DerivativeMatchesAnalyticDerivative) {
  const HarmonicSet set = HarmonicSet::up_to(3);
  const FourierBasis basis(set, 16);
  Eigen::VectorXd c(7);
  c << 1, 2, -1, 0.5, 0.25, -0.3, 0.1;
  const Eigen::VectorXd dc = basis.derivative() * c;
  for (double theta : {0.1, 1.0, 4.0}) {
    double d = 0;
    for (int k = 1; k <= 3; ++k) {
      const int o = set.offset(k);
      d += -k * c[o] * std::sin(k * theta) + k * c[o + 1] * std::cos(k * theta);
    }
    EXPECT_NEAR(series(set, dc, theta), d, 1e-13);
  }
}

TEST(Fourier, RejectsBadInput) {
  EXPECT_THROW(FourierBasis(HarmonicSet::up_to(3), 13), InvalidInput);
  EXPECT_THROW(HarmonicSet({1, 1}), InvalidInput);
  EXPECT_THROW(HarmonicSet({}), InvalidInput);
  EXPECT_THROW(HarmonicSet({-1, 2}), InvalidInput);
  EXPECT_THROW(HarmonicSet::up_to(0, false), InvalidInput);
}

}  // namespace
}  // namespace stickslip
