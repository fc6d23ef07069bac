// Ray x convex polyhedron (seed 000 "Convex polyhedron"): the intersection of K halfspaces
// n_i . X + D_i <= 0 (outward normals). t_in, t_out start at the ray's interval (the slide's
// 0 and infinity are tmin and tmax of a default ray); per plane, with den = n . p1 and
// s = n . P0 + D (the signed distance of the origin):
//   den < 0 (entering):  t_in  = max(t_in,  -s / den)
//   den > 0 (leaving):   t_out = min(t_out, -s / den)
//   den == 0 (parallel): the ray is outside for good when s > 0
// and the early exit when t_in > t_out (per plane, when every lane is out: the slide's early exit).
// Per plane: 5+- 6* 1/, 5 cmp, 2 select, 2 min/max. Returns the first surface crossing in
// [tmin, tmax], as every closed primitive does: t_in, or t_out when the origin is inside (t_in and
// t_out start from the whole line, -inf and +inf, and the choice costs 3 cmp 1 select).
//
// Special cases using parallelism (the slide's "e.g. cuboid"): SlabsK, K pairs of parallel planes
// sharing one normal (n, D_lo, D_hi): per pair the parallel-planes cost (kernels/parallel_planes.hpp)
// 5+- 6* 1/ + 1+- 1/, then min/max of the two t as in the slab test. An axis-aligned box is three
// axis slabs (make_box_slabs) or six halfspaces (make_box_halfspaces); tests check both agree
// with kernels/box.hpp.
// CSG: polyhedron_roots / slabs_roots return the entry and exit along the whole line as Roots<F,2>.
// Plain per-primitive data (PrimSoA), so rays in lanes and primitives in lanes both apply.
#pragma once

#include "core/ray.hpp"
#include "core/why.hpp"
#include "core/roots.hpp"

#include <array>
#include <stdexcept>
#include <utility>
#include <vector>

namespace rb {

// ---- K halfspaces ----------------------------------------------------------------------------
template <class F, int K>
struct HalfspacesK {
  static constexpr int kPlanes = K;
  Vec3<F> n[K];
  F D[K];
  auto fields() {
    return [this]<std::size_t... I>(std::index_sequence<I...>) {
      return std::tuple_cat(std::tie(n[I].x, n[I].y, n[I].z)..., std::tie(D[I]...));
    }(std::make_index_sequence<K>{});
  }
  // Slot 0: 0 . X + 1 <= 0 fails everywhere (parallel and outside for every ray); others unused.
  static HalfspacesK never() {
    HalfspacesK h;
    for (int i = 0; i < K; ++i) { h.n[i] = {F(0), F(0), F(0)}; h.D[i] = F(-1); }
    h.D[0] = F(1);
    return h;
  }
};
template <class F>
using Halfspaces8 = HalfspacesK<F, 8>;

// A halfspace n . X + D <= 0 given by an outward normal and a point on its plane.
struct HalfspaceIn {
  Vec3f normal, point;
};

// Normals are normalised in double. Unused slots: n = 0, D = -1 (always inside, no constraint).
// More than K halfspaces: std::invalid_argument (a programming error: K is the caller's choice).
// Zero or non-finite normal or point: never() (a polyhedron with a degenerate face is not a
// defined solid; the reason in *why).
template <int K>
inline HalfspacesK<float, K> make_halfspaces(const std::vector<HalfspaceIn>& hs, std::string* why = nullptr) {
  if (hs.size() > std::size_t(K)) throw std::invalid_argument("make_halfspaces: more halfspaces than slots");
  HalfspacesK<float, K> h;
  for (int i = 0; i < K; ++i) { h.n[i] = {0.f, 0.f, 0.f}; h.D[i] = -1.f; }
  for (std::size_t i = 0; i < hs.size(); ++i) {
    const Vec3d n = to_double(hs[i].normal), p = to_double(hs[i].point);
    const double len = std::sqrt(dot(n, n));
    if (!finite3(p) || !std::isfinite(len) || len == 0.0)
      return never_because<HalfspacesK<float, K>>(why, "polyhedron: a face normal is zero or not finite, or its point is not finite");
    const Vec3d u = n * (1.0 / len);
    h.n[i] = to_float(u);
    h.D[i] = float(-dot(u, p));
  }
  return h;
}

// An axis-aligned box as six halfspaces (normals +-x, +-y, +-z; D = -+ the bounds, exact).
// Non-finite or inverted: never() (the reason in *why).
template <int K = 8>
inline HalfspacesK<float, K> make_box_halfspaces(Vec3f lo, Vec3f hi, std::string* why = nullptr) {
  static_assert(K >= 6);
  if (!finite3(lo) || !finite3(hi) || lo.x > hi.x || lo.y > hi.y || lo.z > hi.z)
    return never_because<HalfspacesK<float, K>>(why, "box: a corner is not finite or min is above max on an axis");
  HalfspacesK<float, K> h;
  for (int i = 0; i < K; ++i) { h.n[i] = {0.f, 0.f, 0.f}; h.D[i] = -1.f; }
  for (int a = 0; a < 3; ++a) {
    Vec3f e{0.f, 0.f, 0.f};
    (a == 0 ? e.x : a == 1 ? e.y : e.z) = 1.f;
    h.n[2 * a] = -e; h.D[2 * a] = lo[a];       // -x + lo <= 0
    h.n[2 * a + 1] = e; h.D[2 * a + 1] = -hi[a];  //  x - hi <= 0
  }
  return h;
}

namespace detail {
// Clips [t_in, t_out] by every halfspace. `early`: return false as soon as every lane is empty.
template <bool early, class F, int K>
RB_INLINE bool halfspace_clip(const Ray<F>& r, const HalfspacesK<F, K>& h, F& t_in, F& t_out, mask_t<F>& alive) {
  const F inf = F(kInf<F>), z = F(0);
  for (int i = 0; i < K; ++i) {
    const F den = dot(h.n[i], r.d);                         // 2+- 3*
    const F s = dot(h.n[i], r.o) + h.D[i];                  // 3+- 3*
    const F t = -s / den;                                   // 1/
    // A NaN t (den == 0 and s == 0) is never selected: den == 0 is neither entering nor leaving.
    t_in = vmax(vselect(den < z, t, -inf), t_in);           // 1 cmp 1 select 1 max
    t_out = vmin(vselect(den > z, t, inf), t_out);          // 1 cmp 1 select 1 min
    alive = alive & mask_not<F>((den == z) & (s > z)) & (t_in <= t_out);  // 3 cmp
    if constexpr (early) {
      if (none_of<F>(alive)) return false;
    }
  }
  return true;
}
}  // namespace detail

namespace detail {
// The first crossing of [t_in, t_out] (the line's interval in the solid) within [tmin, tmax]:
// t_in, or t_out when t_in is before tmin (origin inside).  3 cmp 1 select (+ make_hit)
template <class F>
RB_INLINE Hit<F> first_crossing(const Ray<F>& r, const mask_t<F>& alive, const F& t_in, const F& t_out) {
  const F t = vselect(t_in >= r.tmin, t_in, t_out);
  const mask_t<F> m = alive & (t >= r.tmin) & (t <= r.tmax);
  return make_hit<F>(m, t);
}
}  // namespace detail

template <class F, int K>
RB_INLINE Hit<F> intersect_polyhedron(const Ray<F>& r, const HalfspacesK<F, K>& h) {
  F t_in = F(-kInf<F>), t_out = F(kInf<F>);
  mask_t<F> alive = mask_true<F>();
  if (!detail::halfspace_clip<true>(r, h, t_in, t_out, alive)) return miss_hit<F>();
  return detail::first_crossing(r, alive, t_in, t_out);     // 3 cmp 2 select
}

// Entry and exit along the whole line (t_in from -inf, t_out from +inf), valid where the line
// meets the solid; an unbounded set (fewer than 4 independent planes) may give infinite roots.
template <class F, int K>
RB_INLINE Roots<F, 2> polyhedron_roots(const Ray<F>& r, const HalfspacesK<F, K>& h) {
  F t_in = F(-kInf<F>), t_out = F(kInf<F>);
  mask_t<F> alive = mask_true<F>();
  if (!detail::halfspace_clip<true>(r, h, t_in, t_out, alive)) return Roots<F, 2>::none();
  return Roots<F, 2>::closed_span(alive, t_in, t_out);
}

// Outward unit normal of the face nearest to a point on the surface (largest signed distance).
template <class F, int K>
RB_INLINE Vec3<F> polyhedron_normal(const HalfspacesK<F, K>& h, const Vec3<F>& p) {
  F best = dot(h.n[0], p) + h.D[0];
  Vec3<F> n = h.n[0];
  for (int i = 1; i < K; ++i) {
    const F s = dot(h.n[i], p) + h.D[i];                    // 3+- 3*
    const mask_t<F> m = s > best;                           // 1 cmp
    best = vselect(m, s, best);
    n = vselect3(m, h.n[i], n);
  }
  return n;
}

// ---- K slabs (pairs of parallel planes) ------------------------------------------------------
template <class F, int K>
struct SlabsK {
  static constexpr int kSlabs = K;
  Vec3<F> n[K];
  F Dlo[K], Dhi[K];  // the slab is between n . X + Dlo = 0 and n . X + Dhi = 0
  auto fields() {
    return [this]<std::size_t... I>(std::index_sequence<I...>) {
      return std::tuple_cat(std::tie(n[I].x, n[I].y, n[I].z)..., std::tie(Dlo[I]...), std::tie(Dhi[I]...));
    }(std::make_index_sequence<K>{});
  }
  // Slab 0 with n = 0 and both offsets 1: t = -1/0 = -inf on both planes (or +inf for a
  // negative-zero den), an empty interval for every ray.
  static SlabsK never() {
    SlabsK s;
    for (int i = 0; i < K; ++i) { s.n[i] = {F(0), F(0), F(0)}; s.Dlo[i] = F(1); s.Dhi[i] = F(1); }
    return s;
  }
};
template <class F>
using Slabs3 = SlabsK<F, 3>;

// Slab i: the points with lo_i <= u_i . X <= hi_i (u_i normalised in double). A zero or
// non-finite axis, non-finite bounds or lo > hi: never() (the reason in *why).
template <int K>
inline SlabsK<float, K> make_slabs(const std::array<Vec3f, K>& axis, const std::array<float, K>& lo, const std::array<float, K>& hi,
                                   std::string* why = nullptr) {
  SlabsK<float, K> s;
  for (int i = 0; i < K; ++i) {
    const Vec3d n = to_double(axis[i]);
    const double len = std::sqrt(dot(n, n));
    if (!std::isfinite(len) || len == 0.0) return never_because<SlabsK<float, K>>(why, "slabs: an axis is zero or not finite");
    if (!std::isfinite(lo[i]) || !std::isfinite(hi[i]) || !(lo[i] <= hi[i]))
      return never_because<SlabsK<float, K>>(why, "slabs: a bound is not finite or lo is above hi");
    s.n[i] = to_float(n * (1.0 / len));
    s.Dlo[i] = float(-double(lo[i]) / len);
    s.Dhi[i] = float(-double(hi[i]) / len);
  }
  return s;
}

// An axis-aligned box as three axis slabs (exact data). Non-finite or inverted: never() (the
// reason in *why).
inline Slabs3<float> make_box_slabs(Vec3f lo, Vec3f hi, std::string* why = nullptr) {
  if (!finite3(lo) || !finite3(hi) || lo.x > hi.x || lo.y > hi.y || lo.z > hi.z)
    return never_because<Slabs3<float>>(why, "box: a corner is not finite or min is above max on an axis");
  Slabs3<float> s;
  for (int a = 0; a < 3; ++a) {
    s.n[a] = {a == 0 ? 1.f : 0.f, a == 1 ? 1.f : 0.f, a == 2 ? 1.f : 0.f};
    s.Dlo[a] = -lo[a];
    s.Dhi[a] = -hi[a];
  }
  return s;
}

namespace detail {
template <bool early, class F, int K>
RB_INLINE bool slab_clip(const Ray<F>& r, const SlabsK<F, K>& s, F& t_in, F& t_out, mask_t<F>& alive) {
  for (int i = 0; i < K; ++i) {
    const F den = dot(s.n[i], r.d);                         // 2+- 3*
    const F no = dot(s.n[i], r.o);                          // 2+- 3*
    const F t1 = -(no + s.Dlo[i]) / den;                    // 1+- 1/
    const F t2 = -(no + s.Dhi[i]) / den;                    // 1+- 1/
    // A NaN t (origin on a plane, ray parallel) sits in the first argument and is dropped.
    t_in = vmax(vmin(t1, t2), t_in);                        // 2 min/max
    t_out = vmin(vmax(t1, t2), t_out);                      // 2 min/max
    alive = alive & (t_in <= t_out);                        // 1 cmp
    if constexpr (early) {
      if (none_of<F>(alive)) return false;
    }
  }
  return true;
}
}  // namespace detail

// The first surface crossing in [tmin, tmax] (the exit when the origin is inside), as
// intersect_polyhedron.
template <class F, int K>
RB_INLINE Hit<F> intersect_slabs(const Ray<F>& r, const SlabsK<F, K>& s) {
  F t_in = F(-kInf<F>), t_out = F(kInf<F>);
  mask_t<F> alive = mask_true<F>();
  if (!detail::slab_clip<true>(r, s, t_in, t_out, alive)) return miss_hit<F>();
  return detail::first_crossing(r, alive, t_in, t_out);     // 3 cmp 2 select
}

template <class F, int K>
RB_INLINE Roots<F, 2> slabs_roots(const Ray<F>& r, const SlabsK<F, K>& s) {
  F t_in = F(-kInf<F>), t_out = F(kInf<F>);
  mask_t<F> alive = mask_true<F>();
  if (!detail::slab_clip<true>(r, s, t_in, t_out, alive)) return Roots<F, 2>::none();
  return Roots<F, 2>::closed_span(alive, t_in, t_out);
}

}  // namespace rb
