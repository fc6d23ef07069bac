// The quadric kernel family: sphere stable / Hearn-Baker / [u,v] / roots, the general
// quadric (matrix and ten-coefficient methods) with every named quadric of seed 004, the quadric
// of revolution, cylinder and cone (open and capped), and transformed instances.
//   - hand-worked hits, misses, t, normals, [u,v], typed over the value types
//     (float, double, f8, d4; Counted<T> computes what T computes: tests/kernel_test_util.hpp);
//   - seeded random rays checked independently in double (hit points on the surface, misses
//     against a dense sampling of the implicit function, capped solids against caps + lateral);
//   - SIMD lanes (both mappings) equal the scalar float result bit for bit (-ffp-contract=off);
//   - golden Counted<float> op counts; degenerate inputs; stable vs naive accuracy.
#include "kernels/cylinder_cone.hpp"
#include "kernels/quadric.hpp"
#include "kernels/sphere.hpp"
#include "kernels/transform.hpp"
#include "kernel_test_util.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <tuple>
#include <vector>

namespace rb::test {
namespace {

template <class F>
struct QuadricKernels : ::testing::Test {};
TYPED_TEST_SUITE(QuadricKernels, ValueNumbers);

constexpr double kTolQuadric = 2e-5;  // on t for float data, hand cases (|t| <= 20)
const double kSqrt2 = std::sqrt(2.0);

Ray<float> ray(Vec3f o, Vec3f d, float t0 = 0.f, float t1 = kInfF) { return make_ray(o, d, t0, t1); }

template <class F, template <class> class P, class Fn>
Vec3d lane_vec(Fn fn, const P<float>& p, Vec3f at) {
  const Vec3<F> n = fn(prim_cast<F>(p), Vec3<F>{F(at.x), F(at.y), F(at.z)});
  return {double(lane(n.x, 0)), double(lane(n.y, 0)), double(lane(n.z, 0))};
}

template <class F, template <class> class P, class Fn>
std::pair<double, double> lane_roots(Fn fn, const Ray<float>& r, const P<float>& p, bool* valid) {
  const Roots<F, 2> rt = fn(Ray<F>::broadcast(r), prim_cast<F>(p));
  *valid = lane_mask<F>(rt.valid[0], 0);
  EXPECT_EQ(lane_mask<F>(rt.valid[1], 0), *valid);
  return {double(lane(rt.t[0], 0)), double(lane(rt.t[1], 0))};
}

#define EXPECT_VEC_NEAR(a, ex, ey, ez, tol) \
  do {                                      \
    EXPECT_NEAR((a).x, (ex), (tol));        \
    EXPECT_NEAR((a).y, (ey), (tol));        \
    EXPECT_NEAR((a).z, (ez), (tol));        \
  } while (0)

// ---- spheres ------------------------------------------------------------------------------------
TYPED_TEST(QuadricKernels, SphereStableAndHearnBaker) {
  using F = TypeParam;
  const auto s = make_sphere(Vec3f{0, 0, 10}, 2.f);
  for (int m = 0; m < 2; ++m) {
    auto run = [&](const Ray<float>& r) {
      return m == 0 ? run_one<F>(RB_KERNEL(intersect_sphere_stable), r, s) : run_one<F>(RB_KERNEL(intersect_sphere_hearn_baker), r, s);
    };
    HitF h = run(ray({0, 0, 0}, {0, 0, 1}));
    EXPECT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 8.0, kTolQuadric);
    h = run(ray({0, 0, 10}, {0, 1, 0}));  // inside: the far root
    EXPECT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 2.0, kTolQuadric);
    h = run(ray({1.2f, 0, 0}, {0, 0, 1}));
    EXPECT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 8.4, kTolQuadric);
    h = run(ray({0, 0, 20}, {0, 0, -1}));  // b > 0: the other sign branch of q
    EXPECT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 8.0, kTolQuadric);
    EXPECT_FALSE(run(ray({3, 0, 0}, {0, 0, 1})).hit);
    EXPECT_FALSE(run(ray({0, 0, 0}, {0, 0, -1})).hit);
    EXPECT_FALSE(run(ray({0, 0, 0}, {0, 0, 1}, 0.f, 7.f)).hit);
    for (float r : {0.f, -1.f, kNaNF, kInfF}) {
      const HitF d = m == 0 ? run_one<F>(RB_KERNEL(intersect_sphere_stable), ray({0, 0, 0}, {0, 0, 1}), make_sphere(Vec3f{0, 0, 10}, r))
                            : run_one<F>(RB_KERNEL(intersect_sphere_hearn_baker), ray({0, 0, 0}, {0, 0, 1}), make_sphere(Vec3f{0, 0, 10}, r));
      EXPECT_FALSE(d.hit) << r;
      EXPECT_EQ(d.t, kInfD);
    }
  }
  bool v = false;
  auto [t0, t1] = lane_roots<F>(RB_KERNEL(sphere_roots), ray({0, 0, 0}, {0, 0, 1}), s, &v);
  EXPECT_TRUE(v);
  EXPECT_NEAR(t0, 8.0, kTolQuadric);
  EXPECT_NEAR(t1, 12.0, kTolQuadric);
  std::tie(t0, t1) = lane_roots<F>(RB_KERNEL(sphere_roots), ray({0, 0, 20}, {0, 0, 1}), s, &v);  // behind: still reported
  EXPECT_TRUE(v);
  EXPECT_NEAR(t0, -12.0, kTolQuadric);
  EXPECT_NEAR(t1, -8.0, kTolQuadric);
  std::tie(t0, t1) = lane_roots<F>(RB_KERNEL(sphere_roots), ray({3, 0, 0}, {0, 0, 1}), s, &v);
  EXPECT_FALSE(v);
  EXPECT_EQ(t0, kInfD);
  EXPECT_EQ(t1, kInfD);
}

TYPED_TEST(QuadricKernels, SphereUV) {
  using F = TypeParam;
  // Pole +z, equator +x: P x E = +y.
  const auto s = make_sphere_uv(Vec3f{0, 0, 10}, 2.f, Vec3f{0, 0, 1}, Vec3f{1, 0, 0});
  auto uv = [&](Vec3d N) {  // a ray from outside along -N onto c + 2N
    const Vec3d c{0, 0, 10};
    const HitF h = run_one<F>(RB_KERNEL(intersect_sphere_uv), ray(to_float(c + N * 5.0), to_float(N * -1.0)), s);
    EXPECT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 3.0, kTolQuadric);
    return std::pair<double, double>{h.u, h.v};
  };
  const double tol = 2e-6;
  auto check = [&](Vec3d N, double u, double v) {
    const auto [hu, hv] = uv(N);
    EXPECT_NEAR(hu, u, tol) << N.x << " " << N.y << " " << N.z;
    EXPECT_NEAR(hv, v, tol) << N.x << " " << N.y << " " << N.z;
  };
  check({-1, 0, 0}, 0.5, 0.5);   // N.E = -1: theta = 1/2; (PxE).N = 0: u = 1 - theta
  check({0, -1, 0}, 0.75, 0.5);  // theta = 1/4, (PxE).N < 0
  check({0, 1, 0}, 0.25, 0.5);   // theta = 1/4, (PxE).N > 0
  check({0, 0, 1}, 0.5, 1.0);    // north pole: Phi = pi, sin Phi = 0 -> u = 1/2 (defined)
  check({0, 0, -1}, 0.5, 0.0);   // south pole
  {
    const Vec3d N{0.6, 0.48, 0.64};
    const double phi = std::acos(-0.64), theta = std::acos(0.6 / std::sin(phi)) / (2 * M_PI);
    check(N, theta, phi / M_PI);
  }
  {
    const Vec3d N{0.6, -0.48, -0.64};
    const double phi = std::acos(0.64), theta = std::acos(0.6 / std::sin(phi)) / (2 * M_PI);
    check(N, 1 - theta, phi / M_PI);
  }
  // A miss has u = v = 0 and t = +inf.
  const HitF m = run_one<F>(RB_KERNEL(intersect_sphere_uv), ray({5, 0, 0}, {0, 0, 1}), s);
  EXPECT_FALSE(m.hit);
  EXPECT_EQ(m.t, kInfD);
  EXPECT_EQ(m.u, 0.0);
  EXPECT_EQ(m.v, 0.0);
}

TEST(QuadricKernelsScalar, SphereUVConstruction) {
  // A zero or NaN pole, or an equator parallel to it: never(), with the reason.
  const auto r0 = make_ray(Vec3f{0, 0, -5}, Vec3f{0, 0, 1});
  for (const auto& [pole, eq, part] : {std::tuple{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, "pole"}, std::tuple{Vec3f{0, 0, 1}, Vec3f{0, 0, 2}, "parallel"},
                                       std::tuple{Vec3f{kNaNF, 0, 1}, Vec3f{1, 0, 0}, "pole"}}) {
    std::string why;
    const auto bad = make_sphere_uv(Vec3f{0, 0, 0}, 1.f, pole, eq, &why);
    EXPECT_NE(why.find(part), std::string::npos) << why;
    EXPECT_FALSE(intersect_sphere_uv(r0, bad).mask);
  }
  // A non-orthogonal equator is made orthogonal; a zero radius is never().
  const auto s = make_sphere_uv(Vec3f{0, 0, 0}, 1.f, Vec3f{0, 0, 2}, Vec3f{1, 0, 1});
  EXPECT_NEAR(s.E.x, 1.f, 1e-7);
  EXPECT_NEAR(s.E.z, 0.f, 1e-7);
  EXPECT_FALSE(make_sphere_uv(Vec3f{0, 0, 0}, 0.f).s.r2 > 0.f);
}

// ---- general quadric: every named quadric of seed 004 --------------------------------------------
struct NamedCase {
  const char* name;
  QuadricCoeffs q;
  Vec3f o, d;
  double t;  // < 0: miss
};
std::vector<NamedCase> named_cases() {
  using namespace quadrics;
  return {
      {"ellipsoid", ellipsoid(1, 2, 3), {0, 0, -10}, {0, 0, 1}, 7},
      {"ellipsoid side", ellipsoid(1, 2, 3), {0, -10, 0}, {0, 1, 0}, 8},
      {"ellipsoid miss", ellipsoid(1, 2, 3), {1.5f, 0, -10}, {0, 0, 1}, -1},
      {"elliptic cylinder", elliptic_cylinder(2, 1), {-10, 0, 0}, {1, 0, 0}, 8},
      {"elliptic cylinder along axis", elliptic_cylinder(2, 1), {0, 0, -10}, {0, 0, 1}, -1},
      {"hyperboloid 1 sheet", hyperboloid_one_sheet(1, 1, 1), {-10, 0, 0}, {1, 0, 0}, 9},
      {"hyperboloid 1 sheet, axis", hyperboloid_one_sheet(1, 1, 1), {0, 0, -10}, {0, 0, 1}, -1},
      {"hyperboloid 1 sheet at z=1", hyperboloid_one_sheet(1, 1, 1), {-10, 0, 1}, {1, 0, 0}, 10 - std::sqrt(2.0)},
      {"hyperboloid 2 sheets", hyperboloid_two_sheets(1, 1, 1), {0, 0, -10}, {0, 0, 1}, 9},
      {"hyperboloid 2 sheets, between", hyperboloid_two_sheets(1, 1, 1), {-10, 0, 0}, {1, 0, 0}, -1},
      {"elliptic cone", elliptic_cone(1, 1), {-10, 0, 1}, {1, 0, 0}, 9},
      {"elliptic cone 2:1", elliptic_cone(2, 1), {0, -10, 1}, {0, 1, 0}, 9},
      {"elliptic paraboloid, axial (A = 0)", elliptic_paraboloid(1, 1), {0.5f, 0, 10}, {0, 0, -1}, 9.75},
      {"elliptic paraboloid, vertex (A = 0)", elliptic_paraboloid(1, 1), {0, 0, -5}, {0, 0, 1}, 5},
      {"elliptic paraboloid, across", elliptic_paraboloid(1, 1), {-10, 0, 4}, {1, 0, 0}, 8},
      {"hyperbolic paraboloid (A = 0)", hyperbolic_paraboloid(1, 1), {1, 2, 10}, {0, 0, -1}, 7},
      {"hyperbolic paraboloid, across", hyperbolic_paraboloid(1, 1), {-10, 0, -1}, {1, 0, 0}, 9},
      {"parabolic cylinder (A = 0)", parabolic_cylinder(), {2, 10, 0}, {0, -1, 0}, 12},
      {"parabolic cylinder, across", parabolic_cylinder(), {-10, -2, 0}, {1, 0, 0}, 8},
      {"hyperbolic cylinder", hyperbolic_cylinder(1, 1), {-10, 0, 0}, {1, 0, 0}, 9},
      {"hyperbolic cylinder, between", hyperbolic_cylinder(1, 1), {0, -10, 0}, {0, 1, 0}, -1},
      {"placed ellipsoid", ellipsoid(1, 2, 3).placed(Affine3d::translate({1, 2, 3}) * Affine3d::rotate({0, 1, 0}, M_PI / 2)),
       {-10, 2, 3}, {1, 0, 0}, 8},  // the z semi-axis 3 now along x, centre x = 1: entry at x = -2
  };
}

TYPED_TEST(QuadricKernels, NamedQuadricsBothMethods) {
  using F = TypeParam;
  for (const auto& c : named_cases()) {
    const auto q = make_quadric(c.q);
    double Q[4][4];
    c.q.matrix(Q);
    const auto qm = make_quadric_matrix(Q);
    for (int m = 0; m < 2; ++m) {
      const HitF h = m == 0 ? run_one<F>(RB_KERNEL(intersect_quadric_matrix), ray(c.o, c.d), qm)
                            : run_one<F>(RB_KERNEL(intersect_quadric_coeffs10), ray(c.o, c.d), q);
      if (c.t < 0) {
        EXPECT_FALSE(h.hit) << c.name << " method " << m;
        EXPECT_EQ(h.t, kInfD) << c.name;
        continue;
      }
      ASSERT_TRUE(h.hit) << c.name << " method " << m;
      EXPECT_NEAR(h.t, c.t, 1e-4) << c.name << " method " << m;
      // The hit point satisfies the equation (relative to the gradient: a distance).
      const Vec3d p = to_double(c.o) + to_double(ray(c.o, c.d).d) * h.t;
      const Vec3d g = c.q.half_gradient(p);
      EXPECT_LT(std::fabs(c.q.value(p)) / (2 * std::sqrt(dot(g, g))), 1e-4) << c.name;
    }
  }
  // Normal: ellipsoid(1, 2, 3) at (0, 0, -3) is (0, 0, -1); at (1, 0, 0) it is (1, 0, 0).
  const auto e = make_quadric(quadrics::ellipsoid(1, 2, 3));
  Vec3d n = lane_vec<F>(RB_KERNEL(quadric_normal), e, Vec3f{0, 0, -3});
  EXPECT_VEC_NEAR(n, 0.0, 0.0, -1.0, 1e-6);
  n = lane_vec<F>(RB_KERNEL(quadric_normal), e, Vec3f{1, 0, 0});
  EXPECT_VEC_NEAR(n, 1.0, 0.0, 0.0, 1e-6);
  // Elliptic cone z^2 = x^2 + y^2 at (1, 0, 1): gradient (1, 0, -1) / sqrt 2.
  n = lane_vec<F>(RB_KERNEL(quadric_normal), make_quadric(quadrics::elliptic_cone(1, 1)), Vec3f{1, 0, 1});
  EXPECT_VEC_NEAR(n, 1 / kSqrt2, 0.0, -1 / kSqrt2, 1e-6);
}

TYPED_TEST(QuadricKernels, DegenerateQuadrics) {
  using F = TypeParam;
  const auto r = ray({0, 0, -5}, {0, 0, 1});
  // Singular Q: all zero, or constant only, or non-finite: never() (a defined miss).
  for (const QuadricCoeffs& q : {QuadricCoeffs{}, QuadricCoeffs{0, 0, 0, 0, 0, 0, 0, 0, 0, 1}, QuadricCoeffs{1, 1, 1, 0, 0, 0, 0, 0, 0, kInfD},
                                 QuadricCoeffs{std::nan(""), 1, 1, 0, 0, 0, 0, 0, 0, -1}}) {
    for (int m = 0; m < 2; ++m) {
      const HitF h = m == 0 ? run_one<F>(RB_KERNEL(intersect_quadric_matrix), r, make_quadric(q))
                            : run_one<F>(RB_KERNEL(intersect_quadric_coeffs10), r, make_quadric(q));
      EXPECT_FALSE(h.hit);
      EXPECT_EQ(h.t, kInfD);
    }
  }
  // A plane written as a quadric (a2 = 0 for every ray, 2j z + k): the linear case only.
  const auto plane = make_quadric(QuadricCoeffs{0, 0, 0, 0, 0, 0, 0, 0, 0.5, -2});  // z = 2
  HitF h = run_one<F>(RB_KERNEL(intersect_quadric_coeffs10), r, plane);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 7.0, kTolQuadric);
  h = run_one<F>(RB_KERNEL(intersect_quadric_matrix), ray({0, 0, -5}, {1, 0, 0}), plane);  // parallel: A = B = 0
  EXPECT_FALSE(h.hit);
  EXPECT_EQ(h.t, kInfD);
}

TEST(QuadricKernelsScalar, QuadricConstruction) {
  double Q[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, -1}};
  std::string why;
  (void)make_quadric_matrix(Q, &why);
  EXPECT_TRUE(why.empty()) << why;
  Q[0][1] = 0.5;  // not symmetric: never(), with the reason
  const auto asym = make_quadric_matrix(Q, &why);
  EXPECT_NE(why.find("not symmetric"), std::string::npos) << why;
  EXPECT_FALSE(intersect_quadric_matrix(make_ray(Vec3f{0, 0, -5}, Vec3f{0, 0, 1}), asym).mask);
  // Large coefficients are scaled into float range without changing the surface.
  const auto q = make_quadric(QuadricCoeffs{1e30, 1e30, 1e30, 0, 0, 0, 0, 0, 0, -4e30});
  const HitF h = run_one<float>(RB_KERNEL(intersect_quadric_coeffs10), ray({0, 0, -5}, {0, 0, 1}), q);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 3.0, kTolQuadric);
}

// ---- quadric of revolution ------------------------------------------------------------------------
TYPED_TEST(QuadricKernels, QuadricOfRevolution) {
  using F = TypeParam;
  auto k = RB_KERNEL(intersect_quadric_rev);
  // Sphere (a = 1, b = 0, c = -4) about (0, 0, 10).
  const auto s = make_quadric_rev(Vec3f{0, 0, 10}, 1.f, 0.f, -4.f);
  HitF h = run_one<F>(k, ray({0, 0, 0}, {0, 0, 1}), s);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 8.0, kTolQuadric);
  // Paraboloid x^2 + y^2 - z = 0 (a = 0, b = -1): axial ray, the linear case, hits z = 1.
  const auto p = make_quadric_rev(Vec3f{0, 0, 0}, 0.f, -1.f, 0.f);
  h = run_one<F>(k, ray({1, 0, 10}, {0, 0, -1}), p);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 9.0, kTolQuadric);
  // Hyperboloid of one sheet x^2 + y^2 - z^2 - 1 = 0 (a = -1): ray along x at z = 0.
  const auto hy = make_quadric_rev(Vec3f{0, 0, 0}, -1.f, 0.f, -1.f);
  h = run_one<F>(k, ray({-10, 0, 0}, {1, 0, 0}), hy);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 9.0, kTolQuadric);
  EXPECT_FALSE(run_one<F>(k, ray({0, 0, -10}, {0, 0, 1}), hy).hit);
  // Normals.
  Vec3d n = lane_vec<F>(RB_KERNEL(quadric_rev_normal), s, Vec3f{0, 0, 8});
  EXPECT_VEC_NEAR(n, 0.0, 0.0, -1.0, 1e-6);
  n = lane_vec<F>(RB_KERNEL(quadric_rev_normal), p, Vec3f{1, 0, 1});  // (1, 0, -1/2) normalised
  EXPECT_VEC_NEAR(n, 2 / std::sqrt(5.0), 0.0, -1 / std::sqrt(5.0), 1e-6);
  // Non-finite: never().
  EXPECT_FALSE(run_one<F>(k, ray({0, 0, 0}, {0, 0, 1}), make_quadric_rev(Vec3f{0, 0, 10}, kNaNF, 0.f, -4.f)).hit);
}

// ---- cylinder and cone ------------------------------------------------------------------------------
TYPED_TEST(QuadricKernels, Cylinder) {
  using F = TypeParam;
  const auto c = make_cylinder(0.f, 0.f, 1.f, -1.f, 1.f);
  auto open = [&](const Ray<float>& r) { return run_one<F>(RB_KERNEL(intersect_cylinder), r, c); };
  auto capped = [&](const Ray<float>& r) { return run_one<F>(RB_KERNEL(intersect_cylinder_capped), r, c); };
  HitF a = open(ray({-5, 0, 0}, {1, 0, 0})), b = capped(ray({-5, 0, 0}, {1, 0, 0}));
  EXPECT_TRUE(a.hit && b.hit);
  EXPECT_NEAR(a.t, 4.0, kTolQuadric);
  EXPECT_NEAR(b.t, 4.0, kTolQuadric);
  // Along the axis (A = 0): the tube is missed, the capped solid is hit on its bottom cap.
  EXPECT_FALSE(open(ray({0.5f, 0, -5}, {0, 0, 1})).hit);
  b = capped(ray({0.5f, 0, -5}, {0, 0, 1}));
  EXPECT_TRUE(b.hit);
  EXPECT_NEAR(b.t, 4.0, kTolQuadric);
  EXPECT_FALSE(capped(ray({1.5f, 0, -5}, {0, 0, 1})).hit);  // parallel, outside
  // Above the height range; from inside (the exit).
  EXPECT_FALSE(open(ray({-5, 0, 1.5f}, {1, 0, 0})).hit);
  EXPECT_FALSE(capped(ray({-5, 0, 1.5f}, {1, 0, 0})).hit);
  a = open(ray({0, 0, 0}, {1, 0, 0}));
  b = capped(ray({0, 0, 0}, {1, 0, 0}));
  EXPECT_NEAR(a.t, 1.0, kTolQuadric);
  EXPECT_NEAR(b.t, 1.0, kTolQuadric);
  // Oblique (1, 0, 1)/sqrt 2 from (-2, 0, -3): the tube is first met at x = 1, z = 0 (u = 3);
  // the solid is entered through the bottom cap at z = -1, x = 0 (u = 2).
  a = open(ray({-2, 0, -3}, {1, 0, 1}));
  b = capped(ray({-2, 0, -3}, {1, 0, 1}));
  EXPECT_NEAR(a.t, 3 * kSqrt2, kTolQuadric);
  EXPECT_NEAR(b.t, 2 * kSqrt2, kTolQuadric);
  bool v = false;
  auto [t0, t1] = lane_roots<F>(RB_KERNEL(cylinder_roots), ray({-2, 0, -3}, {1, 0, 1}), c, &v);
  EXPECT_TRUE(v);
  EXPECT_NEAR(t0, 2 * kSqrt2, kTolQuadric);
  EXPECT_NEAR(t1, 3 * kSqrt2, kTolQuadric);
  std::tie(t0, t1) = lane_roots<F>(RB_KERNEL(cylinder_roots), ray({0.5f, 0, -5}, {0, 0, 1}), c, &v);
  EXPECT_TRUE(v);
  EXPECT_NEAR(t0, 4.0, kTolQuadric);
  EXPECT_NEAR(t1, 6.0, kTolQuadric);
  std::tie(t0, t1) = lane_roots<F>(RB_KERNEL(cylinder_roots), ray({-5, 0, 1.5f}, {1, 0, 0}), c, &v);
  EXPECT_FALSE(v);
  EXPECT_EQ(t0, kInfD);
  // Normals: lateral, and the capped solid's caps.
  Vec3d n = lane_vec<F>(RB_KERNEL(cylinder_normal), c, Vec3f{-1, 0, 0.3f});
  EXPECT_VEC_NEAR(n, -1.0, 0.0, 0.0, 1e-6);
  n = lane_vec<F>(RB_KERNEL(capped_cylinder_normal), c, Vec3f{0.5f, 0, -1});
  EXPECT_VEC_NEAR(n, 0.0, 0.0, -1.0, 1e-6);
  n = lane_vec<F>(RB_KERNEL(capped_cylinder_normal), c, Vec3f{0.2f, 0.1f, 1});
  EXPECT_VEC_NEAR(n, 0.0, 0.0, 1.0, 1e-6);
  n = lane_vec<F>(RB_KERNEL(capped_cylinder_normal), c, Vec3f{0, 1, 0.5f});
  EXPECT_VEC_NEAR(n, 0.0, 1.0, 0.0, 1e-6);
  // An infinite cylinder (no caps in reach) and a translated, wider one.
  const auto inf = make_cylinder(0.f, 0.f, 1.f, -kInfF, kInfF);
  EXPECT_NEAR((run_one<F>(RB_KERNEL(intersect_cylinder), ray({-5, 0, 1e3f}, {1, 0, 0}), inf).t), 4.0, kTolQuadric);
  EXPECT_NEAR((run_one<F>(RB_KERNEL(intersect_cylinder_capped), ray({-5, 0, 1e3f}, {1, 0, 0}), inf).t), 4.0, kTolQuadric);
  EXPECT_NEAR((run_one<F>(RB_KERNEL(intersect_cylinder), ray({0, 0, 0}, {1, 0, 0}), make_cylinder(5.f, 0.f, 2.f, -1.f, 1.f)).t), 3.0, kTolQuadric);
  // Degenerate: r = 0, r < 0, zero height, inverted, NaN: never() -> miss.
  for (const auto& d : {make_cylinder(0.f, 0.f, 0.f, -1.f, 1.f), make_cylinder(0.f, 0.f, -1.f, -1.f, 1.f), make_cylinder(0.f, 0.f, 1.f, 1.f, 1.f),
                        make_cylinder(0.f, 0.f, 1.f, 1.f, -1.f), make_cylinder(kNaNF, 0.f, 1.f, -1.f, 1.f), make_cylinder(0.f, 0.f, 1.f, kNaNF, 1.f)}) {
    for (const auto& r : {ray({-5, 0, 0}, {1, 0, 0}), ray({0, 0, -5}, {0, 0, 1}), ray({0, 0, 0}, {1, 0, 0})}) {
      EXPECT_FALSE((run_one<F>(RB_KERNEL(intersect_cylinder), r, d).hit));
      const HitF hc = run_one<F>(RB_KERNEL(intersect_cylinder_capped), r, d);
      EXPECT_FALSE(hc.hit);
      EXPECT_EQ(hc.t, kInfD);
    }
  }
}

TYPED_TEST(QuadricKernels, Cone) {
  using F = TypeParam;
  const auto dbl = make_cone(Vec3f{0, 0, 0}, -2.f, 2.f);  // both nappes, open
  auto open = [&](const Ray<float>& r, const Cone<float>& c) { return run_one<F>(RB_KERNEL(intersect_cone), r, c); };
  auto capped = [&](const Ray<float>& r, const Cone<float>& c) { return run_one<F>(RB_KERNEL(intersect_cone_capped), r, c); };
  HitF h = open(ray({-5, 0, 1}, {1, 0, 0}), dbl);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 4.0, kTolQuadric);
  h = open(ray({0.5f, 0, -5}, {0, 0, 1}), dbl);  // A < 0: lower nappe first, at z = -0.5
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 4.5, kTolQuadric);
  // Parallel to a generator (A = 0): the linear root, on the upper nappe at (-1.5, 0, 1.5).
  h = open(ray({-3, 0, 0}, {1, 0, 1}), dbl);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 1.5 * kSqrt2, kTolQuadric);
  // Frustum z in [1, 2] (radius 1..2), closed.
  const auto fr = make_capped_cone(Vec3f{0, 0, 0}, 1.f, 2.f);
  h = capped(ray({-5, 0, 1.5f}, {1, 0, 0}), fr);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 3.5, kTolQuadric);
  h = capped(ray({0.5f, 0, -5}, {0, 0, 1}), fr);  // steeper than the cone: the bottom cap at z = 1
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 6.0, kTolQuadric);
  EXPECT_FALSE(open(ray({0.5f, 0, -5}, {0, 0, 1}), fr).hit);  // the shell is met only outside [1, 2]
  h = capped(ray({0, 0, 5}, {0, 0, -1}), fr);  // from above: the top cap
  EXPECT_NEAR(h.t, 3.0, kTolQuadric);
  h = capped(ray({-3, 0, 0}, {1, 0, 1}), fr);  // A = 0: enters the lateral surface at z = 1.5
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 1.5 * kSqrt2, kTolQuadric);
  EXPECT_FALSE(capped(ray({-5, 0, 0.5f}, {1, 0, 0}), fr).hit);  // below the frustum
  // Lower nappe frustum z in [-2, -1] from below along the axis: bottom cap z = -2.
  h = capped(ray({0.2f, 0, -5}, {0, 0, 1}), make_capped_cone(Vec3f{0, 0, 0}, -2.f, -1.f));
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 3.0, kTolQuadric);
  bool v = false;
  auto [t0, t1] = lane_roots<F>(RB_KERNEL(cone_roots), ray({0.5f, 0, -5}, {0, 0, 1}), fr, &v);
  EXPECT_TRUE(v);
  EXPECT_NEAR(t0, 6.0, kTolQuadric);
  EXPECT_NEAR(t1, 7.0, kTolQuadric);
  // Normals.
  Vec3d n = lane_vec<F>(RB_KERNEL(cone_normal), fr, Vec3f{1.5f, 0, 1.5f});
  EXPECT_VEC_NEAR(n, 1 / kSqrt2, 0.0, -1 / kSqrt2, 1e-6);
  n = lane_vec<F>(RB_KERNEL(capped_cone_normal), fr, Vec3f{0.5f, 0, 1});
  EXPECT_VEC_NEAR(n, 0.0, 0.0, -1.0, 1e-6);
  n = lane_vec<F>(RB_KERNEL(capped_cone_normal), fr, Vec3f{0.5f, 0, 2});
  EXPECT_VEC_NEAR(n, 0.0, 0.0, 1.0, 1e-6);
  // Degenerate: zero height, NaN apex: never() -> miss; a capped range over the apex: error.
  for (const auto& d : {make_cone(Vec3f{0, 0, 0}, 1.f, 1.f), make_cone(Vec3f{kNaNF, 0, 0}, 1.f, 2.f), make_cone(Vec3f{0, 0, 0}, kNaNF, 2.f)}) {
    for (const auto& r : {ray({-5, 0, 1.5f}, {1, 0, 0}), ray({0.5f, 0, -5}, {0, 0, 1})}) {
      EXPECT_FALSE(open(r, d).hit);
      const HitF hc = capped(r, d);
      EXPECT_FALSE(hc.hit);
      EXPECT_EQ(hc.t, kInfD);
    }
  }
  std::string why;
  const auto two_nappes = make_capped_cone(Vec3f{0, 0, 0}, -1.f, 1.f, &why);
  EXPECT_NE(why.find("apex"), std::string::npos) << why;
  EXPECT_FALSE(intersect_cone_capped(make_ray(Vec3f{0.5f, 0, -5}, Vec3f{0, 0, 1}), two_nappes).mask);
}

// ---- transformed instances ----------------------------------------------------------------------------
TYPED_TEST(QuadricKernels, Transformed) {
  using F = TypeParam;
  auto sph = [](const auto& r, const auto& x) {
    return intersect_transformed(r, x, [](const auto& lr, const auto& p) { return intersect_sphere_stable(lr, p); });
  };
  const auto unit = make_sphere(Vec3f{0, 0, 0}, 1.f);
  // Uniform scale 2 at z = 10: t = 8 in world units (the local direction has length 1/2).
  auto x = make_transformed(Affine3d::translate({0, 0, 10}) * Affine3d::scale({2, 2, 2}), unit);
  HitF h = run_one<F>(sph, ray({0, 0, 0}, {0, 0, 1}), x);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 8.0, kTolQuadric);
  EXPECT_FALSE((run_one<F>(sph, ray({0, 0, 0}, {0, 0, 1}, 0.f, 7.f), x).hit));  // tmax in world units
  // Non-uniform: ellipsoid with semi-axis 3 along z; rotated so that semi-axis lies along x.
  x = make_transformed(Affine3d::translate({0, 0, 10}) * Affine3d::scale({1, 1, 3}), unit);
  EXPECT_NEAR((run_one<F>(sph, ray({0, 0, 0}, {0, 0, 1}), x).t), 7.0, kTolQuadric);
  x = make_transformed(Affine3d::translate({0, 0, 10}) * Affine3d::rotate({0, 1, 0}, M_PI / 2) * Affine3d::scale({1, 1, 3}), unit);
  EXPECT_NEAR((run_one<F>(sph, ray({0, 0, 0}, {0, 0, 1}), x).t), 9.0, 1e-4);
  EXPECT_NEAR((run_one<F>(sph, ray({-10, 0, 10}, {1, 0, 0}), x).t), 7.0, 1e-4);
  // World normal by (M^-1)^T at the world point (0, 0, 9): (0, 0, -1); at (-3, 0, 10): (-1, 0, 0).
  auto wn = [&](Vec3f p) {
    const auto xf = prim_cast<F>(x);
    const Vec3<F> n = transformed_normal(xf, Vec3<F>{F(p.x), F(p.y), F(p.z)}, [](const auto& s, const auto& q) { return sphere_normal(s, q); });
    return Vec3d{double(lane(n.x, 0)), double(lane(n.y, 0)), double(lane(n.z, 0))};
  };
  EXPECT_VEC_NEAR(wn({0, 0, 9}), 0.0, 0.0, -1.0, 1e-5);
  EXPECT_VEC_NEAR(wn({-3, 0, 10}), -1.0, 0.0, 0.0, 1e-5);
  // A sheared ellipsoid: the normal is the gradient of the world quadric.
  {
    const Affine3d M = Affine3d::translate({0, 0, 10}) * Affine3d::rotate({1, 2, 3}, 0.7) * Affine3d::scale({1, 2, 0.5});
    const auto xs = make_transformed(M, unit);
    const QuadricCoeffs wq = quadrics::ellipsoid(1, 1, 1).placed(M);
    const Ray<float> r = ray({0.2f, 0.1f, 0}, {0, 0, 1});
    const HitF hs = run_one<F>(sph, r, xs);
    const HitF hq = run_one<F>(RB_KERNEL(intersect_quadric_coeffs10), r, make_quadric(wq));
    ASSERT_TRUE(hs.hit && hq.hit);
    EXPECT_NEAR(hs.t, hq.t, 1e-4);
    const Vec3d p = to_double(r.o) + to_double(r.d) * hs.t;
    const auto xf = prim_cast<F>(xs);
    const Vec3<F> n = transformed_normal(xf, Vec3<F>{F(float(p.x)), F(float(p.y)), F(float(p.z))},
                                         [](const auto& s, const auto& q) { return sphere_normal(s, q); });
    Vec3d g = wq.half_gradient(p);
    g = g * (1.0 / std::sqrt(dot(g, g)));
    EXPECT_VEC_NEAR((Vec3d{double(lane(n.x, 0)), double(lane(n.y, 0)), double(lane(n.z, 0))}), g.x, g.y, g.z, 1e-4);
  }
  // Cylinder laid along x at z = 10 (capped, radius 1, x in [-1, 1]): lateral at z = 9, cap at x = -1.
  const auto cyl = make_transformed(Affine3d::translate({0, 0, 10}) * Affine3d::rotate({0, 1, 0}, M_PI / 2), make_cylinder(0.f, 0.f, 1.f, -1.f, 1.f));
  auto cylk = [](const auto& r, const auto& xx) {
    return intersect_transformed(r, xx, [](const auto& lr, const auto& p) { return intersect_cylinder_capped(lr, p); });
  };
  EXPECT_NEAR((run_one<F>(cylk, ray({0.5f, 0, 0}, {0, 0, 1}), cyl).t), 9.0, 1e-4);
  EXPECT_NEAR((run_one<F>(cylk, ray({-5, 0, 10.5f}, {1, 0, 0}), cyl).t), 4.0, 1e-4);
  EXPECT_FALSE((run_one<F>(cylk, ray({1.5f, 0, 0}, {0, 0, 1}), cyl).hit));
  // Cone frustum scaled 2x along its axis, laid along y.
  const auto cone = make_transformed(Affine3d::rotate({1, 0, 0}, -M_PI / 2) * Affine3d::scale({1, 1, 2}), make_capped_cone(Vec3f{0, 0, 0}, 1.f, 2.f));
  auto conek = [](const auto& r, const auto& xx) {
    return intersect_transformed(r, xx, [](const auto& lr, const auto& p) { return intersect_cone_capped(lr, p); });
  };
  // Local z in [1, 2] -> world y in [2, 4]; radius at local z = 1.5 is 1.5: a ray along x at y = 3.
  EXPECT_NEAR((run_one<F>(conek, ray({-5, 3, 0}, {1, 0, 0}), cone).t), 3.5, 1e-4);
  // NFF-style shells between two circles (place_cylinder / place_cone), open.
  const auto pcyl = place_cylinder({1, 1, 1}, {1, 1, 3}, 0.5);
  auto pcylk = [](const auto& r, const auto& xx) {
    return intersect_transformed(r, xx, [](const auto& lr, const auto& p) { return intersect_cylinder(lr, p); });
  };
  EXPECT_NEAR((run_one<F>(pcylk, ray({1, -5, 2}, {0, 1, 0}), pcyl).t), 5.5, 1e-4);
  EXPECT_FALSE((run_one<F>(pcylk, ray({1, -5, 3.5f}, {0, 1, 0}), pcyl).hit));  // beyond the top circle
  // Radius 1 at z = 0 down to 0.5 at z = 2: 0.75 at z = 1, either end order.
  auto pconek = [](const auto& r, const auto& xx) {
    return intersect_transformed(r, xx, [](const auto& lr, const auto& p) { return intersect_cone(lr, p); });
  };
  for (const auto& pc : {place_cone({0, 0, 0}, 1.0, {0, 0, 2}, 0.5), place_cone({0, 0, 2}, 0.5, {0, 0, 0}, 1.0)}) {
    EXPECT_NEAR((run_one<F>(pconek, ray({5, 0, 1}, {-1, 0, 0}), pc).t), 4.25, 1e-4);
    EXPECT_NEAR((run_one<F>(pconek, ray({0, 5, 0.5f}, {0, -1, 0}), pc).t), 4.125, 1e-4);
    EXPECT_FALSE((run_one<F>(pconek, ray({5, 0, 2.5f}, {-1, 0, 0}), pc).hit));  // above the narrow end
    EXPECT_FALSE((run_one<F>(pconek, ray({0.2f, 0, 5}, {0, 0, -1}), pc).hit));  // down the open axis
  }
  EXPECT_FALSE((run_one<F>(pconek, ray({5, 0, 1}, {-1, 0, 0}), place_cone({0, 0, 0}, 1.0, {0, 0, 0}, 0.5)).hit));
  // Quadric instance: a placed hyperboloid equals the coefficient placement.
  {
    const Affine3d M = Affine3d::translate({1, -2, 3}) * Affine3d::rotate({0, 0, 1}, 0.3);
    const auto qh = make_quadric(quadrics::hyperboloid_one_sheet(1, 1, 1));
    const auto xq = make_transformed(M, qh);
    auto qk = [](const auto& r, const auto& xx) {
      return intersect_transformed(r, xx, [](const auto& lr, const auto& p) { return intersect_quadric_matrix(lr, p); });
    };
    const Ray<float> r = ray({-10, -2, 3}, {1, 0.05f, 0});
    const HitF a = run_one<F>(qk, r, xq);
    const HitF b = run_one<F>(RB_KERNEL(intersect_quadric_matrix), r, make_quadric(quadrics::hyperboloid_one_sheet(1, 1, 1).placed(M)));
    ASSERT_TRUE(a.hit && b.hit);
    EXPECT_NEAR(a.t, b.t, 1e-4);
  }
  // never() misses everything.
  using X = Transformed<Sphere>::T<float>;
  EXPECT_FALSE((run_one<F>(sph, ray({0, 0, 0}, {0, 0, 1}), X::never()).hit));
}

TEST(QuadricKernelsScalar, TransformConstruction) {
  const auto unit = make_sphere(Vec3f{0, 0, 0}, 1.f);
  const auto through = make_ray(Vec3f{0, 0, -5}, Vec3f{0, 0, 1});
  auto expect_never = [&](const Affine3d& M, const char* part) {
    std::string why;
    const auto x = make_transformed(M, unit, &why);
    EXPECT_NE(why.find(part), std::string::npos) << why;
    EXPECT_FALSE(intersect_transformed(through, x, RB_KERNEL(intersect_sphere_stable)).mask);
  };
  expect_never(Affine3d::scale({1, 0, 1}), "singular");
  Affine3d near_singular = Affine3d::identity();  // rows 0 and 1 parallel to 1e-14
  near_singular.m[1][0] = 1;
  near_singular.m[1][1] = 1e-14;
  expect_never(near_singular, "singular");
  std::string why;
  (void)make_transformed(Affine3d::scale({1, 1e-20, 1}), unit, &why);  // tiny but well conditioned
  EXPECT_TRUE(why.empty()) << why;
  Affine3d nan = Affine3d::identity();
  nan.m[1][3] = std::nan("");
  expect_never(nan, "non-finite");
  expect_never(Affine3d::scale({1e-39, 1e-39, 1e-39}), "overflows float");
  EXPECT_FALSE(Affine3d::frame({0, 0, 0}, {0, 0, 0}, &why).has_value());
  EXPECT_NE(why.find("axis"), std::string::npos) << why;
  EXPECT_FALSE(place_cylinder({0, 0, 0}, {0, 0, 0}, 1.0, &why).prim.r2 > 0.f);
  EXPECT_NE(why.find("cylinder"), std::string::npos) << why;
  // Inverse is the inverse.
  const Affine3d M = Affine3d::translate({1, 2, 3}) * Affine3d::rotate({1, 1, 0}, 0.4) * Affine3d::scale({2, 3, 0.5});
  const Affine3d I = *M.inverse() * M;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(I.m[i][j], i == j ? 1.0 : 0.0, 1e-12);
}

// ---- bad rays: a miss with t = +inf in every kernel ----------------------------------------------------
TYPED_TEST(QuadricKernels, BadRaysMiss) {
  using F = TypeParam;
  const std::vector<Ray<float>> bad = {ray({0, 0, 0}, {0, 0, 0}),     ray({kNaNF, 0, 0}, {0, 0, 1}), ray({0, 0, 0}, {0, kNaNF, 1}),
                                       ray({kInfF, 0, 0}, {0, 0, 1}), ray({0, 0, 0}, {0, 0, 1}, 5.f, 1.f),
                                       ray({0, 0, 0}, {0, 0, 1}, kNaNF, 1.f)};
  const auto s = make_sphere(Vec3f{0, 0, 0}, 3.f);
  const auto su = make_sphere_uv(Vec3f{0, 0, 0}, 3.f);
  const auto q = make_quadric(quadrics::ellipsoid(2, 3, 4));
  const auto qr = make_quadric_rev(Vec3f{0, 0, 0}, 1.f, 0.f, -9.f);
  const auto c = make_cylinder(0.f, 0.f, 3.f, -3.f, 3.f);
  const auto k = make_capped_cone(Vec3f{0, 0, -5}, 1.f, 8.f);
  const auto x = make_transformed(Affine3d::scale({2, 2, 2}), s);
  for (const auto& r : bad) {
    const std::vector<HitF> hs = {
        run_one<F>(RB_KERNEL(intersect_sphere_stable), r, s), run_one<F>(RB_KERNEL(intersect_sphere_hearn_baker), r, s),
        run_one<F>(RB_KERNEL(intersect_sphere_uv), r, su),    run_one<F>(RB_KERNEL(intersect_quadric_matrix), r, q),
        run_one<F>(RB_KERNEL(intersect_quadric_coeffs10), r, q), run_one<F>(RB_KERNEL(intersect_quadric_rev), r, qr),
        run_one<F>(RB_KERNEL(intersect_cylinder), r, c),      run_one<F>(RB_KERNEL(intersect_cylinder_capped), r, c),
        run_one<F>(RB_KERNEL(intersect_cone), r, k),          run_one<F>(RB_KERNEL(intersect_cone_capped), r, k),
        run_one<F>([](const auto& rr, const auto& xx) {
          return intersect_transformed(rr, xx, [](const auto& lr, const auto& p) { return intersect_sphere_stable(lr, p); });
        }, r, x)};
    for (std::size_t i = 0; i < hs.size(); ++i) {
      EXPECT_FALSE(hs[i].hit) << "kernel " << i;
      EXPECT_EQ(hs[i].t, kInfD) << "kernel " << i;
    }
  }
}

// ---- seeded random rays, checked independently in double ---------------------------------------------
// A surface for the checks: its value and gradient in double, and whether a point is on the part
// the kernel models (height ranges).
struct Surface {
  std::function<double(Vec3d)> value;
  std::function<Vec3d(Vec3d)> grad;
  std::function<bool(Vec3d)> in_range = [](Vec3d) { return true; };
};

// Checks one kernel result: a hit point lies on the surface (|F| / |grad F| <= tol * scale) and no
// sign change of F on the modelled part occurs before it; a miss has no sign change in [0, 60].
void check_against_sampling(const Surface& s, const Ray<float>& r, const HitF& h, double scale, const char* what, int i) {
  const Vec3d o = to_double(r.o), d = to_double(r.d);
  if (h.hit) {
    const Vec3d p = o + d * h.t;
    const Vec3d g = s.grad(p);
    EXPECT_LE(std::fabs(s.value(p)) / std::sqrt(dot(g, g)), 2e-5 * scale) << what << " ray " << i << " t " << h.t;
  }
  const double end = h.hit ? h.t : 60.0;
  const int n = 4000;
  double prev = s.value(o);
  for (int k = 1; k <= n; ++k) {
    const double t = end * k / n;
    const double cur = s.value(o + d * t);
    // A sign change well before the reported t (beyond float resolution) on the modelled part.
    if ((prev < 0) != (cur < 0) && t < end - 1e-3 * scale && s.in_range(o + d * t)) {
      ADD_FAILURE() << what << " ray " << i << ": root near t = " << t << " but kernel says " << (h.hit ? h.t : -1.0);
      return;
    }
    prev = cur;
  }
}

template <class F, template <class> class P, class K>
void random_check(const char* what, K k, const P<float>& prim, const Surface& s, Vec3d centre, double scale, int n, std::uint32_t seed,
                  bool expect_mixed = true) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  int hits = 0;
  for (int i = 0; i < n; ++i) {
    // From a shell around the centre toward a random point near it.
    Vec3d dir{u(g), u(g), u(g)};
    dir = dir * (1.0 / std::sqrt(dot(dir, dir)));
    const Vec3d o = centre + dir * (3.0 * scale);
    const Vec3d target = centre + Vec3d{u(g), u(g), u(g)} * (1.2 * scale);
    const Ray<float> r = make_ray(to_float(o), to_float(target - o));
    const HitF h = run_one<F>(k, r, prim);
    hits += h.hit;
    check_against_sampling(s, r, h, scale, what, i);
  }
  if (expect_mixed) {
    EXPECT_GT(hits, n / 10) << what;
    EXPECT_LT(hits, n) << what;
  }
}

TYPED_TEST(QuadricKernels, RandomRaysAgainstSampling) {
  using F = TypeParam;
  if constexpr (lanes_v<F> > 1 && !std::is_same_v<F, f8>) return;  // lanes are covered by the bit tests
  const int n = 60;
  {
    const Vec3d c{1, -2, 3};
    const double R = 1.5;
    const auto s = make_sphere(to_float(c), float(R));
    const Surface sf{[=](Vec3d p) { return dot(p - c, p - c) - R * R; }, [=](Vec3d p) { return (p - c) * 2.0; }};
    random_check<F>("sphere stable", RB_KERNEL(intersect_sphere_stable), s, sf, c, R, n, 1);
    random_check<F>("sphere hearn_baker", RB_KERNEL(intersect_sphere_hearn_baker), s, sf, c, R, n, 2);
  }
  {
    const auto& cases = named_cases();
    std::uint32_t seed = 10;
    for (const auto& nc : cases) {
      const QuadricCoeffs q = nc.q.translated({0.5, -0.25, 0.75});
      const Surface sf{[=](Vec3d p) { return q.value(p); }, [=](Vec3d p) { return q.half_gradient(p) * 2.0; }};
      random_check<F>(nc.name, RB_KERNEL(intersect_quadric_matrix), make_quadric(q), sf, {0.5, -0.25, 0.75}, 2.0, n / 3, seed++, false);
      random_check<F>(nc.name, RB_KERNEL(intersect_quadric_coeffs10), make_quadric(q), sf, {0.5, -0.25, 0.75}, 2.0, n / 3, seed++, false);
    }
  }
  {
    const Vec3d c{0, 1, -1};
    const auto qr = make_quadric_rev(to_float(c), -0.5f, 0.3f, -1.f);  // a hyperboloid of one sheet, shifted
    const Surface sf{[=](Vec3d p) {
                       const Vec3d l = p - c;
                       return l.x * l.x + l.y * l.y - 0.5 * l.z * l.z + 0.3 * l.z - 1.0;
                     },
                     [=](Vec3d p) {
                       const Vec3d l = p - c;
                       return Vec3d{2 * l.x, 2 * l.y, -l.z + 0.3};
                     }};
    random_check<F>("quadric_rev", RB_KERNEL(intersect_quadric_rev), qr, sf, c, 2.0, n, 40);
  }
  {
    const auto cy = make_cylinder(0.5f, -0.5f, 1.2f, -1.f, 1.5f);
    const Surface sf{[](Vec3d p) { return (p.x - 0.5) * (p.x - 0.5) + (p.y + 0.5) * (p.y + 0.5) - double(1.2f) * double(1.2f); },
                     [](Vec3d p) { return Vec3d{2 * (p.x - 0.5), 2 * (p.y + 0.5), 0}; },
                     [](Vec3d p) { return p.z >= -1 && p.z <= 1.5; }};
    random_check<F>("cylinder", RB_KERNEL(intersect_cylinder), cy, sf, {0.5, -0.5, 0.25}, 1.5, n, 41);
    const auto co = make_cone(Vec3f{0, 0, 0}, -1.f, 2.f);
    const Surface sc{[](Vec3d p) { return p.x * p.x + p.y * p.y - p.z * p.z; }, [](Vec3d p) { return Vec3d{2 * p.x, 2 * p.y, -2 * p.z}; },
                     [](Vec3d p) { return p.z >= -1 && p.z <= 2; }};
    random_check<F>("cone", RB_KERNEL(intersect_cone), co, sc, {0, 0, 0.5}, 1.5, n, 42);
  }
  {
    const Affine3d M = Affine3d::translate({1, 1, 1}) * Affine3d::rotate({1, -1, 2}, 1.1) * Affine3d::scale({1.5, 0.7, 1});
    const QuadricCoeffs q = quadrics::ellipsoid(1, 1, 1).placed(M);
    const Surface sf{[=](Vec3d p) { return q.value(p); }, [=](Vec3d p) { return q.half_gradient(p) * 2.0; }};
    random_check<F>("transformed sphere", [](const auto& r, const auto& x) {
      return intersect_transformed(r, x, [](const auto& lr, const auto& p) { return intersect_sphere_stable(lr, p); });
    }, make_transformed(M, make_sphere(Vec3f{0, 0, 0}, 1.f)), sf, {1, 1, 1}, 1.5, n, 43);
  }
}

// Capped solids against an independent double computation: the nearest of the lateral roots with z
// in range and the cap-plane crossings inside the cap discs (origins outside the solids).
TEST(QuadricKernelsScalar, CappedSolidsAgainstDoubleReference) {
  std::mt19937 g(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const double z0 = -1, z1 = 1.5;
  for (int kind = 0; kind < 2; ++kind) {
    // kind 0: cylinder radius 1.2 about (0.5, -0.5); kind 1: cone frustum apex (0, 0, -2), z in [1, 3.5] (radius = local z).
    const auto cy = make_cylinder(0.5f, -0.5f, 1.2f, float(z0), float(z1));
    const auto co = make_capped_cone(Vec3f{0, 0, -2}, 1.f, 3.5f);
    int hits = 0, checked = 0;
    for (int i = 0; i < 400; ++i) {
      const Vec3d ctr = kind == 0 ? Vec3d{0.5, -0.5, 0.25} : Vec3d{0, 0, 0.25};
      Vec3d dir{u(g), u(g), u(g)};
      dir = dir * (1.0 / std::sqrt(dot(dir, dir)));
      const Ray<float> r = make_ray(to_float(ctr + dir * 8.0), to_float(ctr + Vec3d{u(g), u(g), u(g)} * 2.0 - (ctr + dir * 8.0)));
      const Vec3d o = to_double(r.o), d = to_double(r.d);
      // Reference in double.
      auto radius2 = [&](Vec3d p) { return kind == 0 ? 1.44 : (p.z + 2) * (p.z + 2); };
      auto axis_d2 = [&](Vec3d p) { return kind == 0 ? (p.x - 0.5) * (p.x - 0.5) + (p.y + 0.5) * (p.y + 0.5) : p.x * p.x + p.y * p.y; };
      double best = kInfD;
      // Lateral: solve the quadratic in double.
      {
        double A, B, C;
        if (kind == 0) {
          const double ox = o.x - 0.5, oy = o.y + 0.5;
          A = d.x * d.x + d.y * d.y; B = ox * d.x + oy * d.y; C = ox * ox + oy * oy - 1.44;
        } else {
          const double oz = o.z + 2;
          A = d.x * d.x + d.y * d.y - d.z * d.z; B = o.x * d.x + o.y * d.y - oz * d.z; C = o.x * o.x + o.y * o.y - oz * oz;
        }
        const double disc = B * B - A * C;
        if (disc >= 0 && A != 0)
          for (double t : {(-B - std::sqrt(disc)) / A, (-B + std::sqrt(disc)) / A}) {
            const Vec3d p = o + d * t;
            if (t >= 0 && p.z >= z0 && p.z <= z1) best = std::min(best, t);
          }
      }
      const double cz0 = z0, cz1 = z1;
      for (double zc : {cz0, cz1}) {
        if (d.z == 0) continue;
        const double t = (zc - o.z) / d.z;
        const Vec3d p = o + d * t;
        if (t >= 0 && axis_d2(p) <= radius2(p)) best = std::min(best, t);
      }
      const HitF h = kind == 0 ? run_one<float>(RB_KERNEL(intersect_cylinder_capped), r, cy) : run_one<float>(RB_KERNEL(intersect_cone_capped), r, co);
      // Skip rays grazing an edge (the decision is legitimately ambiguous there).
      if (std::isfinite(best)) {
        const Vec3d p = o + d * best;
        const double edge = std::min(std::fabs(p.z - cz0), std::fabs(p.z - cz1)) + std::fabs(std::sqrt(axis_d2(p)) - std::sqrt(radius2(p)));
        if (edge < 1e-3) continue;
      }
      ++checked;
      EXPECT_EQ(h.hit, std::isfinite(best)) << "kind " << kind << " ray " << i << " ref " << best << " got " << h.t;
      if (h.hit && std::isfinite(best)) {
        EXPECT_NEAR(h.t, best, 1e-4) << "kind " << kind << " ray " << i;
      }
      hits += h.hit;
    }
    EXPECT_GT(hits, 40) << kind;
    EXPECT_GT(checked, 350) << kind;
  }
}

// ---- SIMD lanes equal the scalar float result ------------------------------------------------------------
// Both mappings: 8 different rays against one primitive, and one ray against 8 different primitives.
template <template <class> class P, class K>
void check_lanes(const char* what, K k, const std::vector<P<float>>& prims, const std::vector<Ray<float>>& rays, bool uv_exact = true) {
  auto same = [&](const Hit<float>& s, const Hit<f8>& v, int l, const char* map, std::size_t i) {
    EXPECT_EQ(s.mask, lane_mask<f8>(v.mask, l)) << what << " " << map << " " << i << " lane " << l;
#ifdef RB_FP_CONTRACT_off
    EXPECT_TRUE(same_bits(s.t, lane(v.t, l))) << what << " " << map << " " << i << " lane " << l << ": " << s.t << " vs " << lane(v.t, l);
#else
    // Contracted builds: the scalar and SIMD code may fuse differently: 64 ulps of |t| bound.
    // (Equal values first: two misses both hold +inf, and inf - inf is NaN.)
    EXPECT_TRUE(s.t == lane(v.t, l) || std::fabs(s.t - lane(v.t, l)) <= 64 * std::numeric_limits<float>::epsilon() * std::fabs(s.t))
        << what << " " << map << " " << i << " lane " << l << ": " << s.t << " vs " << lane(v.t, l);
#endif
    if (uv_exact) {
      EXPECT_TRUE(same_bits(s.u, lane(v.u, l)) && same_bits(s.v, lane(v.v, l))) << what;
    } else {
      // xsimd's acos is not libm's: a few ulps of [0, 1]. Contracted builds add the t difference
      // above, which acos and atan2 amplify near the poles (up to 2e-4 measured).
      const double tol = kExact ? 4e-7 : 1e-3;
      EXPECT_NEAR(s.u, lane(v.u, l), tol) << what;
      EXPECT_NEAR(s.v, lane(v.v, l), tol) << what;
    }
  };
  RaySoA rs;
  for (const auto& r : rays) rs.push(r);
  for (const auto& p : prims) {
    const P<f8> pv = prim_cast<f8>(p);
    for (std::size_t i = 0; i < rs.size(); i += 8) {
      const Hit<f8> v = k(rs.packet<f8>(i), pv);
      for (int l = 0; l < 8; ++l) same(k(rs.get(i + std::size_t(l)), p), v, l, "rays_in_lanes", i);
    }
  }
  PrimSoA<P> ps;
  for (const auto& p : prims) ps.push(p);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Ray<f8> rv = Ray<f8>::broadcast(rays[i]);
    for (std::size_t j = 0; j < ps.size(); j += 8) {
      const Hit<f8> v = k(rv, ps.template load<f8>(j));
      for (int l = 0; l < 8; ++l) same(k(rays[i], ps.get(j + std::size_t(l))), v, l, "prims_in_lanes", i);
    }
  }
}

TEST(QuadricKernelsScalar, SimdLanesEqualScalar) {
  std::mt19937 g(99);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::vector<Ray<float>> rays;
  for (int i = 0; i < 64; ++i) rays.push_back(make_ray(Vec3f{3 * u(g), 3 * u(g), -10.f + u(g)}, Vec3f{0.3f * u(g), 0.3f * u(g), 1.f}));
  for (int i = 0; i < 16; ++i) rays.push_back(make_ray(Vec3f{3 * u(g), -10.f, u(g)}, Vec3f{0.3f * u(g), 1.f, 0.3f * u(g)}));
  rays.push_back(make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 0}));  // invalid
  std::vector<Sphere<float>> sph;
  std::vector<SphereUV<float>> suv;
  std::vector<Quadric<float>> qs;
  std::vector<QuadricRev<float>> qr;
  std::vector<Cylinder<float>> cy;
  std::vector<Cone<float>> co, cc;
  std::vector<Transformed<Sphere>::T<float>> xs;
  for (int j = 0; j < 12; ++j) {
    const Vec3f c{u(g), u(g), 2.f * u(g)};
    sph.push_back(make_sphere(c, 1.f + 0.5f * u(g)));
    suv.push_back(make_sphere_uv(c, 1.f + 0.5f * u(g), Vec3f{u(g), u(g), 1.f}, Vec3f{1.f, u(g), 0.f}));
    const NamedCase nc = named_cases()[std::size_t(j) % named_cases().size()];
    qs.push_back(make_quadric(nc.q.placed(Affine3d::translate(to_double(c)) * Affine3d::rotate({u(g), u(g), 1.0}, double(u(g))))));
    qr.push_back(make_quadric_rev(c, u(g), u(g), -1.f));
    cy.push_back(make_cylinder(c.x, c.y, 1.f + 0.5f * u(g), -1.f + u(g), 2.f));
    co.push_back(make_cone(c, -2.f, 2.f + u(g)));
    cc.push_back(make_capped_cone(c, 0.5f, 2.f + u(g)));
    xs.push_back(make_transformed(Affine3d::translate(to_double(c)) * Affine3d::rotate({1, u(g), 0}, double(u(g))) * Affine3d::scale({1.5, 1, 0.7}),
                                  make_sphere(Vec3f{0, 0, 0}, 1.f)));
  }
  check_lanes<Sphere>("sphere stable", RB_KERNEL(intersect_sphere_stable), sph, rays);
  check_lanes<Sphere>("sphere hearn_baker", RB_KERNEL(intersect_sphere_hearn_baker), sph, rays);
  check_lanes<SphereUV>("sphere uv", RB_KERNEL(intersect_sphere_uv), suv, rays, false);
  check_lanes<Quadric>("quadric matrix", RB_KERNEL(intersect_quadric_matrix), qs, rays);
  check_lanes<Quadric>("quadric coeffs10", RB_KERNEL(intersect_quadric_coeffs10), qs, rays);
  check_lanes<QuadricRev>("quadric_rev", RB_KERNEL(intersect_quadric_rev), qr, rays);
  check_lanes<Cylinder>("cylinder", RB_KERNEL(intersect_cylinder), cy, rays);
  check_lanes<Cylinder>("cylinder capped", RB_KERNEL(intersect_cylinder_capped), cy, rays);
  check_lanes<Cone>("cone", RB_KERNEL(intersect_cone), co, rays);
  check_lanes<Cone>("cone capped", RB_KERNEL(intersect_cone_capped), cc, rays);
  check_lanes<Transformed<Sphere>::T>("transformed sphere", [](const auto& r, const auto& x) {
    return intersect_transformed(r, x, [](const auto& lr, const auto& p) { return intersect_sphere_stable(lr, p); });
  }, xs, rays);
}

// ---- accuracy: stable root and Hearn-Baker discriminant vs the naive quadratic --------------------------
// Mean |t - t_ref| / R over rays that hit in the double reference (exact float inputs promoted).
struct Acc {
  double err = 0;
  int misses = 0, n = 0;
};
template <class K>
Acc accuracy(K k, const Sphere<float>& s, const std::vector<Ray<float>>& rays, double R) {
  Acc a;
  for (const auto& r : rays) {
    const Hit<double> ref = intersect_sphere_stable(Ray<double>::broadcast(r), prim_cast<double>(s));
    if (!ref.mask) continue;
    const Hit<float> h = k(r, s);
    ++a.n;
    if (!h.mask) { ++a.misses; continue; }
    a.err += std::fabs(double(h.t) - ref.t) / R;
  }
  if (a.n) a.err /= a.n;
  return a;
}

TEST(QuadricKernelsScalar, StableAndHearnBakerBeatNaive) {
  std::mt19937 g(5);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  // (1) A small sphere far away (R = 1, 2000 units): the discriminant b^2 - c cancels in the
  // naive and plain stable forms; Hearn-Baker's |f - (f.d)d|^2 does not.
  {
    const Vec3f c{0, 0, 2000};
    const auto s = make_sphere(c, 1.f);
    std::vector<Ray<float>> rays;
    for (int i = 0; i < 2000; ++i) rays.push_back(make_ray(Vec3f{0, 0, 0}, Vec3f{u(g) * 5e-4f, u(g) * 5e-4f, 1.f}));
    const Acc naive = accuracy(RB_KERNEL(intersect_sphere_algebraic), s, rays, 1.0);
    const Acc hb = accuracy(RB_KERNEL(intersect_sphere_hearn_baker), s, rays, 1.0);
    ASSERT_GT(hb.n, 500);
    EXPECT_LT(hb.err * 10, naive.err) << "hb " << hb.err << " naive " << naive.err;
    EXPECT_LE(hb.misses, naive.misses);
  }
  // (2) Origins 1e-3 outside a large sphere (a secondary ray heading back in): the near root is
  // tiny and the naive (-B - sqrt) / 2A cancels; the stable t1 = c / q avoids that cancellation,
  // but c = |f|^2 - R^2 itself carries the rounding of |f|^2, so the gain is modest for a sphere.
  {
    const auto s = make_sphere(Vec3f{0, 0, 0}, 100.f);
    std::vector<Ray<float>> rays;
    for (int i = 0; i < 2000; ++i) {
      Vec3d n{u(g), u(g), u(g)};
      n = n * (1.0 / std::sqrt(dot(n, n)));
      const Vec3d o = n * 100.001;
      rays.push_back(make_ray(to_float(o), to_float(n * -1.0 + Vec3d{u(g), u(g), u(g)} * 0.3)));
    }
    // Relative error of the near root (t ~ 1e-3).
    double e_naive = 0, e_stable = 0;
    int n = 0;
    for (const auto& r : rays) {
      const Hit<double> ref = intersect_sphere_stable(Ray<double>::broadcast(r), prim_cast<double>(s));
      const Hit<float> a = intersect_sphere_algebraic(r, s), b = intersect_sphere_stable(r, s);
      if (!ref.mask || !a.mask || !b.mask || ref.t > 0.01) continue;
      ++n;
      e_naive += std::fabs(double(a.t) - ref.t) / ref.t;
      e_stable += std::fabs(double(b.t) - ref.t) / ref.t;
    }
    ASSERT_GT(n, 500);
    EXPECT_LT(e_stable, e_naive) << "stable " << e_stable / n << " naive " << e_naive / n;
  }
  // (3) The quadratic itself, near-linear (A << B: a ray almost along a paraboloid's axis), with
  // exact float coefficients: the naive near root (-B + sqrt(B^2 - AC)) / A cancels; stable_roots
  // keeps a few ulps (reference: the same float coefficients in double).
  {
    std::uniform_real_distribution<double> ua(-8, -2);
    double e_naive = 0, e_stable = 0;
    for (int i = 0; i < 1000; ++i) {
      const float A = float(std::pow(10.0, ua(g))), B = 1.f + 0.5f * u(g), C = -(1.f + 0.5f * u(g));  // roots of both signs
      const float disc = B * B - A * C;
      const Roots<float, 2> q = stable_roots(A, B, C, disc, disc >= 0.f);
      const float naive = (-B + std::sqrt(disc)) / A;  // the positive (small) root
      const double dA = A, dB = B, dC = C;
      const double ref = dC / -(dB + std::sqrt(dB * dB - dA * dC));
      e_naive += std::fabs(double(naive) - ref) / std::fabs(ref);
      e_stable += std::fabs(double(q.hi()) - ref) / std::fabs(ref);
    }
    EXPECT_LT(e_stable / 1000, 1e-6);
    EXPECT_GT(e_naive / 1000, 1e-2) << "naive";
  }
}

// ---- golden op counts (Counted<float>) -----------------------------------------------------------------
template <template <class> class P, class K>
Golden count(K k, const Ray<float>& r, const P<float>& p, bool expect_hit) {
  const auto rc = Ray<cfloat>::broadcast(r);
  const auto pc = prim_cast<cfloat>(p);
  const ops::Scope s;
  const Hit<cfloat> h = k(rc, pc);
  const OpCounts o = s.elapsed();
  EXPECT_EQ(bool(h.mask), expect_hit);
  return gold(o);
}

TEST(QuadricKernelsScalar, GoldenOpCounts) {
  const auto s = make_sphere(Vec3f{0, 0, 10}, 2.f);
  const auto hit = ray({0, 0, 0}, {0, 0, 1}), miss = ray({5, 0, 0}, {0, 0, 1});
  EXPECT_EQ(count(RB_KERNEL(intersect_sphere_stable), miss, s, false), Golden(11, 11, 0, 0, 1, 0, 0, 0));
  EXPECT_EQ(count(RB_KERNEL(intersect_sphere_stable), hit, s, true), Golden(12, 11, 2, 1, 4, 2, 2, 0));
  EXPECT_EQ(count(RB_KERNEL(intersect_sphere_hearn_baker), miss, s, false), Golden(11, 9, 0, 0, 1, 0, 0, 0));
  EXPECT_EQ(count(RB_KERNEL(intersect_sphere_hearn_baker), hit, s, true), Golden(15, 12, 1, 1, 4, 2, 2, 0));
  const auto su = make_sphere_uv(Vec3f{0, 0, 10}, 2.f);
  const std::uint64_t tr0 = ops::trans_current();
  EXPECT_EQ(count(RB_KERNEL(intersect_sphere_uv), hit, su, true), Golden(26, 29, 3, 2, 5, 6, 5, 0));
  EXPECT_EQ(ops::trans_current() - tr0, 2u);  // two arccos
  const auto q = make_quadric(quadrics::ellipsoid(1, 2, 3).translated({0, 0, 10}));
  EXPECT_EQ(count(RB_KERNEL(intersect_quadric_matrix), miss, q, false), Golden(29, 35, 0, 0, 1, 0, 0, 0));
  EXPECT_EQ(count(RB_KERNEL(intersect_quadric_matrix), hit, q, true), Golden(30, 35, 2, 1, 4, 2, 2, 0));
  EXPECT_EQ(count(RB_KERNEL(intersect_quadric_coeffs10), miss, q, false), Golden(26, 49, 0, 0, 1, 0, 0, 0));
  EXPECT_EQ(count(RB_KERNEL(intersect_quadric_coeffs10), hit, q, true), Golden(27, 49, 2, 1, 4, 2, 2, 0));
  const auto qr = make_quadric_rev(Vec3f{0, 0, 10}, 1.f, 0.f, -4.f);
  EXPECT_EQ(count(RB_KERNEL(intersect_quadric_rev), miss, qr, false), Golden(13, 13, 0, 0, 1, 0, 0, 0));
  EXPECT_EQ(count(RB_KERNEL(intersect_quadric_rev), hit, qr, true), Golden(14, 13, 2, 1, 4, 2, 2, 0));
  const auto cy = make_cylinder(0.f, 10.f, 2.f, -1.f, 1.f);
  const auto yhit = ray({0, 0, 0}, {0, 1, 0}), ymiss = ray({5, 0, 0}, {0, 1, 0});
  EXPECT_EQ(count(RB_KERNEL(intersect_cylinder), ymiss, cy, false), Golden(7, 8, 0, 0, 1, 0, 0, 0));
  EXPECT_EQ(count(RB_KERNEL(intersect_cylinder), yhit, cy, true), Golden(10, 10, 2, 1, 9, 2, 2, 0));
  EXPECT_EQ(count(RB_KERNEL(intersect_cylinder_capped), ymiss, cy, false), Golden(7, 8, 0, 0, 1, 0, 0, 0));
  EXPECT_EQ(count(RB_KERNEL(intersect_cylinder_capped), yhit, cy, true), Golden(10, 10, 3, 1, 8, 4, 7, 0));
  const auto co = make_capped_cone(Vec3f{0, 10, -2}, 1.f, 3.f);
  // Cone: A < 0 1 cmp and the clamp of disc 1 min/max in the quadratic (a steep ray always meets
  // the cone; through the apex its disc rounds below 0); the capped nappe choice by signs, 1 cmp.
  EXPECT_EQ(count(RB_KERNEL(intersect_cone), ymiss, co, false), Golden(10, 11, 0, 0, 2, 1, 0, 0));
  EXPECT_EQ(count(RB_KERNEL(intersect_cone), yhit, co, true), Golden(13, 13, 2, 1, 10, 3, 2, 0));
  EXPECT_EQ(count(RB_KERNEL(intersect_cone_capped), ymiss, co, false), Golden(10, 11, 0, 0, 2, 1, 0, 0));
  EXPECT_EQ(count(RB_KERNEL(intersect_cone_capped), yhit, co, true), Golden(13, 13, 3, 1, 8, 5, 8, 0));
  // The transformation alone: the slide's 15+- 18*.
  const auto x = make_transformed(Affine3d::translate({0, 0, 10}) * Affine3d::scale({2, 2, 2}), make_sphere(Vec3f{0, 0, 0}, 1.f));
  {
    const auto rc = Ray<cfloat>::broadcast(hit);
    const auto xc = prim_cast<cfloat>(x);
    const ops::Scope sc;
    (void)transform_ray(rc, xc.inv);
    const OpCounts o = sc.elapsed();
    EXPECT_EQ(o.add, 15u);
    EXPECT_EQ(o.mul, 18u);
    EXPECT_EQ(o.div + o.sqrt + o.cmp + o.minmax + o.select + o.fma, 0u);
  }
  auto xk = [](const auto& r, const auto& xx) {
    return intersect_transformed(r, xx, [](const auto& lr, const auto& p) { return intersect_sphere_stable(lr, p); });
  };
  EXPECT_EQ(count<Transformed<Sphere>::T>(xk, miss, x, false), Golden(26, 29, 0, 0, 1, 0, 0, 0));
  EXPECT_EQ(count<Transformed<Sphere>::T>(xk, hit, x, true), Golden(27, 29, 2, 1, 4, 2, 2, 0));
}

}  // namespace
}  // namespace rb::test
