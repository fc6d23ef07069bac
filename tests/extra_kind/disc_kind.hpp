// A primitive kind that exists only in a test: flat discs (a centre, a unit normal, a radius),
// added the way an engine kind is, to show what that takes (docs/DESIGN.md, "Adding a primitive
// kind"). The tracer's sources are compiled a second time with it in the kind list
// (tests/extra_kind/CMakeLists.txt); tests/extra_kind/test_disc_kind.cpp traces, plans and shades it.
//
// The steps, as an engine kind takes them:
//   1. its kernel: a template over the number type (float, double, their SIMD batches, Counted):
//      intersect_disc below, where an engine kind's lives in kernels/;
//   2. its kind struct: which primitives, their boxes and sizes, how one is stored, its methods
//      with their plan evidence, its surface (DiscKind below; an engine kind's in tracer/kinds/);
//   3. its line in the kind table (tracer/kinds.hpp: RB_KIND_TABLE; here tests/extra_kind/disc_line.hpp);
//   4. its scene array and the loaders that fill it (scene/scene.hpp). A test cannot add a member
//      to scene::Scene: the discs of a scene live in a table beside it (discs_of below).
// Not needed to trace: its Embree mapping (bench/embree_trace.cpp) and its lab reference
// (accuracy/kind_reference.hpp), which the report and the accuracy lab need of an engine kind.
// Included by tracer/kinds.hpp after the engine's kinds.
#pragma once

#include <map>
#include <vector>

namespace rb {

// ---- 1. the kernel -----------------------------------------------------------------------------
template <class F>
struct Disc {
  Vec3<F> c, n;  // centre, unit normal
  F r2;          // radius squared
  auto fields() { return std::tie(c.x, c.y, c.z, n.x, n.y, n.z, r2); }
  static Disc never() { return {{F(0), F(0), F(0)}, {F(0), F(0), F(0)}, F(-1)}; }  // n = 0: parallel to every ray
};

// The plane through c with normal n at t = n . (c - o) / (n . d), then |p - c|^2 <= r^2.
template <class F>
RB_INLINE Hit<F> intersect_disc(const Ray<F>& r, const Disc<F>& q) {
  const F den = dot(q.n, r.d);
  mask_t<F> m = den != F(0);
  if (none_of<F>(m)) return miss_hit<F>();
  const F t = dot(q.n, q.c - r.o) / den;
  const Vec3<F> p = r.o + r.d * t - q.c;
  m = m & (t >= r.tmin) & (t <= r.tmax) & (dot(p, p) <= q.r2);
  return make_hit<F>(m, t);
}

namespace kinds {

// ---- 4. the scene's discs (an engine kind: an array of scene::Scene) ---------------------------
struct DiscIn {
  Vec3d c, n;  // n: any length but 0
  double r = 0;
  std::uint32_t mat = 0;
};
inline std::map<const Scene*, std::vector<DiscIn>>& disc_table() {
  static std::map<const Scene*, std::vector<DiscIn>> t;
  return t;
}
inline const std::vector<DiscIn>& discs_of(const Scene& s) {
  static const std::vector<DiscIn> none;
  const auto it = disc_table().find(&s);
  return it == disc_table().end() ? none : it->second;
}

// ---- 2. the kind -------------------------------------------------------------------------------
struct DiscKind {
  static constexpr Kind id = Kind::disc;
  static constexpr const char* name = "disc";
  static constexpr bool custom = false;

  static std::size_t count(const Scene& s) { return discs_of(s).size(); }
  template <class Fn>
  static void each(const Scene& s, Fn&& f) {
    for (std::size_t i = 0; i < count(s); ++i) f(std::uint32_t(i));
  }
  static std::uint32_t material(const Scene& s, std::uint32_t i) { return discs_of(s)[i].mat; }
  static Vec3d unit_normal(const DiscIn& d) { return detail::unit_d(d.n); }
  // The box of the circle: on axis k the rim reaches r sqrt(1 - n_k^2) from the centre.
  static Bounds bounds(const Scene& s, std::uint32_t i) {
    const DiscIn& d = discs_of(s)[i];
    Bounds b;
    const Vec3d n = unit_normal(d);
    if (!(d.r > 0) || !std::isfinite(d.r) || !(dot(n, n) > 0.5)) return b;
    const Vec3d e{d.r * std::sqrt(std::max(0.0, 1 - n.x * n.x)), d.r * std::sqrt(std::max(0.0, 1 - n.y * n.y)),
                  d.r * std::sqrt(std::max(0.0, 1 - n.z * n.z))};
    b.grow(d.c - e);
    b.grow(d.c + e);
    return b;
  }
  static Feature feature(const Scene& s, std::uint32_t i) {
    const DiscIn& d = discs_of(s)[i];
    return {d.c, d.r > 0 ? d.r : 0.0, d.r > 0 ? 2 * d.r : 0.0};
  }

  template <class S>
  using Prim = Disc<S>;
  template <class S>
  static Prim<S> make(const Scene& s, std::uint32_t i, const Vec3d& origin, std::string* why = nullptr) {
    static_assert(std::is_same_v<S, float>, "discs are stored in float");
    const DiscIn& d = discs_of(s)[i];
    const Vec3d n = unit_normal(d), c = d.c - origin;
    if (!finite3(c) || !(dot(n, n) > 0.5)) return never_because<Prim<S>>(why, "disc: centre not finite or normal zero");
    if (!(d.r > 0) || !std::isfinite(d.r)) return never_because<Prim<S>>(why, "disc: radius not positive and finite");
    return {to_float(c), to_float(n), float(d.r * d.r)};
  }
  template <class F>
  struct Pre {};
  template <class F>
  static RB_INLINE Pre<F> pre(const Ray<F>&) { return {}; }
  static constexpr std::array<MethodInfo, 1> methods{{
      {"plane_radius", "the plane's t, then the distance from the centre against the radius", true, false},
  }};
  // No lab cases (a test kind): every option covers every scene, so the plan takes the first,
  // the method in float, and says where its evidence would go.
  static constexpr std::array<PlanOption, 2> plan{{
      {0, false, kAny, kAny, kAny, "", "a test kind: the disc test in float, no lab cases"},
      {0, true, kAny, kAny, kAny, "", "a test kind: the disc test in double, no lab cases"},
  }};
  template <int M, class F>
  static RB_INLINE Hit<F> hit(const Ray<F>& r, const Pre<F>&, const Prim<F>& p) {
    return intersect_disc(r, p);
  }

  static Surface surface(const HitQuery& q, std::uint32_t i) {
    const DiscIn& d = discs_of(*q.scene).at(i);
    const Vec3d n = unit_normal(d);
    Surface h;
    h.p = detail::onto_plane(q.p, n, d.c);
    h.ng = h.ns = to_float(n);
    h.mat = d.mat;
    return h;
  }
};

}  // namespace kinds
}  // namespace rb
