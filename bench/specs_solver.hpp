// Bench specs of the solver kernel family (see bench/specs.hpp for the shape of a spec):
// torus (ferrari, robust), algebraic (derivative isolation, degree 4 and 6), implicit (sphere
// tracing, illinois) and surface of revolution (polynomial and Bezier profiles).
// Iterative specs also provide run_ic(ray, prim, IterCount*) for the ops table's iteration
// statistics. Class-c primitives sit around (10 c, 0, 3 k) with bounding radius < 1.5, so the
// class-0 rays (from z = -50 along +z, |x|, |y| <= 0.3) hit them and class-1 rays miss them.
#pragma once

#include "bench/specs.hpp"
#include "kernels/algebraic.hpp"
#include "kernels/implicit.hpp"
#include "kernels/revolution.hpp"
#include "kernels/torus.hpp"

namespace rb::bench {

// Ring radius 1, tube 0.35..0.45, axis near x: the rays along z cross the tube at y ~ 0.
inline Torus<float> bench_torus(int cls, int k, Rng& g) {
  const Vec3f c{10.f * float(cls) + uni(g, -0.05f, 0.05f), uni(g, -0.05f, 0.05f), 3.f * float(k)};
  return make_torus(c, Vec3f{1.f, uni(g, -0.1f, 0.1f), uni(g, -0.1f, 0.1f)}, 1.f, uni(g, 0.35f, 0.45f));
}

struct TorusFerrariSpec : PlainSoaSpec<Torus> {
  static constexpr const char* kernel = "torus";
  static constexpr const char* method = "ferrari";
  static Input make(int cls, int k, Rng& g) { return bench_torus(cls, k, g); }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Torus<F>& t, const Soa&, std::size_t) { return intersect_torus_ferrari(r, t); }
};

struct TorusRobustSpec : TorusFerrariSpec {
  static constexpr const char* method = "robust";
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Torus<F>& t, const Soa&, std::size_t) { return intersect_torus_robust(r, t); }
  template <class F>
  static RB_INLINE Hit<F> run_ic(const Ray<F>& r, const Torus<F>& t, IterCount* ic) { return intersect_torus_robust(r, t, ic); }
};

// The same tori as degree-4 algebraic surfaces (seed 000's T_ab with the axis along z rotated
// to x by swapping coordinates: (x^2+y^2+z^2-R^2-r^2)^2 - 4R^2(r^2 - x^2)).
inline Algebraic4<float> bench_alg_torus(int cls, int k, Rng& g) {
  const Vec3d c{10.0 * cls + double(uni(g, -0.05f, 0.05f)), double(uni(g, -0.05f, 0.05f)), 3.0 * k};
  const double R = 1.0, r = double(uni(g, 0.35f, 0.45f));
  const TriPoly X = TriPoly::linear(-c.x, 1, 0, 0), Y = TriPoly::linear(-c.y, 0, 1, 0), Z = TriPoly::linear(-c.z, 0, 0, 1);
  const TriPoly G = X * X + Y * Y + Z * Z + TriPoly::constant(-R * R - r * r);
  return {make_algebraic<4>(G * G + (4.0 * R * R) * (X * X + TriPoly::constant(-r * r)), c, R + r)};
}

struct AlgebraicD4Spec : PlainSoaSpec<Algebraic4> {
  static constexpr const char* kernel = "algebraic";
  static constexpr const char* method = "isolation_d4";
  static Input make(int cls, int k, Rng& g) { return bench_alg_torus(cls, k, g); }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Algebraic4<F>& a, const Soa&, std::size_t) { return intersect_algebraic<4>(r, a); }
  template <class F>
  static RB_INLINE Hit<F> run_ic(const Ray<F>& r, const Algebraic4<F>& a, IterCount* ic) { return intersect_algebraic<4>(r, a, ic); }
};

// Degree 6: the product of three spheres of radius ~0.5 strung along the x axis.
inline Algebraic6<float> bench_alg_spheres3(int cls, int k, Rng& g) {
  const Vec3d c{10.0 * cls + double(uni(g, -0.05f, 0.05f)), double(uni(g, -0.05f, 0.05f)), 3.0 * k};
  const double r = double(uni(g, 0.45f, 0.55f));
  const TriPoly p = tri_sphere({c.x - 0.8, c.y, c.z}, r) * tri_sphere(c, r) * tri_sphere({c.x + 0.8, c.y, c.z}, r);
  return {make_algebraic<6>(p, c, 1.4)};
}

struct AlgebraicD6Spec : PlainSoaSpec<Algebraic6> {
  static constexpr const char* kernel = "algebraic";
  static constexpr const char* method = "isolation_d6";
  static Input make(int cls, int k, Rng& g) { return bench_alg_spheres3(cls, k, g); }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Algebraic6<F>& a, const Soa&, std::size_t) { return intersect_algebraic<6>(r, a); }
  template <class F>
  static RB_INLINE Hit<F> run_ic(const Ray<F>& r, const Algebraic6<F>& a, IterCount* ic) { return intersect_algebraic<6>(r, a, ic); }
};

// The slide's surface with a = 1, c = 0.5 in a ball of radius 1.4: on the axis x = y = 0 it is
// 0.5 cos z = 0, so the rays along z meet it near z = -pi/2 + 3k... inside the ball.
inline Wavy<float> bench_wavy(int cls, int k, Rng& g) {
  const Vec3f c{10.f * float(cls) + uni(g, -0.05f, 0.05f), uni(g, -0.05f, 0.05f), 3.f * float(k)};
  return make_wavy(c, 1.f + uni(g, -0.05f, 0.05f), 0.5f, 1.7f);
}

struct ImplicitSphereTraceSpec : PlainSoaSpec<Wavy> {
  static constexpr const char* kernel = "implicit";
  static constexpr const char* method = "sphere_tracing";
  static Input make(int cls, int k, Rng& g) { return bench_wavy(cls, k, g); }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Wavy<F>& w, const Soa&, std::size_t) { return intersect_wavy_sphere_trace(r, w); }
  template <class F>
  static RB_INLINE Hit<F> run_ic(const Ray<F>& r, const Wavy<F>& w, IterCount* ic) { return intersect_wavy_sphere_trace(r, w, ic); }
};

struct ImplicitIllinoisSpec : ImplicitSphereTraceSpec {
  static constexpr const char* method = "illinois";
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Wavy<F>& w, const Soa&, std::size_t) { return intersect_wavy_illinois(r, w); }
  template <class F>
  static RB_INLINE Hit<F> run_ic(const Ray<F>& r, const Wavy<F>& w, IterCount* ic) { return intersect_wavy_illinois(r, w, ic); }
};

// Surfaces of revolution with the axis tilted 45 degrees from the rays (z1 ~ 0.7, the general
// case of the elimination), profile extent < 1.5.
inline Vec3f bench_rev_axis(Rng& g) { return Vec3f{1.f + uni(g, -0.05f, 0.05f), uni(g, -0.05f, 0.05f), 1.f}; }

struct RevolutionPolySpec : PlainSoaSpec<Revolution> {
  static constexpr const char* kernel = "revolution";
  static constexpr const char* method = "polynomial";
  // A vase: r(s) = 0.8 - 0.6 s + 0.5 s^2, z(s) = -1 + 2 s.
  static Input make(int cls, int k, Rng& g) {
    const Vec3f c{10.f * float(cls), uni(g, -0.05f, 0.05f), 3.f * float(k)};
    return make_revolution_poly(c, bench_rev_axis(g), {0.8, -0.6, 0.5, 0.0}, {-1.0, 2.0, 0.0, 0.0});
  }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Revolution<F>& s, const Soa&, std::size_t) { return intersect_revolution(r, s); }
  template <class F>
  static RB_INLINE Hit<F> run_ic(const Ray<F>& r, const Revolution<F>& s, IterCount* ic) { return intersect_revolution(r, s, ic); }
};

struct RevolutionBezierSpec : RevolutionPolySpec {
  static constexpr const char* method = "bezier";
  // A closed bulge: control points (0, -1), (1.3, -1), (1.3, 1), (0, 1).
  static Input make(int cls, int k, Rng& g) {
    const Vec3f c{10.f * float(cls), uni(g, -0.05f, 0.05f), 3.f * float(k)};
    return make_revolution_bezier(c, bench_rev_axis(g), {{{0.0, -1.0}, {1.3, -1.0}, {1.3, 1.0}, {0.0, 1.0}}});
  }
};

// Every benchmarked (kernel, method) of this family.
template <class V>
void for_each_spec_solver(V&& v) {
  v.template operator()<TorusFerrariSpec>();
  v.template operator()<TorusRobustSpec>();
  v.template operator()<AlgebraicD4Spec>();
  v.template operator()<AlgebraicD6Spec>();
  v.template operator()<ImplicitSphereTraceSpec>();
  v.template operator()<ImplicitIllinoisSpec>();
  v.template operator()<RevolutionPolySpec>();
  v.template operator()<RevolutionBezierSpec>();
}

}  // namespace rb::bench
