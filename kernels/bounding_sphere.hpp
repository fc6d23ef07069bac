// The bounding-sphere clip shared by the solver kernels (torus, algebraic, implicit surfaces,
// surfaces of revolution): the part of the ray inside a sphere of radius^2 R2 (R2 = -inf: a
// primitive no ray hits), as a raw Roots<F, 2> span clipped to [tmin, tmax].
//
// Formulation (accuracy): with q = o - c and m = d . d the roots of |q + t d|^2 = R2 are
//   t = (-(q . d) +- sqrt(disc)) / m,   disc = m R2 - |q x d|^2   (= (q.d)^2 - m (q.q - R2)).
// Two things matter far from the sphere (|q| >> R):
//   - m is formed, not assumed 1: a float-rounded unit direction has |d|^2 - 1 up to ~1e-7, and
//     the textbook disc = (q.d)^2 - (q.q - R2) then carries an error of (|d|^2 - 1) |q|^2, which at
//     |q| = 500 R is a sizeable fraction of R2: the clip moves by a fraction of R and cuts off
//     roots near the sphere (the torus touches its bounding sphere all along the outer equator);
//   - |q x d|^2 is the squared distance of the line from the centre (times m), formed without
//     subtracting two numbers of the size of |q|^2, so rounding stays relative to the sphere,
//     not to the distance (the idea of Hearn and Baker's geometric sphere test).
// Operations: 6* 3+- (q x d), 3* 2+- (its square), 3* 2+- (m), 1* 1+- (disc), 1 cmp: the
// negative case ends here, without a division. Then 3* 2+- (q . d), 1/, 2*, 1 sqrt, 2+-,
// 2 minmax, 1 cmp. The caller forms q (3+-).
#pragma once

#include "core/ray.hpp"
#include "core/roots.hpp"

namespace rb {

template <class F>
RB_INLINE Roots<F, 2> bounding_sphere_span(const Ray<F>& r, const Vec3<F>& q, const F& R2) {
  const Vec3<F> qxd = cross(q, r.d);
  const F m = dot(r.d, r.d);
  const F disc = m * R2 - dot(qxd, qxd);
  const mask_t<F> in = disc >= F(0);
  if (none_of<F>(in)) return Roots<F, 2>::none();
  const F inv_m = F(1) / m;
  const F tc = -dot(q, r.d) * inv_m, h = vsqrt(disc) * inv_m;
  const F t0 = vmax(r.tmin, tc - h), t1 = vmin(r.tmax, tc + h);
  return Roots<F, 2>::span(in & (t0 <= t1), t0, t1);
}

}  // namespace rb
