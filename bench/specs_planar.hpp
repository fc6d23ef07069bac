// Bench specs of the planar kernel family (see bench/specs.hpp for the shape of a spec).
// Class-0 rays hit class-0 primitives; class-1 rays (shifted by 10 in x, or pointing -z for the
// unbounded planes) miss them (bench/harness.hpp).
#pragma once

#include "bench/specs.hpp"
#include "kernels/parallel_planes.hpp"
#include "kernels/plane_uv.hpp"
#include "kernels/polygon.hpp"
#include "kernels/polyhedron.hpp"
#include "kernels/triangle_cramer.hpp"
#include "kernels/triangle_woop.hpp"

#include <cmath>
#include <numbers>

namespace rb::bench {

// Rays of the unbounded kinds (as PlaneSpec): class 0 towards +z, class 1 towards -z.
struct UnboundedRays {
  static Ray<float> ray(int cls, Rng& g) { return PlaneSpec::ray(cls, g); }
  // The lecture's negative case: a ray parallel to the plane(s).
  static Ray<float> ops_miss_ray(Rng&) { return make_ray(Vec3f{0, 0, -50}, Vec3f{1, 0, 0}); }
};

// ---- plane with [u,v] ------------------------------------------------------------------------
struct PlaneUVSpec : UnboundedRays {
  static constexpr const char* kernel = "plane";
  static constexpr const char* method = "uv";
  struct Input { Vec3f p0, u, v; };
  using Soa = TriLectureSoA;
  // Class 0 in front of the class-0 rays (z = 2 + k), class 1 behind them (z = -100 - k).
  static Input make(int cls, int k, Rng& g) {
    // Plane 0 faces the rays squarely (the ops table's parallel ray is exactly parallel to it).
    const float z = cls == 0 ? 2.f + float(k) : -100.f - float(k);
    const float j = k == 0 ? 0.f : 0.1f;
    return {Vec3f{uni(g, -1, 1), uni(g, -1, 1), z}, Vec3f{1.f, uni(g, -j, j), uni(g, -j, j)}, Vec3f{uni(g, -j, j), 1.f, uni(g, -j, j)}};
  }
  static Soa build(const std::vector<Input>& in) {
    std::vector<TriLecture<float>> p(in.size());
    std::vector<int> ax(in.size());
    for (std::size_t i = 0; i < in.size(); ++i) p[i] = make_plane_uv(in[i].p0, in[i].u, in[i].v, ax[i]);
    return TriLectureSoA::from(p, ax);
  }
  static std::size_t count(const Soa& s) { return s.real; }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const TriLecture<F>& q, const Soa& s, std::size_t j) {
    return intersect_plane_uv(r, q, s.axis_of(j));
  }
};

// ---- parallelogram ---------------------------------------------------------------------------
struct ParallelogramSpec {
  static constexpr const char* kernel = "parallelogram";
  static constexpr const char* method = "lecture";
  using Input = std::array<Vec3f, 3>;  // R0, R0 + U, R0 + V
  using Soa = TriLectureSoA;
  static Input make(int cls, int k, Rng& g) {
    const float x = 10.f * float(cls), z = 2.f + float(k);
    return {Vec3f{x - 1.f + uni(g, -0.1f, 0.1f), -1.f, z + uni(g, -0.2f, 0.2f)},
            Vec3f{x + 1.5f, -1.f + uni(g, -0.1f, 0.1f), z + uni(g, -0.2f, 0.2f)},
            Vec3f{x - 1.f + uni(g, -0.1f, 0.1f), 1.5f, z + uni(g, -0.2f, 0.2f)}};
  }
  static Soa build(const std::vector<Input>& in) { return Soa::build(in); }
  static std::size_t count(const Soa& s) { return s.real; }
  static Ray<float> ray(int cls, Rng& g) { return default_ray(cls, g); }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const TriLecture<F>& q, const Soa& s, std::size_t j) {
    return intersect_parallelogram(r, q, s.axis_of(j));
  }
};

// ---- triangle: Cramer's rule and Woop-Benthin-Wald -------------------------------------------
struct TriangleCramerSpec : PlainSoaSpec<Triangle> {
  static constexpr const char* kernel = "triangle";
  static constexpr const char* method = "cramer";
  static Input make(int cls, int k, Rng& g) {
    const auto t = bench_triangle(cls, k, g);
    return make_triangle(t[0], t[1], t[2]);
  }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Triangle<F>& q, const Soa&, std::size_t) { return intersect_triangle_cramer(r, q); }
};

// The benchmark harness hands a spec one ray and one primitive per call, so the per-ray
// precompute (make_woop_ray) is redone per test here: the timed number is an upper bound of
// Woop's cost (a renderer computes WoopRay once per ray). The ops table counts the test alone
// and the precompute in its own row.
struct TriangleWoopSpec : PlainSoaSpec<TriVerts> {
  static constexpr const char* kernel = "triangle";
  static constexpr const char* method = "woop";
  static Input make(int cls, int k, Rng& g) {
    const auto t = bench_triangle(cls, k, g);
    return make_tri_verts(t[0], t[1], t[2]);
  }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const TriVerts<F>& q, const Soa&, std::size_t) {
    return intersect_triangle_woop(make_woop_ray(r), r, q);
  }
};

// ---- general polygon -------------------------------------------------------------------------
// A concave star of 2m vertices (outer radius ~2, inner ~1) around (10 c, 0) in a slightly
// tilted plane near z = 2 + k; m = 6 .. 12, so a primitives-in-lanes group mixes vertex counts.
inline std::vector<Vec3f> bench_star(int cls, int k, Rng& g, int m) {
  const float cx = 10.f * float(cls), z = 2.f + float(k);
  const float sx = uni(g, -0.05f, 0.05f), sy = uni(g, -0.05f, 0.05f);
  std::vector<Vec3f> v;
  for (int i = 0; i < 2 * m; ++i) {
    const double a = std::numbers::pi * double(i) / double(m);
    const float rad = (i % 2 ? 1.f : 2.f) + uni(g, -0.05f, 0.05f);
    const float x = rad * float(std::cos(a)), y = rad * float(std::sin(a));
    v.push_back(Vec3f{cx + x, y, z + sx * x + sy * y});
  }
  return v;
}

struct PolygonSpec {
  static constexpr const char* kernel = "polygon";
  static constexpr const char* method = "crossing";
  static constexpr int max_prim_lanes = 8;  // the vertices interleaved per group of 8 (kernels/polygon.hpp)
  using Input = std::vector<Vec3f>;
  using Soa = PolygonSoA;
  static Input make(int cls, int k, Rng& g) { return bench_star(cls, k, g, 6 + k % 7); }
  static Soa build(const std::vector<Input>& in) { return Soa::build(in); }
  static std::size_t count(const Soa& s) { return s.real; }
  static Ray<float> ray(int cls, Rng& g) { return default_ray(cls, g); }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const PolygonRef<F>& p, const Soa&, std::size_t) { return intersect_polygon(r, p); }
};

// ---- parallel planes -------------------------------------------------------------------------
struct ParallelPlanesSpec : PlainSoaSpec<ParallelPlanes4>, UnboundedRays {
  using UnboundedRays::ray;
  static constexpr const char* kernel = "parallel_planes";
  static constexpr const char* method = "lecture";
  // Four planes 0.5 apart, class 0 at z = 2 + k .. 3.5 + k, class 1 behind the class-0 rays.
  static Input make(int cls, int k, Rng& g) {
    const float z = cls == 0 ? 2.f + float(k) : -100.f - float(k);
    const float j = k == 0 ? 0.f : 0.05f;  // set 0 faces the rays squarely (the ops table's parallel ray)
    const Vec3f n{uni(g, -j, j), uni(g, -j, j), -1.f};
    return make_parallel_planes<4>(n, std::vector<float>{z, z + 0.5f, z + 1.f, z + 1.5f});
  }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const ParallelPlanes4<F>& p, const Soa&, std::size_t) {
    return intersect_parallel_planes(r, p);
  }
};

// ---- convex polyhedron -----------------------------------------------------------------------
// A regular octahedron |x| + |y| + |z| <= r around (10 c, 0, 3 k): 8 halfspaces.
inline Halfspaces8<float> bench_octahedron(int cls, int k, Rng& g) {
  const Vec3f c{10.f * float(cls) + uni(g, -0.1f, 0.1f), uni(g, -0.1f, 0.1f), 3.f * float(k)};
  const float r = uni(g, 1.f, 1.4f);
  std::vector<HalfspaceIn> hs;
  for (int s = 0; s < 8; ++s) {
    const Vec3f n{s & 1 ? -1.f : 1.f, s & 2 ? -1.f : 1.f, s & 4 ? -1.f : 1.f};
    hs.push_back({n, c + Vec3f{n.x * r, 0.f, 0.f}});
  }
  return make_halfspaces<8>(hs);
}

struct PolyhedronSpec : PlainSoaSpec<Halfspaces8> {
  static constexpr const char* kernel = "polyhedron";
  static constexpr const char* method = "halfspaces";
  static Input make(int cls, int k, Rng& g) { return bench_octahedron(cls, k, g); }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Halfspaces8<F>& h, const Soa&, std::size_t) { return intersect_polyhedron(r, h); }
};

// An oriented box (three slabs with slightly rotated axes) around (10 c, 0, 3 k).
inline Slabs3<float> bench_oriented_box(int cls, int k, Rng& g) {
  const Vec3d c{10.0 * cls + double(uni(g, -0.1f, 0.1f)), double(uni(g, -0.1f, 0.1f)), 3.0 * k};
  const double a = double(uni(g, -0.3f, 0.3f)), b = double(uni(g, -0.3f, 0.3f));
  const Vec3d u0{std::cos(a), std::sin(a), 0}, u1{-std::sin(a) * std::cos(b), std::cos(a) * std::cos(b), std::sin(b)};
  const Vec3d u2 = cross(u0, u1);
  std::array<Vec3f, 3> ax{to_float(u0), to_float(u1), to_float(u2)};
  std::array<float, 3> lo{}, hi{};
  for (int i = 0; i < 3; ++i) {
    const double h = double(uni(g, 0.6f, 1.f));
    const double m = dot(to_double(ax[std::size_t(i)]), c);
    lo[std::size_t(i)] = float(m - h);
    hi[std::size_t(i)] = float(m + h);
  }
  return make_slabs<3>(ax, lo, hi);
}

struct SlabsSpec : PlainSoaSpec<Slabs3> {
  static constexpr const char* kernel = "polyhedron";
  static constexpr const char* method = "slabs";
  static Input make(int cls, int k, Rng& g) { return bench_oriented_box(cls, k, g); }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Slabs3<F>& s, const Soa&, std::size_t) { return intersect_slabs(r, s); }
};

// Every benchmarked (kernel, method) of this family.
template <class V>
void for_each_spec_planar(V&& v) {
  v.template operator()<PlaneUVSpec>();
  v.template operator()<ParallelogramSpec>();
  v.template operator()<TriangleCramerSpec>();
  v.template operator()<TriangleWoopSpec>();
  v.template operator()<PolygonSpec>();
  v.template operator()<ParallelPlanesSpec>();
  v.template operator()<PolyhedronSpec>();
  v.template operator()<SlabsSpec>();
}

}  // namespace rb::bench
