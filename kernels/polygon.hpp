// Ray x general planar polygon (seed 000 "General planar polygon", seed 002 "Ray-Polygon
// Intersection"): intersect the polygon's plane (t, the point [x,y,z]; lecture 8+- 9* 1/), then
// decide point-in-polygon in the plane projected along the dominant axis of the normal, by the
// crossing (Jordan curve) test: a half-line from the point towards +x' crosses the boundary an
// odd number of times iff the point is inside. Works for convex and concave polygons alike.
//   Per edge (x0,y0) -> (x1,y1), coordinates relative to the point: the edge straddles the
//   half-line's line when (y0 >= 0) != (y1 >= 0); it crosses on the +x' side when
//   (y1 (x0 - x1) >= x1 (y0 - y1)) == (y1 >= 0) (the intersection's x' sign, with the division
//   by y0 - y1 replaced by its known sign). Per edge: 4+- 2* 2 cmp, mask logic, no branch.
//
// Data (PolygonSoA): the plane of each polygon (Plane<float>: unit normal by Newell's method in
// double, D through the vertex centroid) in a PrimSoA; the projected 2D vertices (the float input
// coordinates on the two kept axes, copied exactly) in two flat aligned arrays. Polygons are
// grouped by dropped axis and, within an axis, sorted by vertex count; each group of 8 slots
// stores its vertices interleaved (vertex i of slot s at base + 8 i + s % 8) and padded to the
// group's largest count with copies of each polygon's first vertex. A padded edge has both ends
// equal, so it never straddles: the loop to the group's maximum needs no per-lane count mask.
//   rays in lanes:       PolygonSoA::broadcast<F>(j): one polygon, its own vertex count,
//                        each vertex a broadcast scalar;
//   primitives in lanes: PolygonSoA::load<F>(j): 8 polygons of one axis group, the loop runs to
//                        the group's largest count, each vertex step one aligned load.
//   edges in lanes:      intersect_polygon_edges(r, soa, j): a polygon of at least kEdgeLanes
//                        vertices, its edges eight at a time for each ray that reaches its plane
//                        (the polygon's vertices also stored in a run of their own, PolygonSoA::ex,
//                        ey); the crossing count's parity is that of the per-edge answers, which
//                        are polygon_contains' own. What the tracer takes, for single rays and
//                        packets.
// A 144-vertex concave polygon (SPD gears) is 145 edge steps of 4+- 2* 2 cmp per lane: one ray at
// a time, 145 scalar steps; with its edges in lanes, 18 steps of eight edges.
// [u,v] is not defined for a polygon by the lecture: 0.
#pragma once

#include "core/lanes.hpp"
#include "kernels/plane.hpp"
#include "kernels/triangle.hpp"
#include "soa/axis_grouped.hpp"

#include <algorithm>
#include <bit>
#include <numeric>
#include <type_traits>
#include <vector>

namespace rb {

// What the kernel sees of one polygon (broadcast) or of a lane group (load).
template <class F>
struct PolygonRef {
  Plane<F> pl;
  const float* x;       // vertex i of this lane (group) at x[8 i]
  const float* y;
  std::uint32_t edges;  // edges to test: the polygon's vertex count (broadcast) or the group's maximum (load)
  int axis;             // dropped axis (uniform over the group)
  bool lanes;           // true: x, y hold one vertex per lane (load), false: a scalar per vertex (broadcast)
  RB_INLINE F vx(std::uint32_t i) const { return lanes ? load<F>(x + 8 * std::size_t(i)) : F(x[8 * std::size_t(i)]); }
  RB_INLINE F vy(std::uint32_t i) const { return lanes ? load<F>(y + 8 * std::size_t(i)) : F(y[8 * std::size_t(i)]); }
};

// The plane and projection of one polygon, or the reason it is degenerate.
struct PolygonInfo {
  Plane<float> plane = Plane<float>::never();
  int axis = 2;
  bool valid = false;
  const char* why = "";
};

// Validates a polygon: >= 3 vertices, all finite, non-zero area (Newell normal in double and the
// projected shoelace area both non-zero). Collinear or repeated vertices: zero area, invalid.
template <class T>
inline PolygonInfo polygon_info(const std::vector<Vec3<T>>& v) {
  PolygonInfo info;
  if (v.size() < 3) { info.why = "fewer than 3 vertices"; return info; }
  Vec3d c{0, 0, 0};
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!finite3(v[i])) { info.why = "non-finite vertex"; return info; }
    c = c + to_double(v[i]);
  }
  const Vec3d n = newell_normal(v.data(), v.size());
  const double len = std::sqrt(dot(n, n));
  if (!std::isfinite(len) || len == 0.0) { info.why = "zero area (collinear or repeated vertices)"; return info; }
  const int ax = dominant_axis(n);
  const int a = (ax + 1) % 3, b = (ax + 2) % 3;
  double area2 = 0;  // of the projected float vertices, as the kernel sees them
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Vec3d p = to_double(to_float(to_double(v[i]))), q = to_double(to_float(to_double(v[(i + 1) % v.size()])));
    area2 += p[a] * q[b] - q[a] * p[b];
  }
  if (area2 == 0.0 || !std::isfinite(area2)) { info.why = "zero projected area"; return info; }
  const Vec3d u = n * (1.0 / len);
  c = c * (1.0 / double(v.size()));
  info.plane = {to_float(u), float(-dot(u, c))};
  info.axis = ax;
  info.valid = true;
  return info;
}

// The planes, axes and ids are the axis-grouped batch of soa/axis_grouped.hpp (prims: one Plane
// slot per polygon, padded per group of 8); the projected vertices are added per group.
// Polygons of at least this many vertices also keep their projected vertices in a run of their
// own, for the edges-in-lanes test (intersect_polygon_edges); smaller ones are a few scalar steps.
inline constexpr std::uint32_t kEdgeLanes = 8;
inline constexpr std::uint32_t kNoRun = UINT32_MAX;

struct PolygonSoA : AxisGrouped<Plane> {
  std::vector<std::uint32_t> nverts; // per slot (0: padding or degenerate)
  std::vector<std::uint32_t> base;   // per group of 8 slots: offset of its vertex 0 in vx, vy
  std::vector<std::uint32_t> maxv;   // per group: its largest vertex count
  avec<float> vx, vy;                // projected vertices, interleaved per group (see the header)
  // Per slot, where its run starts in ex, ey (kNoRun: fewer than kEdgeLanes vertices): vertex i at
  // run + i for i < n, then copies of vertex 0 up to index round_up(n, 8), so that the last group
  // of eight edges reads vertex i + 1 within the run and its padding edges have equal ends (never
  // straddling).
  std::vector<std::uint32_t> run;
  avec<float> ex, ey;
  std::size_t degenerate = 0;        // inputs stored as never-hit slots

  std::size_t bytes() const {
    return prims.bytes() + (vx.size() + vy.size() + ex.size() + ey.size()) * sizeof(float) + run.size() * sizeof(std::uint32_t);
  }

  // Degenerate polygons are kept (so ids stay aligned with the input) as slots that never hit;
  // polygon_info(p).why says why a polygon is degenerate.
  template <class T>
  static PolygonSoA build(const std::vector<std::vector<Vec3<T>>>& polys) {
    PolygonSoA s;
    s.real = polys.size();
    std::vector<PolygonInfo> info(polys.size());
    for (std::size_t i = 0; i < polys.size(); ++i) {
      info[i] = polygon_info(polys[i]);
      if (!info[i].valid) ++s.degenerate;
    }
    auto count = [&](std::size_t i) { return info[i].valid ? polys[i].size() : std::size_t(0); };
    auto groups = by_axis(polys.size(), [&](std::size_t i) { return info[i].axis; });
    for (int a = 0; a < 3; ++a) {
      std::vector<std::size_t>& idx = groups[std::size_t(a)];
      std::stable_sort(idx.begin(), idx.end(), [&](std::size_t p, std::size_t q) { return count(p) < count(q); });
      for (std::size_t g = 0; g < idx.size(); g += 8) {
        const std::size_t n = std::min<std::size_t>(8, idx.size() - g);
        std::size_t mv = 0;
        for (std::size_t k = 0; k < n; ++k) mv = std::max(mv, count(idx[g + k]));
        s.base.push_back(std::uint32_t(s.vx.size()));
        s.maxv.push_back(std::uint32_t(mv));
        const int ka = (a + 1) % 3, kb = (a + 2) % 3;
        // mv + 1 vertex rows: the closing edge of the largest polygon reads row mv.
        s.vx.resize(s.vx.size() + 8 * (mv + 1), 0.f);
        s.vy.resize(s.vy.size() + 8 * (mv + 1), 0.f);
        float* X = s.vx.data() + s.base.back();
        float* Y = s.vy.data() + s.base.back();
        for (std::size_t k = 0; k < 8; ++k) {
          const std::size_t i = k < n ? idx[g + k] : SIZE_MAX;
          const std::size_t c = k < n ? count(i) : 0;
          for (std::size_t r = 0; r <= mv; ++r) {
            if (c == 0) continue;  // stays (0, 0): all edges degenerate
            const Vec3f p = to_float(to_double(polys[i][r < c ? r : 0]));
            X[8 * r + k] = p[ka];
            Y[8 * r + k] = p[kb];
          }
          s.nverts.push_back(std::uint32_t(c));
          s.run.push_back(c >= kEdgeLanes ? std::uint32_t(s.ex.size()) : kNoRun);
          if (c >= kEdgeLanes)
            for (std::size_t r = 0; r <= round_up(c, 8); ++r) {
              s.ex.push_back(X[8 * (r < c ? r : 0) + k]);
              s.ey.push_back(Y[8 * (r < c ? r : 0) + k]);
            }
        }
        s.push_group(a, idx.data() + g, n, [&](std::size_t i) { return info[i].plane; });
      }
    }
    return s;
  }

  template <class F>
  RB_INLINE PolygonRef<F> broadcast(std::size_t j) const {
    const std::size_t g = j / 8, off = base[g] + j % 8;
    return {prims.broadcast<F>(j), vx.data() + off, vy.data() + off, nverts[j], axis[j], false};
  }
  // Lanes j .. j + lanes_v<F> - 1, all in one group of 8 (j a multiple of the lane count).
  template <class F>
  RB_INLINE PolygonRef<F> load(std::size_t j) const {
    const std::size_t g = j / 8, off = base[g] + j % 8;
    return {prims.load<F>(j), vx.data() + off, vy.data() + off, maxv[g], axis[j], true};
  }
};

// The plane part: t and the two kept coordinates of [x,y,z] (lecture 8+- 9* 1/ for t and all
// three coordinates). Returns false when every lane has missed the plane (early exit).
// Every product is rounded on its own (dot_rounded, vrounded), so that no FMA contraction makes
// the scalar instantiation (single rays) differ from the 8-lane one (packets): a ray gets the same
// t and the same inside/outside answer in either.
template <class F>
RB_INLINE bool polygon_plane_point(const Ray<F>& r, const PolygonRef<F>& p, mask_t<F>& m, F& t, F& pa, F& pb) {
  const F den = dot_rounded(p.pl.n, r.d);           // 2+- 3*
  m = den != F(0);                                  // 1 cmp
  if (none_of<F>(m)) return false;
  t = -(dot_rounded(p.pl.n, r.o) + p.pl.D) / den;   // 3+- 3* 1/
  m = m & (t >= r.tmin) & (t <= r.tmax);            // 2 cmp
  if (none_of<F>(m)) return false;
  const int a = (p.axis + 1) % 3, b = (p.axis + 2) % 3;
  pa = r.o[a] + vrounded(r.d[a] * t);               // 2+- 2*
  pb = r.o[b] + vrounded(r.d[b] * t);
  return true;
}

// One edge (x0, y0) -> (x1, y1), relative to the point, whose ends lie above the half-line's line
// where c0, c1 are set: whether it flips the point's inside answer (it straddles the line and
// crosses it on the +x' side). Every crossing test's per-edge arithmetic.
template <class F>
RB_INLINE mask_t<F> edge_flips(const F& x0, const F& y0, const mask_t<F>& c0, const F& x1, const F& y1, const mask_t<F>& c1) {
  const mask_t<F> cross = vrounded(y1 * (x0 - x1)) >= vrounded(x1 * (y0 - y1));  // 2+- 2* 1 cmp
  return mask_xor<F>(c0, c1) & mask_not<F>(mask_xor<F>(cross, c1));
}

// Crossing test of the point (pa, pb) against the polygon's projected boundary.
template <class F>
RB_INLINE mask_t<F> polygon_contains(const PolygonRef<F>& p, const F& pa, const F& pb) {
  const F z = F(0);
  F x0 = p.vx(0) - pa, y0 = p.vy(0) - pb;           // 2+-
  mask_t<F> c0 = y0 >= z;                           // 1 cmp
  mask_t<F> inside = mask_false<F>();
  for (std::uint32_t i = 1; i <= p.edges; ++i) {
    const F x1 = p.vx(i) - pa, y1 = p.vy(i) - pb;   // 2+-
    const mask_t<F> c1 = y1 >= z;                   // 1 cmp
    inside = mask_xor<F>(inside, edge_flips<F>(x0, y0, c0, x1, y1, c1));
    x0 = x1; y0 = y1; c0 = c1;
  }
  return inside;
}

template <class F>
RB_INLINE Hit<F> intersect_polygon(const Ray<F>& r, const PolygonRef<F>& p) {
  mask_t<F> m;
  F t, pa, pb;
  if (!polygon_plane_point(r, p, m, t, pa, pb)) return miss_hit<F>();
  m = m & polygon_contains(p, pa, pb);
  return make_hit<F>(m, t);                         // 1 select
}

// The crossing test of the point (pa, pb) against `edges` edges of a run (PolygonSoA::run), eight
// edges at a time: each edge's answer is polygon_contains' (edge_flips on the same differences),
// and the point is inside when an odd number of edges flip it.
RB_INLINE bool polygon_contains_edges(const float* x, const float* y, std::uint32_t edges, float pa, float pb) {
  const f8 a(pa), b(pb), z(0.0f);
  unsigned flips = 0;
  for (std::uint32_t i = 0; i < edges; i += 8) {
    const f8 x0 = f8::load_unaligned(x + i) - a, y0 = f8::load_unaligned(y + i) - b;
    const f8 x1 = f8::load_unaligned(x + i + 1) - a, y1 = f8::load_unaligned(y + i + 1) - b;
    flips += unsigned(std::popcount(lanes::bits(edge_flips<f8>(x0, y0, y0 >= z, x1, y1, y1 >= z))));
  }
  return (flips & 1u) != 0;
}

// One ray (or eight in lanes) against polygon slot j: the plane part as intersect_polygon, then,
// where the polygon has its run, the crossing test with the edges in lanes, once for each ray
// still in (the same hit, bit for bit, as intersect_polygon on s.broadcast<F>(j)). Eight rays
// against a 144-vertex polygon took 145 steps whether one ray or eight reached its plane.
template <class F>
RB_INLINE Hit<F> intersect_polygon_edges(const Ray<F>& r, const PolygonSoA& s, std::size_t j) {
  const PolygonRef<F> p = s.broadcast<F>(j);
  if (s.run[j] == kNoRun) return intersect_polygon(r, p);
  mask_t<F> m;
  F t, pa, pb;
  if (!polygon_plane_point(r, p, m, t, pa, pb)) return miss_hit<F>();
  const float* x = s.ex.data() + s.run[j];
  const float* y = s.ey.data() + s.run[j];
  if constexpr (std::is_same_v<F, float>) {
    m = m && polygon_contains_edges(x, y, p.edges, pa, pb);
  } else {
    static_assert(std::is_same_v<F, f8>, "rays in lanes: the 8-lane batch");
    alignas(kSimdAlign) float a[8], b[8];
    pa.store_aligned(a), pb.store_aligned(b);
    unsigned in = 0;
    for (unsigned left = lanes::bits(m); left != 0; left &= left - 1) {
      const int l = std::countr_zero(left);
      if (polygon_contains_edges(x, y, p.edges, a[l], b[l])) in |= 1u << l;
    }
    m = m & lanes::of(in);
  }
  return make_hit<F>(m, t);
}

template <class F>
RB_INLINE Vec3<F> polygon_normal(const PolygonRef<F>& p) { return p.pl.n; }

}  // namespace rb
