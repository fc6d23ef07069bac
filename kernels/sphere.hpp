// Ray x sphere.
//   geometric (seed 000 "Sphere (geometric solution)"): v = C - P0, t0 = v . p1,
//     D^2 = v . v - t0^2, tD^2 = R^2 - D^2; miss if tD^2 < 0, else t = t0 -+ tD.
//     lecture: negative case 9+- 6* 1<, positive additionally 2+- 1 sqrt. Needs |p1| = 1; here
//     a = p1 . p1 is used where the lecture has 1 (negative case 11+- 12* 1<, positive
//     additionally 2+- 2* 1/ 1 sqrt), see intersect_sphere_geometric.
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

// Zero, negative or non-finite radius, or a non-finite centre: Sphere::never() (the reason in *why).
template <class T>
inline Sphere<float> make_sphere(Vec3<T> c, T r, std::string* why = nullptr) {
  using S = Sphere<float>;
  if (!finite3(c)) return never_because<S>(why, "sphere: centre is not finite");
  if (!std::isfinite(r) || !(r > T(0))) return never_because<S>(why, "sphere: radius is not positive and finite");
  const double rd = double(r);
  if (!std::isfinite(float(rd * rd)) || float(rd * rd) == 0.f)
    return never_because<S>(why, "sphere: radius squared is not representable in float");
  return {to_float(to_double(c)), float(rd * rd), float(1.0 / rd)};
}

// The lecture's construction divides by |p1|^2 = p1 . p1 where it assumed 1: a unit direction
// rounded to float has |p1|^2 = 1 +- 1e-7, and t0^2 (up to (distance)^2) then carries an error of
// 1e-7 t0^2, which exceeds R^2 once distance / R is above ~3e3: half the rays at distance / R =
// 1e4 were misclassified, in double too (the double ray is the float one, widened). With
// a = p1 . p1 the squares are kept multiplied by a (no division before the test):
// a D^2 = a v . v - t0^2, a tD^2 = a R^2 - a D^2, and the roots t = t0 / a -+ sqrt(a tD^2) / a.
template <class F>
RB_INLINE Hit<F> intersect_sphere_geometric(const Ray<F>& r, const Sphere<F>& s) {
  const Vec3<F> v = s.c - r.o;                  // 3+-
  const F t0 = dot(v, r.d);                     // 2+- 3*
  const F a = dot(r.d, r.d);                    // 2+- 3*
  const F D2a = a * dot(v, v) - t0 * t0;        // 3+- 5*
  const F tD2a = a * s.r2 - D2a;                // 1+- 1*
  mask_t<F> m = tD2a >= F(0);                   // 1 cmp   (negative case ends here)
  if (none_of<F>(m)) return miss_hit<F>();
  const F ia = F(1) / a;                        // 1/
  const F t0a = t0 * ia;                        // 1*
  const F tD = vsqrt(tD2a) * ia;                // 1* 1 sqrt
  const F t1 = t0a - tD, t2 = t0a + tD;         // 2+-
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

// ---- the quadric family: stable algebraic, Hearn-Baker, [u,v], all roots -----------------
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

// ---- compensated: float in, float out, right on a planet ------------------------------------------
//   A viewer 1 above a sphere of radius 6.4e6 sees grazing rays whose distance from the centre
//   differs from R by less than a float ulp of R (0.5): every method above misclassifies a large
//   share of them in float (f = P0 - C and R^2 are ~1e7 and ~4e13, and c = f.f - R^2 and b = f.d
//   are differences of such numbers). This method forms the two small quantities without that
//   loss, with error-free transformations (Ogita, Rump and Oishi's Dot2; Dekker/Knuth two-sum,
//   two-product by FMA):
//     f = P0 - C as an unevaluated sum fh + fl (two-sum per coordinate),
//     b = f . d and c = f . f - R^2 each as if summed exactly and rounded once (the rounding errors
//     of the products and partial sums are collected and added at the end),
//     disc = b^2 - a c with a = d . d (one product rounded, one inside the FMA),
//   then the stable roots. disc is then wrong by a few ulps of b^2 (about 1 for the planet at
//   height 1) instead of by ulps of R^2 (4e6). Products are vrounded so that contraction cannot
//   fuse a product into a two-sum (which would make the collected errors wrong). Any |d|.
//   miss: 42+- 9* 6 fma 1 cmp more or less (see the ops table); hit: + the stable roots.
namespace detail {
// s + e == a + b exactly (Knuth's two-sum: any order of magnitude).  6+-
template <class F>
RB_INLINE F two_sum(const F& a, const F& b, F& e) {
  const F s = a + b;
  const F bb = s - a;
  e = (a - (s - bb)) + (b - bb);
  return s;
}
// p + e == a * b exactly (FMA).  1* 1 fma
template <class F>
RB_INLINE F two_prod(const F& a, const F& b, F& e) {
  const F p = vrounded(a * b);
  e = vfma(a, b, -p);
  return p;
}
}  // namespace detail

template <class F>
RB_INLINE Hit<F> intersect_sphere_compensated(const Ray<F>& r, const Sphere<F>& s) {
  using detail::two_prod;
  using detail::two_sum;
  // f = fh + fl exactly.                                                        18+-
  Vec3<F> fl;
  const Vec3<F> fh{two_sum(r.o.x, -s.c.x, fl.x), two_sum(r.o.y, -s.c.y, fl.y), two_sum(r.o.z, -s.c.z, fl.z)};
  // b = f . d: the products' and partial sums' errors, and fl . d, collected.     3* 3 fma 3* 20+-
  F ex, ey, ez, e1, e2;
  const F px = two_prod(fh.x, r.d.x, ex), py = two_prod(fh.y, r.d.y, ey), pz = two_prod(fh.z, r.d.z, ez);
  const F s1 = two_sum(px, py, e1);
  const F s2 = two_sum(s1, pz, e2);
  const F bl = ((e1 + e2) + (ex + ey + ez)) + vrounded(dot(fl, r.d));  // b = s2 + bl
  // c = f . f - R^2 likewise (2 fh . fl for the cross term; fl . fl is below the rounding).  3* 3 fma 3* 27+-
  F qx, qy, qz, g1, g2, g3;
  const F ux = two_prod(fh.x, fh.x, qx), uy = two_prod(fh.y, fh.y, qy), uz = two_prod(fh.z, fh.z, qz);
  const F u1 = two_sum(ux, uy, g1);
  const F u2 = two_sum(u1, uz, g2);
  const F u3 = two_sum(u2, -s.r2, g3);
  const F cl = ((g1 + g2) + g3) + ((qx + qy + qz) + F(2) * vrounded(dot(fh, fl)));  // c = u3 + cl
  // a = d . d = 1 +- 1e-7 likewise (its rounding, times c ~ 1e7, would be an error of ~1 in disc).  3* 3 fma 16+-
  F ax, ay, az, h1, h2;
  const F wx = two_prod(r.d.x, r.d.x, ax), wy = two_prod(r.d.y, r.d.y, ay), wz = two_prod(r.d.z, r.d.z, az);
  const F w1 = two_sum(wx, wy, h1);
  const F a = two_sum(w1, wz, h2);
  const F al = (h1 + h2) + (ax + ay + az);                                    // a + al = d . d
  // disc = b^2 - a c from the unrounded pairs: s2^2 and a u3 exactly (two-products), their
  // difference (exact when they are close: the grazing case), then the small terms.  5* 2 fma 8+-
  F bbe, ace;
  const F bb = two_prod(s2, s2, bbe), ac = two_prod(a, u3, ace);
  const F small = F(2) * vrounded(s2 * bl) - (vrounded(a * cl) + vrounded(al * u3));
  const F disc = (bb - ac) + ((bbe - ace) + small);
  const mask_t<F> m = disc >= F(0);                                           // 1 cmp
  if (none_of<F>(m)) return miss_hit<F>();
  const F b = s2 + bl, c = u3 + cl;                                           // 2+-
  return first_hit(r, stable_roots(a, b, c, disc, m));
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
  const Sphere<float> s = make_sphere(c, r, why);
  if (!(s.r2 > 0.f)) return S::never();
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
