// The solver-only set: quartics with known roots (clustered, widely spread, multiple), solved by
// the engine's root isolation + safeguarded Newton (core/poly.hpp, the robust torus's solver) in
// float, double and simd8. The coefficients are formed from the roots in double and stored as
// floats; the reference is the stored polynomial's own first root in [lo, hi] (long double
// isolation), so rounding the coefficients is not counted against the solver.
#include "accuracy/exact.hpp"
#include "core/poly.hpp"

#include <cmath>

namespace rb {
// A quartic c0 + c1 x + ... + c4 x^4 on [lo, hi], as a primitive of the lab's runner.
template <class F>
struct Quartic {
  F c0, c1, c2, c3, c4, lo, hi;
  auto fields() { return std::tie(c0, c1, c2, c3, c4, lo, hi); }
  static Quartic never() { return {F(1), F(0), F(0), F(0), F(0), F(0), F(1)}; }  // p = 1: no root
};
}  // namespace rb

namespace rb::acc {

namespace {
// First root in [lo, hi] (the ray is not used: the lab's runner shape).
template <class F>
Hit<F> first_root(const Ray<F>&, const Quartic<F>& q, IterCount* ic) {
  const F c[5] = {q.c0, q.c1, q.c2, q.c3, q.c4};
  const F tol = cst<F>(4 * double(std::numeric_limits<scalar_t<F>>::epsilon())) * (vabs(q.lo) + vabs(q.hi));
  F x[4];
  mask_t<F> ok[4];
  poly_roots_in<4, F>(c, q.lo, q.hi, tol, x, ok, ic);
  F t = F(kInf<F>);
  mask_t<F> m = mask_false<F>();
  for (int k = 3; k >= 0; --k) {
    t = vselect(ok[k], x[k], t);
    m = m | ok[k];
  }
  return make_hit<F>(m, t);
}
}  // namespace

std::vector<CaseInfo> quartic_cases() {
  return {
      {"quartic", "clustered", "four roots r + k delta, delta 1e-1..1e-5 of r, r in [0.5, 2], interval [-4, 4]"},
      {"quartic", "spread", "roots of magnitudes 1e-3..1e3 (signs random), interval [-2000, 2000]"},
      {"quartic", "multiple", "a double root (x - a)^2 (x - b)(x - c): no sign change at a (the isolation's blind spot)"},
  };
}

void run_quartics(Ctx& x) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  x.each_case(quartic_cases(), [&](const auto& ci) {
    Case<Quartic> c;
    c.family = ci.family, c.name = ci.name, c.what = ci.what;
    for (std::size_t i = 0; i < n; ++i) {
      double r[4], lo = -4, hi = 4;
      if (ci.name == "clustered") {
        const double a = urand(g, 0.5, 2) * (i % 2 ? 1 : -1), dl = a * lurand(g, 1e-5, 1e-1);
        for (int k = 0; k < 4; ++k) r[k] = a + k * dl;
      } else if (ci.name == "spread") {
        for (int k = 0; k < 4; ++k) r[k] = lurand(g, 1e-3, 1e3) * (urand(g, 0, 1) < 0.5 ? -1 : 1);
        lo = -2000, hi = 2000;
      } else {
        const double a = urand(g, -2, 2);
        r[0] = r[1] = a, r[2] = urand(g, -3, 3), r[3] = urand(g, -3, 3);
      }
      double p[5] = {1, 0, 0, 0, 0};
      for (int k = 0; k < 4; ++k) {
        for (int j = k + 1; j >= 1; --j) p[j] = p[j - 1] - r[k] * p[j];
        p[0] = -r[k] * p[0];
      }
      // Monic in x^4 after the loop: p[4] = 1 (coefficients ascending).
      const Quartic<float> q{float(p[0]), float(p[1]), float(p[2]), float(p[3]), float(p[4]), float(lo), float(hi)};
      c.prims.push(q);
      c.rays.push(make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}));
      const long double cf[5] = {q.c0, q.c1, q.c2, q.c3, q.c4};
      const auto roots = poly_roots_ld(cf, 4, (long double)q.lo, (long double)q.hi);
      Ref f;
      f.scale = std::fabs(double(q.lo)) + std::fabs(double(q.hi));
      if (!roots.empty()) f.cls = Cls::hit, f.t = roots.front(), f.has_t = true;
      // A root of even multiplicity is invisible to sign tests, the reference's included: stored
      // as floats, it becomes two close simple roots or none, and both sides see the same.
      c.ref.push_back(f);
    }
    // No "wrong root" figure: the solver's tolerance is absolute (4 eps x the interval), so the t
    // error of small roots is large by design; it is in the ulp columns.
    measure(x, c, "isolation_newton", [](const auto& r, const auto& q, IterCount* ic) { return first_root(r, q, ic); }, false, true);
  });
}

}  // namespace rb::acc
