#include "accuracy/exact.hpp"

#include <gmpxx.h>
#include <mpfr.h>

#include <algorithm>
#include <cmath>

namespace rb::acc {

namespace {

// ---------------------------------------------------------------- rationals (triangles, boxes)
using Q = mpq_class;
struct Q3 {
  Q x, y, z;
};
Q3 q3(const Vec3f& v) { return {Q(double(v.x)), Q(double(v.y)), Q(double(v.z))}; }
Q3 sub(const Q3& a, const Q3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Q3 crs(const Q3& a, const Q3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
Q dotq(const Q3& a, const Q3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

long double to_ld(const Q& q) {
  mpfr_t m;
  mpfr_init2(m, 128);
  mpfr_set_q(m, q.get_mpq_t(), MPFR_RNDN);
  const long double r = mpfr_get_ld(m, MPFR_RNDN);
  mpfr_clear(m);
  return r;
}

// Sign of the triple product d . (X x Y) with X = x - o, Y = y - o; a double filter with a
// conservative bound first, rationals when it cannot decide or the differences are inexact.
int triple_sign(const Vec3f& o, const Vec3f& d, const Vec3f& x, const Vec3f& y) {
  const Vec3d od = to_double(o), X = to_double(x) - od, Y = to_double(y) - od;
  const bool exact_diff = (X.x + od.x == double(x.x)) && (X.y + od.y == double(x.y)) && (X.z + od.z == double(x.z)) &&
                          (Y.x + od.x == double(y.x)) && (Y.y + od.y == double(y.y)) && (Y.z + od.z == double(y.z)) &&
                          (double(x.x) - X.x == od.x) && (double(x.y) - X.y == od.y) && (double(x.z) - X.z == od.z) &&
                          (double(y.x) - Y.x == od.x) && (double(y.y) - Y.y == od.y) && (double(y.z) - Y.z == od.z);
  if (exact_diff) {
    const Vec3d D = to_double(d);
    const Vec3d c = cross(X, Y);
    const double v = D.x * c.x + D.y * c.y + D.z * c.z;
    const double perm = std::fabs(D.x) * (std::fabs(X.y * Y.z) + std::fabs(X.z * Y.y)) +
                        std::fabs(D.y) * (std::fabs(X.z * Y.x) + std::fabs(X.x * Y.z)) +
                        std::fabs(D.z) * (std::fabs(X.x * Y.y) + std::fabs(X.y * Y.x));
    if (std::fabs(v) > 1e-14 * perm) return v > 0 ? 1 : -1;
  }
  const Q3 O = q3(o), Xq = sub(q3(x), O), Yq = sub(q3(y), O);
  return sgn(dotq(q3(d), crs(Xq, Yq)));
}

// ---------------------------------------------------------------- MPFR numbers
constexpr mpfr_prec_t kPrec = 512;
struct M {
  mpfr_t v;
  M() { mpfr_init2(v, kPrec), mpfr_set_zero(v, 1); }
  M(double x) { mpfr_init2(v, kPrec), mpfr_set_d(v, x, MPFR_RNDN); }
  M(const M& o) { mpfr_init2(v, kPrec), mpfr_set(v, o.v, MPFR_RNDN); }
  M& operator=(const M& o) {
    mpfr_set(v, o.v, MPFR_RNDN);
    return *this;
  }
  ~M() { mpfr_clear(v); }
  int sgn() const { return mpfr_sgn(v); }
  long double ld() const { return mpfr_get_ld(v, MPFR_RNDN); }
};
M operator+(const M& a, const M& b) {
  M r;
  mpfr_add(r.v, a.v, b.v, MPFR_RNDN);
  return r;
}
M operator-(const M& a, const M& b) {
  M r;
  mpfr_sub(r.v, a.v, b.v, MPFR_RNDN);
  return r;
}
M operator*(const M& a, const M& b) {
  M r;
  mpfr_mul(r.v, a.v, b.v, MPFR_RNDN);
  return r;
}
M operator/(const M& a, const M& b) {
  M r;
  mpfr_div(r.v, a.v, b.v, MPFR_RNDN);
  return r;
}
M msqrt(const M& a) {
  M r;
  mpfr_sqrt(r.v, a.v, MPFR_RNDN);
  return r;
}
bool operator<(const M& a, const M& b) { return mpfr_less_p(a.v, b.v); }
bool operator<=(const M& a, const M& b) { return mpfr_lessequal_p(a.v, b.v); }
bool operator==(const M& a, const M& b) { return mpfr_equal_p(a.v, b.v); }

// Real roots of A t^2 + 2 B t + C (A may be 0), ascending; `tangent` when the disc is exactly 0.
std::vector<M> quad_roots(const M& A, const M& B, const M& C, bool& tangent) {
  tangent = false;
  std::vector<M> r;
  if (A.sgn() == 0) {
    if (B.sgn() != 0) r.push_back(M(0.0) - C / (M(2.0) * B));
    return r;
  }
  const M disc = B * B - A * C;
  if (disc.sgn() < 0) return r;
  if (disc.sgn() == 0) {
    tangent = true;
    r.push_back(M(0.0) - B / A);
    return r;
  }
  const M s = msqrt(disc);
  M t1 = (M(0.0) - B - s) / A, t2 = (M(0.0) - B + s) / A;
  if (t2 < t1) std::swap(t1, t2);
  r.push_back(t1);
  r.push_back(t2);
  return r;
}

double scale_of(const Vec3f& o, double extent) { return norm(to_double(o)) + extent; }

}  // namespace

// ---------------------------------------------------------------- triangle
Ref triangle_ref(const Vec3f& o, const Vec3f& d, float tmin, float tmax, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  Ref r;
  r.scale = scale_of(o, std::max({norm(to_double(a)), norm(to_double(b)), norm(to_double(c))}));
  // Edge functions as signed volumes: U = d.(C x B), V = d.(A x C), W = d.(B x A) (X = x - o).
  const int U = triple_sign(o, d, c, b), V = triple_sign(o, d, a, c), W = triple_sign(o, d, b, a);
  const bool neg = U < 0 || V < 0 || W < 0, pos = U > 0 || V > 0 || W > 0;
  if (neg && pos) return r;  // the line passes outside
  if (!neg && !pos) {        // the line lies in the plane: neither answer is wrong
    r.cls = Cls::either;
    return r;
  }
  // t = (a - o) . n / (d . n), n = (b - a) x (c - a).
  const Q3 A = q3(a), B = q3(b), C = q3(c), O = q3(o), D = q3(d);
  const Q3 n = crs(sub(B, A), sub(C, A));
  const Q den = dotq(D, n);
  if (sgn(den) == 0) {
    r.cls = Cls::either;
    return r;
  }
  const Q t = dotq(sub(A, O), n) / den;
  if (t < Q(double(tmin)) || t > Q(double(tmax))) return r;
  r.cls = (U == 0 || V == 0 || W == 0) ? Cls::either : Cls::hit;
  r.t = to_ld(t);
  r.has_t = true;
  return r;
}

int triangle_facing(const Vec3f& d, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  const Q3 A = q3(a);
  return sgn(dotq(q3(d), crs(sub(q3(b), A), sub(q3(c), A))));
}

// ---------------------------------------------------------------- sphere
Ref sphere_ref(const Vec3f& o, const Vec3f& d, float tmin, float tmax, const Vec3f& c, float r2) {
  Ref r;
  r.scale = scale_of(o, norm(to_double(c)) + std::sqrt(double(r2)));
  const M fx = M(o.x) - M(c.x), fy = M(o.y) - M(c.y), fz = M(o.z) - M(c.z);
  const M dx(d.x), dy(d.y), dz(d.z);
  const M A = dx * dx + dy * dy + dz * dz, B = fx * dx + fy * dy + fz * dz, C = fx * fx + fy * fy + fz * fz - M(r2);
  bool tangent = false;
  const std::vector<M> ts = quad_roots(A, B, C, tangent);
  const M lo(tmin), hi(tmax);
  for (const M& t : ts) {
    if (lo <= t && t <= hi) {
      r.cls = tangent ? Cls::either : Cls::hit;
      r.t = t.ld();
      r.has_t = true;
      return r;
    }
  }
  if (tangent) r.cls = Cls::either;
  return r;
}

// ---------------------------------------------------------------- cylinder, cone
namespace {
// The ray in the quadric's frame, exactly (MPFR).
Ref quadric_ref_m(Quad kind, bool solid, const M (&o)[3], const M (&d)[3], float tmin, float tmax, float cx, float cy, float r2,
                  float z0, float z1, double scale) {
  Ref r;
  r.scale = scale;
  M ox, oy, A, B, C;
  const M oz = o[2], dx = d[0], dy = d[1], dz = d[2];
  if (kind == Quad::cylinder) {
    ox = o[0] - M(cx), oy = o[1] - M(cy);
    A = dx * dx + dy * dy, B = ox * dx + oy * dy, C = ox * ox + oy * oy - M(r2);
  } else {  // x^2 + y^2 - z^2 about the apex at the origin of the local frame
    ox = o[0], oy = o[1];
    A = dx * dx + dy * dy - dz * dz, B = ox * dx + oy * dy - oz * dz, C = ox * ox + oy * oy - oz * oz;
  }
  bool tangent = false;
  const std::vector<M> roots = quad_roots(A, B, C, tangent);
  const M lo(tmin), hi(tmax);
  auto zin = [&](const M& t) {
    const M z = oz + t * dz;
    return (!std::isfinite(z0) || M(z0) <= z) && (!std::isfinite(z1) || z <= M(z1));
  };
  if (!solid) {
    for (const M& t : roots) {
      if (lo <= t && t <= hi && zin(t)) {
        const M z = oz + t * dz;
        r.cls = (tangent || z == M(z0) || z == M(z1)) ? Cls::either : Cls::hit;
        r.t = t.ld();
        r.has_t = true;
        return r;
      }
    }
    if (tangent) r.cls = Cls::either;
    return r;
  }
  // Solid: breakpoints (roots and slab planes) in (tmin, tmax]; the first change of membership.
  std::vector<M> bp;
  for (const M& t : roots) bp.push_back(t);
  if (dz.sgn() != 0) {
    if (std::isfinite(z0)) bp.push_back((M(z0) - oz) / dz);
    if (std::isfinite(z1)) bp.push_back((M(z1) - oz) / dz);
  }
  std::sort(bp.begin(), bp.end(), [](const M& p, const M& q) { return p < q; });
  std::vector<M> in_range;
  for (const M& t : bp)
    if (lo < t && t <= hi) in_range.push_back(t);
  auto member = [&](const M& t) {
    const M f = A * t * t + M(2.0) * B * t + C;
    return f.sgn() <= 0 && zin(t);
  };
  M prev = lo;
  bool inside = false;
  for (std::size_t k = 0; k <= in_range.size(); ++k) {
    const M mid = k < in_range.size() ? (prev + in_range[k]) * M(0.5) : prev + M(1.0) + (prev.sgn() < 0 ? M(0.0) - prev : prev);
    const bool m = member(mid);
    if (k > 0 && m != inside) {
      r.cls = tangent ? Cls::either : Cls::hit;
      r.t = prev.ld();
      r.has_t = true;
      // An entry exactly at a rim (root == slab plane) is an edge: either answer is fine.
      for (const M& t : roots)
        if (t == prev && dz.sgn() != 0 && ((std::isfinite(z0) && oz + t * dz == M(z0)) || (std::isfinite(z1) && oz + t * dz == M(z1))))
          r.cls = Cls::either;
      return r;
    }
    inside = m;
    if (k < in_range.size()) prev = in_range[k];
  }
  if (tangent) r.cls = Cls::either;
  return r;
}
}  // namespace

Ref quadric_ref(Quad kind, bool solid, const Vec3f& o, const Vec3f& d, float tmin, float tmax, float cx, float cy, float r2,
                float z0, float z1) {
  const double zext = std::max(std::isfinite(z0) ? std::fabs(double(z0)) : 0.0, std::isfinite(z1) ? std::fabs(double(z1)) : 0.0);
  const double scale = scale_of(o, std::hypot(double(cx), double(cy)) + std::sqrt(std::max(double(r2), 0.0)) + zext);
  const M om[3] = {M(o.x), M(o.y), M(o.z)}, dm[3] = {M(d.x), M(d.y), M(d.z)};
  return quadric_ref_m(kind, solid, om, dm, tmin, tmax, cx, cy, r2, z0, z1, scale);
}

Ref placed_quadric_ref(Quad kind, const Affine34<float>& inv, const Vec3f& o, const Vec3f& d, float tmin, float tmax, float cx, float cy,
                       float r2, float z0, float z1, double extent) {
  const M m[3][4] = {{M(inv.m00), M(inv.m01), M(inv.m02), M(inv.m03)},
                     {M(inv.m10), M(inv.m11), M(inv.m12), M(inv.m13)},
                     {M(inv.m20), M(inv.m21), M(inv.m22), M(inv.m23)}};
  const M ow[3] = {M(o.x), M(o.y), M(o.z)}, dw[3] = {M(d.x), M(d.y), M(d.z)};
  M ol[3], dl[3];
  for (int i = 0; i < 3; ++i) {
    ol[i] = m[i][0] * ow[0] + m[i][1] * ow[1] + m[i][2] * ow[2] + m[i][3];
    dl[i] = m[i][0] * dw[0] + m[i][1] * dw[1] + m[i][2] * dw[2];
  }
  return quadric_ref_m(kind, false, ol, dl, tmin, tmax, cx, cy, r2, z0, z1, scale_of(o, extent));
}

// ---------------------------------------------------------------- torus
std::vector<long double> torus_ref_roots(const Vec3f& o, const Vec3f& d, float tmin, float tmax, const Vec3f& c,
                                         const Vec3f& w, float R, float r) {
  using L = long double;
  const L qx = L(o.x) - L(c.x), qy = L(o.y) - L(c.y), qz = L(o.z) - L(c.z);
  const L dx = d.x, dy = d.y, dz = d.z, wx = w.x, wy = w.y, wz = w.z;
  const L m = dx * dx + dy * dy + dz * dz;
  const L tc = -(qx * dx + qy * dy + qz * dz) / m;  // closest approach to the centre
  const L px = qx + tc * dx, py = qy + tc * dy, pz = qz + tc * dz;
  const L RR = L(R) * L(R), rr = L(r) * L(r);
  const L n = px * dx + py * dy + pz * dz, k = px * px + py * py + pz * pz - RR - rr;
  const L pw = px * wx + py * wy + pz * wz, dw = dx * wx + dy * wy + dz * wz;
  const L cf[5] = {k * k + 4 * RR * (pw * pw - rr), 4 * n * k + 8 * RR * pw * dw, 4 * n * n + 2 * m * k + 4 * RR * dw * dw,
                   4 * m * n, m * m};
  const L ext = 2 * (L(R) + L(r)) / std::sqrt(m) + 1;
  std::vector<L> out;
  for (L s : poly_roots_ld(cf, 4, -ext, ext)) {
    const L t = tc + s;
    if (t >= L(tmin) && t <= L(tmax)) out.push_back(t);
  }
  return out;
}

// ---------------------------------------------------------------- box
Ref box_ref(const Vec3f& o, const Vec3f& d, float tmin, float tmax, const Vec3f& lo, const Vec3f& hi) {
  Ref r;
  r.scale = scale_of(o, std::max(norm(to_double(lo)), norm(to_double(hi))));
  const float oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z}, ll[3] = {lo.x, lo.y, lo.z}, hh[3] = {hi.x, hi.y, hi.z};
  const Q tn{double(tmin)}, tf{double(tmax)};
  bool in_plane = false, none = false, first = true;
  Q near_all, far_all, s0[3], s1[3];
  bool moving[3] = {false, false, false};
  for (int a = 0; a < 3; ++a) {
    if (dd[a] == 0.f) {
      if (oo[a] < ll[a] || oo[a] > hh[a]) none = true;
      if (oo[a] == ll[a] || oo[a] == hh[a]) in_plane = true;
      continue;
    }
    Q t0 = (Q(double(ll[a])) - Q(double(oo[a]))) / Q(double(dd[a])), t1 = (Q(double(hh[a])) - Q(double(oo[a]))) / Q(double(dd[a]));
    if (t1 < t0) std::swap(t0, t1);
    s0[a] = t0, s1[a] = t1, moving[a] = true;
    if (first || t0 > near_all) near_all = t0;
    if (first || t1 < far_all) far_all = t1;
    first = false;
  }
  // near == far: an edge or corner touch, unless it is the crossing of a flat box's plane with
  // the point strictly inside the other slabs (a flat box is a rectangle: a proper hit).
  bool flat_cross = false;
  if (!first && near_all == far_all && !in_plane) {
    for (int a = 0; a < 3; ++a) {
      if (!moving[a] || ll[a] != hh[a]) continue;
      bool strict = true;
      for (int b = 0; b < 3; ++b)
        if (b != a && (moving[b] ? !(s0[b] < near_all && near_all < s1[b]) : !(ll[b] < oo[b] && oo[b] < hh[b]))) strict = false;
      flat_cross = flat_cross || strict;
    }
  }
  if (none) return r;
  if (first) {  // zero direction: not a ray
    return r;
  }
  // The whole line meets the box on [near_all, far_all]; the first crossing in [tmin, tmax].
  if (near_all > far_all) return r;
  Q t;
  if (near_all >= tn) t = near_all;
  else t = far_all;
  if (t < tn || t > tf) return r;
  r.cls = (in_plane || (near_all == far_all && !flat_cross)) ? Cls::either : Cls::hit;
  r.t = to_ld(t);
  r.has_t = true;
  return r;
}

}  // namespace rb::acc
