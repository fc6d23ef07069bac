// The accuracy lab's reference: each kind's first hit in long double, from the scene's own double
// geometry (accuracy/scenes.cpp traces a whole scene with it). A ray in long double, world
// coordinates; `first(kind, scene, i, ray)` gives the first t of primitive i in [lo, hi] (+inf:
// none). A kind without an overload here has no reference: `first_of` gives NaN for it (CSG trees
// are checked against their own interval algebra, tests/test_csg.cpp).
#pragma once

#include "core/roots_ld.hpp"
#include "tracer/kinds.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>

namespace rb::acc::reference {

using LD = long double;
struct V3 {
  LD x, y, z;
};
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator*(V3 a, LD k) { return {a.x * k, a.y * k, a.z * k}; }
inline LD dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline V3 of(const Vec3d& v) { return {LD(v.x), LD(v.y), LD(v.z)}; }
inline constexpr LD kNone = std::numeric_limits<LD>::infinity();
struct Ray {
  V3 o, d;
  LD lo, hi;
};
// The first root in [lo, hi] of a t^2 + 2 b t + c (kNone: none).
inline LD quadratic_first(LD a, LD b, LD c, LD lo, LD hi) {
  if (a == 0) return kNone;
  const LD disc = b * b - a * c;
  if (disc < 0) return kNone;
  const LD sq = std::sqrt(disc);
  const LD q = -(b + (b < 0 ? -sq : sq));
  LD t0 = q / a, t1 = q != 0 ? c / q : t0;
  if (t0 > t1) std::swap(t0, t1);
  if (t0 >= lo && t0 <= hi) return t0;
  if (t1 >= lo && t1 <= hi) return t1;
  return kNone;
}

// An NFF shell (open, cylinder or cone): |q_perp| = r(s) for 0 <= s <= len, q = p - base, s = q . a.
inline LD shell(const scene::ConeIn& c, const Ray& r) {
  const V3 b = of(c.base), ax0 = of(c.apex) - b;
  const LD len = std::sqrt(dot(ax0, ax0));
  const V3 a = ax0 * (LD(1) / len);
  const LD r0 = std::fabs(LD(c.base_r)), r1 = std::fabs(LD(c.apex_r)), k = (r1 - r0) / len;
  const V3 f = r.o - b;
  const LD fa = dot(f, a), da = dot(r.d, a);
  const V3 fp = f - a * fa, dp = r.d - a * da;
  const LD A = dot(dp, dp) - k * k * da * da, B = dot(fp, dp) - (r0 + k * fa) * k * da,
           C = dot(fp, fp) - (r0 + k * fa) * (r0 + k * fa);
  const LD disc = B * B - A * C;
  if (A == 0 || disc < 0) return kNone;
  const LD sq = std::sqrt(disc);
  const LD q = -(B + (B < 0 ? -sq : sq));
  LD ts[2] = {q / A, q != 0 ? C / q : q / A};
  if (ts[0] > ts[1]) std::swap(ts[0], ts[1]);
  for (LD tt : ts) {
    if (!(tt >= r.lo && tt <= r.hi)) continue;
    const LD sa = fa + tt * da;
    if (sa >= 0 && sa <= len && r0 + k * sa >= 0) return tt;
  }
  return kNone;
}

// Moller-Trumbore in long double: at this precision which of two triangles sharing an edge a ray
// through it hits does not matter (the lab compares distances).
inline LD first(std::type_identity<kinds::TriangleKind>, const scene::Scene& s, std::uint32_t i, const Ray& r) {
  const auto& t = s.triangles[i];
  const V3 a = of(s.verts[t.v[0]]), e1 = of(s.verts[t.v[1]]) - a, e2 = of(s.verts[t.v[2]]) - a;
  const V3 p = cross(r.d, e2);
  const LD det = dot(e1, p);
  if (det == 0) return kNone;
  const V3 tv = r.o - a;
  const LD u = dot(tv, p) / det;
  if (u < 0 || u > 1) return kNone;
  const V3 q = cross(tv, e1);
  const LD v = dot(r.d, q) / det;
  if (v < 0 || u + v > 1) return kNone;
  const LD tt = dot(e2, q) / det;
  return tt >= r.lo && tt <= r.hi ? tt : kNone;
}

inline LD first(std::type_identity<kinds::SphereKind>, const scene::Scene& s, std::uint32_t i, const Ray& r) {
  const auto& sp = s.spheres[i];
  const V3 f = r.o - of(sp.c);
  return quadratic_first(dot(r.d, r.d), dot(f, r.d), dot(f, f) - LD(sp.r) * LD(sp.r), r.lo, r.hi);
}

inline LD first(std::type_identity<kinds::PolygonKind>, const scene::Scene& s, std::uint32_t i, const Ray& r) {
  const auto& pg = s.polygons[i];
  const Vec3d* v = s.poly_verts.data() + pg.first;
  const Vec3d n = newell_normal(v, pg.count);
  const V3 nl = of(n);
  const LD den = dot(nl, r.d);
  if (den == 0) return kNone;
  const LD tt = dot(of(v[0]) - r.o, nl) / den;
  if (!(tt >= r.lo && tt <= r.hi)) return kNone;
  const V3 p = r.o + r.d * tt;
  const int ax = dominant_axis(n), a = (ax + 1) % 3, b = (ax + 2) % 3;
  auto c = [](V3 q, int k) { return k == 0 ? q.x : k == 1 ? q.y : q.z; };
  bool in = false;
  for (std::uint32_t k = 0; k < pg.count; ++k) {
    const V3 p0 = of(v[k]) - p, p1 = of(v[(k + 1) % pg.count]) - p;
    const LD y0 = c(p0, b), y1 = c(p1, b), x0 = c(p0, a), x1 = c(p1, a);
    if ((y0 >= 0) != (y1 >= 0) && ((y1 * (x0 - x1) >= x1 * (y0 - y1)) == (y1 >= 0))) in = !in;
  }
  return in ? tt : kNone;
}

// The quartic T(o + t d) re-centred at the closest approach to the centre, its roots isolated in
// long double (kernels/poly.hpp's isolation on the long double polynomial).
// T(q + s d) = (|q + s d|^2 - R^2 - r^2)^2 - 4 R^2 (r^2 - ((q + s d) . w)^2), in s.
inline LD first(std::type_identity<kinds::TorusKind>, const scene::Scene& s, std::uint32_t i, const Ray& r) {
  const auto& tr = s.tori[i];
  const V3 w = of(kinds::TorusKind::unit_axis(tr)), c = of(tr.c);
  const LD R = LD(tr.R), rr = LD(tr.r);
  const LD dd = dot(r.d, r.d);
  const LD t0 = -dot(r.o - c, r.d) / dd;
  const V3 q = r.o + r.d * t0 - c;
  const LD qq = dot(q, q), qd = dot(q, r.d), qw = dot(q, w), dw = dot(r.d, w);
  const LD k0 = qq - R * R - rr * rr, k1 = 2 * qd, k2 = dd;
  const long double cf[5] = {k0 * k0 - 4 * R * R * (rr * rr - qw * qw), 2 * k0 * k1 + 8 * R * R * qw * dw,
                             k1 * k1 + 2 * k0 * k2 + 4 * R * R * dw * dw, 2 * k1 * k2, k2 * k2};
  const LD ext = (2 * (R + rr) + std::sqrt(qq)) / std::sqrt(dd);
  for (LD sr : poly_roots_ld(cf, 4, -ext, ext)) {
    const LD tt = t0 + sr;
    if (tt >= r.lo && tt <= r.hi) return tt;
  }
  return kNone;
}

inline LD first(std::type_identity<kinds::CylinderKind>, const scene::Scene& s, std::uint32_t i, const Ray& r) { return shell(s.cones[i], r); }
inline LD first(std::type_identity<kinds::ConeKind>, const scene::Scene& s, std::uint32_t i, const Ray& r) { return shell(s.cones[i], r); }

// Kind K's reference for primitive i, NaN when the kind has none.
template <class K>
LD first_of(const scene::Scene& s, std::uint32_t i, const Ray& r) {
  if constexpr (requires { first(std::type_identity<K>{}, s, i, r); }) return first(std::type_identity<K>{}, s, i, r);
  else return std::numeric_limits<LD>::quiet_NaN();
}

}  // namespace rb::acc::reference
