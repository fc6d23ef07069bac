// Bench specs: for each kernel and method, how to make the benchmark's primitives and rays of a
// class (bench/harness.hpp) and which kernel to call. One struct per (kernel, method); the list
// that every benchmark and report loops over is for_each_spec at the bottom.
#pragma once

#include "bench/harness.hpp"
#include "kernels/box.hpp"
#include "kernels/plane.hpp"
#include "kernels/sphere.hpp"
#include "kernels/triangle.hpp"

#include <array>

namespace rb::bench {

// Base for kinds stored in a plain PrimSoA<P> built from P<float>.
template <template <class> class P>
struct PlainSoaSpec {
  using Input = P<float>;
  using Soa = PrimSoA<P>;
  static Soa build(const std::vector<Input>& in) {
    Soa s;
    s.reserve(in.size());
    for (const auto& p : in) s.push(p);
    return s;
  }
  static std::size_t count(const Soa& s) { return s.count; }
  static Ray<float> ray(int cls, Rng& g) { return default_ray(cls, g); }
};

// A triangle of class c in the plane z = 2 + k, around (10 c, 0), covering the rays' jitter.
inline std::array<Vec3f, 3> bench_triangle(int cls, int k, Rng& g) {
  const float x = 10.f * float(cls), z = 2.f + float(k);
  return {Vec3f{x - 1.f + uni(g, -0.1f, 0.1f), -1.f, z + uni(g, -0.2f, 0.2f)},
          Vec3f{x + 2.f, -1.f + uni(g, -0.1f, 0.1f), z + uni(g, -0.2f, 0.2f)},
          Vec3f{x - 1.f, 2.f + uni(g, -0.1f, 0.1f), z + uni(g, -0.2f, 0.2f)}};
}

struct PlaneSpec : PlainSoaSpec<Plane> {
  static constexpr const char* kernel = "plane";
  static constexpr const char* method = "lecture";
  // Class 0 planes face the class-0 rays ahead (z > 0); class 1 planes lie behind them at
  // z = -100, where only the class-1 rays (pointing -z) reach.
  static Input make(int cls, int k, Rng& g) {
    // Plane 0 faces the rays squarely (the ops table's parallel ray is exactly parallel to it).
    const float z = cls == 0 ? 2.f + float(k) : -100.f - float(k);
    const float j = k == 0 ? 0.f : 0.1f;
    return make_plane(Vec3f{0, 0, z}, Vec3f{uni(g, -j, j), uni(g, -j, j), -1.f});
  }
  static Ray<float> ray(int cls, Rng& g) {
    const Vec3f o{uni(g, -0.3f, 0.3f), uni(g, -0.3f, 0.3f), -50.f};
    const Vec3f d{uni(g, -0.01f, 0.01f), uni(g, -0.01f, 0.01f), cls == 0 ? 1.f : -1.f};
    return make_ray(o, d);
  }
  // The lecture's negative case: a ray parallel to the plane.
  static Ray<float> ops_miss_ray(Rng&) { return make_ray(Vec3f{0, 0, -50}, Vec3f{1, 0, 0}); }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Plane<F>& p, const Soa&, std::size_t) { return intersect_plane(r, p); }
};

struct SphereGeometricSpec : PlainSoaSpec<Sphere> {
  static constexpr const char* kernel = "sphere";
  static constexpr const char* method = "geometric";
  static Input make(int cls, int k, Rng& g) {
    return make_sphere(Vec3f{10.f * float(cls) + uni(g, -0.1f, 0.1f), uni(g, -0.1f, 0.1f), 3.f * float(k)}, uni(g, 0.8f, 1.2f));
  }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Sphere<F>& s, const Soa&, std::size_t) { return intersect_sphere_geometric(r, s); }
};

struct SphereAlgebraicSpec : SphereGeometricSpec {
  static constexpr const char* method = "algebraic";
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Sphere<F>& s, const Soa&, std::size_t) { return intersect_sphere_algebraic(r, s); }
};

struct TriangleLectureSpec {
  static constexpr const char* kernel = "triangle";
  static constexpr const char* method = "lecture";
  using Input = std::array<Vec3f, 3>;
  using Soa = TriLectureSoA;
  static Input make(int cls, int k, Rng& g) { return bench_triangle(cls, k, g); }
  static Soa build(const std::vector<Input>& in) { return Soa::build(in); }
  static std::size_t count(const Soa& s) { return s.real; }
  static Ray<float> ray(int cls, Rng& g) { return default_ray(cls, g); }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const TriLecture<F>& q, const Soa& s, std::size_t j) {
    return intersect_triangle_lecture(r, q, s.axis_of(j));
  }
};

struct TriangleMTSpec : PlainSoaSpec<Triangle> {
  static constexpr const char* kernel = "triangle";
  static constexpr const char* method = "moller_trumbore";
  static Input make(int cls, int k, Rng& g) {
    const auto t = bench_triangle(cls, k, g);
    return make_triangle(t[0], t[1], t[2]);
  }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Triangle<F>& q, const Soa&, std::size_t) { return intersect_triangle_mt(r, q); }
};

struct BoxSpec : PlainSoaSpec<Box> {
  static constexpr const char* kernel = "box";
  static constexpr const char* method = "slab";
  static Input make(int cls, int k, Rng& g) {
    const Vec3f c{10.f * float(cls), 0.f, 3.f * float(k)};
    const Vec3f h{uni(g, 0.6f, 1.f), uni(g, 0.6f, 1.f), uni(g, 0.5f, 1.f)};
    return make_box(c - h, c + h);
  }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Box<F>& b, const Soa&, std::size_t) { return intersect_box(r, b); }
};

// Every benchmarked (kernel, method) of the basic family (plane, triangle, sphere, box). Other
// families list theirs in bench/specs_<family>.hpp.
template <class V>
void for_each_spec(V&& v) {
  v.template operator()<PlaneSpec>();
  v.template operator()<TriangleLectureSpec>();
  v.template operator()<TriangleMTSpec>();
  v.template operator()<SphereGeometricSpec>();
  v.template operator()<SphereAlgebraicSpec>();
  v.template operator()<BoxSpec>();
}

}  // namespace rb::bench
