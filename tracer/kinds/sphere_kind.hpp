// Spheres (Scene::spheres: NFF `s`, JSON spheres without a transform).
#pragma once

#include "kernels/sphere.hpp"

namespace rb::kinds {

struct SphereKind {
  static constexpr Kind id = Kind::sphere;
  static constexpr const char* name = "sphere";
  static constexpr bool custom = false;

  static std::size_t count(const Scene& s) { return s.spheres.size(); }
  template <class Fn>
  static void each(const Scene& s, Fn&& f) {
    for (std::size_t i = 0; i < s.spheres.size(); ++i) f(std::uint32_t(i));
  }
  static std::uint32_t material(const Scene& s, std::uint32_t i) { return s.spheres[i].mat; }
  static Bounds bounds(const Scene& s, std::uint32_t i) {
    const auto& sp = s.spheres[i];
    Bounds b;
    if (!(sp.r > 0) || !std::isfinite(sp.r)) return b;
    b.grow(sp.c - Vec3d{sp.r, sp.r, sp.r});
    b.grow(sp.c + Vec3d{sp.r, sp.r, sp.r});
    return b;
  }
  static Feature feature(const Scene& s, std::uint32_t i) {
    const auto& sp = s.spheres[i];
    return {sp.c, sp.r > 0 ? sp.r : 0.0, sp.r > 0 ? 2 * sp.r : 0.0};
  }

  template <class S>
  using Prim = Sphere<S>;
  template <class S>
  static Prim<S> make(const Scene& s, std::uint32_t i, const Vec3d& origin, std::string* why = nullptr) {
    const auto& sp = s.spheres[i];
    if constexpr (std::is_same_v<S, float>) {
      return make_sphere(sp.c - origin, sp.r, why);
    } else {
      const Vec3d c = sp.c - origin;
      if (!finite3(c)) return never_because<Prim<S>>(why, "sphere: centre is not finite");
      if (!(sp.r > 0) || !std::isfinite(sp.r * sp.r)) return never_because<Prim<S>>(why, "sphere: radius is not positive and finite");
      return {c, sp.r * sp.r, 1.0 / sp.r};
    }
  }
  template <class F>
  struct Pre {};
  template <class F>
  static RB_INLINE Pre<F> pre(const Ray<F>&) { return {}; }
  static constexpr std::array<MethodInfo, 3> methods{{
      {"geometric", "the lecture's geometric solution: closest approach t0 = v . d, then D^2 and tD^2", true, true},
      {"hearn_baker", "Hearn and Baker's form: the discriminant from the offset f - (f . d) d, accurate for a small sphere far away", true, true},
      {"compensated", "error-free transformations (two-sum, two-product) for b and c: right at planet scale", true, true},
  }};
  // The lab's evidence per option (PlanOption in tracer/kinds.hpp), cheapest first. "above_1eK": a
  // viewer 1..10 above a sphere of radius 10^K looking every way (the scale ratio of a sphere 10^K
  // times the objects near it); "far_small_1eK": seen from 10^K radii. Float passes both up to 1e5
  // with the geometric test only up to 1e2 radii away; grazing rays from a viewer on a planet need
  // the compensated form or double.
  static constexpr std::array<PlanOption, 5> plan{{
      {0, false, 1e2, 5e4, kAny,
       "sphere/far_small_1e1 sphere/far_small_1e2 sphere/tangent sphere/above_1e2 sphere/above_1e3 sphere/above_1e4 sphere/above_1e5",
       "the lecture's geometric test is right while spheres are seen from at most 100 radii"},
      {1, false, 1e5, 5e4, kAny,
       "sphere/far_small_1e1 sphere/far_small_1e3 sphere/far_small_1e4 sphere/far_small_1e5 sphere/tangent sphere/above_1e2 "
       "sphere/above_1e3 sphere/above_1e4 sphere/above_1e5",
       "Hearn and Baker's form keeps a small sphere right up to 1e5 radii away"},
      {2, false, 1e5, kAny, kAny,
       "sphere/far_small_1e5 sphere/tangent sphere/above_1e5 sphere/above_1e6 sphere/planet_pole sphere/planet_45",
       "the compensated form is right on a planet (grazing rays from 1..100 above a sphere of radius 6.4e6) and from 1e5 radii"},
      {0, true, 1e5, kAny, kAny, "sphere/far_small_1e5 sphere/tangent sphere/above_1e6 sphere/planet_pole sphere/planet_45",
       "the geometric test in double is right on a planet and from 1e5 radii"},
      {2, true, 1e7, kAny, kAny, "sphere/far_small_1e5 sphere/far_small_1e7 sphere/planet_pole sphere/planet_45",
       "the compensated form in double is right from 1e7 radii"},
  }};
  // Stored apart: a ray's cost against the kind in the frame (StorageCost in tracer/kinds.hpp).
  static constexpr StorageCost storage{1.15, 1.30, "storage/sphere", "Intel Xeon family 6 model 207, release build, one thread"};
  template <int M, class F>
  static RB_INLINE Hit<F> hit(const Ray<F>& r, const Pre<F>&, const Prim<F>& p) {
    if constexpr (M == 0) return intersect_sphere_geometric(r, p);
    else if constexpr (M == 1) return intersect_sphere_hearn_baker(r, p);
    else return intersect_sphere_compensated(r, p);
  }

  static std::size_t input_bytes(const Scene& s) { return s.spheres.size() * sizeof(scene::SphereIn); }

  static Surface surface(const HitQuery& q, std::uint32_t i) {
    const auto& sp = q.scene->spheres.at(i);
    Surface h;
    // The radial direction normalised once: the point projected onto the sphere along it, and the
    // normal (detail::unit_d and unit_or of the same vector, without a second square root).
    const Vec3d v = q.p - sp.c;
    const double l = std::sqrt(dot(v, v));
    const bool unit = l > 0.0 && std::isfinite(l);
    const Vec3d n = unit ? v * (1.0 / l) : v;
    h.p = dot(n, n) > 0 ? sp.c + n * sp.r : q.p;
    h.ng = h.ns = unit ? to_float(n) : -q.ray.d;
    h.mat = sp.mat;
    return h;
  }
};

}  // namespace rb::kinds
