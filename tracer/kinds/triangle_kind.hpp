// Triangles of a mesh (Scene::triangles, vertices shared in Scene::verts).
#pragma once

#include "kernels/triangle_woop.hpp"

namespace rb::kinds {

struct TriangleKind {
  static constexpr Kind id = Kind::triangle;
  static constexpr const char* name = "triangle";
  static constexpr bool custom = false;

  static std::size_t count(const Scene& s) { return s.triangles.size(); }
  template <class Fn>
  static void each(const Scene& s, Fn&& f) {
    for (std::size_t i = 0; i < s.triangles.size(); ++i) f(std::uint32_t(i));
  }
  static std::uint32_t material(const Scene& s, std::uint32_t i) { return s.triangles[i].mat; }
  // Fetches what make() reads, ahead of it: stage 0 the triangle's indices, stage 1 (once those
  // are in cache) its three vertices.
  static void prefetch_input(const Scene& s, std::uint32_t i, int stage) {
    if (stage == 0) __builtin_prefetch(&s.triangles[i]);
    else
      for (const auto v : s.triangles[i].v) __builtin_prefetch(&s.verts[v]);
  }
  static Bounds bounds(const Scene& s, std::uint32_t i) {
    Bounds b;
    for (auto v : s.triangles[i].v) b.grow(s.verts[v]);
    return b;
  }
  static Feature feature(const Scene& s, std::uint32_t i) {
    const auto& t = s.triangles[i];
    const Vec3d a = s.verts[t.v[0]], b = s.verts[t.v[1]], c = s.verts[t.v[2]];
    const double e0 = std::sqrt(dot(b - a, b - a)), e1 = std::sqrt(dot(c - b, c - b)), e2 = std::sqrt(dot(a - c, a - c));
    const Vec3d n = cross(b - a, c - a);
    return {(a + b + c) * (1.0 / 3.0), std::min({e0, e1, e2}), std::max({e0, e1, e2}), !(dot(n, n) > 0.0)};
  }
  // feature(s, i).extent with one square root (of the longest squared edge: the same value, as the
  // square root is monotone and correctly rounded): every hit's surface asks for it.
  static double extent(const HitQuery& q, std::uint32_t i) {
    const Scene& s = *q.scene;
    const auto& t = s.triangles[i];
    const Vec3d a = s.verts[t.v[0]], b = s.verts[t.v[1]], c = s.verts[t.v[2]];
    return std::sqrt(std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)}));
  }
  static const std::array<std::uint32_t, 3>& mesh_vertices(const Scene& s, std::uint32_t i) { return s.triangles[i].v; }

  // The vertices relative to the frame origin, each coordinate rounded once (shared vertices stay
  // bit-identical, so the watertight test stays watertight in any frame).
  template <class S>
  using Prim = TriVerts<S>;
  template <class S>
  static Prim<S> make(const Scene& s, std::uint32_t i, const Vec3d& origin, std::string* why = nullptr) {
    const auto& t = s.triangles[i];
    const Vec3d a = s.verts[t.v[0]] - origin, b = s.verts[t.v[1]] - origin, c = s.verts[t.v[2]] - origin;
    if constexpr (std::is_same_v<S, float>) {
      return make_tri_verts(a, b, c, why);
    } else {
      const Vec3d n = cross(b - a, c - a);
      if (!finite3(a) || !finite3(b) || !finite3(c) || !finite3(n)) return never_because<Prim<S>>(why, "triangle: a vertex is not finite");
      if (dot(n, n) == 0.0) return never_because<Prim<S>>(why, "triangle: zero area");
      return {a, b, c};
    }
  }
  template <class F>
  using Pre = WoopRay<F>;
  template <class F>
  static RB_INLINE Pre<F> pre(const Ray<F>& r) { return make_woop_ray(r); }
  static constexpr std::array<MethodInfo, 1> methods{
      {{"woop", "Woop, Benthin and Wald's watertight test: the triangle sheared into the ray's frame, exact edge signs", true, true}}};
  // The lab's evidence per option (PlanOption in tracer/kinds.hpp), cheapest first.
  static constexpr std::array<PlanOption, 2> plan{{
      {0, false, kAny, kAny, kAny,
       "triangle/octahedron_edges triangle/octahedron_vertices triangle/sphere_mesh_edges triangle/sphere_mesh_vertices triangle/fan_square "
       "triangle/far_mesh_1e3 triangle/far_mesh_1e6 triangle/far_camera_1e4",
       "watertight: no ray passes between the shared edges of a closed mesh, whatever the frame"},
      {0, true, kAny, kAny, kAny, "triangle/octahedron_edges triangle/sphere_mesh_vertices triangle/far_mesh_1e6", "watertight, in double"},
  }};
  // Stored apart: a ray's cost against the kind in the frame (StorageCost in tracer/kinds.hpp).
  static constexpr StorageCost storage{1.25, 2.80, "storage/triangle", "Intel Xeon family 6 model 207, release build, one thread"};
  template <int M, class F>
  static RB_INLINE Hit<F> hit(const Ray<F>& r, const Pre<F>& w, const Prim<F>& p) {
    return intersect_triangle_woop(w, r, p);
  }

  static std::size_t input_bytes(const Scene& s) {
    return s.triangles.size() * sizeof(scene::TriangleIn) + s.verts.size() * sizeof(Vec3d) + s.vert_normals.size() * sizeof(Vec3f);
  }

  static Surface surface(const HitQuery& q, std::uint32_t i) {
    const Scene& s = *q.scene;
    const auto& tr = s.triangles.at(i);
    const Vec3d v[3] = {s.verts[tr.v[0]], s.verts[tr.v[1]], s.verts[tr.v[2]]};
    Surface h;
    // The normal normalised once: the plane the point is projected onto and the geometric normal
    // (detail::unit_d, then unit_or of its result, without a second square root).
    const Vec3d c = cross(v[1] - v[0], v[2] - v[0]);
    const double l = std::sqrt(dot(c, c));
    const bool unit = l > 0.0 && std::isfinite(l);
    const Vec3d n = unit ? c * (1.0 / l) : c;
    h.p = detail::onto_plane(q.p, n, v[0]);
    h.ng = unit ? to_float(n) : -q.ray.d;
    if (s.vert_normals.empty()) {
      h.ns = h.ng;
    } else {
      const Vec3f vn[3] = {s.vert_normals[tr.v[0]], s.vert_normals[tr.v[1]], s.vert_normals[tr.v[2]]};
      h.ns = detail::interpolate(v, vn, 3, q.p, h.ng);
    }
    h.mat = tr.mat;
    return h;
  }
};

}  // namespace rb::kinds
