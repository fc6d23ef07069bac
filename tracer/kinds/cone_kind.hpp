// Cones: NFF `c` shells with different radii (a frustum of the unit cone placed by an affine map,
// open: no caps).
#pragma once

#include "tracer/kinds/cylinder_kind.hpp"

namespace rb::kinds {

struct ConeKind {
  static constexpr Kind id = Kind::cone;
  static constexpr const char* name = "cone";
  static constexpr bool custom = false;

  static std::size_t count(const Scene& s) { return s.cones.size() - CylinderKind::count(s); }
  template <class Fn>
  static void each(const Scene& s, Fn&& f) {
    for (std::size_t i = 0; i < s.cones.size(); ++i)
      if (!CylinderKind::is_cylinder(s.cones[i])) f(std::uint32_t(i));
  }
  static std::uint32_t material(const Scene& s, std::uint32_t i) { return s.cones[i].mat; }
  static Bounds bounds(const Scene& s, std::uint32_t i) { return detail::shell_bounds(s.cones[i]); }
  static Feature feature(const Scene& s, std::uint32_t i) { return detail::shell_feature(s.cones[i]); }

  template <class S>
  using Prim = Transformed<Cone>::T<S>;
  template <class S>
  static Prim<S> make(const Scene& s, std::uint32_t i, const Vec3d& origin, std::string* why = nullptr) {
    static_assert(std::is_same_v<S, float>, "cones are stored in float");
    const auto& c = s.cones[i];
    return place_cone(c.base - origin, std::fabs(c.base_r), c.apex - origin, std::fabs(c.apex_r), why);
  }
  template <class F>
  struct Pre {};
  template <class F>
  static RB_INLINE Pre<F> pre(const Ray<F>&) { return {}; }
  static constexpr std::array<MethodInfo, 2> methods{{
      {"transformed", "the unit cone x^2 + y^2 = z^2 cut to the frustum in its own frame, the ray transformed into it (seed 000)", true,
       false},
      {"recentred", "the same with the ray's origin first moved along it to the frustum: right from far away in float", true, false},
  }};
  // The lab's evidence per option (PlanOption in tracer/kinds.hpp), cheapest first: NFF frusta seen
  // from 10^K radii.
  static constexpr std::array<PlanOption, 3> plan{{
      {0, false, 1e1, kAny, kAny, "quadric/shell_cone_far_1e1", "a placed cone frustum in float is right while seen from at most 10 radii"},
      {1, false, 1e5, kAny, kAny,
       "quadric/shell_cone_far_1e1 quadric/shell_cone_far_1e2 quadric/shell_cone_far_1e3 quadric/shell_cone_far_1e4 "
       "quadric/shell_cone_far_1e5",
       "the ray re-centred on the frustum before the transform keeps it right up to 1e5 radii away in float"},
      {1, true, kAny, kAny, kAny, "quadric/shell_cone_far_1e5", "re-centred, in double"},
  }};
  template <int M, class F>
  static RB_INLINE Hit<F> hit(const Ray<F>& r, const Pre<F>&, const Prim<F>& p) {
    auto k = [](const Ray<F>& l, const Cone<F>& c) { return intersect_cone(l, c); };
    if constexpr (M == 0) return intersect_transformed(r, p, k);
    else return intersect_transformed_recentred(r, p, Vec3<F>{F(0), F(0), F(0.5) * (p.prim.z0 + p.prim.z1)}, k);
  }
  static std::size_t input_bytes(const Scene& s) { return count(s) * sizeof(scene::ConeIn); }
  static Surface surface(const HitQuery& q, std::uint32_t i) { return detail::shell_surface(q, q.scene->cones.at(i)); }
};

}  // namespace rb::kinds
