// Helpers of the quadric kernel family's tests (tests/test_sphere_quadric_kernels.cpp,
// tests/test_cylinder_cone_transform_kernels.cpp, tests/test_quadric_family_checks.cpp): the typed
// fixture, tolerances, a ray maker, lane-0 normals and root pairs, and the named quadrics.
#pragma once

#include "kernels/quadric.hpp"
#include "kernels/transform.hpp"
#include "kernel_test_util.hpp"

#include <cmath>
#include <utility>
#include <vector>

namespace rb::test {

template <class F>
struct QuadricKernels : ::testing::Test {};
TYPED_TEST_SUITE(QuadricKernels, ValueNumbers);

inline constexpr double kTolQuadric = 2e-5;  // on t for float data, hand cases (|t| <= 20)
inline const double kSqrt2 = std::sqrt(2.0);

inline Ray<float> ray(Vec3f o, Vec3f d, float t0 = 0.f, float t1 = kInfF) { return make_ray(o, d, t0, t1); }

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

// Every named quadric of seed 004, with a ray and its expected t.
struct NamedCase {
  const char* name;
  QuadricCoeffs q;
  Vec3f o, d;
  double t;  // < 0: miss
};
inline std::vector<NamedCase> named_cases() {
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

}  // namespace rb::test
