// Implicit surfaces: thin features closer than the marching step. Two surfaces, each the product
// of two factors whose zero sets are known exactly, so the reference roots come from the same
// float inputs:
//   thin_shell   F = (|q|^2 - a)(|q|^2 - b), q = p - c: two concentric spheres of squared radii a
//                and b (R = 1, wall thickness 2e-3..2e-2), negative inside the wall;
//   twin_planes  F = (n.q - a)(n.q - b): two parallel planes 2e-3..2e-2 apart, negative between.
// Both are cut to a bounding sphere of radius 1.25 (the kernels' search interval). The engine's
// two implicit methods run on them as a scene would configure them: sphere tracing with a
// Lipschitz bound of F on the bounding sphere, the fixed-step sign search + Illinois with the
// step the wavy surface uses (bounding radius / 8), and the same marcher with a step below the
// feature (a third of the wall), the fix, at the cost of its iterations. A hit on a later
// surface than the first (stepping over the near wall and finding the far side of the shell) is
// a wrong root. Reference roots: MPFR for the spheres, long double for the planes.
#include "accuracy/exact.hpp"
#include "kernels/implicit.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace rb::acc {

// Lab-only primitives (the engine's implicit kernels take any callable F).
template <class F>
struct Shell {
  Vec3<F> c;
  F a, b;                     // squared radii, a < b
  F br2, inv_L, h, h_fine, eps;  // bounding sphere, 1 / Lipschitz bound, coarse and fine step, tolerance
  auto fields() { return std::tie(c.x, c.y, c.z, a, b, br2, inv_L, h, h_fine, eps); }
  static Shell never() { return {{F(0), F(0), F(0)}, F(1), F(1), F(-kInf<F>), F(1), F(1), F(1), F(1)}; }
};
template <class F>
struct TwinPlanes {
  Vec3<F> c, n;
  F a, b;  // plane offsets along n, a < b
  F br2, inv_L, h, h_fine, eps;
  auto fields() { return std::tie(c.x, c.y, c.z, n.x, n.y, n.z, a, b, br2, inv_L, h, h_fine, eps); }
  static TwinPlanes never() { return {{F(0), F(0), F(0)}, {F(0), F(0), F(1)}, F(0), F(1), F(-kInf<F>), F(1), F(1), F(1), F(1)}; }
};

namespace {

constexpr double kBound = 1.25;  // bounding radius
constexpr double kEps = 1e-5 * kBound;

template <class F>
RB_INLINE F shell_eval(const Shell<F>& s, const Vec3<F>& p) {
  const Vec3<F> q = p - s.c;
  const F m = dot(q, q);
  return (m - s.a) * (m - s.b);
}
template <class F>
RB_INLINE F twin_eval(const TwinPlanes<F>& s, const Vec3<F>& p) {
  const F z = dot(p - s.c, s.n);
  return (z - s.a) * (z - s.b);
}

// The three methods on a primitive with an eval function.
template <template <class> class P, class Eval>
void measure_methods(Ctx& x, const Case<P>& c, Eval ev) {
  measure(
      x, c, "sphere_tracing",
      [ev](const auto& r, const auto& s, IterCount* ic) {
        using F = std::decay_t<decltype(s.a)>;
        return intersect_implicit_sphere_trace(r, [&s, ev](const Vec3<F>& p) { return ev(s, p); }, s.c, s.br2, s.inv_L, s.eps, ic);
      },
      true, true);
  measure(
      x, c, "illinois",
      [ev](const auto& r, const auto& s, IterCount* ic) {
        using F = std::decay_t<decltype(s.a)>;
        return intersect_implicit_illinois(r, [&s, ev](const Vec3<F>& p) { return ev(s, p); }, s.c, s.br2, s.h, s.eps, ic);
      },
      true, true);
  measure(
      x, c, "illinois_fine_step",
      [ev](const auto& r, const auto& s, IterCount* ic) {
        using F = std::decay_t<decltype(s.a)>;
        return intersect_implicit_illinois(r, [&s, ev](const Vec3<F>& p) { return ev(s, p); }, s.c, s.br2, s.h_fine, s.eps, ic);
      },
      true, true);
}

// The reference from the sorted roots (first: the answer; second: what a wrong root lands near).
Ref from_roots(std::vector<long double> ts, const Ref& first, double scale) {
  Ref f = first;
  f.scale = scale;
  std::sort(ts.begin(), ts.end());
  for (long double t : ts)
    if (f.has_t && t > f.t + 1e-9L * (1 + std::fabs(f.t))) {
      f.t_next = t, f.has_next = true;
      break;
    }
  return f;
}

inline long double L(float v) { return static_cast<long double>(v); }

// Roots of |o + t d - c|^2 = r2 in [lo, hi] (long double; only the later roots use it).
void sphere_roots_ld(const Vec3f& o, const Vec3f& d, const Vec3f& c, float r2, long double lo, long double hi,
                     std::vector<long double>& out) {
  const long double fx = L(o.x) - L(c.x), fy = L(o.y) - L(c.y), fz = L(o.z) - L(c.z);
  const long double A = L(d.x) * L(d.x) + L(d.y) * L(d.y) + L(d.z) * L(d.z);
  const long double B = fx * L(d.x) + fy * L(d.y) + fz * L(d.z), C = fx * fx + fy * fy + fz * fz - L(r2);
  const long double disc = B * B - A * C;
  if (disc < 0) return;
  const long double s = std::sqrt(disc);
  for (long double t : {(-B - s) / A, (-B + s) / A})
    if (lo <= t && t <= hi) out.push_back(t);
}

}  // namespace

std::vector<CaseInfo> implicit_cases() {
  return {
      {"implicit", "thin_shell",
       "spherical shell R = 1, wall 2e-3..2e-2 (below the marching step 1.25 / 8), rays aimed at radii within 3 walls of it"},
      {"implicit", "twin_planes", "two parallel planes 2e-3..2e-2 apart in a bounding sphere of radius 1.25, rays crossing them"},
  };
}

void run_implicit(Ctx& x) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  x.each_case(implicit_cases(), [&](const auto& ci) {
    if (ci.name == "thin_shell") {
      Case<Shell> c;
      c.family = ci.family, c.name = ci.name, c.what = ci.what;
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3d ctr = Vec3d{0.5, -0.25, 0.125} + unit_rand(g) * urand(g, 0, 1);
        const double w = lurand(g, 2e-3, 2e-2), r1 = 1 - w / 2, r2 = 1 + w / 2;
        Shell<float> s;
        s.c = to_float(ctr);
        s.a = float(r1 * r1), s.b = float(r2 * r2);
        s.br2 = float(kBound * kBound);
        // |grad F| = |2 q (2 |q|^2 - a - b)| <= 2 rb max(2 rb^2 - a - b, a + b), 1 % margin.
        const double A = double(s.a), B = double(s.b);
        s.inv_L = float(1.0 / (1.01 * 2 * kBound * std::max(2 * kBound * kBound - A - B, A + B)));
        s.h = float(kBound / 8), s.h_fine = float(w / 3), s.eps = float(kEps);
        const Vec3d eye = ctr + unit_rand(g) * 4.0;
        const Vec3d target = ctr + unit_rand(g) * urand(g, r1 - 3 * w, r2 + 3 * w);
        c.prims.push(s);
        c.rays.push(make_ray(eye, target - eye));
        const Ray<float> r = c.rays.get(c.rays.count - 1);
        const Ref ra = sphere_ref(r.o, r.d, r.tmin, r.tmax, s.c, s.a), rb = sphere_ref(r.o, r.d, r.tmin, r.tmax, s.c, s.b);
        Ref first;
        if (ra.cls == Cls::hit || rb.cls == Cls::hit)
          first.cls = Cls::hit;
        else if (ra.cls == Cls::either || rb.cls == Cls::either)
          first.cls = Cls::either;
        for (const Ref* q : {&ra, &rb})
          if (q->has_t && (!first.has_t || q->t < first.t)) first.t = q->t, first.has_t = true;
        std::vector<long double> ts;
        sphere_roots_ld(r.o, r.d, s.c, s.a, L(r.tmin), L(r.tmax), ts);
        sphere_roots_ld(r.o, r.d, s.c, s.b, L(r.tmin), L(r.tmax), ts);
        c.ref.push_back(from_roots(ts, first, norm(to_double(r.o)) + norm(ctr) + kBound));
      }
      measure_methods(x, c, [](const auto& s, const auto& p) { return shell_eval(s, p); });
    } else {
      Case<TwinPlanes> c;
      c.family = ci.family, c.name = ci.name, c.what = ci.what;
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3d ctr = Vec3d{0.5, -0.25, 0.125} + unit_rand(g) * urand(g, 0, 1);
        const double w = lurand(g, 2e-3, 2e-2), mid = urand(g, -0.3, 0.3);
        TwinPlanes<float> s;
        s.c = to_float(ctr);
        s.n = to_float(unit_rand(g));
        s.a = float(mid - w / 2), s.b = float(mid + w / 2);
        s.br2 = float(kBound * kBound);
        // |grad F| = |n| |2 n.q - a - b| <= |n| (2 |n| rb + |a + b|), 1 % margin.
        const Vec3d nd = to_double(s.n);
        const double ln = norm(nd);
        s.inv_L = float(1.0 / (1.01 * ln * (2 * ln * kBound + std::fabs(double(s.a) + double(s.b)))));
        s.h = float(kBound / 8), s.h_fine = float(w / 3), s.eps = float(kEps);
        // Rays at least 0.2 off the planes' direction, crossing near the middle of the slab.
        Vec3d dir = unit_rand(g);
        while (std::fabs(dot(dir, nd)) < 0.2 * ln) dir = unit_rand(g);
        Vec3d inplane = unit_rand(g);
        inplane = inplane - nd * (dot(inplane, nd) / (ln * ln));
        const Vec3d target = ctr + nd * (mid / (ln * ln)) + inplane * urand(g, 0, 0.4);
        c.prims.push(s);
        c.rays.push(make_ray(target - dir * 4.0, dir));
        const Ray<float> r = c.rays.get(c.rays.count - 1);
        // Plane k: n . (o + t d - c) = a_k; a root counts inside the bounding sphere only.
        const long double qx = L(r.o.x) - L(s.c.x), qy = L(r.o.y) - L(s.c.y), qz = L(r.o.z) - L(s.c.z);
        const long double nq = qx * L(s.n.x) + qy * L(s.n.y) + qz * L(s.n.z);
        const long double ndd = L(r.d.x) * L(s.n.x) + L(r.d.y) * L(s.n.y) + L(r.d.z) * L(s.n.z);
        std::vector<long double> ts;
        for (float off : {s.a, s.b}) {
          const long double t = (L(off) - nq) / ndd;
          const long double px = qx + t * L(r.d.x), py = qy + t * L(r.d.y), pz = qz + t * L(r.d.z);
          if (t >= L(r.tmin) && t <= L(r.tmax) && px * px + py * py + pz * pz <= L(s.br2)) ts.push_back(t);
        }
        std::sort(ts.begin(), ts.end());
        Ref first;
        if (!ts.empty()) first.cls = Cls::hit, first.t = ts.front(), first.has_t = true;
        c.ref.push_back(from_roots(ts, first, norm(to_double(r.o)) + norm(ctr) + kBound));
      }
      measure_methods(x, c, [](const auto& s, const auto& p) { return twin_eval(s, p); });
    }
  });
}

}  // namespace rb::acc
