// Tori (Scene::tori: JSON "torus" without a transform): a ring of radius R about the centre and
// the axis, swept by a tube of radius r < R.
#pragma once

#include "kernels/torus.hpp"

namespace rb::kinds {

struct TorusKind {
  static constexpr Kind id = Kind::torus;
  static constexpr const char* name = "torus";
  static constexpr bool custom = false;

  static std::size_t count(const Scene& s) { return s.tori.size(); }
  template <class Fn>
  static void each(const Scene& s, Fn&& f) {
    for (std::size_t i = 0; i < s.tori.size(); ++i) f(std::uint32_t(i));
  }
  static std::uint32_t material(const Scene& s, std::uint32_t i) { return s.tori[i].mat; }
  static Vec3d unit_axis(const scene::TorusIn& t) {
    const double l = std::sqrt(dot(t.axis, t.axis));
    return l > 0 ? t.axis * (1.0 / l) : Vec3d{0, 0, 1};
  }
  static Bounds bounds(const Scene& s, std::uint32_t i) {
    const auto& t = s.tori[i];
    Bounds b;
    if (!(t.r > 0) || !(t.R > t.r) || !std::isfinite(t.R)) return b;
    const Vec3d u = unit_axis(t);
    const Vec3d e{t.R * std::sqrt(std::max(0.0, 1 - u.x * u.x)) + t.r, t.R * std::sqrt(std::max(0.0, 1 - u.y * u.y)) + t.r,
                  t.R * std::sqrt(std::max(0.0, 1 - u.z * u.z)) + t.r};
    b.grow(t.c - e);
    b.grow(t.c + e);
    return b;
  }
  static Feature feature(const Scene& s, std::uint32_t i) {
    const auto& t = s.tori[i];
    return {t.c, t.r > 0 ? t.r : 0.0, t.r > 0 ? 2 * (t.R + t.r) : 0.0};
  }

  template <class S>
  using Prim = Torus<S>;
  template <class S>
  static Prim<S> make(const Scene& s, std::uint32_t i, const Vec3d& origin, std::string* why = nullptr) {
    static_assert(std::is_same_v<S, float>, "tori are stored in float");
    const auto& t = s.tori[i];
    return make_torus(t.c - origin, t.axis, t.R, t.r, Vec3d{1, 0, 0}, why);
  }
  template <class F>
  struct Pre {};
  template <class F>
  static RB_INLINE Pre<F> pre(const Ray<F>&) { return {}; }
  static constexpr std::array<MethodInfo, 2> methods{{
      {"ferrari", "the quartic in t solved in closed form (Ferrari's resolvent cubic)", true, false},
      {"robust", "the quartic re-centred at the closest approach, roots isolated and polished", true, false},
  }};
  // The lab's evidence per option (PlanOption in tracer/kinds.hpp), cheapest first. far is over the
  // tube radius r, aspect = 2 (R + r) / r (10 for R = 4 r; 202 for R = 100 r). Ferrari's closed form
  // is never chosen: in float it misses rays at 5 sizes already, and in double its figures change
  // with the build's contraction (it passes the lab's cases in the release build and fails them
  // without FMA contraction).
  static constexpr std::array<PlanOption, 2> plan{{
      {1, false, 2.5e3, kAny, 10, "torus/camera_5x torus/camera_50x torus/camera_500x torus/along_axis",
       "the robust isolation in float is right up to 500 torus sizes away (2500 tube radii)"},
      {1, true, 5.05e4, kAny, 202, "torus/camera_500x torus/thin_tube torus/thin_500x torus/along_axis",
       "the robust isolation in double is right on a tube 100 times thinner than its ring, seen from 500 sizes"},
  }};
  template <int M, class F>
  static RB_INLINE Hit<F> hit(const Ray<F>& r, const Pre<F>&, const Prim<F>& p) {
    if constexpr (M == 0) return intersect_torus_ferrari(r, p);
    else return intersect_torus_robust(r, p);
  }
  static std::size_t input_bytes(const Scene& s) { return s.tori.size() * sizeof(scene::TorusIn); }

  static Surface surface(const HitQuery& q, std::uint32_t i) {
    const auto& t = q.scene->tori.at(i);
    const Vec3d w = unit_axis(t);
    const Vec3d rel = q.p - t.c;
    const Vec3d radial = rel - w * dot(rel, w);
    const double rl = std::sqrt(dot(radial, radial));
    const Vec3d ring = rl > 0 ? t.c + radial * (t.R / rl) : t.c;  // the tube's centre nearest to p
    Surface h;
    // The tube's radial direction normalised once (as the sphere's).
    const Vec3d v = q.p - ring;
    const double l = std::sqrt(dot(v, v));
    const bool unit = l > 0.0 && std::isfinite(l);
    const Vec3d n = unit ? v * (1.0 / l) : v;
    h.p = rl > 0 && dot(n, n) > 0 ? ring + n * t.r : q.p;
    h.ng = h.ns = unit ? to_float(n) : -q.ray.d;
    h.mat = t.mat;
    return h;
  }
};

}  // namespace rb::kinds
