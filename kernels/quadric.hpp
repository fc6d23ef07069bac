// Ray x general quadric and x quadric of revolution.
//
//   general quadric, two methods on one set of ten coefficients (seed 004's names):
//     F(x,y,z) = a x^2 + b y^2 + c z^2 + 2d xy + 2e yz + 2f xz + 2g x + 2h y + 2j z + k = 0,
//     i.e. x^T Q x = 0 with the symmetric (seed 000)
//         Q = [a d f g; d b e h; f e c j; g h j k],  x = [x y z 1]^T.
//     matrix   (seed 000 "Quadric (d=2)"): a2 = P1^T Q P1, a1 = 2 P1^T Q P0, a0 = P0^T Q P0 with
//              P1 = [p1; 0], P0 = [P0; 1]: Q P1 and Q P0 as matrix-vector products, then dots.
//              (P1^T Q P0 = (Q P1) . P0 by symmetry: Q P1 serves both a2 and a1.)
//     coeffs10 (seed 004 "Ray Quadric Intersection"): A, B, C expanded term by term as on the
//              slide. Both then solve A t^2 + B t + C = 0 in the stable half-B form
//              (kernels/quadratic.hpp: a1 / 2 and B / 2 are formed directly, so the slides'
//              factor 2 is never multiplied in) which also handles A ~ 0 (the linear case).
//     normal (seed 004 "Quadric Normals"): the gradient / 2 = (ax + dy + fz + g, dx + by + ez + h,
//              fx + ey + cz + j), normalised; it points to the side where F > 0 (for the named
//              closed quadrics written as "... - 1 = 0", outwards). Face it to the ray yourself.
//   quadric of revolution (seed 000): x^2 + y^2 + a z^2 + b z + c = 0 about the z axis through a
//     centre (cx, cy, cz) (the lecture's basic position is the centre 0: the translation costs
//     3+-). Substituted: A = x1^2 + y1^2 + a z1^2, B/2 = x0 x1 + y0 y1 + (a z0 + b/2) z1,
//     C = x0^2 + y0^2 + (a z0 + b) z0 + c.
// All kernels accept a direction of any length (usable under kernels/transform.hpp) and return
// the nearer root in [tmin, tmax] (the far one when the near one is before tmin); no [u,v] (the
// lecture defines none for these surfaces).
#pragma once

#include "kernels/quadratic.hpp"
#include "kernels/transform.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace rb {

// ---- construction-time description (double) ---------------------------------------------------
struct QuadricCoeffs {
  double a = 0, b = 0, c = 0, d = 0, e = 0, f = 0, g = 0, h = 0, j = 0, k = 0;

  // Value and gradient / 2 at a point (tests, references).
  double value(Vec3d p) const {
    return a * p.x * p.x + b * p.y * p.y + c * p.z * p.z + 2 * (d * p.x * p.y + e * p.y * p.z + f * p.x * p.z) +
           2 * (g * p.x + h * p.y + j * p.z) + k;
  }
  Vec3d half_gradient(Vec3d p) const {
    return {a * p.x + d * p.y + f * p.z + g, d * p.x + b * p.y + e * p.z + h, f * p.x + e * p.y + c * p.z + j};
  }
  // The symmetric 4x4 matrix Q of seed 000.
  void matrix(double Q[4][4]) const {
    const double q[4][4] = {{a, d, f, g}, {d, b, e, h}, {f, e, c, j}, {g, h, j, k}};
    for (int r = 0; r < 4; ++r)
      for (int s = 0; s < 4; ++s) Q[r][s] = q[r][s];
  }
  static QuadricCoeffs from_matrix(const double Q[4][4]) {
    return {Q[0][0], Q[1][1], Q[2][2], Q[0][1], Q[1][2], Q[0][2], Q[0][3], Q[1][3], Q[2][3], Q[3][3]};
  }
  // The same surface placed by M (world = M local): Q' = M^-T Q M^-1 (4x4 with the row 0 0 0 1).
  // A singular or non-finite M gives all-zero coefficients (make_quadric: never()), the reason
  // in *why.
  QuadricCoeffs placed(const Affine3d& M, std::string* why = nullptr) const {
    const std::optional<Affine3d> inv = M.inverse(why);
    if (!inv) return {};
    const Affine3d& v = *inv;
    double I[4][4] = {};
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 4; ++s) I[r][s] = v.m[r][s];
    I[3][3] = 1;
    double Q[4][4], T[4][4] = {}, R[4][4] = {};
    matrix(Q);
    for (int r = 0; r < 4; ++r)
      for (int s = 0; s < 4; ++s)
        for (int t = 0; t < 4; ++t) T[r][s] += Q[r][t] * I[t][s];  // Q M^-1
    for (int r = 0; r < 4; ++r)
      for (int s = 0; s < 4; ++s)
        for (int t = 0; t < 4; ++t) R[r][s] += I[t][r] * T[t][s];  // M^-T (Q M^-1)
    for (int r = 0; r < 4; ++r)
      for (int s = 0; s < r; ++s) R[r][s] = R[s][r] = 0.5 * (R[r][s] + R[s][r]);
    return from_matrix(R);
  }
  QuadricCoeffs translated(Vec3d c0) const { return placed(Affine3d::translate(c0)); }
};

// The named quadrics of seed 004 in standard position, as instances of the general quadric.
namespace quadrics {
inline double inv2(double s) { return 1.0 / (s * s); }
// x^2/a^2 + y^2/b^2 + z^2/c^2 = 1
inline QuadricCoeffs ellipsoid(double a, double b, double c) { return {inv2(a), inv2(b), inv2(c), 0, 0, 0, 0, 0, 0, -1}; }
// x^2/a^2 + y^2/b^2 = 1
inline QuadricCoeffs elliptic_cylinder(double a, double b) { return {inv2(a), inv2(b), 0, 0, 0, 0, 0, 0, 0, -1}; }
// x^2/a^2 + y^2/b^2 - z^2/c^2 = 1
inline QuadricCoeffs hyperboloid_one_sheet(double a, double b, double c) { return {inv2(a), inv2(b), -inv2(c), 0, 0, 0, 0, 0, 0, -1}; }
// x^2/a^2 + y^2/b^2 - z^2/c^2 = -1
inline QuadricCoeffs hyperboloid_two_sheets(double a, double b, double c) { return {inv2(a), inv2(b), -inv2(c), 0, 0, 0, 0, 0, 0, 1}; }
// z^2 = x^2/a^2 + y^2/b^2
inline QuadricCoeffs elliptic_cone(double a, double b) { return {inv2(a), inv2(b), -1, 0, 0, 0, 0, 0, 0, 0}; }
// z = x^2/a^2 + y^2/b^2   (2j = -1)
inline QuadricCoeffs elliptic_paraboloid(double a, double b) { return {inv2(a), inv2(b), 0, 0, 0, 0, 0, 0, -0.5, 0}; }
// z = y^2/b^2 - x^2/a^2
inline QuadricCoeffs hyperbolic_paraboloid(double a, double b) { return {-inv2(a), inv2(b), 0, 0, 0, 0, 0, 0, -0.5, 0}; }
// x^2 + 2y = 0   (2h = 2)
inline QuadricCoeffs parabolic_cylinder() { return {1, 0, 0, 0, 0, 0, 0, 1, 0, 0}; }
// x^2/a^2 - y^2/b^2 = 1
inline QuadricCoeffs hyperbolic_cylinder(double a, double b) { return {inv2(a), -inv2(b), 0, 0, 0, 0, 0, 0, 0, -1}; }
}  // namespace quadrics

// ---- the batch type ----------------------------------------------------------------------------
template <class F>
struct Quadric {
  F a, b, c, d, e, f, g, h, j, k;
  auto fields() { return std::tie(a, b, c, d, e, f, g, h, j, k); }
  // x^2 + y^2 + z^2 + inf: C = +inf, disc = B^2 - A inf = -inf for every ray (NaN when the
  // direction is 0, e.g. a never() transformed instance): the negative case, always.
  static Quadric never() { return {F(1), F(1), F(1), F(0), F(0), F(0), F(0), F(0), F(0), F(kInf<F>)}; }
};

// Scaled by its largest |coefficient| (the surface is unchanged; float can hold it). Non-finite
// coefficients, or a..j all zero (singular Q: F is the constant k, every point or none is on
// it), give never() (the reason in *why). A k-only scale of exactly 0 everywhere (Q = 0) is never() too.
inline Quadric<float> make_quadric(const QuadricCoeffs& q, std::string* why = nullptr) {
  using Q = Quadric<float>;
  const double v[10] = {q.a, q.b, q.c, q.d, q.e, q.f, q.g, q.h, q.j, q.k};
  double mx = 0, mx9 = 0;
  for (int i = 0; i < 10; ++i) {
    if (!std::isfinite(v[i])) return never_because<Q>(why, "quadric: a coefficient is not finite");
    mx = std::max(mx, std::fabs(v[i]));
    if (i < 9) mx9 = std::max(mx9, std::fabs(v[i]));
  }
  if (mx9 == 0.0 || !(mx9 > 1e-30 * mx)) return never_because<Q>(why, "quadric: every coefficient a..j is zero (no surface)");
  float o[10];
  for (int i = 0; i < 10; ++i) o[i] = float(v[i] / mx);
  bool any = false;
  for (int i = 0; i < 9; ++i) any = any || o[i] != 0.f;
  if (!any) return never_because<Q>(why, "quadric: coefficients a..j vanish in float");
  return {o[0], o[1], o[2], o[3], o[4], o[5], o[6], o[7], o[8], o[9]};
}

// From the symmetric 4x4 matrix of seed 000. A non-symmetric Q gives never() (the reason in
// *why): x^T Q x only sees the symmetric part, and a caller passing an asymmetric matrix has most
// likely mixed up the layout.
inline Quadric<float> make_quadric_matrix(const double Q[4][4], std::string* why = nullptr) {
  double mx = 0;
  for (int r = 0; r < 4; ++r)
    for (int s = 0; s < 4; ++s) mx = std::max(mx, std::fabs(Q[r][s]));
  for (int r = 0; r < 4; ++r)
    for (int s = 0; s < r; ++s)
      if (!(std::fabs(Q[r][s] - Q[s][r]) <= 1e-12 * mx)) {
        if (std::isfinite(mx)) return never_because<Quadric<float>>(why, "quadric: Q is not symmetric");
      }
  return make_quadric(QuadricCoeffs::from_matrix(Q), why);
}

// matrix method (seed 000).
template <class F>
RB_INLINE Hit<F> intersect_quadric_matrix(const Ray<F>& r, const Quadric<F>& q) {
  const Vec3<F>& o = r.o;
  const Vec3<F>& p = r.d;
  // Q P1 (P1 = [p1; 0]): 4 rows of 3* 2+-
  const F u0 = q.a * p.x + q.d * p.y + q.f * p.z;
  const F u1 = q.d * p.x + q.b * p.y + q.e * p.z;
  const F u2 = q.f * p.x + q.e * p.y + q.c * p.z;
  const F u3 = q.g * p.x + q.h * p.y + q.j * p.z;
  // Q P0 (P0 = [P0; 1]): 4 rows of 3* 3+-
  const F w0 = q.a * o.x + q.d * o.y + q.f * o.z + q.g;
  const F w1 = q.d * o.x + q.b * o.y + q.e * o.z + q.h;
  const F w2 = q.f * o.x + q.e * o.y + q.c * o.z + q.j;
  const F w3 = q.g * o.x + q.h * o.y + q.j * o.z + q.k;
  const F A = u0 * p.x + u1 * p.y + u2 * p.z;          // a2      3* 2+-
  const F B = u0 * o.x + u1 * o.y + u2 * o.z + u3;     // a1 / 2  3* 3+-
  const F C = w0 * o.x + w1 * o.y + w2 * o.z + w3;     // a0      3* 3+-
  const F disc = B * B - A * C;                        // 2* 1+-
  const mask_t<F> m = disc >= F(0);                    // 1 cmp   (negative case ends here)
  if (none_of<F>(m)) return miss_hit<F>();
  return first_hit(r, stable_roots(A, B, C, disc, m));
}

// coeffs10 method (seed 004), the slide's A, B, C term by term (B halved).
template <class F>
RB_INLINE Hit<F> intersect_quadric_coeffs10(const Ray<F>& r, const Quadric<F>& q) {
  const F x0 = r.o.x, y0 = r.o.y, z0 = r.o.z, xd = r.d.x, yd = r.d.y, zd = r.d.z;
  const F two = F(2);
  const F A = q.a * xd * xd + q.b * yd * yd + q.c * zd * zd + two * (q.d * xd * yd + q.e * yd * zd + q.f * xd * zd);
  const F B = q.a * x0 * xd + q.b * y0 * yd + q.c * z0 * zd + q.d * (x0 * yd + xd * y0) + q.e * (y0 * zd + yd * z0) +
              q.f * (x0 * zd + xd * z0) + q.g * xd + q.h * yd + q.j * zd;
  const F C = q.a * x0 * x0 + q.b * y0 * y0 + q.c * z0 * z0 +
              two * (q.d * x0 * y0 + q.e * y0 * z0 + q.f * x0 * z0 + q.g * x0 + q.h * y0 + q.j * z0) + q.k;
  const F disc = B * B - A * C;                        // 2* 1+-
  const mask_t<F> m = disc >= F(0);                    // 1 cmp   (negative case ends here)
  if (none_of<F>(m)) return miss_hit<F>();
  return first_hit(r, stable_roots(A, B, C, disc, m));
}

// The closed solid F <= 0 of a bounded quadric (an ellipsoid: its quadratic part is positive
// definite, so A > 0 for every direction): the interval between the roots on the whole line
// (not clipped to [tmin, tmax]: CSG combines intervals first), canonical. The caller guarantees
// boundedness (the CSG builder checks it). coeffs10's A, B, C, then the stable roots.
template <class F>
RB_INLINE Roots<F, 2> quadric_solid_roots(const Ray<F>& r, const Quadric<F>& q) {
  const Vec3<F>& o = r.o;
  const Vec3<F>& p = r.d;
  const F u0 = q.a * p.x + q.d * p.y + q.f * p.z, u1 = q.d * p.x + q.b * p.y + q.e * p.z;
  const F u2 = q.f * p.x + q.e * p.y + q.c * p.z, u3 = q.g * p.x + q.h * p.y + q.j * p.z;
  const F w0 = q.a * o.x + q.d * o.y + q.f * o.z + q.g, w1 = q.d * o.x + q.b * o.y + q.e * o.z + q.h;
  const F w2 = q.f * o.x + q.e * o.y + q.c * o.z + q.j, w3 = q.g * o.x + q.h * o.y + q.j * o.z + q.k;
  const F A = u0 * p.x + u1 * p.y + u2 * p.z;
  const F B = u0 * o.x + u1 * o.y + u2 * o.z + u3;
  const F C = w0 * o.x + w1 * o.y + w2 * o.z + w3;
  const F disc = B * B - A * C;
  const mask_t<F> m = disc >= F(0);
  if (none_of<F>(m)) return Roots<F, 2>::none();
  const Roots<F, 2> s = stable_roots(A, B, C, disc, m);
  return Roots<F, 2>::closed_span(m & (s.lo() <= s.hi()), s.lo(), s.hi());
}

// Unit gradient at p (seed 004): 9* 9+-, normalised 3* 2+- 1 sqrt 1/ 3*.
template <class F>
RB_INLINE Vec3<F> quadric_normal(const Quadric<F>& q, const Vec3<F>& p) {
  const Vec3<F> g{q.a * p.x + q.d * p.y + q.f * p.z + q.g, q.d * p.x + q.b * p.y + q.e * p.z + q.h,
                  q.f * p.x + q.e * p.y + q.c * p.z + q.j};
  return normalize(g);
}

// ---- quadric of revolution ----------------------------------------------------------------------
template <class F>
struct QuadricRev {
  Vec3<F> ctr;
  F a, b, hb, c;  // x^2 + y^2 + a z^2 + b z + c = 0 about ctr; hb = b / 2
  auto fields() { return std::tie(ctr.x, ctr.y, ctr.z, a, b, hb, c); }
  // a = 1, c = +inf: C = +inf, disc = -inf (NaN for a zero direction): always the negative case.
  static QuadricRev never() { return {{F(0), F(0), F(0)}, F(1), F(0), F(0), F(kInf<F>)}; }
};

// Non-finite input: never() (the reason in *why). (a = b = 0, c > 0 is a legitimate empty surface; c = 0 with
// a = b = 0 is the z axis: a line, hit by no ray in general position.)
template <class T>
inline QuadricRev<float> make_quadric_rev(Vec3<T> centre, T a, T b, T c, std::string* why = nullptr) {
  if (!finite3(centre) || !std::isfinite(a) || !std::isfinite(b) || !std::isfinite(c))
    return never_because<QuadricRev<float>>(why, "quadric of revolution: a coefficient or the centre is not finite");
  return {to_float(to_double(centre)), float(a), float(b), float(0.5 * double(b)), float(c)};
}

template <class F>
RB_INLINE Hit<F> intersect_quadric_rev(const Ray<F>& r, const QuadricRev<F>& q) {
  const Vec3<F> o = r.o - q.ctr;                       // 3+-
  const Vec3<F>& p = r.d;
  const F az = q.a * o.z;                              // 1*
  const F A = p.x * p.x + p.y * p.y + q.a * p.z * p.z; // 4* 2+-
  const F B = o.x * p.x + o.y * p.y + (az + q.hb) * p.z;  // 3* 3+-
  const F C = o.x * o.x + o.y * o.y + (az + q.b) * o.z + q.c;  // 3* 4+-
  const F disc = B * B - A * C;                        // 2* 1+-
  const mask_t<F> m = disc >= F(0);                    // 1 cmp
  if (none_of<F>(m)) return miss_hit<F>();
  return first_hit(r, stable_roots(A, B, C, disc, m));
}

// Unit normal (x, y, a z + b/2) about the centre: 3+- 1* 1+-, normalised.
template <class F>
RB_INLINE Vec3<F> quadric_rev_normal(const QuadricRev<F>& q, const Vec3<F>& p) {
  const Vec3<F> l = p - q.ctr;
  return normalize(Vec3<F>{l.x, l.y, q.a * l.z + q.hb});
}

}  // namespace rb
