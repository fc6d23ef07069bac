// Root-solver kernels, hand-worked: torus (ferrari, robust), algebraic surfaces (derivative
// isolation), implicit surfaces (sphere tracing, illinois), surfaces of revolution; bad rays and
// degenerate primitives. Typed tests run the value types (float, double, f8, d4).
// The scalar reference comparisons, SIMD lanes and op counts: tests/test_solver_family_checks.cpp.
#include "kernels/algebraic.hpp"
#include "kernels/implicit.hpp"
#include "kernels/revolution.hpp"
#include "kernels/torus.hpp"
#include "kernel_test_util.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace rb::test {
namespace {

template <class F>
struct SolverKernels : ::testing::Test {};
TYPED_TEST_SUITE(SolverKernels, ValueNumbers);

// Ferrari in float is only good to ~1e-3 here (see SolverAccuracy in
// test_solver_family_checks.cpp); the others to 1e-4.
template <class F> constexpr double tol_closed() { return std::is_same_v<scalar_t<F>, float> ? 5e-3 : 1e-6; }
template <class F> constexpr double tol_iter() { return std::is_same_v<scalar_t<F>, float> ? 2e-4 : 1e-6; }

TYPED_TEST(SolverKernels, TorusHandWorked) {
  using F = TypeParam;
  const auto T = make_torus(Vec3f{0, 0, 10}, Vec3f{0, 0, 1}, 2.f, 0.5f);
  auto fer = RB_KERNEL(intersect_torus_ferrari);
  auto rob = RB_KERNEL(intersect_torus_robust);
  // Down through the tube's centre circle at (2, 0): enters at z = 9.5.
  const auto down = make_ray(Vec3f{2, 0, 0}, Vec3f{0, 0, 1});
  HitF h = run_one<F>(fer, down, T);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 9.5, tol_closed<F>());
  h = run_one<F>(rob, down, T);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 9.5, tol_iter<F>());
  // Across the ring plane along x from x = -5: roots at 2.5, 3.5, 6.5, 7.5.
  const auto across = make_ray(Vec3f{-5, 0, 10}, Vec3f{1, 0, 0});
  const Roots<F, 4> rr = torus_roots_robust(Ray<F>::broadcast(across), prim_cast<F>(T));
  const Roots<F, 4> rf = torus_roots_ferrari(Ray<F>::broadcast(across), prim_cast<F>(T));
  const double want[4] = {2.5, 3.5, 6.5, 7.5};
  for (int k = 0; k < 4; ++k) {
    EXPECT_TRUE(lane_mask<F>(rr.valid[k], 0));
    EXPECT_TRUE(lane_mask<F>(rf.valid[k], 0));
    EXPECT_NEAR(double(lane(rr.t[k], 0)), want[k], tol_iter<F>());
    EXPECT_NEAR(double(lane(rf.t[k], 0)), want[k], tol_closed<F>());
  }
  // From inside the tube (origin at x = 2): the exit at t = 0.5.
  h = run_one<F>(rob, make_ray(Vec3f{2, 0, 10}, Vec3f{1, 0, 0}), T);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 0.5, tol_iter<F>());
  // Misses: through the hole, beside, behind, beyond tmax; t = +inf.
  for (const auto& r : {make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}), make_ray(Vec3f{3, 0, 0}, Vec3f{0, 0, 1}),
                        make_ray(Vec3f{2, 0, 0}, Vec3f{0, 0, -1}), make_ray(Vec3f{2, 0, 0}, Vec3f{0, 0, 1}, 0.f, 9.f)}) {
    for (const HitF m : {run_one<F>(fer, r, T), run_one<F>(rob, r, T)}) {
      EXPECT_FALSE(m.hit);
      EXPECT_EQ(m.t, kInfD);
    }
  }
  // Normal at the first hit (2, 0, 9.5): -z. uv: u = 0, v = 3/4 (bottom of the tube).
  const Vec3<F> n = torus_normal(prim_cast<F>(T), Vec3<F>{F(2), F(0), F(9.5f)});
  EXPECT_NEAR(double(lane(n.z, 0)), -1.0, 1e-5);
  F u, v;
  torus_uv(prim_cast<F>(T), Vec3<F>{F(2), F(0), F(9.5f)}, u, v);
  EXPECT_NEAR(double(lane(u, 0)), 0.0, 1e-5);
  EXPECT_NEAR(double(lane(v, 0)), 0.75, 1e-5);
}

// A ray from 500 torus sizes away, nearly through the bounding sphere's centre line: its
// float-rounded unit direction has |d|^2 - 1 = -7e-8, and a bounding-sphere clip that assumed
// |d| = 1 moved the entry past the torus's entry (the robust method then returned the exit,
// 624.6837). Exact roots 624.3249 and 624.6837 (ferrari is not accurate this far away in float).
TYPED_TEST(SolverKernels, TorusFarRayKeepsTheEntryRoot) {
  using F = TypeParam;
  const auto T = make_torus(Vec3f{0.5f, -0.25f, 0.125f}, Vec3f{0, 0, 1}, 1.f, 0.25f);
  const auto r = make_ray(Vec3f{-375.5374450683594f, 128.5894012451172f, -482.1832580566406f},
                          Vec3f{375.24676513671875f, -129.3311004638672f, 482.7933654785156f});
  const HitF h = run_one<F>(RB_KERNEL(intersect_torus_robust), r, T);
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 624.3249, 2e-4);
  const Roots<F, 4> rr = torus_roots_robust(Ray<F>::broadcast(r), prim_cast<F>(T));
  EXPECT_EQ(rr.count_in_lane(0), 2);
  EXPECT_NEAR(double(lane(rr.t[1], 0)), 624.6837, 2e-4);
  if constexpr (std::is_same_v<scalar_t<F>, double>) {
    const Roots<F, 4> rf = torus_roots_ferrari(Ray<F>::broadcast(r), prim_cast<F>(T));
    EXPECT_NEAR(double(lane(rf.t[0], 0)), 624.3249, 2e-4);
  }
  // The same clip serves the algebraic form of this torus.
  const Algebraic4<float> A{make_algebraic<4>(tri_torus({0.5, -0.25, 0.125}, 1.0, 0.25), {0.5, -0.25, 0.125}, 1.25)};
  const HitF ha = run_one<F>([](const auto& kr, const auto& ka) { return intersect_algebraic<4>(kr, ka); }, r, A);
  if constexpr (std::is_same_v<scalar_t<F>, double>) {
    ASSERT_TRUE(ha.hit);
    EXPECT_NEAR(ha.t, 624.3249, 2e-4);
  }
}

TYPED_TEST(SolverKernels, AlgebraicHandWorked) {
  using F = TypeParam;
  // Sphere (d = 2) of radius 2 at (0, 0, 10) and the torus above as d = 4.
  const Algebraic2<float> S{make_algebraic<2>(tri_sphere({0, 0, 10}, 2.0), {0, 0, 10}, 2.5)};
  const Algebraic4<float> T{make_algebraic<4>(tri_torus({0, 0, 10}, 2.0, 0.5), {0, 0, 10}, 2.6)};
  auto k2 = [](const auto& r, const auto& a) { return intersect_algebraic<2>(r, a); };
  auto k4 = [](const auto& r, const auto& a) { return intersect_algebraic<4>(r, a); };
  HitF h = run_one<F>(k2, make_ray(Vec3f{1.2f, 0, 0}, Vec3f{0, 0, 1}), S);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 8.4, tol_iter<F>());
  h = run_one<F>(k4, make_ray(Vec3f{2, 0, 0}, Vec3f{0, 0, 1}), T);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 9.5, tol_iter<F>());
  const Roots<F, 4> rt = algebraic_roots<4>(Ray<F>::broadcast(make_ray(Vec3f{-5, 0, 10}, Vec3f{1, 0, 0})), prim_cast<F>(T));
  const double want[4] = {2.5, 3.5, 6.5, 7.5};
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(double(lane(rt.t[k], 0)), want[k], tol_iter<F>());
  EXPECT_FALSE(run_one<F>(k4, make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}), T).hit);
  EXPECT_FALSE(run_one<F>(k2, make_ray(Vec3f{3, 0, 0}, Vec3f{0, 0, 1}), S).hit);
  const Vec3<F> n = algebraic_normal<2>(prim_cast<F>(S), Vec3<F>{F(0), F(0), F(8)});
  EXPECT_NEAR(double(lane(n.z, 0)), -1.0, 1e-5);
}

TYPED_TEST(SolverKernels, ImplicitHandWorked) {
  using F = TypeParam;
  // a = 1, c = 0.5 at (0, 0, 10): on the axis x = y = 0, F = 0.5 cos z: first root z = -pi/2.
  const auto W = make_wavy(Vec3f{0, 0, 10}, 1.f, 0.5f, 2.f);
  const auto r = make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1});
  const double want = 10.0 - 1.5707963267948966;
  HitF h = run_one<F>(RB_KERNEL(intersect_wavy_sphere_trace), r, W);
  EXPECT_TRUE(h.hit);
  // Sphere tracing stops short by up to eps L / |grad F| = 2e-4 x 6.5 / 0.5 here.
  EXPECT_NEAR(h.t, want, 4e-3);
  EXPECT_LE(h.t, want);
  h = run_one<F>(RB_KERNEL(intersect_wavy_illinois), r, W);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, want, 1e-3);
  // Outside the bounding ball: a miss.
  EXPECT_FALSE(run_one<F>(RB_KERNEL(intersect_wavy_sphere_trace), make_ray(Vec3f{3, 0, 0}, Vec3f{0, 0, 1}), W).hit);
  EXPECT_FALSE(run_one<F>(RB_KERNEL(intersect_wavy_illinois), make_ray(Vec3f{3, 0, 0}, Vec3f{0, 0, 1}), W).hit);
}

TYPED_TEST(SolverKernels, RevolutionHandWorked) {
  using F = TypeParam;
  // Cylinder r = 1, z in [-1, 1] about (0, 0, 10), axis z, seen obliquely and from the side.
  const auto C = make_revolution_poly(Vec3f{0, 0, 10}, Vec3f{0, 0, 1}, {1, 0, 0, 0}, {-1, 2, 0, 0});
  auto k = RB_KERNEL(intersect_revolution);
  // From (-3, 0, 8) along (1, 0, 1)/sqrt2: reaches x = -1 at t = 2 sqrt2, z = 10.
  HitF h = run_one<F>(k, make_ray(Vec3f{-3, 0, 8}, Vec3f{1, 0, 1}), C);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 2 * std::sqrt(2.0), tol_iter<F>());
  EXPECT_NEAR(h.u, 0.5, tol_iter<F>());
  // Horizontal (z1 = 0): the flat path; enters at x = -1.
  h = run_one<F>(k, make_ray(Vec3f{-5, 0, 10.5f}, Vec3f{1, 0, 0}), C);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 4.0, tol_iter<F>());
  EXPECT_NEAR(h.u, 0.75, tol_iter<F>());
  // Along the axis inside the open tube: no wall crossed.
  EXPECT_FALSE(run_one<F>(k, make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}), C).hit);
  EXPECT_FALSE(run_one<F>(k, make_ray(Vec3f{-5, 0, 12}, Vec3f{1, 0, 0}), C).hit);
  // Normal on the wall at (-1, 0, 10): -x.
  const Vec3<F> n = revolution_normal(prim_cast<F>(C), Vec3<F>{F(-1), F(0), F(10)}, F(0.5f));
  EXPECT_NEAR(double(lane(n.x, 0)), -1.0, 1e-5);
}

// Bad rays: a miss with t = +inf everywhere.
TYPED_TEST(SolverKernels, BadRaysMiss) {
  using F = TypeParam;
  const std::vector<Ray<float>> bad = {make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 0}), make_ray(Vec3f{kNaNF, 0, 0}, Vec3f{0, 0, 1}),
                                       make_ray(Vec3f{2, 0, 0}, Vec3f{0, 0, 1}, 5.f, 1.f),
                                       make_ray(Vec3f{2, 0, 0}, Vec3f{0, 0, 1}, kNaNF, 1.f)};
  const auto T = make_torus(Vec3f{0, 0, 10}, Vec3f{0, 0, 1}, 2.f, 0.5f);
  const Algebraic4<float> A{make_algebraic<4>(tri_torus({0, 0, 10}, 2.0, 0.5), {0, 0, 10}, 2.6)};
  const auto W = make_wavy(Vec3f{0, 0, 10}, 1.f, 0.5f, 2.f);
  const auto C = make_revolution_poly(Vec3f{0, 0, 10}, Vec3f{0, 0, 1}, {1, 0, 0, 0}, {-1, 2, 0, 0});
  for (const auto& r : bad) {
    for (const HitF h : {run_one<F>(RB_KERNEL(intersect_torus_ferrari), r, T), run_one<F>(RB_KERNEL(intersect_torus_robust), r, T),
                         run_one<F>([](const auto& a, const auto& b) { return intersect_algebraic<4>(a, b); }, r, A),
                         run_one<F>(RB_KERNEL(intersect_wavy_sphere_trace), r, W), run_one<F>(RB_KERNEL(intersect_wavy_illinois), r, W),
                         run_one<F>(RB_KERNEL(intersect_revolution), r, C)}) {
      EXPECT_FALSE(h.hit);
      EXPECT_EQ(h.t, kInfD);
    }
  }
}

// ---- degenerate primitives ----------------------------------------------------------------------

// Degenerate input gives never() and, when asked, the reason (docs/DESIGN.md section 7).
template <class P>
void expect_never_because(const P& p, const std::string& why, const std::string& part) {
  const auto r = make_ray(Vec3f{0, 0, -5}, Vec3f{0, 0, 1});
  EXPECT_NE(why.find(part), std::string::npos) << why;
  if constexpr (requires { intersect_torus_robust(r, p); }) {
    EXPECT_FALSE(intersect_torus_robust(r, p).mask);
  }
}

TEST(SolverDegenerate, ConstructionErrorsAndNever) {
  std::string why;
  const Vec3f ref{1, 0, 0};
  expect_never_because(make_torus(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 0.5f, 1.f, ref, &why), why, "r = 1");  // R < r
  why.clear();
  expect_never_because(make_torus(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 1.f, 1.f, ref, &why), why, "self-intersecting");  // horn
  why.clear();
  expect_never_because(make_torus(Vec3f{0, 0, 0}, Vec3f{0, 0, 0}, 1.f, 0.5f, ref, &why), why, "zero axis");
  why.clear();
  (void)make_torus(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 1.f, 0.5f, ref, &why);
  EXPECT_TRUE(why.empty()) << why;  // a valid torus leaves why alone
  const auto r = make_ray(Vec3f{0, 0, -5}, Vec3f{0, 0, 1});
  auto alg_never = [&](const auto& a, const char* part) {
    EXPECT_NE(why.find(part), std::string::npos) << why;
    EXPECT_FALSE(intersect_algebraic<std::remove_cvref_t<decltype(a)>::kDegree>(r, a).mask);
    why.clear();
  };
  why.clear();
  alg_never(make_algebraic<4>(TriPoly(4), {0, 0, 0}, 1.0, &why), "all coefficients are zero");
  TriPoly nan = tri_sphere({0, 0, 0}, 1.0);
  nan.at(1, 0, 0) = std::numeric_limits<double>::quiet_NaN();
  alg_never(make_algebraic<2>(nan, {0, 0, 0}, 1.0, &why), "non-finite coefficient");
  alg_never(make_algebraic<2>(tri_torus({0, 0, 0}, 2, 1), {0, 0, 0}, 1.0, &why), "degree 4 exceeds 2");
  (void)make_revolution_poly(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, {kNaNF, 0, 0, 0}, {0, 1, 0, 0}, &why);
  EXPECT_NE(why.find("non-finite profile"), std::string::npos) << why;
  const auto rv = make_revolution_poly(Vec3f{0, 0, 0}, Vec3f{0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, &why);
  EXPECT_NE(why.find("zero axis"), std::string::npos) << why;
  EXPECT_FALSE(intersect_revolution(r, rv).mask);
  // never(): zero tube, NaN torus, zero-length profile, zero radius ball, NaN wavy.
  for (const auto& T : {make_torus(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 1.f, 0.f), make_torus(Vec3f{kNaNF, 0, 0}, Vec3f{0, 0, 1}, 1.f, 0.5f),
                        make_torus(Vec3f{0, 0, 0}, Vec3f{0, 0, 0}, 1.f, 0.5f)}) {
    EXPECT_FALSE(intersect_torus_robust(r, T).mask);
    EXPECT_FALSE(intersect_torus_ferrari(r, T).mask);
  }
  const auto P = make_revolution_bezier(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, {{{1, 0}, {1, 0}, {1, 0}, {1, 0}}});
  EXPECT_FALSE(intersect_revolution(make_ray(Vec3f{-5, 0, 0}, Vec3f{1, 0, 0}), P).mask);
  EXPECT_FALSE(intersect_algebraic<2>(r, make_algebraic<2>(tri_sphere({0, 0, 0}, 1.0), {0, 0, 0}, 0.0)).mask);
  EXPECT_FALSE(intersect_wavy_illinois(r, make_wavy(Vec3f{0, 0, 0}, kNaNF, 0.5f, 2.f)).mask);
  EXPECT_FALSE(intersect_wavy_sphere_trace(r, make_wavy(Vec3f{0, 0, 0}, 1.f, 0.5f, 0.f)).mask);
}

}  // namespace
}  // namespace rb::test
