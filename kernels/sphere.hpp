// Ray x sphere.
//   geometric (seed 000 "Sphere (geometric solution)"): v = C - P0, t0 = v . p1,
//     D^2 = v . v - t0^2, tD^2 = R^2 - D^2; miss if tD^2 < 0, else t = t0 -+ tD.
//     lecture: negative case 9+- 6* 1<, positive additionally 2+- 1 sqrt. Needs |p1| = 1.
//   algebraic (seed 002 "Ray-Sphere Intersection"): A = d . d, B = 2 d . (e - c),
//     C = (e - c) . (e - c) - R^2, disc = B^2 - 4AC, t = (-B -+ sqrt(disc)) / 2A.
// Both return the nearer root in [tmin, tmax] (the far one when the near one is before tmin).
#pragma once

#include "core/ray.hpp"

namespace rb {

template <class F>
struct Sphere {
  Vec3<F> c;
  F r2, inv_r;
  auto fields() { return std::tie(c.x, c.y, c.z, r2, inv_r); }
  // R^2 = -inf: tD^2 = -inf (geometric) and disc = -inf (algebraic) for every ray.
  static Sphere never() { return {{F(0), F(0), F(0)}, F(-kInf<F>), F(0)}; }
};

// Zero, negative or non-finite radius, or a non-finite centre: Sphere::never().
template <class T>
inline Sphere<float> make_sphere(Vec3<T> c, T r) {
  if (!finite3(c) || !std::isfinite(r) || !(r > T(0))) return Sphere<float>::never();
  const double rd = double(r);
  if (!std::isfinite(float(rd * rd)) || float(rd * rd) == 0.f) return Sphere<float>::never();
  return {to_float(to_double(c)), float(rd * rd), float(1.0 / rd)};
}

template <class F>
RB_INLINE Hit<F> intersect_sphere_geometric(const Ray<F>& r, const Sphere<F>& s) {
  const Vec3<F> v = s.c - r.o;                  // 3+-
  const F t0 = dot(v, r.d);                     // 2+- 3*
  const F D2 = dot(v, v) - t0 * t0;             // 3+- 4*
  const F tD2 = s.r2 - D2;                      // 1+-
  mask_t<F> m = tD2 >= F(0);                    // 1 cmp   (negative case ends here)
  if (none_of<F>(m)) return miss_hit<F>();
  const F tD = vsqrt(tD2);                      // 1 sqrt
  const F t1 = t0 - tD, t2 = t0 + tD;           // 2+-
  const F t = vselect(t1 >= r.tmin, t1, t2);    // 1 cmp 1 select
  m = m & (t >= r.tmin) & (t <= r.tmax);        // 2 cmp
  return make_hit<F>(m, t);                     // 1 select
}

template <class F>
RB_INLINE Hit<F> intersect_sphere_algebraic(const Ray<F>& r, const Sphere<F>& s) {
  const Vec3<F> oc = r.o - s.c;                 // 3+-
  const F A = dot(r.d, r.d);                    // 2+- 3*
  const F B = F(2) * dot(r.d, oc);              // 2+- 4*
  const F C = dot(oc, oc) - s.r2;               // 3+- 3*
  const F disc = B * B - F(4) * A * C;          // 1+- 3*
  mask_t<F> m = disc >= F(0);                   // 1 cmp
  if (none_of<F>(m)) return miss_hit<F>();
  const F sq = vsqrt(disc);                     // 1 sqrt
  const F twoA = F(2) * A;                      // 1*
  const F t1 = (-B - sq) / twoA;                // 1+- 1/
  const F t2 = (-B + sq) / twoA;                // 1+- 1/
  const F t = vselect(t1 >= r.tmin, t1, t2);    // 1 cmp 1 select
  m = m & (t >= r.tmin) & (t <= r.tmax);        // 2 cmp
  return make_hit<F>(m, t);                     // 1 select
}

// Outward unit normal at a point on the sphere: (P - C) / R.  3+- 3*
template <class F>
RB_INLINE Vec3<F> sphere_normal(const Sphere<F>& s, const Vec3<F>& p) { return (p - s.c) * s.inv_r; }

}  // namespace rb
