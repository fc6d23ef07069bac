// Hand-worked cases for the first kernels (plane, triangle lecture + Moller-Trumbore, sphere
// geometric + algebraic, box), typed over every number type; bad rays and degenerate
// primitives give a miss with t = +inf.
#include "kernels/box.hpp"
#include "kernels/plane.hpp"
#include "kernels/sphere.hpp"
#include "kernels/triangle.hpp"
#include "kernel_test_util.hpp"

#include <limits>

namespace rb::test {
namespace {

template <class F>
struct FirstKernels : ::testing::Test {};
TYPED_TEST_SUITE(FirstKernels, AllNumbers);


// Tolerance on t for double-precision instantiations of float data (inputs are exact here).
constexpr double kTol = 1e-5;

TYPED_TEST(FirstKernels, Plane) {
  using F = TypeParam;
  const auto pl = make_plane(Vec3f{0, 0, 5}, Vec3f{0, 0, 2});
  auto k = RB_KERNEL(intersect_plane);
  HitF h = run_one<F>(k, make_ray(Vec3f{1, 2, 0}, Vec3f{0, 0, 1}), pl);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 5.0, kTol);
  // Oblique: direction (0, 3, 4) / 5, t = 5 / 0.8 = 6.25.
  h = run_one<F>(k, make_ray(Vec3f{0, 0, 0}, Vec3f{0, 3, 4}), pl);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 6.25, kTol);
  // From the other side (two-sided).
  h = run_one<F>(k, make_ray(Vec3f{0, 0, 9}, Vec3f{0, 0, -1}), pl);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 4.0, kTol);
  // Parallel, behind, beyond tmax.
  EXPECT_FALSE((run_one<F>(k, make_ray(Vec3f{0, 0, 0}, Vec3f{1, 0, 0}), pl).hit));
  EXPECT_FALSE((run_one<F>(k, make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, -1}), pl).hit));
  EXPECT_FALSE((run_one<F>(k, make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 0.f, 4.f), pl).hit));
  // Zero normal: never hits.
  EXPECT_FALSE((run_one<F>(k, make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}), make_plane(Vec3f{0, 0, 5}, Vec3f{0, 0, 0})).hit));
}

TYPED_TEST(FirstKernels, Sphere) {
  using F = TypeParam;
  const auto s = make_sphere(Vec3f{0, 0, 10}, 2.f);
  for (int m = 0; m < 2; ++m) {
    auto run = [&](const Ray<float>& r) {
      return m == 0 ? run_one<F>(RB_KERNEL(intersect_sphere_geometric), r, s) : run_one<F>(RB_KERNEL(intersect_sphere_algebraic), r, s);
    };
    HitF h = run(make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}));
    EXPECT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 8.0, kTol);
    // Origin inside: the far root.
    h = run(make_ray(Vec3f{0, 0, 10}, Vec3f{0, 1, 0}));
    EXPECT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 2.0, kTol);
    // Off-centre: x = 1.2, half chord sqrt(4 - 1.44) = 1.6, t = 8.4.
    h = run(make_ray(Vec3f{1.2f, 0, 0}, Vec3f{0, 0, 1}));
    EXPECT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 8.4, 1e-5);
    // Misses: beside, behind, beyond tmax.
    EXPECT_FALSE(run(make_ray(Vec3f{3, 0, 0}, Vec3f{0, 0, 1})).hit);
    EXPECT_FALSE(run(make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, -1})).hit);
    EXPECT_FALSE(run(make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 0.f, 7.f)).hit);
    // Degenerate spheres never hit, even through their centre.
    for (float r : {0.f, -1.f, kNaNF, kInfF}) {
      const auto d = make_sphere(Vec3f{0, 0, 10}, r);
      const auto ray = make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1});
      const HitF dh = m == 0 ? run_one<F>(RB_KERNEL(intersect_sphere_geometric), ray, d)
                             : run_one<F>(RB_KERNEL(intersect_sphere_algebraic), ray, d);
      EXPECT_FALSE(dh.hit) << "radius " << r;
      EXPECT_EQ(dh.t, std::numeric_limits<double>::infinity());
    }
  }
  // Normal at the hit point (0, 0, 8): (0, 0, -1).
  const Vec3<F> n = sphere_normal(prim_cast<F>(s), Vec3<F>{F(0), F(0), F(8)});
  EXPECT_NEAR(double(lane(n.z, 0)), -1.0, 1e-6);
}

TYPED_TEST(FirstKernels, Triangle) {
  using F = TypeParam;
  const Vec3f a{0, 0, 5}, b{2, 0, 5}, c{0, 2, 5};
  int axis = -1;
  const auto lec = make_tri_lecture(a, b, c, axis);
  EXPECT_EQ(axis, 2);
  const auto mt = make_triangle(a, b, c);
  auto run = [&](int m, const Ray<float>& r) {
    return m == 0 ? run_one<F>([axis](const auto& rr, const auto& q) { return intersect_triangle_lecture(rr, q, axis); }, r, lec)
                  : run_one<F>(RB_KERNEL(intersect_triangle_mt), r, mt);
  };
  for (int m = 0; m < 2; ++m) {
    // P = (0.5, 0.25, 5) = a + 0.25 (b - a) + 0.125 (c - a).
    HitF h = run(m, make_ray(Vec3f{0.5f, 0.25f, 0}, Vec3f{0, 0, 1}));
    EXPECT_TRUE(h.hit) << m;
    EXPECT_NEAR(h.t, 5.0, kTol);
    EXPECT_NEAR(h.u, 0.25, kTol);
    EXPECT_NEAR(h.v, 0.125, kTol);
    // From behind (two-sided).
    h = run(m, make_ray(Vec3f{0.5f, 0.25f, 8}, Vec3f{0, 0, -1}));
    EXPECT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 3.0, kTol);
    // Outside each edge, parallel, behind.
    EXPECT_FALSE(run(m, make_ray(Vec3f{-0.1f, 0.5f, 0}, Vec3f{0, 0, 1})).hit);
    EXPECT_FALSE(run(m, make_ray(Vec3f{0.5f, -0.1f, 0}, Vec3f{0, 0, 1})).hit);
    EXPECT_FALSE(run(m, make_ray(Vec3f{1.1f, 1.1f, 0}, Vec3f{0, 0, 1})).hit);
    EXPECT_FALSE(run(m, make_ray(Vec3f{0.5f, 0.25f, 0}, Vec3f{1, 0, 0})).hit);
    EXPECT_FALSE(run(m, make_ray(Vec3f{0.5f, 0.25f, 0}, Vec3f{0, 0, -1})).hit);
  }
  // Degenerate triangles (repeated vertex, collinear, NaN vertex) never hit.
  const auto ray = make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1});
  for (const auto& t : {std::array<Vec3f, 3>{a, a, c}, std::array<Vec3f, 3>{a, Vec3f{1, 0, 5}, b},
                        std::array<Vec3f, 3>{a, b, Vec3f{kNaNF, 0, 5}}}) {
    int ax = 0;
    const auto l = make_tri_lecture(t[0], t[1], t[2], ax);
    EXPECT_FALSE((run_one<F>([ax](const auto& rr, const auto& q) { return intersect_triangle_lecture(rr, q, ax); }, ray, l).hit));
    EXPECT_FALSE((run_one<F>(RB_KERNEL(intersect_triangle_mt), ray, make_triangle(t[0], t[1], t[2])).hit));
  }
}

TYPED_TEST(FirstKernels, Box) {
  using F = TypeParam;
  const auto bx = make_box(Vec3f{-1, -1, -1}, Vec3f{1, 1, 1});
  auto k = RB_KERNEL(intersect_box);
  HitF h = run_one<F>(k, make_ray(Vec3f{0, 0, -5}, Vec3f{0, 0, 1}), bx);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 4.0, kTol);
  // Diagonal entry through the corner region: from (-3,-3,-3) along (1,1,1): t = 2 sqrt(3).
  h = run_one<F>(k, make_ray(Vec3f{-3, -3, -3}, Vec3f{1, 1, 1}), bx);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 2.0 * std::sqrt(3.0), 1e-5);
  // Inside: the exit surface (the first crossing in [tmin, tmax], as the sphere's far root); the
  // overlap form keeps the clamped entry tmin.
  h = run_one<F>(k, make_ray(Vec3f{0, 0, 0}, Vec3f{0, 1, 0}), bx);
  EXPECT_TRUE(h.hit);
  EXPECT_EQ(h.t, 1.0);
  h = run_one<F>(RB_KERNEL(intersect_box_overlap), make_ray(Vec3f{0, 0, 0}, Vec3f{0, 1, 0}), bx);
  EXPECT_TRUE(h.hit);
  EXPECT_EQ(h.t, 0.0);
  // Inside with the exit beyond tmax: no crossing in [tmin, tmax]; the overlap form still overlaps.
  EXPECT_FALSE(run_one<F>(k, make_ray(Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, 0.f, 0.5f), bx).hit);
  EXPECT_TRUE(run_one<F>(RB_KERNEL(intersect_box_overlap), make_ray(Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, 0.f, 0.5f), bx).hit);
  // Axis-parallel ray outside the x slab; behind; beyond tmax.
  EXPECT_FALSE(run_one<F>(k, make_ray(Vec3f{2, 0, -5}, Vec3f{0, 0, 1}), bx).hit);
  EXPECT_FALSE(run_one<F>(k, make_ray(Vec3f{0, 0, -5}, Vec3f{0, 0, -1}), bx).hit);
  EXPECT_FALSE(run_one<F>(k, make_ray(Vec3f{0, 0, -5}, Vec3f{0, 0, 1}, 0.f, 3.f), bx).hit);
  // Inverted and NaN boxes never hit.
  EXPECT_FALSE(run_one<F>(k, make_ray(Vec3f{0, 0, -5}, Vec3f{0, 0, 1}), make_box(Vec3f{1, -1, -1}, Vec3f{-1, 1, 1})).hit);
  EXPECT_FALSE(run_one<F>(k, make_ray(Vec3f{0, 0, -5}, Vec3f{0, 0, 1}), make_box(Vec3f{kNaNF, -1, -1}, Vec3f{1, 1, 1})).hit);
  // Normal of the entry face.
  const Vec3<F> n = box_normal(prim_cast<F>(bx), Vec3<F>{F(0.2f), F(0.1f), F(-1)});
  EXPECT_EQ(double(lane(n.z, 0)), -1.0);
  EXPECT_EQ(double(lane(n.x, 0)), 0.0);
  // Normal of the exit face seen from inside: outward, as the sphere's.
  const Vec3<F> ne = box_normal(prim_cast<F>(bx), Vec3<F>{F(0.f), F(1.f), F(0.f)});
  EXPECT_EQ(double(lane(ne.y, 0)), 1.0);
}

// NaN, inf and zero-direction rays, and NaN / reversed intervals: a miss with t = +inf in every kernel.
TYPED_TEST(FirstKernels, BadRaysMiss) {
  using F = TypeParam;
  const std::vector<Ray<float>> bad = {
      make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 0}),     make_ray(Vec3f{kNaNF, 0, 0}, Vec3f{0, 0, 1}),
      make_ray(Vec3f{0, 0, 0}, Vec3f{0, kNaNF, 1}), make_ray(Vec3f{kInfF, 0, 0}, Vec3f{0, 0, 1}),
      make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, kInfF}), make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 5.f, 1.f),
      make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, kNaNF, 1.f), make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 0.f, kNaNF)};
  int axis = 0;
  const auto lec = make_tri_lecture(Vec3f{-1, -1, 5}, Vec3f{2, -1, 5}, Vec3f{-1, 2, 5}, axis);
  const auto mt = make_triangle(Vec3f{-1, -1, 5}, Vec3f{2, -1, 5}, Vec3f{-1, 2, 5});
  for (const auto& r : bad) {
    std::vector<HitF> hs = {run_one<F>(RB_KERNEL(intersect_plane), r, make_plane(Vec3f{0, 0, 5}, Vec3f{0, 0, 1})),
                            run_one<F>(RB_KERNEL(intersect_sphere_geometric), r, make_sphere(Vec3f{0, 0, 0}, 3.f)),
                            run_one<F>(RB_KERNEL(intersect_sphere_algebraic), r, make_sphere(Vec3f{0, 0, 0}, 3.f)),
                            run_one<F>([axis](const auto& rr, const auto& q) { return intersect_triangle_lecture(rr, q, axis); }, r, lec),
                            run_one<F>(RB_KERNEL(intersect_triangle_mt), r, mt),
                            run_one<F>(RB_KERNEL(intersect_box), r, make_box(Vec3f{-1, -1, -1}, Vec3f{1, 1, 1}))};
    for (const auto& h : hs) {
      EXPECT_FALSE(h.hit);
      EXPECT_EQ(h.t, std::numeric_limits<double>::infinity());
    }
  }
}

}  // namespace
}  // namespace rb::test
