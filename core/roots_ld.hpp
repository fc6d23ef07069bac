// Real roots of a polynomial of degree <= 4 (c[k] the coefficient of x^k) in [lo, hi], in long
// double: isolated between the roots of its derivatives (recursively) and bisected to full
// precision. Roots of even multiplicity are found only where the value is exactly 0. Reference
// quality, not speed: the accuracy lab's torus and quartic references and the torus kind's
// whole-scene reference use it.
#pragma once

#include <cstddef>
#include <vector>

namespace rb {

namespace roots_ld_detail {
inline long double peval(const long double* c, int deg, long double x) {
  long double p = c[deg];
  for (int k = deg - 1; k >= 0; --k) p = p * x + c[k];
  return p;
}
inline long double bisect(const long double* c, int deg, long double a, long double b) {
  long double fa = peval(c, deg, a);
  for (int it = 0; it < 200; ++it) {
    const long double m = a + (b - a) / 2;
    if (m <= a || m >= b) break;
    const long double fm = peval(c, deg, m);
    if (fm == 0) return m;
    if ((fm < 0) == (fa < 0)) a = m, fa = fm;
    else b = m;
  }
  return a + (b - a) / 2;
}
inline std::vector<long double> roots_rec(const long double* c, int deg, long double lo, long double hi) {
  std::vector<long double> r;
  while (deg > 0 && c[deg] == 0) --deg;
  if (deg == 0) return r;
  if (deg == 1) {
    const long double x = -c[0] / c[1];
    if (x >= lo && x <= hi) r.push_back(x);
    return r;
  }
  long double dc[5];
  for (int k = 1; k <= deg; ++k) dc[k - 1] = c[k] * k;
  std::vector<long double> pts{lo};
  for (long double x : roots_rec(dc, deg - 1, lo, hi))
    if (x > pts.back()) pts.push_back(x);
  if (hi > pts.back()) pts.push_back(hi);
  for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
    const long double a = pts[k], b = pts[k + 1];
    const long double fa = peval(c, deg, a), fb = peval(c, deg, b);
    if (fa == 0) {
      if (r.empty() || r.back() != a) r.push_back(a);
    } else if (fb != 0 && (fa < 0) != (fb < 0)) {
      r.push_back(bisect(c, deg, a, b));
    }
  }
  if (peval(c, deg, hi) == 0 && (r.empty() || r.back() != hi)) r.push_back(hi);
  return r;
}
}  // namespace roots_ld_detail

inline std::vector<long double> poly_roots_ld(const long double (&c)[5], int deg, long double lo, long double hi) {
  return roots_ld_detail::roots_rec(c, deg, lo, hi);
}


}  // namespace rb
