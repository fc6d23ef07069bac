// Ray x sphere.
//   geometric (seed 000 "Sphere (geometric solution)"): v = C - P0, t0 = v . p1,
//     D^2 = v . v - t0^2, tD^2 = R^2 - D^2; miss if tD^2 < 0, else t = t0 -+ tD.
//     lecture: negative case 9+- 6* 1<, positive additionally 2+- 1 sqrt. Needs |p1| = 1.
//   algebraic (seed 002 "Ray-Sphere Intersection"): A = d . d, B = 2 d . (e - c),
//     C = (e - c) . (e - c) - R^2, disc = B^2 - 4AC, t = (-B -+ sqrt(disc)) / 2A.
// Both return the nearer root in [tmin, tmax] (the far one when the near one is before tmin).
#pragma once

#include "core/ray.hpp"
#include "core/roots.hpp"
#include "core/why.hpp"
#include "kernels/quadratic.hpp"


namespace rb {

template <class F>
struct Sphere {
  Vec3<F> c;
  F r2, inv_r;
  auto fields() { return std::tie(c.x, c.y, c.z, r2, inv_r); }
  // R^2 = -inf: tD^2 = -inf (geometric) and disc = -inf (algebraic) for every ray.
  static Sphere never() { return {{F(0), F(0), F(0)}, F(-kInf<F>), F(0)}; }
};

// Zero, negative or non-finite radius, or a non-finite centre: Sphere::never().
template <class T>
inline Sphere<float> make_sphere(Vec3<T> c, T r) {
  if (!finite3(c) || !std::isfinite(r) || !(r > T(0))) return Sphere<float>::never();
  const double rd = double(r);
  if (!std::isfinite(float(rd * rd)) || float(rd * rd) == 0.f) return Sphere<float>::never();
  return {to_float(to_double(c)), float(rd * rd), float(1.0 / rd)};
}

template <class F>
RB_INLINE Hit<F> intersect_sphere_geometric(const Ray<F>& r, const Sphere<F>& s) {
  const Vec3<F> v = s.c - r.o;                  // 3+-
  const F t0 = dot(v, r.d);                     // 2+- 3*
  const F D2 = dot(v, v) - t0 * t0;             // 3+- 4*
  const F tD2 = s.r2 - D2;                      // 1+-
  mask_t<F> m = tD2 >= F(0);                    // 1 cmp   (negative case ends here)
  if (none_of<F>(m)) return miss_hit<F>();
  const F tD = vsqrt(tD2);                      // 1 sqrt
  const F t1 = t0 - tD, t2 = t0 + tD;           // 2+-
  const F t = vselect(t1 >= r.tmin, t1, t2);    // 1 cmp 1 select
  m = m & (t >= r.tmin) & (t <= r.tmax);        // 2 cmp
  return make_hit<F>(m, t);                     // 1 select
}

template <class F>
RB_INLINE Hit<F> intersect_sphere_algebraic(const Ray<F>& r, const Sphere<F>& s) {
  const Vec3<F> oc = r.o - s.c;                 // 3+-
  const F A = dot(r.d, r.d);                    // 2+- 3*
  const F B = F(2) * dot(r.d, oc);              // 2+- 4*
  const F C = dot(oc, oc) - s.r2;               // 3+- 3*
  const F disc = B * B - F(4) * A * C;          // 1+- 3*
  mask_t<F> m = disc >= F(0);                   // 1 cmp
  if (none_of<F>(m)) return miss_hit<F>();
  const F sq = vsqrt(disc);                     // 1 sqrt
  const F twoA = F(2) * A;                      // 1*
  const F t1 = (-B - sq) / twoA;                // 1+- 1/
  const F t2 = (-B + sq) / twoA;                // 1+- 1/
  const F t = vselect(t1 >= r.tmin, t1, t2);    // 1 cmp 1 select
  m = m & (t >= r.tmin) & (t <= r.tmax);        // 2 cmp
  return make_hit<F>(m, t);                     // 1 select
}

// Outward unit normal at a point on the sphere: (P - C) / R.  3+- 3*
template <class F>
RB_INLINE Vec3<F> sphere_normal(const Sphere<F>& s, const Vec3<F>& p) { return (p - s.c) * s.inv_r; }

// ---- issue 3 (quadric family): stable algebraic, Hearn-Baker, [u,v], all roots -----------------
//   stable (Press et al., Numerical Recipes 5.6; Haines et al., Ray Tracing Gems ch. 7):
//     f = P0 - C, a = d . d, b = f . d (half b), c = f . f - R^2, disc = b^2 - a c,
//     q = -(b + sign(b) sqrt(disc)), t0 = q / a, t1 = c / q (kernels/quadratic.hpp).
//     Any direction length: t is in units of |d| (usable under a transformation).
//   hearn_baker (Hearn & Baker; Ray Tracing Gems ch. 7 eq. 7.11): with |d| = 1, the squared
//     distance of the centre from the ray's line is |f - (f . d) d|^2, formed as the length of a
//     vector rather than as the difference f . f - b^2 of two large numbers, so
//     disc = R^2 - |f - (f . d) d|^2 keeps its accuracy for a small sphere far away; the roots
//     then use the stable q (t0 = q, t1 = c / q). Requires a unit direction (the Ray contract;
//     not usable under a transformation that scales d).

template <class F>
RB_INLINE Hit<F> intersect_sphere_stable(const Ray<F>& r, const Sphere<F>& s) {
  const Vec3<F> f = r.o - s.c;                  // 3+-
  const F a = dot(r.d, r.d);                    // 2+- 3*
  const F b = dot(f, r.d);                      // 2+- 3*
  const F c = dot(f, f) - s.r2;                 // 3+- 3*
  const F disc = b * b - a * c;                 // 1+- 2*
  const mask_t<F> m = disc >= F(0);             // 1 cmp   (negative case ends here)
  if (none_of<F>(m)) return miss_hit<F>();
  return first_hit(r, stable_roots(a, b, c, disc, m));  // 1+- 1 sqrt 2/ 2 minmax, 3 cmp 2 select
}

template <class F>
RB_INLINE Hit<F> intersect_sphere_hearn_baker(const Ray<F>& r, const Sphere<F>& s) {
  const Vec3<F> f = r.o - s.c;                  // 3+-
  const F b = dot(f, r.d);                      // 2+- 3*
  const Vec3<F> l = f - r.d * b;                // 3+- 3*
  const F disc = s.r2 - dot(l, l);              // 3+- 3*
  const mask_t<F> m = disc >= F(0);             // 1 cmp   (negative case ends here)
  if (none_of<F>(m)) return miss_hit<F>();
  const F c = dot(f, f) - s.r2;                 // 3+- 3*
  const F q = -(b + vcopysign(vsqrt(disc), b)); // 1+- 1 sqrt
  const F t1 = c / q;                           // 1/   (a = 1: t0 = q)
  return first_hit(r, Roots<F, 2>::span(m, vmin(t1, q), vmax(t1, q)));  // 2 minmax, 3 cmp 2 select
}

// All roots of the (closed) sphere: one entry/exit interval [t[0], t[1]] on the whole line
// (not clipped to [tmin, tmax]: CSG combines intervals first). Stable form, any |d|.
template <class F>
RB_INLINE Roots<F, 2> sphere_roots(const Ray<F>& r, const Sphere<F>& s) {
  const Vec3<F> f = r.o - s.c;
  const F a = dot(r.d, r.d);
  const F b = dot(f, r.d);
  const F c = dot(f, f) - s.r2;
  const F disc = b * b - a * c;
  const mask_t<F> m = disc >= F(0);
  if (none_of<F>(m)) return Roots<F, 2>::none();
  const Roots<F, 2> q = stable_roots(a, b, c, disc, m);
  return Roots<F, 2>::closed_span(m, q.lo(), q.hi());
}

// ---- [u,v] on the sphere (seed 000 "Inverse transformation on the sphere") ----------------------
// Pole P and equator E (unit, orthogonal), N the unit normal at the hit point:
//   Phi = arccos(-N . P), theta = arccos((N . E) / sin Phi) / 2 pi,
//   v = Phi / pi, u = theta if (P x E) . N > 0 else 1 - theta.
// sin Phi = sqrt(1 - (N . P)^2) (no sine call); both arccos arguments are clamped to [-1, 1]
// (rounding puts |N . P| slightly above 1 near the poles); at a pole sin Phi = 0 and the 0/0 is
// clamped to -1 (NaN in the first argument of vmax gives the second), so u = 1/2 there: defined.
// Counts: 8+- 12* 1/ 1 sqrt 4 minmax 1 cmp 1 select, and 2 arccos (a separate tally:
// ops::trans_current()).
template <class F>
struct SphereUV {
  Sphere<F> s;
  Vec3<F> P, E, PxE;  // pole, equator, P x E (precomputed)
  auto fields() {
    return std::tie(s.c.x, s.c.y, s.c.z, s.r2, s.inv_r, P.x, P.y, P.z, E.x, E.y, E.z, PxE.x, PxE.y, PxE.z);
  }
  static SphereUV never() {
    return {Sphere<F>::never(), {F(0), F(0), F(1)}, {F(1), F(0), F(0)}, {F(0), F(1), F(0)}};
  }
};

// Degenerate sphere (as make_sphere), a zero or non-finite pole, or an equator direction that is
// zero or parallel to the pole: never() (the reason in *why). E is made orthogonal to P
// (Gram-Schmidt in double) and both are normalised.
template <class T>
inline SphereUV<float> make_sphere_uv(Vec3<T> c, T r, Vec3<T> pole = {T(0), T(0), T(1)}, Vec3<T> equator = {T(1), T(0), T(0)},
                                      std::string* why = nullptr) {
  using S = SphereUV<float>;
  const Vec3d p = to_double(pole), e = to_double(equator);
  const double lp = std::sqrt(dot(p, p));
  if (!finite3(p) || !std::isfinite(lp) || lp == 0.0) return never_because<S>(why, "sphere: pole direction is zero or not finite");
  const Vec3d P = p * (1.0 / lp);
  const Vec3d e2 = e - P * dot(e, P);
  const double le = std::sqrt(dot(e2, e2));
  const double le0 = std::sqrt(dot(e, e));
  if (!finite3(e) || !std::isfinite(le0) || !(le > 1e-6 * le0))
    return never_because<S>(why, "sphere: equator direction is zero, not finite or parallel to the pole");
  const Vec3d E = e2 * (1.0 / le);
  const Sphere<float> s = make_sphere(c, r);
  if (!(s.r2 > 0.f)) return never_because<S>(why, "sphere: radius is not positive and finite");
  return {s, to_float(P), to_float(E), to_float(cross(P, E))};
}

template <class F>
struct SphereUVCoord {
  F u, v;
};

template <class F>
RB_INLINE SphereUVCoord<F> sphere_uv_map(const Vec3<F>& N, const Vec3<F>& P, const Vec3<F>& E, const Vec3<F>& PxE) {
  const F one = F(1);
  const F np = vclamp(dot(N, P), -one, one);              // 2+- 3*, 2 minmax
  const F phi = vacos(-np);                               // 1 acos
  const F sin_phi = vsqrt(one - np * np);                 // 1+- 1* 1 sqrt
  const F ce = vclamp(dot(N, E) / sin_phi, -one, one);    // 2+- 3* 1/, 2 minmax (0/0 at a pole -> -1)
  const F theta = vacos(ce) * F(scalar_t<F>(0.15915494309189535));     // 1 acos 1*   (1 / 2 pi)
  const F v = phi * F(scalar_t<F>(0.31830988618379067));               // 1*          (1 / pi)
  const mask_t<F> side = dot(PxE, N) > F(0);              // 2+- 3* 1 cmp
  return {vselect(side, theta, one - theta), v};          // 1+- 1 select
}

// Stable intersection plus [u,v] of the hit: N = (P0 + t d - C) / R. u, v are 0 on missing lanes.
template <class F>
RB_INLINE Hit<F> intersect_sphere_uv(const Ray<F>& r, const SphereUV<F>& s) {
  Hit<F> h = intersect_sphere_stable(r, s.s);
  if (none_of<F>(h.mask)) return h;
  const Vec3<F> N = (r.at(h.t) - s.s.c) * s.s.inv_r;      // 6+- 6*
  const SphereUVCoord<F> uv = sphere_uv_map(N, s.P, s.E, s.PxE);
  h.u = vselect(h.mask, uv.u, F(0));                      // 2 select
  h.v = vselect(h.mask, uv.v, F(0));
  return h;
}

}  // namespace rb
