// The quadric kernel family, part 3: the checks run over every kernel of the family (spheres,
// general quadric, quadric of revolution, cylinder, cone, transformed instances).
//   - bad rays: a miss with t = +inf in every kernel, typed over the value types;
//   - seeded random rays checked independently in double (hit points on the surface, misses
//     against a dense sampling of the implicit function);
//   - SIMD lanes (both mappings) equal the scalar float result bit for bit (-ffp-contract=off);
//   - golden Counted<float> op counts.
// The hand-worked cases: tests/test_sphere_quadric_kernels.cpp,
// tests/test_cylinder_cone_transform_kernels.cpp.
#include "kernels/cylinder_cone.hpp"
#include "kernels/quadric.hpp"
#include "kernels/sphere.hpp"
#include "kernels/transform.hpp"
#include "quadric_test_util.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

namespace rb::test {
namespace {

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
