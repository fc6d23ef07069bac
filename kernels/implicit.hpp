// Ray x implicit surface F(x, y, z) = 0 (seed 000 "Implicit surface"): roots of F*(t) = F(P0 + t p1).
// The surface is any callable f(const Vec3<F>&) -> F written with the number layer (so it runs
// for every number type), restricted to a bounding sphere (centre bc, radius^2 br2) that also
// gives the search interval [t0, t1].
//
//   sphere tracing  t += |F(P(t))| / L with L a Lipschitz bound of F on the bounding sphere:
//                   |F(p)| <= L dist(p, surface), so the step never crosses the surface. Hit when
//                   the step is below eps; linear convergence, slow for grazing rays.
//   illinois        march a fixed step h until F changes sign, then Illinois regula falsi on the
//                   bracket (false position, halving the value kept twice in a row). Misses pairs
//                   of roots closer than h (a ray clipping a thin feature).
// Both loops are capped; a packet loops until its last lane finishes (lanes that finished are
// masked), so SIMD speed follows the slowest lane. Iterations are reported through IterCount.
//
// The slide's example, here with a placement c and parameters a, cc:
//   (cc - cos a x) cos z + (y + a sin a x) sin z + cos a(x + z) = 0.
#pragma once

#include "core/poly.hpp"
#include "core/ray.hpp"
#include "core/why.hpp"
#include "kernels/bounding_sphere.hpp"

#include <tuple>

namespace rb {

inline constexpr int kSphereTraceCap = 1024;
inline constexpr int kMarchCap = 4096;

namespace detail {
// f at the ray point of parameter t on live lanes, at the bounding centre bc on the others (3
// selects). A dead lane's point can be far from the surface (a lane that missed the bounding
// sphere sits at the ray origin), and a transcendental f (the slide's example uses sin and cos)
// then takes xsimd's slow wide-argument range reduction for the whole packet: measured, this made
// the 8-lane forms slower in the half-hit case than the scalar form.
template <class F, class Fn>
RB_INLINE F eval_live(const Fn& f, const Ray<F>& r, const F& t, const mask_t<F>& live, const Vec3<F>& bc) {
  const Vec3<F> p = r.at(t);
  return f(Vec3<F>{vselect(live, p.x, bc.x), vselect(live, p.y, bc.y), vselect(live, p.z, bc.z)});
}

}  // namespace detail

// Sphere tracing with step |f| * inv_L; hit when the step is <= eps.
template <class F, class Fn>
RB_INLINE Hit<F> intersect_implicit_sphere_trace(const Ray<F>& r, const Fn& f, const Vec3<F>& bc, const F& br2, const F& inv_L,
                                                 const F& eps, IterCount* ic = nullptr) {
  const Roots<F, 2> clip = bounding_sphere_span(r, r.o - bc, br2);
  if (none_of<F>(clip.valid[0])) return miss_hit<F>();
  mask_t<F> act = clip.valid[0];
  const F t0 = clip.lo(), t1 = clip.hi();
  F t = vselect(act, t0, F(0));
  mask_t<F> hit = mask_false<F>();
  for (int it = 0; it < kSphereTraceCap && any_of<F>(act); ++it) {
    iter_add(ic);
    const F step = vabs(detail::eval_live(f, r, t, act, bc)) * inv_L;
    const mask_t<F> close = step <= eps;
    hit = hit | (act & close);
    t = vselect(act & mask_not<F>(close), t + step, t);
    act = act & mask_not<F>(close) & (t <= t1);
  }
  return make_hit<F>(hit & (t >= t0) & (t <= t1), t);
}

// Fixed-step sign search (step h), then Illinois refinement to |bracket| <= tol.
template <class F, class Fn>
RB_INLINE Hit<F> intersect_implicit_illinois(const Ray<F>& r, const Fn& f, const Vec3<F>& bc, const F& br2, const F& h,
                                             const F& tol, IterCount* ic = nullptr) {
  const Roots<F, 2> clip = bounding_sphere_span(r, r.o - bc, br2);
  if (none_of<F>(clip.valid[0])) return miss_hit<F>();
  const F t0 = clip.lo(), t1 = clip.hi();
  mask_t<F> act = clip.valid[0];
  F ta = vselect(act, t0, F(0));
  F fa = detail::eval_live(f, r, ta, act, bc);
  F tb = ta, fb = fa;
  mask_t<F> found = act & (fa == F(0));
  act = act & mask_not<F>(found);
  // March: [ta, tb] advances by h until the sign changes or tb reaches t1.
  for (int it = 0; it < kMarchCap && any_of<F>(act); ++it) {
    iter_add(ic);
    const F tn = vmin(ta + h, t1);
    const F fn = detail::eval_live(f, r, tn, act, bc);
    tb = vselect(act, tn, tb);
    fb = vselect(act, fn, fb);
    const mask_t<F> sc = ((fa < F(0)) & (fb >= F(0))) | ((fa > F(0)) & (fb <= F(0)));
    found = found | (act & sc);
    const mask_t<F> go = act & mask_not<F>(sc);
    const mask_t<F> end = tn >= t1;
    ta = vselect(go, tb, ta);
    fa = vselect(go, fb, fa);
    act = go & mask_not<F>(end);
  }
  // Illinois on the lanes with a bracket; a lane with fa == 0 keeps ta.
  F t = vselect(fa == F(0), ta, tb);
  act = found & (fa != F(0)) & (fb != F(0));
  for (int it = 0; it < kNewtonCap<F> && any_of<F>(act); ++it) {
    iter_add(ic);
    const F tc = (fa * tb - fb * ta) / (fa - fb);
    const F fc = detail::eval_live(f, r, tc, act, bc);
    const mask_t<F> flip = ((fc < F(0)) & (fb > F(0))) | ((fc > F(0)) & (fb < F(0)));
    // flip: the root lies between tb and tc, (tb, fb) becomes the other end; else halve fa.
    ta = vselect(act & flip, tb, ta);
    fa = vselect(act & flip, fb, vselect(act, F(0.5) * fa, fa));
    tb = vselect(act, tc, tb);
    fb = vselect(act, fc, fb);
    t = vselect(act, tc, t);
    act = act & (fc != F(0)) & (vabs(tb - ta) > tol);
  }
  return make_hit<F>(found & (t >= t0) & (t <= t1), t);
}

// Unit normal by central differences of f (6 evaluations), step h.
template <class F, class Fn>
RB_INLINE Vec3<F> implicit_normal(const Fn& f, const Vec3<F>& p, const F& h) {
  const F gx = f(Vec3<F>{p.x + h, p.y, p.z}) - f(Vec3<F>{p.x - h, p.y, p.z});
  const F gy = f(Vec3<F>{p.x, p.y + h, p.z}) - f(Vec3<F>{p.x, p.y - h, p.z});
  const F gz = f(Vec3<F>{p.x, p.y, p.z + h}) - f(Vec3<F>{p.x, p.y, p.z - h});
  return normalize(Vec3<F>{gx, gy, gz});
}

// ---- the slide's example surface --------------------------------------------------------------

template <class F>
struct Wavy {
  Vec3<F> c;      // placement: the formula is evaluated at p - c
  F a, cc;        // parameters a and c of the slide's formula
  F br2, inv_L;   // bounding sphere about c (-inf: never hits), 1 / Lipschitz bound on it
  F h, eps;       // march step (illinois), hit tolerance (both methods)
  auto fields() { return std::tie(c.x, c.y, c.z, a, cc, br2, inv_L, h, eps); }
  static Wavy never() { return {{F(0), F(0), F(0)}, F(1), F(0), F(-kInf<F>), F(1), F(1), F(1)}; }
};

template <class F>
RB_INLINE F wavy_eval(const Wavy<F>& W, const Vec3<F>& p) {
  const Vec3<F> u = p - W.c;
  const F ax = W.a * u.x;
  return (W.cc - vcos(ax)) * vcos(u.z) + (u.y + W.a * vsin(ax)) * vsin(u.z) + vcos(W.a * (u.x + u.z));
}

// A Lipschitz bound on the ball |u| <= rb: |dF/dx| <= 2a + a^2, |dF/dy| <= 1,
// |dF/dz| <= |cc| + 1 + rb + 2a (|y| <= rb), L = |(those)|. Non-finite input: never();
// rb <= 0: never(); a == 0 is allowed (then F = cc cos z + y sin z + cos 0 ...).
template <class T>
inline Wavy<float> make_wavy(Vec3<T> c, T a, T cc, T rb, int steps_per_radius = 8, std::string* why = nullptr) {
  if (!finite3(c) || !std::isfinite(a) || !std::isfinite(cc) || !std::isfinite(rb)) return never_because<Wavy<float>>(why, "wavy: non-finite input");
  if (!(rb > T(0))) return never_because<Wavy<float>>(why, "wavy: bounding radius is not positive");
  if (steps_per_radius < 1) return never_because<Wavy<float>>(why, "wavy: steps_per_radius must be >= 1");
  const double A = std::fabs(double(a)), R = double(rb);
  const double gx = 2 * A + A * A, gy = 1.0, gz = std::fabs(double(cc)) + 1.0 + R + 2 * A;
  const double L = std::sqrt(gx * gx + gy * gy + gz * gz);
  return {to_float(to_double(c)), float(a), float(cc), float(R * R), float(1.0 / L), float(R / steps_per_radius), float(1e-4 * R)};
}

template <class F>
RB_INLINE Hit<F> intersect_wavy_sphere_trace(const Ray<F>& r, const Wavy<F>& W, IterCount* ic = nullptr) {
  return intersect_implicit_sphere_trace(r, [&W](const Vec3<F>& p) { return wavy_eval(W, p); }, W.c, W.br2, W.inv_L, W.eps, ic);
}
// The evaluation lambda is forced inline where kernels are (timed loops): GCC otherwise keeps it out
// of line at the five call sites of the Illinois loop, and the SIMD benchmarks lose much of their
// speed. Sphere tracing gains nothing from it (its scalar loop is a little slower inlined).
template <class F>
RB_INLINE Hit<F> intersect_wavy_illinois(const Ray<F>& r, const Wavy<F>& W, IterCount* ic = nullptr) {
  return intersect_implicit_illinois(r, [&W](const Vec3<F>& p) RB_INLINE_LAMBDA { return wavy_eval(W, p); }, W.c, W.br2, W.h, W.eps, ic);
}
template <class F>
RB_INLINE Vec3<F> wavy_normal(const Wavy<F>& W, const Vec3<F>& p) {
  return implicit_normal([&W](const Vec3<F>& x) { return wavy_eval(W, x); }, p, F(10) * W.eps);
}

}  // namespace rb
