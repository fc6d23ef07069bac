// Ray x torus (seed 000 "Toroid"): in basic position (centre 0, axis z, ring radius R = a,
// tube radius r = b) the surface is T_ab(x, y, z) = (x^2 + y^2 + z^2 - R^2 - r^2)^2 - 4R^2(r^2 - z^2).
// The placement frame is a centre c, a unit axis w and a reference direction e (for u only):
// x^2 + y^2 + z^2 = |p - c|^2 is frame-free and z = (p - c) . w, so the quartic needs w alone.
// With q = o - c, m = d.d, n = q.d, k = q.q - R^2 - r^2, qz = q.w, dz = d.w:
//   A*(t) = m^2 t^4 + 4mn t^3 + (4n^2 + 2mk + 4R^2 dz^2) t^2 + (4nk + 8R^2 qz dz) t + k^2 + 4R^2 (qz^2 - r^2)
//
// Two solvers:
//   ferrari  closed form: depressed quartic, Schwarze's resolvent cubic (Cardano / trigonometric
//            largest root: 2 cbrt or 1 acos + 1 cos), two quadratics. The quartic is formed at
//            the ray origin, as the textbook does; its coefficients then carry terms of size
//            |q|^4 that cancel to the size of the answer, so accuracy falls with distance.
//   robust   moves the origin to the bounding-sphere entry (kernels/bounding_sphere.hpp) (|q| <= R + r there), forms the
//            quartic in s = t - t0 on [0, t1 - t0], isolates its roots between the roots of its
//            derivatives and refines them by safeguarded Newton (core/poly.hpp), then polishes
//            with Newton steps on T_ab evaluated directly at the point (not on the expanded
//            polynomial). Iterations: see IterCount.
// Both reject with the bounding sphere |q| <= R + r first (the negative case).
// Spindle / horn tori (r >= R) self-intersect: make_torus refuses them (never(), with the reason).
#pragma once

#include "core/poly.hpp"
#include "core/ray.hpp"
#include "core/roots.hpp"
#include "core/why.hpp"
#include "kernels/bounding_sphere.hpp"

#include <numbers>
#include <string>
#include <tuple>

namespace rb {

template <class F>
struct Torus {
  Vec3<F> c, w, e;  // centre, unit axis, unit reference direction (u = 0) perpendicular to w
  F R, r, bs2;      // ring radius, tube radius, (R + r)^2 (-inf: never hits)
  auto fields() { return std::tie(c.x, c.y, c.z, w.x, w.y, w.z, e.x, e.y, e.z, R, r, bs2); }
  static Torus never() {
    return {{F(0), F(0), F(0)}, {F(0), F(0), F(1)}, {F(1), F(0), F(0)}, F(0), F(0), F(-kInf<F>)};
  }
};

// Non-finite input, r <= 0, a zero axis, or r >= R (the spindle / horn torus crosses itself; T_ab
// still has roots there, but the tube's inside and the normal at the axis are not defined):
// Torus::never(), the reason in *why. `ref` picks the u = 0 direction (projected onto the plane
// of the ring; any perpendicular is used when it is parallel to the axis).
template <class T>
inline Torus<float> make_torus(Vec3<T> c, Vec3<T> axis, T R, T r, Vec3<T> ref = {T(1), T(0), T(0)}, std::string* why = nullptr) {
  using P = Torus<float>;
  if (!finite3(c) || !finite3(axis) || !finite3(ref) || !std::isfinite(R) || !std::isfinite(r))
    return never_because<P>(why, "torus: non-finite input");
  if (!(r > T(0))) return never_because<P>(why, "torus: tube radius r is not positive");
  if (!(R > r))
    return never_because<P>(why, "torus: tube radius r = " + std::to_string(double(r)) + " >= ring radius R = " +
                                     std::to_string(double(R)) + " (spindle/horn torus is self-intersecting: not supported)");
  Vec3d w = to_double(axis);
  const double wl = std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
  if (!(wl > 0.0)) return never_because<P>(why, "torus: zero axis");
  w = {w.x / wl, w.y / wl, w.z / wl};
  auto perp = [&](Vec3d v) {
    const double k = v.x * w.x + v.y * w.y + v.z * w.z;
    return Vec3d{v.x - k * w.x, v.y - k * w.y, v.z - k * w.z};
  };
  Vec3d e = perp(to_double(ref));
  double el = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
  if (!(el > 1e-6)) {
    e = perp(std::fabs(w.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0});
    el = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
  }
  const double bs = double(R) + double(r);
  return {to_float(to_double(c)), to_float(w), to_float(Vec3d{e.x / el, e.y / el, e.z / el}), float(R), float(r),
          float(bs * bs)};
}

namespace detail {

// Coefficients c[0..4] of T_ab(q + s d) in s.
template <class F>
RB_INLINE void torus_quartic(const Vec3<F>& q, const Vec3<F>& d, const Torus<F>& T, F (&c)[5]) {
  const F R2 = T.R * T.R, r2 = T.r * T.r;
  const F m = dot(d, d), n = dot(q, d), k = dot(q, q) - (R2 + r2);
  const F qz = dot(q, T.w), dz = dot(d, T.w);
  const F fR2 = F(4) * R2;
  c[4] = m * m;
  c[3] = F(4) * m * n;
  c[2] = F(4) * n * n + F(2) * m * k + fR2 * dz * dz;
  c[1] = F(4) * n * k + F(2) * fR2 * qz * dz;
  c[0] = k * k + fR2 * (qz * qz - r2);
}

// T_ab and its derivative along d at p = q + s d, evaluated from the point (not the expansion).
template <class F>
RB_INLINE void torus_f_df(const Vec3<F>& p, const Vec3<F>& d, const Torus<F>& T, F& f, F& df) {
  const F R2 = T.R * T.R, r2 = T.r * T.r;
  const F G = dot(p, p) - (R2 + r2);
  const F z = dot(p, T.w);
  const F fR2 = F(4) * R2;
  f = G * G - fR2 * (r2 - z * z);
  df = F(4) * G * dot(p, d) + F(2) * fR2 * z * dot(d, T.w);
}

}  // namespace detail

// ---- closed form ------------------------------------------------------------------------------

// Largest real root of z^3 + a z^2 + b z + c (Cardano when one real root, trigonometric when three).
template <class F>
RB_INLINE F cubic_largest_root(const F& a, const F& b, const F& c) {
  const F sub = a * cst<F>(1.0 / 3.0);
  const F a2 = a * a;
  const F p = (b - a2 * cst<F>(1.0 / 3.0)) * cst<F>(1.0 / 3.0);                              // P/3
  const F q = F(0.5) * (cst<F>(2.0 / 27.0) * a2 * a - cst<F>(1.0 / 3.0) * a * b + c);       // Q/2
  const F p3 = p * p * p;
  const F D = q * q + p3;
  // one real root
  const F sD = vsqrt(vmax(D, F(0)));
  const F y1 = vcbrt(sD - q) - vcbrt(sD + q);
  // three real roots: the largest, 2 sqrt(-p) cos(phi / 3)
  const F mp = vmax(-p, F(0));
  const F cphi = vclamp(-q / vsqrt(vmax(-p3, F(0))), F(-1), F(1));
  const F y3 = F(2) * vsqrt(mp) * vcos(vacos(cphi) * cst<F>(1.0 / 3.0));
  // Cardano only when D is clearly positive: at D ~ 0 (a double root) Cardano returns the simple
  // root, which may be the smallest, and the factorisation below then needs the largest.
  const F tiny = cst<F>(32 * double(std::numeric_limits<scalar_t<F>>::epsilon())) * (q * q + vabs(p3));
  return vselect(D > tiny, y1, y3) - sub;
}

// All real roots of the torus quartic in [tmin, tmax] by Ferrari / Schwarze, ascending.
template <class F>
RB_INLINE Roots<F, 4> torus_roots_ferrari(const Ray<F>& r, const Torus<F>& T) {
  const Vec3<F> oc = r.o - T.c;
  const Roots<F, 2> clip = bounding_sphere_span(r, oc, T.bs2);
  if (none_of<F>(clip.valid[0])) return Roots<F, 4>::none();
  F c[5];
  detail::torus_quartic(oc, r.d, T, c);
  const F inv = F(1) / c[4];
  const F A = c[3] * inv, B = c[2] * inv, C = c[1] * inv, D = c[0] * inv;
  const F A2 = A * A;
  const F p = B - cst<F>(3.0 / 8.0) * A2;
  const F q = A2 * A * cst<F>(1.0 / 8.0) - F(0.5) * A * B + C;
  const F rr = A2 * (F(-3.0 / 256.0) * A2 + cst<F>(1.0 / 16.0) * B) - F(0.25) * A * C + D;
  // Resolvent z^3 - p/2 z^2 - rr z + (rr p / 2 - q^2 / 8) = 0; its largest root makes u^2, v^2 >= 0.
  const F z = cubic_largest_root(F(-0.5) * p, -rr, F(0.5) * rr * p - F(0.125) * q * q);
  const F u = vsqrt(vmax(z * z - rr, F(0)));
  const F v = vcopysign(vsqrt(vmax(F(2) * z - p, F(0))), q);
  // y^2 + v y + (z - u) = 0 and y^2 - v y + (z + u) = 0; t = y - A/4.
  const F hv = F(0.5) * v, shift = F(0.25) * A;
  const F d1 = hv * hv - (z - u), d2 = hv * hv - (z + u);
  const F s1 = vsqrt(vmax(d1, F(0))), s2 = vsqrt(vmax(d2, F(0)));
  F t[4] = {-hv - s1 - shift, -hv + s1 - shift, hv - s2 - shift, hv + s2 - shift};
  const mask_t<F> ok[4] = {d1 >= F(0), d1 >= F(0), d2 >= F(0), d2 >= F(0)};
  for (int i = 0; i < 4; ++i) t[i] = vselect(clip.valid[0] & ok[i] & (t[i] >= r.tmin) & (t[i] <= r.tmax), t[i], F(kInf<F>));
  return Roots<F, 4>::canonical(t);
}

template <class F>
RB_INLINE Hit<F> intersect_torus_ferrari(const Ray<F>& r, const Torus<F>& T) {
  const Roots<F, 4> rt = torus_roots_ferrari(r, T);
  return make_hit<F>(rt.valid[0], rt.t[0]);
}

// ---- robust: origin at the bounding-sphere entry, isolation + Newton, polish on T_ab --------------

namespace detail {
template <class F>
struct TorusLocal {
  Vec3<F> q0;  // q + t0 d: the shifted origin, |q0| <= R + r
  F t0, s[4];  // roots s = t - t0 (ascending, +inf where none)
  mask_t<F> m;
};

template <class F>
RB_INLINE TorusLocal<F> torus_local_roots(const Ray<F>& r, const Torus<F>& T, IterCount* ic) {
  TorusLocal<F> L;
  const Vec3<F> q = r.o - T.c;
  const Roots<F, 2> clip = bounding_sphere_span(r, q, T.bs2);
  L.m = clip.valid[0];
  if (none_of<F>(L.m)) return L;
  // The search starts a little before the bounding-sphere entry: the torus touches its sphere
  // all along the outer equator, so a ray entering there has a root within rounding of s = 0,
  // and q0 carries an error of ~eps |t0|; when p(0) then rounded to the root's far side, the
  // first root was lost and the next one returned (found by the accuracy lab at 500x the torus
  // size). A root found before the entry is still checked against tmin below. 2+- 1* 1 min/max.
  const F pad = cst<F>(8 * double(std::numeric_limits<scalar_t<F>>::epsilon())) * (vabs(clip.lo()) + T.R + T.r);
  L.t0 = clip.lo() - pad;
  L.q0 = q + r.d * L.t0;
  const F W = vmax(clip.hi() - L.t0, F(0)) + pad;
  F c[5];
  torus_quartic(L.q0, r.d, T, c);
  const F tol = F(4 * std::numeric_limits<scalar_t<F>>::epsilon()) * (W + T.r);
  F s[4];
  mask_t<F> ok[4];
  poly_roots_in<4, F>(c, F(0), W, tol, s, ok, ic);
  for (int i = 0; i < 4; ++i) s[i] = vselect(L.m & ok[i], s[i], F(kInf<F>));
  sort_net<4>(s);
  for (int i = 0; i < 4; ++i) L.s[i] = s[i];
  return L;
}

// Two Newton steps on T_ab at the point; a step longer than r/100 (a tangent or a wrong basin)
// is not taken.
template <class F>
RB_INLINE F torus_polish(const Vec3<F>& q0, const Vec3<F>& d, const Torus<F>& T, F s) {
  const F lim = cst<F>(0.01) * T.r;
  for (int it = 0; it < 2; ++it) {
    F f, df;
    torus_f_df(q0 + d * s, d, T, f, df);
    const F step = f / df;
    s = vselect(vabs(step) <= lim, s - step, s);
  }
  return s;
}
}  // namespace detail

template <class F>
RB_INLINE Roots<F, 4> torus_roots_robust(const Ray<F>& r, const Torus<F>& T, IterCount* ic = nullptr) {
  const detail::TorusLocal<F> L = detail::torus_local_roots(r, T, ic);
  if (none_of<F>(L.m)) return Roots<F, 4>::none();
  F t[4];
  for (int i = 0; i < 4; ++i) {
    const mask_t<F> found = L.s[i] < F(kInf<F>);
    t[i] = L.t0 + detail::torus_polish(L.q0, r.d, T, vselect(found, L.s[i], F(0)));
    t[i] = vselect(found & (t[i] >= r.tmin) & (t[i] <= r.tmax), t[i], F(kInf<F>));
  }
  return Roots<F, 4>::canonical(t);  // polishing may swap two close roots: sorted again
}

template <class F>
RB_INLINE Hit<F> intersect_torus_robust(const Ray<F>& r, const Torus<F>& T, IterCount* ic = nullptr) {
  const detail::TorusLocal<F> L = detail::torus_local_roots(r, T, ic);
  if (none_of<F>(L.m)) return miss_hit<F>();
  mask_t<F> m = L.s[0] < F(kInf<F>);
  const F s = detail::torus_polish(L.q0, r.d, T, vselect(m, L.s[0], F(0)));
  const F t = L.t0 + s;
  m = m & (t >= r.tmin) & (t <= r.tmax);
  return make_hit<F>(m, t);
}

// Outward unit normal at a point p on the torus: grad T_ab = 4 G q + 8 R^2 z w (q = p - c).
template <class F>
RB_INLINE Vec3<F> torus_normal(const Torus<F>& T, const Vec3<F>& p) {
  const Vec3<F> q = p - T.c;
  const F G = dot(q, q) - (T.R * T.R + T.r * T.r);
  const F z = dot(q, T.w);
  return normalize(q * (F(4) * G) + T.w * (F(8) * T.R * T.R * z));
}

// [u, v] in [0, 1)^2: u the angle around the axis from e, v the angle around the tube from the
// outer equator towards +w (seed 000's "two angles"). 2 atan2.
template <class F>
RB_INLINE void torus_uv(const Torus<F>& T, const Vec3<F>& p, F& u, F& v) {
  const Vec3<F> q = p - T.c;
  const F z = dot(q, T.w);
  const F x = dot(q, T.e), y = dot(q, cross(T.w, T.e));
  const F inv2pi = cst<F>(0.5 / std::numbers::pi);
  const F a = vatan2(y, x) * inv2pi, b = vatan2(z, vsqrt(x * x + y * y) - T.R) * inv2pi;
  u = vselect(a < F(0), a + F(1), a);
  v = vselect(b < F(0), b + F(1), b);
}

}  // namespace rb
