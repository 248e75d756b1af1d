// Root location of the event AFT (event_aft.cpp, event_aft_planar.cpp; internal): the instants of
// stick/slip and contact transitions within the period, found as zeros of smooth switching
// functions of the phase θ.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace stickslip::event_roots {

// Zero of fun in (lo, hi), fun(lo) ≥ 0 > fun(hi) taken as given: Newton with dfun from x0 (the
// midpoint when x0 is not inside), safeguarded by bisection of the bracket, to a few ulps of θ.
template <class F, class D>
double locate(const F& fun, const D& dfun, double lo, double hi,
              double x0 = std::numeric_limits<double>::quiet_NaN()) {
  const double eps = std::numeric_limits<double>::epsilon();
  double x = x0 > lo && x0 < hi ? x0 : 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    const double fx = fun(x), dfx = dfun(x);
    (fx >= 0 ? lo : hi) = x;
    if (hi - lo <= 4 * eps * std::max(1.0, std::abs(x))) break;
    double xn = dfx != 0.0 ? x - fx / dfx : lo - 1.0;
    if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
    if (std::abs(xn - x) <= 2 * eps * std::max(1.0, std::abs(x))) {
      x = xn;
      break;
    }
    x = xn;
  }
  return x;
}

// The first θ in (a, b] where fun(θ, 0) < −tol (fun(θ, q): its q-th derivative, q = 0, 1, 2):
// bracketed on the grid θ_k = k·grid plus a check of each interval's interior minimum (the
// derivative going from − to +), then located. The grid must be fine enough that an interval holds
// at most one interior minimum of fun.
template <class F>
std::optional<double> first_exit(const F& fun, double tol, double grid, double a, double b) {
  auto fv = [&](double t) { return fun(t, 0); };
  auto fd = [&](double t) { return fun(t, 1); };
  double left = a, dl = fd(a);
  long k = static_cast<long>(std::floor(a / grid)) + 1;
  for (;;) {
    double t = k * grid;
    const bool last = t >= b;
    if (last) t = b;
    if (t > left) {
      const double ft = fv(t);
      if (ft < -tol) return locate(fv, fd, left, t);
      const double dr = fd(t);
      if (dl < 0 && dr > 0) {
        const double m = locate([&](double x) { return -fun(x, 1); },
                                [&](double x) { return -fun(x, 2); }, left, t);
        if (fv(m) < -tol) return locate(fv, fd, left, m);
      }
      dl = dr;
      left = t;
    }
    if (last) return std::nullopt;
    ++k;
  }
}

}  // namespace stickslip::event_roots
