// One derivative checker for every hand-written derivative (STYLE.md, guideline 10): the
// Taylor-remainder slope. Along a direction δ the remainder
//   e(h) = ‖r(x + hδ) − r(x) − h J δ‖
// falls like h² when J is the derivative of r (slope 2 on log-log) and only like h when it is
// not (slope 1), whatever the scales of x and r. Where r is linear along δ (a stuck friction
// cycle, an open contact, a linear spring) e is round-off at every h: that passes as well.
// Used for every NonlinearElement (tests/contact), the AFT and every ParametrizedSystem
// (HarmonicBalanceSystem, the continuation tests' systems).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "contact/nonlinear_element.h"
#include "continuation/parametrized_system.h"

namespace stickslip::testing {

// A state for derivative checks: n entries uniform in [−amplitude, amplitude], from a fixed seed.
inline Eigen::VectorXd random_state(Eigen::Index n, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> dist(-1, 1);
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) x[i] = amplitude * dist(rng);
  return x;
}

// A remainder below kTaylorRoundOff (‖r(x)‖ + ‖Jδ‖) is round-off: r evaluated in double precision
// with O(10–1000) operations per entry loses ≈ 1e-14 of its scale; 1e-12 leaves a margin.
inline constexpr double kTaylorRoundOff = 1e-12;
// The slope of a correct derivative is 2 up to the third-order term's share of e(h): within
// ±0.2 when the steps are a decade apart and small enough that no regime (stick/slip, contact
// open/closed) changes between x and x + hδ.
inline constexpr double kTaylorSlopeMin = 1.8, kTaylorSlopeMax = 2.2;

struct TaylorRemainder {
  std::vector<double> steps, remainders;
  double floor = 0.0;           // round-off level of e
  double slope = std::nan("");  // over the two smallest steps whose e is above 10 floor
  bool linear = false;          // every e at round-off: r is linear along δ
  std::string describe() const {
    std::ostringstream out;
    out << "Taylor remainders (h, e):";
    for (size_t i = 0; i < steps.size(); ++i)
      out << " (" << steps[i] << ", " << remainders[i] << ")";
    out << "; round-off floor " << floor << ", slope " << slope;
    return out.str();
  }
};

// r_at(h) = r(x + hδ); r0 = r(x); Jd = J δ. Steps decreasing (default three decades).
inline TaylorRemainder taylor_remainder(const std::function<Eigen::VectorXd(double)>& r_at,
                                        const Eigen::VectorXd& r0, const Eigen::VectorXd& Jd,
                                        const std::vector<double>& steps = {1e-3, 1e-4, 1e-5}) {
  TaylorRemainder t;
  t.steps = steps;
  t.floor = kTaylorRoundOff * (r0.norm() + Jd.norm());
  std::vector<double> lh, le;
  for (double h : steps) {
    const double e = (r_at(h) - r0 - h * Jd).norm();
    t.remainders.push_back(e);
    if (e > 10 * t.floor) {
      lh.push_back(std::log10(h));
      le.push_back(std::log10(e));
    }
  }
  t.linear = lh.empty();
  if (lh.size() >= 2) {
    // The two smallest steps above round-off: the asymptotic range. At larger steps a sample may
    // cross a stick/slip or contact boundary between x and x + hδ (a kink), which inflates e(h)
    // there and steepens a slope fitted over every step.
    const size_t a = lh.size() - 2, b = lh.size() - 1;
    t.slope = (le[a] - le[b]) / (lh[a] - lh[b]);
  } else if (lh.size() == 1) {
    // One remainder above round-off and the next ones at it: it falls at least as fast as from
    // e to the floor over one step ratio.
    size_t i = 0;
    while (t.remainders[i] <= 10 * t.floor) ++i;
    if (i + 1 < steps.size()) {
      t.slope = std::log10(t.remainders[i] / (10 * t.floor)) / std::log10(steps[i] / steps[i + 1]);
    }
  }
  return t;
}

// gtest expectation: the remainder is round-off (linear r) or falls with slope 2.
inline void expect_taylor_slope(const TaylorRemainder& t) {
  if (t.linear) return;
  const bool one_point = std::count_if(t.remainders.begin(), t.remainders.end(),
                                       [&](double e) { return e > 10 * t.floor; }) == 1;
  EXPECT_GE(t.slope, kTaylorSlopeMin) << t.describe();
  if (!one_point) {
    EXPECT_LE(t.slope, kTaylorSlopeMax) << t.describe();
  }
}

// A ParametrizedSystem's dR/dx and dR/dλ together, along (δx, δλ): J δ = dR/dx δx + dR/dλ δλ.
inline TaylorRemainder taylor_remainder(const ParametrizedSystem& sys, const Eigen::VectorXd& x,
                                        double lambda, const Eigen::VectorXd& dx, double dlambda,
                                        const std::vector<double>& steps = {1e-3, 1e-4, 1e-5}) {
  Eigen::VectorXd R, dR_dlambda;
  Eigen::MatrixXd dR_dx;
  sys.evaluate(x, lambda, R, &dR_dx, &dR_dlambda);
  const Eigen::VectorXd Jd = dR_dx * dx + dR_dlambda * dlambda;
  return taylor_remainder(
      [&](double h) {
        Eigen::VectorXd Rh;
        sys.evaluate(x + h * dx, lambda + h * dlambda, Rh, nullptr, nullptr);
        return Rh;
      },
      R, Jd, steps);
}

// A NonlinearElement's exact sample derivative along δu (m x N): march with du_dp = δu as the one
// parameter column gives df/dp = J δu.
inline TaylorRemainder taylor_remainder(const NonlinearElement& element, const Eigen::MatrixXd& u,
                                        const Eigen::MatrixXd& du,
                                        const std::vector<double>& steps = {1e-3, 1e-4, 1e-5}) {
  const Eigen::MatrixXd du_dp = Eigen::Map<const Eigen::VectorXd>(du.data(), du.size());
  Eigen::MatrixXd f, df_dp;
  element.march(u, &du_dp, f, &df_dp);
  const Eigen::VectorXd f0 = Eigen::Map<const Eigen::VectorXd>(f.data(), f.size());
  return taylor_remainder(
      [&](double h) {
        Eigen::MatrixXd fh;
        element.march(u + h * du, nullptr, fh, nullptr);
        return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(fh.data(), fh.size()));
      },
      f0, df_dp.col(0), steps);
}

}  // namespace stickslip::testing
