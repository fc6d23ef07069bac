// Root-solver kernels (torus, algebraic, implicit, revolution) beyond the hand-worked cases (those:
// tests/test_solver_hand_worked.cpp), all scalar: seeded random rays against references, SIMD
// lanes against the scalar float result, op counts.
#include "kernels/algebraic.hpp"
#include "kernels/implicit.hpp"
#include "kernels/revolution.hpp"
#include "kernels/torus.hpp"
#include "kernel_test_util.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace rb::test {
namespace {

// ---- seeded random rays against references (scalar) -----------------------------------------------

using Rng = std::mt19937;
float uniform_f(Rng& g, float a, float b) { return std::uniform_real_distribution<float>(a, b)(g); }

// Rays from a sphere of radius `dist` about c towards a random point near c.
Ray<float> aimed_ray(Rng& g, Vec3f c, float dist, float spread) {
  Vec3f dir{uniform_f(g, -1, 1), uniform_f(g, -1, 1), uniform_f(g, -1, 1)};
  const float l = std::sqrt(dir.x * dir.x + dir.y * dir.y + dir.z * dir.z);
  const Vec3f o = c + dir * (dist / l);
  const Vec3f target = c + Vec3f{uniform_f(g, -spread, spread), uniform_f(g, -spread, spread), uniform_f(g, -spread, spread)};
  return make_ray(o, target - o);
}

// Torus reference: T_ab in long double, roots by dense sign sampling + bisection along the float
// ray promoted exactly (the inputs are never regenerated in higher precision).
long double torus_ld(const Ray<float>& r, const Torus<float>& T, long double t) {
  const long double px = (long double)r.o.x + t * r.d.x - T.c.x, py = (long double)r.o.y + t * r.d.y - T.c.y,
                    pz = (long double)r.o.z + t * r.d.z - T.c.z;
  const long double z = px * T.w.x + py * T.w.y + pz * T.w.z;
  const long double R2 = (long double)T.R * T.R, r2 = (long double)T.r * T.r;
  const long double G = px * px + py * py + pz * pz - R2 - r2;
  return G * G - 4 * R2 * (r2 - z * z);
}
template <class Fn>
double first_root_ref(Fn f, double t0, double t1, int samples) {
  long double a = t0, fa = f(a);
  for (int i = 1; i <= samples; ++i) {
    const long double b = t0 + (t1 - t0) * i / samples, fb = f(b);
    if ((fa < 0) != (fb < 0) || fb == 0) {
      long double lo = a, hi = b, flo = fa;
      for (int k = 0; k < 200; ++k) {
        const long double m = 0.5L * (lo + hi);
        if (m == lo || m == hi) break;
        const long double fm = f(m);
        if ((fm < 0) == (flo < 0) && fm != 0) { lo = m; flo = fm; } else { hi = m; }
      }
      return double(0.5L * (lo + hi));
    }
    a = b;
    fa = fb;
  }
  return kInfD;
}

struct ErrStats {
  std::vector<double> e;
  int false_hit = 0, false_miss = 0;
  double med() { if (e.empty()) return 0; std::sort(e.begin(), e.end()); return e[e.size() / 2]; }
  double mx() { return e.empty() ? 0 : *std::max_element(e.begin(), e.end()); }
};

TEST(SolverAccuracy, TorusFerrariVsRobust) {
  Rng g(20261122);
  const auto T = make_torus(Vec3f{0.3f, -0.2f, 0.1f}, Vec3f{0.2f, 0.1f, 1.f}, 1.f, 0.3f);
  std::printf("torus t error vs long double reference (|dt| in units of the tube radius r = 0.3):\n");
  for (float dist : {5.f, 100.f, 1000.f}) {
    ErrStats fer, rob;
    const int n = 300;
    for (int i = 0; i < n; ++i) {
      const Ray<float> r = aimed_ray(g, T.c, dist, 1.3f);
      const double ref = first_root_ref([&](long double t) { return torus_ld(r, T, t); }, double(dist) - 2.0, double(dist) + 2.0, 4000);
      const Hit<float> hf = intersect_torus_ferrari(r, T), hr = intersect_torus_robust(r, T);
      auto acc = [&](ErrStats& s, const Hit<float>& h) {
        if (h.mask && std::isfinite(ref)) s.e.push_back(std::fabs(double(h.t) - ref) / 0.3);
        else if (h.mask) ++s.false_hit;
        else if (std::isfinite(ref)) ++s.false_miss;
      };
      acc(fer, hf);
      acc(rob, hr);
    }
    std::printf("  distance %6.0f: ferrari median %.2e max %.2e (false hit %d, false miss %d) | robust median %.2e max %.2e (%d, %d)\n",
                double(dist), fer.med(), fer.mx(), fer.false_hit, fer.false_miss, rob.med(), rob.mx(), rob.false_hit, rob.false_miss);
    // The robust solver stays within float resolution of the distance (a few ulps of t).
    EXPECT_LT(rob.med(), 8 * 6e-8 * double(dist) / 0.3 + 1e-5) << dist;
    EXPECT_LE(rob.false_hit + rob.false_miss, 3) << dist;  // grazing rays within float resolution
    EXPECT_LE(rob.med(), fer.med() + 1e-7) << dist;
  }
}

// Hit points satisfy |F| / |grad F| small; misses: no sign change of F in dense double sampling.
TEST(SolverAccuracy, RandomRaysResidualAndMisses) {
  Rng g(7);
  const auto A = make_algebraic<6>(tri_sphere({-0.8, 0, 0}, 0.5) * tri_sphere({0, 0, 0}, 0.5) * tri_sphere({0.8, 0, 0}, 0.5),
                                   {0, 0, 0}, 1.5);
  const auto W = make_wavy(Vec3f{0, 0, 0}, 1.f, 0.5f, 1.7f);
  auto Ad = [&](double x, double y, double z) {
    return ((x + 0.8) * (x + 0.8) + y * y + z * z - 0.25) * (x * x + y * y + z * z - 0.25) * ((x - 0.8) * (x - 0.8) + y * y + z * z - 0.25);
  };
  auto Wd = [&](double x, double y, double z) { return (0.5 - std::cos(x)) * std::cos(z) + (y + std::sin(x)) * std::sin(z) + std::cos(x + z); };
  int hits[3] = {0, 0, 0};
  IterCount st, il;
  int total_skipped = 0, disagree = 0;
  int st_max = 0, il_max = 0;
  for (int i = 0; i < 300; ++i) {
    const Ray<float> r = aimed_ray(g, Vec3f{0, 0, 0}, 6.f, 1.2f);
    // Sampled interval for misses: the part of the ray in the ball |p| <= rb about the origin.
    auto ball = [&](double rb, double& lo, double& hi) {
      const double b = double(r.o.x) * double(r.d.x) + double(r.o.y) * double(r.d.y) + double(r.o.z) * double(r.d.z);
      const double c = double(r.o.x) * double(r.o.x) + double(r.o.y) * double(r.o.y) + double(r.o.z) * double(r.o.z) - rb * rb;
      const double disc = b * b - c;
      lo = disc < 0 ? 0 : -b - std::sqrt(disc);
      hi = disc < 0 ? 0 : -b + std::sqrt(disc);
    };
    int skipped = 0;  // illinois misses with a sign change in the ball (roots closer than its step)
    auto check = [&](bool hit, double t, auto fn, double tol, double rb, bool strict = true) {
      auto at = [&](double tt) { return fn(double(r.o.x) + tt * double(r.d.x), double(r.o.y) + tt * double(r.d.y), double(r.o.z) + tt * double(r.d.z)); };
      if (hit) {
        const double px = double(r.o.x) + t * double(r.d.x), py = double(r.o.y) + t * double(r.d.y), pz = double(r.o.z) + t * double(r.d.z), h = 1e-5;
        const double gx = (fn(px + h, py, pz) - fn(px - h, py, pz)) / (2 * h);
        const double gy = (fn(px, py + h, pz) - fn(px, py - h, pz)) / (2 * h);
        const double gz = (fn(px, py, pz + h) - fn(px, py, pz - h)) / (2 * h);
        // |F| / |grad F|: the distance to the surface to first order; scene scale ~1.
        EXPECT_LT(std::fabs(fn(px, py, pz)) / std::sqrt(gx * gx + gy * gy + gz * gz), tol) << i;
      } else {
        double lo, hi;
        ball(rb, lo, hi);
        // A tiny margin inside the ball: roots within float resolution of its boundary are ambiguous.
        lo += 1e-4;
        hi -= 1e-4;
        double prev = at(lo);
        bool sign_change = false;
        for (int k = 1; k <= 20000 && hi > lo; ++k) {
          const double cur = at(lo + (hi - lo) * k / 20000);
          if ((cur < 0) != (prev < 0)) sign_change = true;
          prev = cur;
        }
        if (strict) EXPECT_FALSE(sign_change) << i;
        else skipped += sign_change;
      }
    };
    const Hit<float> ha = intersect_algebraic<6>(r, A);
    check(ha.mask, ha.t, Ad, 1e-3, 1.5);  // float coefficients of a degree-6 product: ~3e-4 seen
    IterCount a, b;
    const Hit<float> hs = intersect_wavy_sphere_trace(r, W, &a);
    const Hit<float> hi = intersect_wavy_illinois(r, W, &b);
    st.n += a.n; il.n += b.n;
    st_max = std::max(st_max, a.n); il_max = std::max(il_max, b.n);
    check(hs.mask, hs.t, Wd, 5e-3, 1.7);
    check(hi.mask, hi.t, Wd, 5e-3, 1.7, false);
    total_skipped += skipped;
    hits[0] += ha.mask; hits[1] += hs.mask; hits[2] += hi.mask;
    if (hs.mask && hi.mask && std::fabs(hs.t - hi.t) > 1e-2f) ++disagree;
  }
  std::printf("random rays: hits algebraic d6 %d, sphere tracing %d, illinois %d of 300; iterations per ray: "
              "sphere tracing mean %.1f max %d, illinois mean %.1f max %d\n",
              hits[0], hits[1], hits[2], st.n / 300.0, st_max, il.n / 300.0, il_max);
  std::printf("illinois: %d misses skipped a root pair closer than its step; %d rays where the two methods found different roots\n",
              total_skipped, disagree);
  EXPECT_GT(hits[0], 30);
  EXPECT_GT(hits[1], 30);
  EXPECT_LE(total_skipped, 15);
  EXPECT_LE(disagree, 15);
}

// Surfaces of revolution against the analytic cylinder and cone, and the Bezier bulge's profile.
TEST(SolverAccuracy, RevolutionVsAnalytic) {
  Rng g(11);
  const auto cyl = make_revolution_poly(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, {1, 0, 0, 0}, {-1, 2, 0, 0});
  const auto cone = make_revolution_poly(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, {0, 1, 0, 0}, {0, 1, 0, 0});  // r = z, z in [0, 1]
  const auto bulge = make_revolution_bezier(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, {{{0, -1}, {1.3, -1}, {1.3, 1}, {0, 1}}});
  int n_cyl = 0, n_cone = 0, n_bulge = 0;
  for (int i = 0; i < 300; ++i) {
    const Ray<float> r = aimed_ray(g, Vec3f{0, 0, 0}, 5.f, 1.f);
    const double ox = r.o.x, oy = r.o.y, oz = r.o.z, dx = r.d.x, dy = r.d.y, dz = r.d.z;
    // analytic: smallest t >= 0 with the quadric = 0 and z in the profile's range
    auto quad_first = [&](double a, double b, double c, double zlo, double zhi) {
      double best = kInfD;
      const double disc = b * b - 4 * a * c;
      if (disc < 0 || a == 0) return best;
      for (double t : {(-b - std::sqrt(disc)) / (2 * a), (-b + std::sqrt(disc)) / (2 * a)}) {
        const double z = oz + t * dz;
        if (t >= 0 && z >= zlo && z <= zhi) best = std::min(best, t);
      }
      return best;
    };
    const double tc = quad_first(dx * dx + dy * dy, 2 * (ox * dx + oy * dy), ox * ox + oy * oy - 1, -1, 1);
    const double tk = quad_first(dx * dx + dy * dy - dz * dz, 2 * (ox * dx + oy * dy - oz * dz), ox * ox + oy * oy - oz * oz, 0, 1);
    // The elimination of t is ill-conditioned for rays nearly perpendicular to the axis: the float
    // t error measured here grows like ~1e-4 / |z1| (K*(s) cancels, then t = (z(s) - z0) / z1).
    const double ztol = 1e-4 + 2e-4 / std::max(std::fabs(dz), 1e-4);
    const Hit<float> hc = intersect_revolution(r, cyl), hk = intersect_revolution(r, cone), hb = intersect_revolution(r, bulge);
    // Tangent rays within float resolution may go either way: skip those within 1e-3 of a rim.
    if (std::isfinite(tc) || hc.mask) {
      const double zc = oz + tc * dz;
      if (std::fabs(std::fabs(zc) - 1) > 1e-3) {
        EXPECT_EQ(bool(hc.mask), std::isfinite(tc)) << i;
        if (hc.mask && std::isfinite(tc)) { EXPECT_NEAR(double(hc.t), tc, ztol) << i; }
        n_cyl += hc.mask;
      }
    }
    if (std::isfinite(tk) || hk.mask) {
      const double zk = oz + tk * dz;
      if (zk > 1e-3 && zk < 1 - 1e-3) {
        EXPECT_EQ(bool(hk.mask), std::isfinite(tk)) << i;
        if (hk.mask && std::isfinite(tk)) { EXPECT_NEAR(double(hk.t), tk, ztol) << i; }
        n_cone += hk.mask;
      }
    }
    if (hb.mask) {  // the hit point lies on the revolved profile at s = u
      const double t = hb.t, s = hb.u;
      const double px = ox + t * dx, py = oy + t * dy, pz = oz + t * dz;
      const double rs = 3.9 * s * (1 - s), zs = -1 + 6 * s * s - 4 * s * s * s;  // Bezier in power basis
      EXPECT_NEAR(std::sqrt(px * px + py * py), rs, 2 * ztol) << i;
      EXPECT_NEAR(pz, zs, 2 * ztol) << i;
      ++n_bulge;
    }
  }
  EXPECT_GT(n_cyl, 30);
  EXPECT_GT(n_cone, 10);
  EXPECT_GT(n_bulge, 30);
}

// ---- SIMD lanes == scalar float ---------------------------------------------------------------------

template <class Run, class Prim>
void lanes_vs_scalar(Run run, const Prim& prim, Vec3f c, double bound, const char* name) {
  Rng g(3);
  RaySoA rays;
  for (int i = 0; i < 64; ++i) rays.push(aimed_ray(g, c, 5.f, 1.5f));
  int diff = 0;
  double worst = 0;
  for (std::size_t i = 0; i < rays.size(); i += 8) {
    const Hit<f8> hv = run(rays.packet<f8>(i), prim_cast<f8>(prim));
    for (int k = 0; k < 8; ++k) {
      const Hit<float> hs = run(rays.get(i + std::size_t(k)), prim);
      const bool mv = lane_mask<f8>(hv.mask, k);
      const float tv = lane(hv.t, k);
      if (mv != bool(hs.mask)) ++diff;
      else if (!same_bits(tv, hs.t)) worst = std::max(worst, std::fabs(double(tv) - double(hs.t)));
    }
  }
#ifdef RB_FP_CONTRACT_off
  if (bound == 0) {
    EXPECT_EQ(diff, 0) << name;
    EXPECT_EQ(worst, 0.0) << name;
    return;
  }
#endif
  EXPECT_LE(diff, 1) << name;  // a grazing ray may flip with a few-ulp transcendental difference
  EXPECT_LE(worst, bound == 0 ? 1e-4 : bound) << name;
}

TEST(SolverSimd, LanesEqualScalar) {
  // No transcendentals: bit for bit under -ffp-contract=off.
  const auto T = make_torus(Vec3f{0, 0, 0}, Vec3f{0.2f, 0.1f, 1.f}, 1.f, 0.3f);
  lanes_vs_scalar([](const auto& r, const auto& p) { return intersect_torus_robust(r, p); }, T, Vec3f{0, 0, 0}, 0, "torus robust");
  const Algebraic4<float> A{make_algebraic<4>(tri_torus({0, 0, 0}, 1.0, 0.3), {0, 0, 0}, 1.3)};
  lanes_vs_scalar([](const auto& r, const auto& p) { return intersect_algebraic<4>(r, p); }, A, Vec3f{0, 0, 0}, 0, "algebraic");
  const auto B = make_revolution_bezier(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, {{{0, -1}, {1.3, -1}, {1.3, 1}, {0, 1}}});
  lanes_vs_scalar([](const auto& r, const auto& p) { return intersect_revolution(r, p); }, B, Vec3f{0, 0, 0}, 0, "revolution");
  // xsimd's sin/cos/cbrt/acos differ from libm by ulps: stated bounds.
  lanes_vs_scalar([](const auto& r, const auto& p) { return intersect_torus_ferrari(r, p); }, T, Vec3f{0, 0, 0}, 5e-3, "ferrari");
  const auto W = make_wavy(Vec3f{0, 0, 0}, 1.f, 0.5f, 1.7f);
  lanes_vs_scalar([](const auto& r, const auto& p) { return intersect_wavy_sphere_trace(r, p); }, W, Vec3f{0, 0, 0}, 2e-3, "sphere tracing");
  lanes_vs_scalar([](const auto& r, const auto& p) { return intersect_wavy_illinois(r, p); }, W, Vec3f{0, 0, 0}, 2e-3, "illinois");
}

// ---- op counts ---------------------------------------------------------------------------------------

TEST(SolverOps, FerrariIsBranchFreeAndMissIsCheap) {
  const auto T = make_torus(Vec3f{0, 0, 10}, Vec3f{0, 0, 1}, 2.f, 0.5f);
  auto count = [&](const Ray<float>& r) {
    const ops::Scope s;
    (void)intersect_torus_ferrari(Ray<cfloat>::broadcast(r), prim_cast<cfloat>(T));
    return s.elapsed();
  };
  const OpCounts h1 = count(make_ray(Vec3f{2, 0, 0}, Vec3f{0, 0, 1}));
  const OpCounts h2 = count(make_ray(Vec3f{-5, 0, 10}, Vec3f{1, 0, 0}));
  const OpCounts m = count(make_ray(Vec3f{5, 0, 0}, Vec3f{0, 0, 1}));
  EXPECT_EQ(h1, h2);  // closed form: the same work for every ray that reaches the quartic
  // Golden miss (kernels/bounding_sphere.hpp): q = o - c (3+), q x d (3+ 6*), its square (2+ 3*),
  // m = d.d (2+ 3*), m R2 - |q x d|^2 (1+ 1*), 1 cmp; no division.
  EXPECT_EQ(m, (OpCounts{11, 13, 0, 0, 1, 0, 1, 0}));  // + 1 select: t = +inf
  std::printf("ferrari hit: %s, miss: %s\n", h1.str().c_str(), m.str().c_str());
}

}  // namespace
}  // namespace rb::test
