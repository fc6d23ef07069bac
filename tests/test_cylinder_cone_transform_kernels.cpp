// The quadric kernel family, part 2: cylinder and cone (open and capped) and transformed instances.
//   - hand-worked hits, misses, t, normals, roots, typed over the value types
//     (float, double, f8, d4; Counted<T> computes what T computes: tests/kernel_test_util.hpp);
//   - degenerate inputs and construction errors;
//   - seeded random rays against the capped solids, checked independently in double (caps + lateral).
// Spheres and general quadrics: tests/test_sphere_quadric_kernels.cpp; the checks over every kernel
// of the family: tests/test_quadric_family_checks.cpp.
#include "kernels/cylinder_cone.hpp"
#include "kernels/quadric.hpp"
#include "kernels/sphere.hpp"
#include "kernels/transform.hpp"
#include "quadric_test_util.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>

namespace rb::test {
namespace {

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

// ---- capped solids, checked independently in double ------------------------------------------------------
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

}  // namespace
}  // namespace rb::test
