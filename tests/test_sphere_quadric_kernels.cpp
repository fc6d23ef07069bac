// The quadric kernel family, part 1: spheres (stable, Hearn-Baker, [u,v], roots), the general
// quadric (matrix and ten-coefficient methods) with every named quadric of seed 004, and the
// quadric of revolution.
//   - hand-worked hits, misses, t, normals, [u,v], typed over the value types
//     (float, double, f8, d4; Counted<T> computes what T computes: tests/kernel_test_util.hpp);
//   - degenerate inputs and construction errors; stable vs naive accuracy.
// Cylinders, cones and transformed instances: tests/test_cylinder_cone_transform_kernels.cpp;
// the checks over every kernel of the family: tests/test_quadric_family_checks.cpp.
#include "kernels/quadric.hpp"
#include "kernels/sphere.hpp"
#include "quadric_test_util.hpp"

#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace rb::test {
namespace {

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

}  // namespace
}  // namespace rb::test
