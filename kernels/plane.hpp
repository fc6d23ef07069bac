// Ray x plane (seed 000 "Plane", seed 004 "Ray/Plane Intersection").
//   plane: n . X + D = 0;  t = -(n . P0 + D) / (n . p1)
//   lecture: negative case 2+- 3*, positive 5+- 6* 1/, point [x,y,z] 3+- 3*.
// Two-sided: a miss only when the ray is parallel (n . p1 == 0) or t leaves [tmin, tmax].
#pragma once

#include "core/ray.hpp"
#include "core/why.hpp"

namespace rb {

template <class F>
struct Plane {
  Vec3<F> n;
  F D;
  auto fields() { return std::tie(n.x, n.y, n.z, D); }
  static Plane never() { return {{F(0), F(0), F(0)}, F(0)}; }  // n = 0: parallel to every ray
};

// From a point on the plane and a normal (normalised in double). A zero or non-finite normal or
// point gives Plane::never() (the reason in *why).
template <class T>
inline Plane<float> make_plane(Vec3<T> point, Vec3<T> normal, std::string* why = nullptr) {
  const Vec3d n = to_double(normal), p = to_double(point);
  const double len = std::sqrt(dot(n, n));
  if (!finite3(p)) return never_because<Plane<float>>(why, "plane: point is not finite");
  if (!finite3(n) || !std::isfinite(len) || len == 0.0) return never_because<Plane<float>>(why, "plane: normal is zero or not finite");
  const Vec3d u = n * (1.0 / len);
  return {to_float(u), float(-dot(u, p))};
}

template <class F>
RB_INLINE Hit<F> intersect_plane(const Ray<F>& r, const Plane<F>& p) {
  const F den = dot(p.n, r.d);                  // 2+- 3*   (the whole negative case)
  mask_t<F> m = den != F(0);                    // 1 cmp
  if (none_of<F>(m)) return miss_hit<F>();
  const F t = -(dot(p.n, r.o) + p.D) / den;     // 3+- 3* 1/
  m = m & (t >= r.tmin) & (t <= r.tmax);        // 2 cmp
  return make_hit<F>(m, t);                     // 1 select
}

template <class F>
RB_INLINE Vec3<F> plane_normal(const Plane<F>& p) { return p.n; }

}  // namespace rb
