// Gauss–Legendre nodes x and weights w on [−1, 1] (q points, exact for polynomials of degree
// 2q − 1), computed once per order and thread. Internal to the event AFT (event_aft*.cpp).
#pragma once

#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "core/types.h"

namespace stickslip {

inline const std::pair<std::vector<double>, std::vector<double>>& gauss_legendre(int q) {
  thread_local std::map<int, std::pair<std::vector<double>, std::vector<double>>> cache;
  auto it = cache.find(q);
  if (it != cache.end()) return it->second;
  std::vector<double> x(q), w(q);
  for (int i = 0; i < (q + 1) / 2; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (q + 0.5)), dp = 0;
    for (int it2 = 0; it2 < 100; ++it2) {
      double p0 = 1, p1 = z;  // Legendre recurrence: P_q(z) and P_q'(z)
      for (int n = 2; n <= q; ++n) {
        const double p2 = ((2 * n - 1) * z * p1 - (n - 1) * p0) / n;
        p0 = p1;
        p1 = p2;
      }
      if (q == 1) p0 = 1;
      dp = q * (z * p1 - p0) / (z * z - 1);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    x[i] = -z;
    x[q - 1 - i] = z;
    w[i] = w[q - 1 - i] = 2 / ((1 - z * z) * dp * dp);
  }
  return cache.emplace(q, std::make_pair(std::move(x), std::move(w))).first->second;
}

}  // namespace stickslip
