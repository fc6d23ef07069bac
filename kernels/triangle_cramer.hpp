// Ray x triangle by Cramer's rule (seed 002 "Ray-Triangle Intersection", seed 004 "Ray/Triangle
// Intersection ... using barycentric coordinates directly"):
//   e + t d = a + beta (b - a) + gamma (c - a)
//   [a-b  a-c  d] [beta gamma t]^T = a - e, solved by Cramer's rule: with M = |a-b a-c d|,
//   t = |a-b a-c a-e| / M, gamma = |a-b a-e d| / M, beta = |a-e a-c d| / M
// (each 3x3 determinant a triple product; the 2x2 minors of the d column and of the a-e column
// are shared, as in Shirley's formulation). Evaluated in the order t, gamma, beta with an early
// exit after each test: t within [tmin, tmax], 0 <= gamma <= 1, 0 <= beta <= 1 - gamma.
// No separate parallel test: a ray parallel to the triangle has M == 0, so t is +-inf or NaN
// and fails the positive-form range test.
// Data: the Moller-Trumbore triangle (v0 = a, e1 = b - a, e2 = c - a, edges rounded once from
// double): a - b = -e1 and a - c = -e2 are free (sign flips), so both methods share one batch.
// [u,v] = [beta, gamma] (the barycentric coordinates of b and c, as Moller-Trumbore returns).
#pragma once

#include "kernels/triangle.hpp"

namespace rb {

template <class F>
RB_INLINE Hit<F> intersect_triangle_cramer(const Ray<F>& r, const Triangle<F>& q) {
  const Vec3<F> ab = -q.e1, ac = -q.e2;                 // free
  const Vec3<F> ae = q.v0 - r.o;                        // 3+-
  // Minors of the columns (a-c, d) and (a-b, a-e):
  const Vec3<F> m1 = cross(ac, r.d);                    // 3+- 6*   (ei-hf, gf-di, dh-eg)
  const F M = dot(ab, m1);                              // 2+- 3*
  const Vec3<F> m2 = cross(ab, ae);                     // 3+- 6*   (bl-kc, jc-al, ak-jb)
  const F t = -dot(ac, m2) / M;                         // 2+- 3* 1/
  mask_t<F> m = (t >= r.tmin) & (t <= r.tmax);          // 2 cmp
  if (none_of<F>(m)) return miss_hit<F>();
  const F gamma = dot(r.d, m2) / M;                     // 2+- 3* 1/
  m = m & (gamma >= F(0)) & (gamma <= F(1));            // 2 cmp
  if (none_of<F>(m)) return miss_hit<F>();
  const F beta = dot(ae, m1) / M;                       // 2+- 3* 1/
  m = m & (beta >= F(0)) & (beta <= F(1) - gamma);      // 1+- 2 cmp
  return make_hit<F>(m, t, beta, gamma);                // 1 select
}

// Normal: triangle_normal(Triangle) in kernels/triangle.hpp (e1 x e2).

}  // namespace rb
