// Planar polygons (Scene::polygons: NFF `p`/`pp` with four or more vertices, JSON polygons): the
// plane, then the crossing test in the plane projected along the normal's dominant axis
// (kernels/polygon.hpp). The batch is the polygon kernel's own axis-grouped PolygonSoA over the
// leaf-ordered polygons; each leaf slot keeps its slot in it.
#pragma once

#include "bvh/hit.hpp"
#include "kernels/polygon.hpp"

#include <cmath>
#include <limits>
#include <vector>

namespace rb::kinds {

struct PolygonKind {
  static constexpr Kind id = Kind::polygon;
  static constexpr const char* name = "polygon";
  static constexpr bool custom = true;

  static std::size_t count(const Scene& s) { return s.polygons.size(); }
  template <class Fn>
  static void each(const Scene& s, Fn&& f) {
    for (std::size_t i = 0; i < s.polygons.size(); ++i) f(std::uint32_t(i));
  }
  static std::uint32_t material(const Scene& s, std::uint32_t i) { return s.polygons[i].mat; }
  static std::vector<Vec3d> vertices(const Scene& s, std::uint32_t i, const Vec3d& origin = {0, 0, 0}) {
    const auto& p = s.polygons[i];
    std::vector<Vec3d> v(p.count);
    for (std::uint32_t k = 0; k < p.count; ++k) v[k] = s.poly_verts[p.first + k] - origin;
    return v;
  }
  static Bounds bounds(const Scene& s, std::uint32_t i) {
    Bounds b;
    const auto v = vertices(s, i);
    if (!polygon_info(v).valid) return b;
    for (const auto& q : v) b.grow(q);
    return b;
  }
  static Feature feature(const Scene& s, std::uint32_t i) {
    const auto v = vertices(s, i);
    Feature f;
    if (v.empty()) return f;
    double emin = 1e300, emax = 0;
    Vec3d c{0, 0, 0};
    for (std::size_t k = 0; k < v.size(); ++k) {
      const Vec3d e = v[(k + 1) % v.size()] - v[k];
      const double l = std::sqrt(dot(e, e));
      if (l > 0) emin = std::min(emin, l);
      emax = std::max(emax, l);
      c = c + v[k];
    }
    f.centre = c * (1.0 / double(v.size()));
    f.size = emin < 1e300 ? emin : 0.0;
    f.extent = emax;
    return f;
  }

  template <class F>
  struct Pre {};
  template <class F>
  static Pre<F> pre(const Ray<F>&) { return {}; }
  static constexpr std::array<MethodInfo, 1> methods{
      {{"crossing", "the plane, then the crossing (Jordan curve) test projected along the normal's dominant axis", false, false}}};
  // The lab's evidence (PlanOption in tracer/kinds.hpp): one method.
  static constexpr std::array<PlanOption, 1> plan{{{0, false, kAny, kAny, kAny, "", "the polygon's only method (float)"}}};

  struct Batch {
    PolygonSoA soa;                  // the polygons in leaf order
    std::vector<std::uint32_t> slot;  // per leaf slot: its slot in soa (UINT32_MAX: padding)
    SlotIds id;                       // per leaf slot: the scene index (UINT32_MAX: padding)
    // Per scene index, what every hit on the polygon needs and each would otherwise recompute from
    // all its vertices: the unit normal (Newell's, in double), the geometric normal in float (NaN
    // where the polygon has none) and the extent.
    std::vector<Vec3d> unit_normal;
    std::vector<Vec3f> ng;
    std::vector<double> extent;
    std::size_t bytes() const {
      return soa.bytes() + (slot.size() + id.size()) * sizeof(std::uint32_t) + unit_normal.size() * sizeof(Vec3d) +
             ng.size() * sizeof(Vec3f) + extent.size() * sizeof(double);
    }
  };
  static Vec3d unit_normal(const Scene& s, std::uint32_t i) {
    const auto& pg = s.polygons[i];
    return detail::unit_d(newell_normal(s.poly_verts.data() + pg.first, pg.count));
  }
  static Vec3f geometric_normal(const Vec3d& unit_normal) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    return detail::unit_or(unit_normal, Vec3f{nan, nan, nan});
  }
  // ids: the scene index of every leaf slot (UINT32_MAX for padding), in leaf order.
  static void build(Batch& b, const Scene& s, SlotIds ids, const Vec3d& origin, int /*method*/, bool /*f64*/,
                    bool /*f64_storage*/) {
    std::vector<std::vector<Vec3d>> polys;
    for (std::uint32_t p : ids)
      if (p != UINT32_MAX) polys.push_back(vertices(s, p, origin));
    b.unit_normal.resize(s.polygons.size());
    b.ng.resize(s.polygons.size());
    b.extent.resize(s.polygons.size());
    for (std::uint32_t i = 0; i < s.polygons.size(); ++i) {
      b.unit_normal[i] = unit_normal(s, i);
      b.ng[i] = geometric_normal(b.unit_normal[i]);
      b.extent[i] = feature(s, i).extent;
    }
    b.id = std::move(ids);
    b.slot.assign(b.id.size(), UINT32_MAX);
    if (polys.empty()) return;
    b.soa = PolygonSoA::build(polys);
    std::vector<std::uint32_t> slot_of(polys.size(), UINT32_MAX);
    for (std::size_t j = 0; j < b.soa.id.size(); ++j)
      if (b.soa.id[j] != UINT32_MAX) slot_of[b.soa.id[j]] = std::uint32_t(j);
    std::size_t p = 0;
    for (std::size_t j = 0; j < b.id.size(); ++j)
      if (b.id[j] != UINT32_MAX) b.slot[j] = slot_of[p++];
  }
  // One ray against the 8 slots from `base`: one polygon at a time (scalar; a polygon of
  // kEdgeLanes or more vertices with its edges in lanes), the closest within h.t (a tie by
  // `bvh::nearer`). The kernel rounds every product on its own, so the scalar instantiation gives
  // the bits of the 8-lane one that packets run.
  static bool single(const Batch& b, std::size_t base, const Ray<float>& r, bvh::Closest& h) {
    bool any = false;
    Ray<float> rr = r;
    rr.tmax = h.t;
    for (std::size_t j = base; j < base + 8; ++j) {
      const std::uint32_t slot = b.slot[j];
      if (slot == UINT32_MAX) continue;
      const Hit<float> hp = intersect_polygon_edges(rr, b.soa, slot);
      if (hp.mask && bvh::nearer(hp.t, code(id, b.id[j]), h)) {
        rr.tmax = hp.t;
        h = {hp.t, code(id, b.id[j])};
        any = true;
      }
    }
    return any;
  }
  // Each group of the packet against the leaf's polygons in slot order (the groups are
  // independent: the order of the two loops changes no hit), the group's rays copied once.
  template <bool Any>
  static void packet(const Batch& b, std::size_t base, bvh::PacketRays& p) {
    for (int q = 0; q < p.n; ++q) {
      const int k = p.list[q];
      Ray<f8> rr = p.r[k];
      for (std::size_t j = base; j < base + 8; ++j) {
        const std::uint32_t slot = b.slot[j];
        if (slot == UINT32_MAX) continue;
        if (none_of<f8>(p.active[k])) break;
        rr.tmax = p.tbest[k];
        const Hit<f8> hit = intersect_polygon_edges(rr, b.soa, slot);
        bvh::packet_update<Any>(p, k, hit.mask, hit.t, code(id, b.id[j]));
      }
    }
  }

  static std::size_t input_bytes(const Scene& s) {
    return s.polygons.size() * sizeof(scene::PolygonIn) + s.poly_verts.size() * sizeof(Vec3d) + s.poly_normals.size() * sizeof(Vec3f);
  }
  // The kernel batch of the whole scene (one slot per polygon) and what it holds.
  static std::size_t batch_bytes(const Scene& s, std::string& what) {
    std::vector<std::vector<Vec3d>> polys;
    for (std::uint32_t i = 0; i < s.polygons.size(); ++i) polys.push_back(vertices(s, i));
    const PolygonSoA soa = PolygonSoA::build(polys);
    what = "PolygonSoA (" + std::to_string(soa.degenerate) + " degenerate kept as never-hit slots)";
    return soa.bytes();
  }

  // The extent of a hit's polygon: the batch's, when the query has one (the tracer's).
  static double extent(const HitQuery& q, std::uint32_t i) {
    const auto* b = static_cast<const Batch*>(q.batch);
    return b && i < b->extent.size() ? b->extent[i] : feature(*q.scene, i).extent;
  }
  static Surface surface(const HitQuery& q, std::uint32_t i) {
    const Scene& s = *q.scene;
    const auto& pg = s.polygons.at(i);
    const Vec3d* v = s.poly_verts.data() + pg.first;
    Surface h;
    const auto* b = static_cast<const Batch*>(q.batch);
    const bool kept = b && i < b->unit_normal.size();
    const Vec3d n = kept ? b->unit_normal[i] : unit_normal(s, i);
    h.p = detail::onto_plane(q.p, n, v[0]);
    const Vec3f ng = kept ? b->ng[i] : geometric_normal(n);
    h.ng = std::isnan(ng.x) ? -q.ray.d : ng;
    h.ns = s.poly_normals.empty() ? h.ng : detail::interpolate(v, s.poly_normals.data() + pg.first, pg.count, q.p, h.ng);
    h.mat = pg.mat;
    return h;
  }
};

}  // namespace rb::kinds
