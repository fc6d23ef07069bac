// Cylinders: NFF `c` shells with equal radii (Scene::cones whose base and apex radius agree), open
// (no caps), each a unit cylinder placed by an affine map (seed 000's transformed instances).
#pragma once

#include "kernels/cylinder_cone.hpp"

namespace rb::kinds {

namespace detail {
// Box of a disc (centre c, unit normal n, radius r): extent r sqrt(1 - n_i^2) per axis.
inline void grow_disc(Bounds& b, const Vec3d& c, const Vec3d& n, double r) {
  const Vec3d e{r * std::sqrt(std::max(0.0, 1 - n.x * n.x)), r * std::sqrt(std::max(0.0, 1 - n.y * n.y)),
                r * std::sqrt(std::max(0.0, 1 - n.z * n.z))};
  b.grow(c - e);
  b.grow(c + e);
}
// An NFF shell's box: the two end discs.
inline Bounds shell_bounds(const scene::ConeIn& c) {
  Bounds b;
  const Vec3d w = c.apex - c.base;
  const double len = std::sqrt(dot(w, w));
  if (!(len > 0) || !std::isfinite(len)) return b;
  const Vec3d n = w * (1.0 / len);
  grow_disc(b, c.base, n, std::fabs(c.base_r));
  grow_disc(b, c.apex, n, std::fabs(c.apex_r));
  return b;
}
inline Feature shell_feature(const scene::ConeIn& c) {
  const Vec3d w = c.apex - c.base;
  const double len = std::sqrt(dot(w, w));
  const double r0 = std::fabs(c.base_r), r1 = std::fabs(c.apex_r);
  const double rmin = r0 > 0 && r1 > 0 ? std::min(r0, r1) : std::max(r0, r1);
  return {(c.base + c.apex) * 0.5, std::min(rmin, len), std::max({2 * r0, 2 * r1, len})};
}

inline Surface shell_surface(const HitQuery& q, const scene::ConeIn& c) {
  const Vec3d axis = c.apex - c.base;
  const double len = std::sqrt(dot(axis, axis));
  const Vec3d a = len > 0 ? axis * (1.0 / len) : Vec3d{0, 1, 0};
  const Vec3d rel = q.p - c.base;
  const Vec3d rq = rel - a * dot(rel, a);
  const double ql = std::sqrt(dot(rq, rq));
  const Vec3d radial = ql > 0 ? rq * (1.0 / ql) : Vec3d{0, 0, 0};
  const double r0 = std::fabs(c.base_r), r1 = std::fabs(c.apex_r);
  Vec3f n = unit_or(radial - a * (len > 0 ? (r1 - r0) / len : 0.0), -q.ray.d);
  if (c.base_r < 0 || c.apex_r < 0) n = -n;
  Surface h;
  // Onto the shell: the radius at the point's height along the axis, in the same radial direction.
  const double s = dot(rel, a), rs = r0 + (len > 0 ? (r1 - r0) * s / len : 0.0);
  h.p = ql > 0 ? c.base + a * s + radial * rs : q.p;
  h.ng = h.ns = n;
  h.mat = c.mat;
  return h;
}
}  // namespace detail

struct CylinderKind {
  static constexpr Kind id = Kind::cylinder;
  static constexpr const char* name = "cylinder";
  static constexpr bool custom = false;

  static bool is_cylinder(const scene::ConeIn& c) { return c.base_r == c.apex_r; }
  static std::size_t count(const Scene& s) {
    std::size_t n = 0;
    for (const auto& c : s.cones) n += is_cylinder(c);
    return n;
  }
  template <class Fn>
  static void each(const Scene& s, Fn&& f) {
    for (std::size_t i = 0; i < s.cones.size(); ++i)
      if (is_cylinder(s.cones[i])) f(std::uint32_t(i));
  }
  static std::uint32_t material(const Scene& s, std::uint32_t i) { return s.cones[i].mat; }
  static Bounds bounds(const Scene& s, std::uint32_t i) { return detail::shell_bounds(s.cones[i]); }
  static Feature feature(const Scene& s, std::uint32_t i) { return detail::shell_feature(s.cones[i]); }

  template <class S>
  using Prim = Transformed<Cylinder>::T<S>;
  // The placement is composed in double relative to the frame origin and rounded once.
  template <class S>
  static Prim<S> make(const Scene& s, std::uint32_t i, const Vec3d& origin, std::string* why = nullptr) {
    static_assert(std::is_same_v<S, float>, "cylinders are stored in float");
    const auto& c = s.cones[i];
    return place_cylinder(c.base - origin, c.apex - origin, std::fabs(c.base_r), why);
  }
  template <class F>
  struct Pre {};
  template <class F>
  static RB_INLINE Pre<F> pre(const Ray<F>&) { return {}; }
  static constexpr std::array<MethodInfo, 2> methods{{
      {"transformed", "the cylinder x^2 + y^2 = r^2 in its own frame, the ray transformed into it (seed 000)", true, false},
      {"recentred", "the same with the ray's origin first moved along it to the shell: right from far away in float", true, false},
  }};
  // The lab's evidence per option (PlanOption in tracer/kinds.hpp), cheapest first: NFF shells seen
  // from 10^K radii.
  static constexpr std::array<PlanOption, 3> plan{{
      {0, false, 1e1, kAny, kAny, "quadric/shell_cyl_far_1e1", "a placed cylinder in float is right while seen from at most 10 radii"},
      {1, false, 1e5, kAny, kAny,
       "quadric/shell_cyl_far_1e1 quadric/shell_cyl_far_1e2 quadric/shell_cyl_far_1e3 quadric/shell_cyl_far_1e4 quadric/shell_cyl_far_1e5",
       "the ray re-centred on the shell before the transform keeps it right up to 1e5 radii away in float"},
      {1, true, kAny, kAny, kAny, "quadric/shell_cyl_far_1e5", "re-centred, in double"},
  }};
  template <int M, class F>
  static RB_INLINE Hit<F> hit(const Ray<F>& r, const Pre<F>&, const Prim<F>& p) {
    auto k = [](const Ray<F>& l, const Cylinder<F>& c) { return intersect_cylinder(l, c); };
    if constexpr (M == 0) return intersect_transformed(r, p, k);
    else return intersect_transformed_recentred(r, p, Vec3<F>{p.prim.cx, p.prim.cy, F(0.5) * (p.prim.z0 + p.prim.z1)}, k);
  }
  static std::size_t input_bytes(const Scene& s) { return count(s) * sizeof(scene::ConeIn); }
  static Surface surface(const HitQuery& q, std::uint32_t i) { return detail::shell_surface(q, q.scene->cones.at(i)); }
};

}  // namespace rb::kinds
