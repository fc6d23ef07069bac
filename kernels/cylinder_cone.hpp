// Ray x cylinder and ray x cone about the z axis (seed 000 "Cylinder and cone").
//
//   unit cylinder x^2 + y^2 - 1 = 0, substituted:
//     t^2 (x1^2 + y1^2) + 2t (x0 x1 + y0 y1) + x0^2 + y0^2 - 1 = 0
//   unit cone x^2 + y^2 - z^2 = 0 (half-angle 45 degrees, apex at 0), substituted:
//     t^2 (x1^2 + y1^2 - z1^2) + 2t (x0 x1 + y0 y1 - z0 z1) + x0^2 + y0^2 - z0^2 = 0
// Placement kept to what the kernels need: the cylinder has an axis (cx, cy) and a radius (R^2
// replaces the 1: no extra operation), the cone an apex (cx, cy, cz); both have a height range
// z0 <= z <= z1 (along the axis, relative to the apex for the cone; +-inf for unbounded). Any
// other placement (tilted axes, other cone angles, elliptic sections) is a transformed instance
// (kernels/transform.hpp). Roots use the stable half-B form (kernels/quadratic.hpp).
//
// Two methods each:
//   lecture (open surface): the two roots of the quadratic, each kept when its z lies in
//     [z0, z1] and t in [tmin, tmax]; the nearer kept root wins. A tube / a (double) cone shell.
//   capped (closed solid, with the disc caps at z0 and z1): the solid is the intersection of
//     the infinite solid {quadric <= 0} with the slab z0 <= z <= z1, so along the ray it is the
//     intersection of two t intervals (seed 000 "Convex polyhedron": t_in = max, t_out = min).
//     The slab interval is ordered by the sign of 1/z1 (as Williams et al. order slabs), not by
//     min/max, so an empty range (never()) stays empty. cylinder_roots / cone_roots return the
//     entry/exit interval (Roots<F, 2>) for CSG.
//     Cylinder, ray parallel to the axis (A == 0): inside the whole line when C <= 0, else
//       nowhere (explicit selects: the quadratic degenerates to the constant C).
//     Cone: must be a single nappe (0 <= z0 or z1 <= 0: make_capped_cone), which is convex.
//       A > 0: inside between the roots; A < 0 (a ray steeper than the cone): inside before lo
//       (one nappe) and after hi (the other): the part in the solid's nappe is taken (by the
//       signs of dz and z1; such a line always meets the cone: a negative disc is rounding near
//       the apex and is clamped to the double root); A == 0
//       (parallel to a generator): t0 = q / A = +-inf makes [lo, hi] the correct half-line.
//   A ray lying in a cap plane and parallel to it makes a slab bound 0 * inf = NaN; the bound
//   is placed first in vmax/vmin so it is dropped: such a boundary ray counts as inside the slab.
// 1/z1 is formed in the kernel (1/) rather than read from the ray's rd, so both work under a
// transformation without kRecip. No [u,v] (the lecture defines none for these surfaces).
#pragma once

#include "core/roots.hpp"
#include "core/why.hpp"
#include "kernels/quadratic.hpp"
#include "kernels/transform.hpp"

#include <cmath>

namespace rb {

// ---- cylinder -----------------------------------------------------------------------------------
template <class F>
struct Cylinder {
  F cx, cy, r2, z0, z1;
  auto fields() { return std::tie(cx, cy, r2, z0, z1); }
  // R^2 = -inf (C = +inf, disc = -inf) and an empty height range.
  static Cylinder never() { return {F(0), F(0), F(-kInf<F>), F(kInf<F>), F(-kInf<F>)}; }
};

// Axis through (cx, cy) along z, radius r, z0 <= z <= z1 (infinite bounds allowed). Zero, negative
// or non-finite radius, NaN bounds, infinite axis position, or zero or negative height: never()
// (the reason in *why).
template <class T>
inline Cylinder<float> make_cylinder(T cx, T cy, T r, T z0, T z1, std::string* why = nullptr) {
  using C = Cylinder<float>;
  if (!std::isfinite(cx) || !std::isfinite(cy)) return never_because<C>(why, "cylinder: axis position is not finite");
  if (!std::isfinite(r) || !(r > T(0))) return never_because<C>(why, "cylinder: radius is not positive and finite");
  if (std::isnan(z0) || std::isnan(z1) || !(z0 < z1) || z0 == std::numeric_limits<T>::infinity() ||
      z1 == -std::numeric_limits<T>::infinity())
    return never_because<C>(why, "cylinder: height range is empty or NaN");
  const double rr = double(r) * double(r);
  if (!std::isfinite(float(rr)) || float(rr) == 0.f) return never_because<C>(why, "cylinder: radius squared is not representable in float");
  if (!(float(z0) < float(z1))) return never_because<C>(why, "cylinder: height range is empty in float");
  return {float(cx), float(cy), float(rr), float(z0), float(z1)};
}

namespace detail {
// The quadratic of the cylinder (half-B): 2+- then A 1+- 2*, B 1+- 2*, C 2+- 2*, disc 1+- 2*.
template <class F>
struct CylQuad {
  F ox, oy, A, B, C, disc;
};
template <class F>
RB_INLINE CylQuad<F> cylinder_quad(const Ray<F>& r, const Cylinder<F>& c) {
  const F ox = r.o.x - c.cx, oy = r.o.y - c.cy;
  const F A = r.d.x * r.d.x + r.d.y * r.d.y;
  const F B = ox * r.d.x + oy * r.d.y;
  const F C = ox * ox + oy * oy - c.r2;
  return {ox, oy, A, B, C, B * B - A * C};
}

// Open surface: the nearer root whose z lies in [z0, z1] and t in [tmin, tmax].
//   2+- 2*, 8 cmp, 1 select (+ make_hit)
template <class F>
RB_INLINE Hit<F> open_surface_hit(const Ray<F>& r, const Roots<F, 2>& q, const F& oz, const F& z0, const F& z1) {
  const F zl = oz + q.lo() * r.d.z, zh = oz + q.hi() * r.d.z;
  const mask_t<F> okl = (q.lo() >= r.tmin) & (q.lo() <= r.tmax) & (zl >= z0) & (zl <= z1);
  const mask_t<F> okh = (q.hi() >= r.tmin) & (q.hi() <= r.tmax) & (zh >= z0) & (zh <= z1);
  const mask_t<F> m = q.valid[0] & (okl | okh);
  return make_hit<F>(m, vselect(okl, q.lo(), q.hi()));
}

// Solid span [lo, hi] of the infinite solid intersected with the slab z0 <= oz + t d.z <= z1
// (a raw Roots<F, 2>: valid where entry <= exit).
//   1/ 2+- 2*, 1 cmp 2 select, 2 min/max, 1 cmp (entry <= exit)
template <class F>
RB_INLINE Roots<F, 2> clip_to_slab(const Ray<F>& r, const mask_t<F>& m, const F& lo, const F& hi, const F& oz, const F& z0, const F& z1) {
  const F idz = F(1) / r.d.z;
  const F ta = (z0 - oz) * idz, tb = (z1 - oz) * idz;
  const mask_t<F> up = idz >= F(0);
  const F slo = vselect(up, ta, tb), shi = vselect(up, tb, ta);
  const F enter = vmax(slo, lo), exit = vmin(shi, hi);  // NaN slab bound first: dropped
  return Roots<F, 2>::span(m & (enter <= exit), enter, exit);
}

template <class F>
RB_INLINE Roots<F, 2> capped_cylinder_interval(const Ray<F>& r, const Cylinder<F>& c, const CylQuad<F>& k, const mask_t<F>& m) {
  const Roots<F, 2> q = stable_roots(k.A, k.B, k.C, k.disc, m);
  const mask_t<F> par = k.A == F(0);                             // 1 cmp
  const F plo = vselect(k.C <= F(0), F(-kInf<F>), F(kInf<F>));   // 1 cmp 1 select
  const F lo = vselect(par, plo, q.lo()), hi = vselect(par, -plo, q.hi());  // 2 select
  return clip_to_slab(r, m, lo, hi, r.o.z, c.z0, c.z1);
}
}  // namespace detail

// lecture: the open tube (seed 000's substituted quadratic, cut to z0 <= z <= z1).
template <class F>
RB_INLINE Hit<F> intersect_cylinder(const Ray<F>& r, const Cylinder<F>& c) {
  const detail::CylQuad<F> k = detail::cylinder_quad(r, c);
  const mask_t<F> m = k.disc >= F(0);                   // 1 cmp (negative case ends here)
  if (none_of<F>(m)) return miss_hit<F>();
  return detail::open_surface_hit(r, stable_roots(k.A, k.B, k.C, k.disc, m), r.o.z, c.z0, c.z1);
}

// capped: the closed solid; t is the entry (or the exit when the origin is inside).
template <class F>
RB_INLINE Hit<F> intersect_cylinder_capped(const Ray<F>& r, const Cylinder<F>& c) {
  const detail::CylQuad<F> k = detail::cylinder_quad(r, c);
  const mask_t<F> m = k.disc >= F(0);                   // a parallel ray has disc = 0: kept
  if (none_of<F>(m)) return miss_hit<F>();
  return first_hit(r, detail::capped_cylinder_interval(r, c, k, m));
}

// Entry/exit interval of the capped cylinder on the whole line (not clipped to [tmin, tmax]).
template <class F>
RB_INLINE Roots<F, 2> cylinder_roots(const Ray<F>& r, const Cylinder<F>& c) {
  const detail::CylQuad<F> k = detail::cylinder_quad(r, c);
  const mask_t<F> m = k.disc >= F(0);
  if (none_of<F>(m)) return Roots<F, 2>::none();
  const Roots<F, 2> s = detail::capped_cylinder_interval(r, c, k, m);
  return Roots<F, 2>::closed_span(s.valid[0], s.lo(), s.hi());
}

// Lateral unit normal (x - cx, y - cy, 0) / R: 2+- 2* 1+- 1 sqrt 1/ 2*.
template <class F>
RB_INLINE Vec3<F> cylinder_normal(const Cylinder<F>& c, const Vec3<F>& p) {
  const F x = p.x - c.cx, y = p.y - c.cy;
  const F s = F(1) / vsqrt(x * x + y * y);
  return {x * s, y * s, F(0)};
}

// Normal of the capped solid: the cap whose plane is nearer than the lateral surface, else lateral.
template <class F>
RB_INLINE Vec3<F> capped_cylinder_normal(const Cylinder<F>& c, const Vec3<F>& p) {
  const F x = p.x - c.cx, y = p.y - c.cy;
  const F rho = vsqrt(x * x + y * y);
  const F dl = vabs(rho - vsqrt(c.r2));
  const F d0 = vabs(p.z - c.z0), d1 = vabs(p.z - c.z1);
  const mask_t<F> cap0 = (d0 < dl) & (d0 <= d1), cap1 = (d1 < dl) & mask_not<F>(cap0);
  const F s = F(1) / rho;
  const F zero = F(0), one = F(1);
  const mask_t<F> cap = cap0 | cap1;
  return {vselect(cap, zero, x * s), vselect(cap, zero, y * s), vselect(cap0, -one, vselect(cap1, one, zero))};
}

// ---- cone ---------------------------------------------------------------------------------------
template <class F>
struct Cone {
  Vec3<F> apex;
  F z0, z1;  // height range relative to the apex
  auto fields() { return std::tie(apex.x, apex.y, apex.z, z0, z1); }
  // Empty height range (z0 = +inf > z1 = -inf): no root is ever in range, the slab is empty.
  static Cone never() { return {{F(0), F(0), F(0)}, F(kInf<F>), F(-kInf<F>)}; }
};

// The open (double) cone shell x^2 + y^2 = z^2 about `apex`, cut to z0 <= z <= z1 (relative to
// the apex; infinite bounds allowed). Non-finite apex, NaN bounds or zero or negative height:
// never() (the reason in *why).
template <class T>
inline Cone<float> make_cone(Vec3<T> apex, T z0, T z1, std::string* why = nullptr) {
  if (!finite3(apex)) return never_because<Cone<float>>(why, "cone: apex is not finite");
  if (std::isnan(z0) || std::isnan(z1) || !(z0 < z1) || z0 == std::numeric_limits<T>::infinity() ||
      z1 == -std::numeric_limits<T>::infinity() || !(float(z0) < float(z1)))
    return never_because<Cone<float>>(why, "cone: height range is empty or NaN");
  return {to_float(to_double(apex)), float(z0), float(z1)};
}

// The closed single-nappe cone (frustum) for intersect_cone_capped / cone_roots: as make_cone, and
// a height range containing the apex strictly inside (z0 < 0 < z1: two nappes, not a convex
// solid) gives never(), the reason in *why.
template <class T>
inline Cone<float> make_capped_cone(Vec3<T> apex, T z0, T z1, std::string* why = nullptr) {
  if (z0 < T(0) && z1 > T(0))
    return never_because<Cone<float>>(why, "capped cone: the height range contains the apex (two nappes are not one closed solid)");
  return make_cone(apex, z0, z1, why);
}

namespace detail {
// The cone's quadratic: 3+- then A 2+- 3*, B 2+- 3*, C 2+- 3*, disc 1+- 2*.
// Only oz (the origin's height above the apex) is kept of P0 - apex: returning the whole vector in
// the struct made GCC 12 copy it through 16-byte halves that a 32-byte load then read back, a
// store-forwarding stall that halved the 8-lane speed of the capped cone (perf annotate).
// A < 0 (a ray steeper than the cone): the line runs from inside one nappe to inside the other,
// which meet only at the apex, so it always meets the double cone (the true disc >= 0); a negative
// disc there is rounding of B^2 - A C for a line through or near the apex (a double root), which
// made rays through the apex miss. Such lanes are kept (m) and disc is clamped to 0 (the double
// root): 1 cmp 1 min/max. `m` is the lanes with real roots.
template <class F>
struct ConeQuad {
  F oz, A, B, C, disc;
  mask_t<F> m, steep;  // real roots; A < 0
};
template <class F>
RB_INLINE ConeQuad<F> cone_quad(const Ray<F>& r, const Cone<F>& c) {
  const Vec3<F> o = r.o - c.apex;
  const Vec3<F>& p = r.d;
  const F A = p.x * p.x + p.y * p.y - p.z * p.z;
  const F B = o.x * p.x + o.y * p.y - o.z * p.z;
  const F C = o.x * o.x + o.y * o.y - o.z * o.z;
  const F disc = B * B - A * C;
  const mask_t<F> steep = A < F(0);
  const mask_t<F> m = (disc >= F(0)) | steep;
  return {o.z, A, B, C, vmax(disc, F(0)), m, steep};
}

template <class F>
RB_INLINE Roots<F, 2> capped_cone_interval(const Ray<F>& r, const Cone<F>& c, const ConeQuad<F>& k, const mask_t<F>& m) {
  const Roots<F, 2> q = stable_roots(k.A, k.B, k.C, k.disc, m);
  // A < 0: inside on (-inf, lo] and [hi, +inf), one per nappe; keep the half-line in the solid's
  // nappe: going up (dz > 0) the upper nappe's (z > 0) part comes last, [hi, +inf), going down it
  // comes first, (-inf, lo]; the lower nappe the other way round. Decided by signs, not by
  // comparing the slab with the roots: for a ray through the apex both roots and the slab's start
  // coincide up to rounding, and that comparison picked the wrong nappe (a miss).
  const F idz = F(1) / r.d.z;
  const F ta = (c.z0 - k.oz) * idz, tb = (c.z1 - k.oz) * idz;
  const mask_t<F> up = idz >= F(0);
  const F slo = vselect(up, ta, tb), shi = vselect(up, tb, ta);
  const mask_t<F> upper = c.z1 > F(0);                               // 1 cmp
  const mask_t<F> low = (up & mask_not<F>(upper)) | (mask_not<F>(up) & upper);  // up != upper
  const mask_t<F> neg = k.steep;
  const F lo = vselect(neg, vselect(low, F(-kInf<F>), q.hi()), q.lo());  // 2 select
  const F hi = vselect(neg, vselect(low, q.lo(), F(kInf<F>)), q.hi());   // 2 select
  const F enter = vmax(slo, lo), exit = vmin(shi, hi);
  return Roots<F, 2>::span(m & (enter <= exit), enter, exit);
}
}  // namespace detail

// lecture: the open cone shell (both nappes if the height range spans the apex).
template <class F>
RB_INLINE Hit<F> intersect_cone(const Ray<F>& r, const Cone<F>& c) {
  const detail::ConeQuad<F> k = detail::cone_quad(r, c);
  const mask_t<F> m = k.m;                              // (negative case ends here)
  if (none_of<F>(m)) return miss_hit<F>();
  return detail::open_surface_hit(r, stable_roots(k.A, k.B, k.C, k.disc, m), k.oz, c.z0, c.z1);
}

// capped: the closed single-nappe frustum (make_capped_cone).
template <class F>
RB_INLINE Hit<F> intersect_cone_capped(const Ray<F>& r, const Cone<F>& c) {
  const detail::ConeQuad<F> k = detail::cone_quad(r, c);
  const mask_t<F> m = k.m;
  if (none_of<F>(m)) return miss_hit<F>();
  return first_hit(r, detail::capped_cone_interval(r, c, k, m));
}

template <class F>
RB_INLINE Roots<F, 2> cone_roots(const Ray<F>& r, const Cone<F>& c) {
  const detail::ConeQuad<F> k = detail::cone_quad(r, c);
  const mask_t<F> m = k.m;
  if (none_of<F>(m)) return Roots<F, 2>::none();
  const Roots<F, 2> s = detail::capped_cone_interval(r, c, k, m);
  return Roots<F, 2>::closed_span(s.valid[0], s.lo(), s.hi());
}

namespace detail {
// (x, y, -z) about the apex, normalised; at the apex itself (where the gradient is 0 and the
// normalisation was 0/0 = NaN) the axis pointing out of the tip: -z for the upper nappe
// (z1 > 0), +z for the lower.
template <class F>
RB_INLINE Vec3<F> cone_lateral_normal(const Cone<F>& c, const Vec3<F>& l) {
  const F n2 = l.x * l.x + l.y * l.y + l.z * l.z;
  const F zero = F(0), one = F(1);
  const mask_t<F> tip = n2 == zero;                     // the apex (or an underflowed offset)
  const F s = one / vsqrt(vselect(tip, one, n2));
  return {vselect(tip, zero, l.x * s), vselect(tip, zero, l.y * s), vselect(tip, vselect(c.z1 > zero, -one, one), -l.z * s)};
}
}  // namespace detail

// Lateral unit normal: the gradient (x, y, -z) about the apex, normalised (the tip's axis at the apex).
template <class F>
RB_INLINE Vec3<F> cone_normal(const Cone<F>& c, const Vec3<F>& p) {
  return detail::cone_lateral_normal(c, p - c.apex);
}

// Normal of the capped frustum: a cap when its plane is nearer than the lateral surface
// (distance |rho - |z|| / sqrt 2), else lateral.
template <class F>
RB_INLINE Vec3<F> capped_cone_normal(const Cone<F>& c, const Vec3<F>& p) {
  const Vec3<F> l = p - c.apex;
  const F rho = vsqrt(l.x * l.x + l.y * l.y);
  const F dl = vabs(rho - vabs(l.z)) * F(scalar_t<F>(0.70710678118654752));
  const F d0 = vabs(l.z - c.z0), d1 = vabs(l.z - c.z1);
  const mask_t<F> cap0 = (d0 < dl) & (d0 <= d1), cap1 = (d1 < dl) & mask_not<F>(cap0);
  const mask_t<F> cap = cap0 | cap1;
  const Vec3<F> n = detail::cone_lateral_normal(c, l);
  const F zero = F(0), one = F(1);
  return {vselect(cap, zero, n.x), vselect(cap, zero, n.y), vselect(cap0, -one, vselect(cap1, one, n.z))};
}

// ---- placed shells: NFF's `c` entity ------------------------------------------------------------
// A shell between two circles, base centre b with radius rb and top centre a with radius ra (open,
// no caps, as NFF's cone/cylinder): a cylinder in basic position when the radii are equal, else
// the unit cone x^2 + y^2 = z^2 cut to the frustum, each placed by an affine map (seed 000's
// transformed instances). Degenerate input (non-finite, zero length, negative or both-zero radii)
// gives never(), the reason in *why.
inline Transformed<Cylinder>::T<float> place_cylinder(Vec3d b, Vec3d a, double r, std::string* why = nullptr) {
  using X = Transformed<Cylinder>::T<float>;
  const Vec3d w = a - b;
  const double len = std::sqrt(dot(w, w));
  if (!(len > 0) || !std::isfinite(len) || !finite3(b)) return never_because<X>(why, "cylinder: zero-length or non-finite axis");
  if (!(r > 0) || !std::isfinite(r)) return never_because<X>(why, "cylinder: radius is not positive and finite");
  return make_transformed(Affine3d::frame(b, w, why), make_cylinder(0.0, 0.0, r, 0.0, len), why);
}

// rb != ra. The unit cone's apex is the shell's virtual apex; local z runs along the axis away
// from it, scaled by the slope k = |rb - ra| / length so that the local radius equals the world
// radius: world = frame(apex, axis) scale(1, 1, 1/k) local, z in [min(ra, rb), max(ra, rb)].
inline Transformed<Cone>::T<float> place_cone(Vec3d b, double rb, Vec3d a, double ra, std::string* why = nullptr) {
  using X = Transformed<Cone>::T<float>;
  if (ra > rb) {
    std::swap(a, b);
    std::swap(ra, rb);
  }
  const Vec3d w = a - b;  // from the wide end towards the narrow end and the virtual apex
  const double len = std::sqrt(dot(w, w));
  if (!(len > 0) || !std::isfinite(len) || !finite3(b)) return never_because<X>(why, "cone: zero-length or non-finite axis");
  if (!(ra >= 0) || !(rb > ra) || !std::isfinite(rb))
    return never_because<X>(why, "cone: radii must be finite, non-negative and different");
  const double k = (rb - ra) / len;
  const Vec3d u = w * (1.0 / len);
  const Vec3d apex = b + u * (rb / k);
  const std::optional<Affine3d> to_apex = Affine3d::frame(apex, u * -1.0, why);
  if (!to_apex) return X::never();
  return make_transformed(*to_apex * Affine3d::scale({1, 1, 1 / k}), make_cone(Vec3d{0, 0, 0}, ra, rb), why);
}

}  // namespace rb
