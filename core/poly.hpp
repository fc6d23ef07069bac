// Univariate polynomials over a number type F, and all their real roots in an interval.
//
// Root finding: isolation by derivatives (Rolle's theorem), then safeguarded Newton.
//   Between two consecutive real roots of p' the polynomial p is monotone, so it has at most one
//   root there, and it has one exactly when p changes sign across the interval. The roots of p'
//   come from the same procedure one degree lower; the recursion ends at the closed-form
//   quadratic. Each bracket is then refined by Newton steps that fall back to bisection whenever
//   the Newton iterate leaves the bracket, so every step keeps a sign-changing bracket.
//   Why this and not Sturm sequences or Bernstein subdivision: it needs no polynomial division
//   (Sturm sequences divide by leading coefficients that vanish for special rays, and need a
//   per-lane case split when a remainder degenerates), its memory is fixed by the degree (no
//   subdivision stack), and all N brackets of one degree are refined in one loop, so a SIMD
//   packet iterates until its slowest lane and bracket converge and every lane does the same
//   instructions. The cost is the root finding at every lower degree (N-2 nested solves).
//   Its known blind spot is shared by every sign-based method: a root of even multiplicity
//   (a tangent ray) has no sign change and is found only when p is exactly 0 at a bracket end.
//
// Conventions: c[k] is the coefficient of x^k. Roots come out ascending; a slot without a root
// holds a value clamped into [lo, hi] (so the list stays sorted) and a clear mask. Every loop is
// capped: kNewtonCap(F) iterations per degree.
#pragma once

#include "core/num.hpp"
#include "core/roots.hpp"

#include <limits>

namespace rb {

// Iteration tally of the iterative solvers: loop trips (per call in scalar code, per packet in
// SIMD code: the packet runs until its slowest lane has converged).
struct IterCount {
  int n = 0;
  RB_INLINE void add(int k = 1) { n += k; }
};
RB_INLINE void iter_add(IterCount* ic, int k = 1) {
  if (ic) ic->add(k);
}

// A constant that is not exact in float (1/3, 0.01, ...), rounded once to the lane type.
template <class F>
RB_INLINE F cst(double x) { return F(static_cast<scalar_t<F>>(x)); }

template <class F>
inline constexpr int kNewtonCap = std::numeric_limits<scalar_t<F>>::digits + 8;  // 32 float, 61 double

// p(x), Horner.
template <int N, class F>
RB_INLINE F poly_eval(const F (&c)[N + 1], const F& x) {
  F p = c[N];
  for (int k = N - 1; k >= 0; --k) p = p * x + c[k];
  return p;
}

// p(x) and p'(x), Horner.
template <int N, class F>
RB_INLINE void poly_eval_d(const F (&c)[N + 1], const F& x, F& p, F& dp) {
  p = c[N];
  dp = F(0);
  for (int k = N - 1; k >= 0; --k) {
    dp = dp * x + p;
    p = p * x + c[k];
  }
}

// Multiplies a polynomial of degree `deg` (stored in c[0..deg]) in place by (a + b x).
template <int Cap, class F>
RB_INLINE void poly_mul_linear(F (&c)[Cap], int deg, const F& a, const F& b) {
  c[deg + 1] = c[deg] * b;
  for (int k = deg; k >= 1; --k) c[k] = c[k] * a + c[k - 1] * b;
  c[0] = c[0] * a;
}

// sort_net (ascending, branch-free) lives with the root lists: core/roots.hpp.

// Real roots of c2 x^2 + c1 x + c0 in [lo, hi] (c2 may be 0: then the linear root), ascending.
template <class F>
RB_INLINE void quadratic_roots_in(const F (&c)[3], const F& lo, const F& hi, F (&x)[2], mask_t<F> (&ok)[2]) {
  const F disc = c[1] * c[1] - F(4) * c[2] * c[0];
  const F sq = vsqrt(vmax(disc, F(0)));
  const F q = F(-0.5) * (c[1] + vcopysign(sq, c[1]));
  const mask_t<F> quad = c[2] != F(0);
  const mask_t<F> qz = q == F(0);
  // Stable pair: q / c2 and c0 / q (q == 0 only for a double root at 0 when c2 != 0).
  F r1 = vselect(quad, q / c[2], -c[0] / c[1]);
  F r2 = vselect(qz, r1, c[0] / q);
  const mask_t<F> real = vselect(quad, disc, F(1)) >= F(0);
  const mask_t<F> two = quad & real;
  const F lo_r = vmin(r1, r2), hi_r = vmax(r1, r2);
  r1 = vselect(two, lo_r, r1);
  r2 = hi_r;
  ok[0] = real & (r1 >= lo) & (r1 <= hi);
  ok[1] = two & (r2 >= lo) & (r2 <= hi);
  // Keep the list sorted inside [lo, hi] (NaN and missing roots go to hi).
  x[0] = vselect(ok[0], r1, vselect(r1 < lo, lo, hi));
  x[1] = vselect(ok[1], r2, vselect(two & (r2 < lo), lo, hi));
}

// All real roots of the degree-N polynomial c in [lo, hi] (lo <= hi, finite), ascending.
// tol: absolute x tolerance of the Newton/bisection refinement.
template <int N, class F>
RB_INLINE void poly_roots_in(const F (&c)[N + 1], const F& lo, const F& hi, const F& tol, F (&x)[N], mask_t<F> (&ok)[N],
                             IterCount* ic = nullptr) {
  if constexpr (N == 1) {
    const F r = -c[0] / c[1];
    ok[0] = (r >= lo) & (r <= hi);
    x[0] = vselect(ok[0], r, vselect(r < lo, lo, hi));
  } else if constexpr (N == 2) {
    quadratic_roots_in(c, lo, hi, x, ok);
  } else {
    // Critical points: roots of p' (sorted, clamped into [lo, hi]).
    F dc[N];
    for (int k = 0; k < N; ++k) dc[k] = F(scalar_t<F>(k + 1)) * c[k + 1];
    F crit[N - 1];
    mask_t<F> cok[N - 1];
    poly_roots_in<N - 1, F>(dc, lo, hi, tol, crit, cok, ic);
    // Brackets [b_k, b_k+1], k = 0..N-1, with b_0 = lo, b_N = hi.
    F b[N + 1], fb[N + 1];
    b[0] = lo;
    for (int k = 0; k < N - 1; ++k) b[k + 1] = crit[k];
    b[N] = hi;
    for (int k = 0; k <= N; ++k) fb[k] = poly_eval<N>(c, b[k]);
    F a[N], e[N], fa[N];
    mask_t<F> act[N];
    mask_t<F> any_act = mask_false<F>();
    for (int k = 0; k < N; ++k) {
      a[k] = b[k];
      e[k] = b[k + 1];
      fa[k] = fb[k];
      const F f1 = fb[k + 1];
      // Half-open: a root exactly at a bracket end belongs to the bracket on its left (the
      // first bracket also owns lo), so a root at a critical point is reported once.
      mask_t<F> sc = ((fa[k] < F(0)) & (f1 >= F(0))) | ((fa[k] > F(0)) & (f1 <= F(0)));
      if (k == 0) sc = sc | (fa[k] == F(0));
      ok[k] = sc;
      x[k] = vselect(fa[k] == F(0), a[k], vselect(f1 == F(0), e[k], F(0.5) * (a[k] + e[k])));
      act[k] = sc & (fa[k] != F(0)) & (f1 != F(0));
      any_act = any_act | act[k];
    }
    for (int it = 0; it < kNewtonCap<F>; ++it) {
      if (none_of<F>(any_act)) break;
      iter_add(ic);
      any_act = mask_false<F>();
      for (int k = 0; k < N; ++k) {
        F f, df;
        poly_eval_d<N>(c, x[k], f, df);
        // Keep the bracket: the end with fa's sign moves to x.
        const mask_t<F> same = ((f < F(0)) & (fa[k] < F(0))) | ((f > F(0)) & (fa[k] > F(0)));
        a[k] = vselect(act[k] & same, x[k], a[k]);
        e[k] = vselect(act[k] & mask_not<F>(same), x[k], e[k]);
        F xn = x[k] - f / df;
        const mask_t<F> inside = (xn > a[k]) & (xn < e[k]);  // false for NaN (df == 0)
        xn = vselect(inside, xn, F(0.5) * (a[k] + e[k]));
        const mask_t<F> zero = f == F(0);
        const mask_t<F> conv = zero | (vabs(xn - x[k]) <= tol) | ((e[k] - a[k]) <= tol);
        x[k] = vselect(act[k] & mask_not<F>(zero), xn, x[k]);
        act[k] = act[k] & mask_not<F>(conv);
        any_act = any_act | act[k];
      }
    }
    for (int k = 0; k < N; ++k) x[k] = vselect(ok[k], x[k], e[k]);
  }
}

}  // namespace rb
