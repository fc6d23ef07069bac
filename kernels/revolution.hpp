// Ray x surface of revolution (seed 000 "Surface of revolution", "Ray in rz plane").
// The profile K(s) = (r(s), z(s)), s in [0, 1], is a cubic in s (given as power-basis
// coefficients or as a cubic Bezier in (r, z), converted at construction), revolved about the
// axis through c along the unit vector w. The ray in the rz plane, with q = P0 - c:
//   z0 = q.w, z1 = p1.w, e = q.p1 - z0 z1 (= x0x1 + y0y1), b = p1.p1 - z1^2 (= x1^2 + y1^2),
//   f = q.q - z0^2 (= x0^2 + y0^2), and after eliminating t:
//   a r^2 + b z^2 + c z + d = 0,  a = -z1^2, c = 2(z1 e - z0 b), d = z0(z0 b - 2 z1 e) + f z1^2   (1)
// (frame-free: only w is needed). Substituting K(s) into (1) gives K*(s) of degree 6, solved on
// [0, 1] by derivative isolation + safeguarded Newton (core/poly.hpp); t = (z(s) - z0) / z1.
// The normal comes from the profile tangent: (z'(s), -r'(s)) in the rz plane (outward for a
// profile running towards +w with r > 0). Hit.u = s (the profile parameter), Hit.v = 0.
//
// Limitation of the elimination, stated: for a ray perpendicular to the axis (z1 = 0) equation
// (1) degenerates to b (z - z0)^2 = 0 and says nothing about r; lanes with |z1| < kRevFlat take
// the horizontal path instead: z(s) = z0 (a cubic in s) and then r(s)^2 = b t^2 + 2 e t + f for
// the two t. That path ignores the ray's tilt, an error of about |z1| t |dr/dz| in t.
#pragma once

#include "core/poly.hpp"
#include "core/ray.hpp"
#include "core/why.hpp"
#include "kernels/bounding_sphere.hpp"

#include <tuple>

namespace rb {

inline constexpr double kRevFlat = 1e-4;

template <class F>
struct Revolution {
  Vec3<F> c, w;       // axis point (profile z = 0) and unit axis
  F rc[4], zc[4];     // r(s) = sum rc[k] s^k, z(s) = sum zc[k] s^k
  F bs2;              // bounding sphere about c, radius^2 (-inf: never hits)
  auto fields() {
    return std::tie(c.x, c.y, c.z, w.x, w.y, w.z, rc[0], rc[1], rc[2], rc[3], zc[0], zc[1], zc[2], zc[3], bs2);
  }
  static Revolution never() {
    return {{F(0), F(0), F(0)}, {F(0), F(0), F(1)}, {F(0), F(0), F(0), F(0)}, {F(0), F(0), F(0), F(0)}, F(-kInf<F>)};
  }
};

// From power-basis profile coefficients (r(s) = r[0] + r[1] s + ..., likewise z). Non-finite
// input, a zero axis, or a zero-length profile (constant: a point or a circle, no area): never(),
// the reason in *why.
template <class T>
inline Revolution<float> make_revolution_poly(Vec3<T> c, Vec3<T> axis, const std::array<double, 4>& r, const std::array<double, 4>& z,
                                              std::string* why = nullptr) {
  using P = Revolution<float>;
  for (int k = 0; k < 4; ++k)
    if (!std::isfinite(r[k]) || !std::isfinite(z[k])) return never_because<P>(why, "revolution: non-finite profile coefficient");
  if (!finite3(c) || !finite3(axis)) return never_because<P>(why, "revolution: non-finite centre or axis");
  Vec3d w = to_double(axis);
  const double wl = std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
  if (!(wl > 0.0)) return never_because<P>(why, "revolution: zero axis");
  if (r[1] == 0 && r[2] == 0 && r[3] == 0 && z[1] == 0 && z[2] == 0 && z[3] == 0)
    return never_because<P>(why, "revolution: constant profile (no area)");
  // Bernstein coefficients bound the curve (convex hull): the bounding sphere about c.
  auto bern = [](const std::array<double, 4>& p) {
    return std::array<double, 4>{p[0], p[0] + p[1] / 3, p[0] + 2 * p[1] / 3 + p[2] / 3, p[0] + p[1] + p[2] + p[3]};
  };
  const auto br = bern(r), bz = bern(z);
  double b2 = 0;
  for (int k = 0; k < 4; ++k) b2 = std::max(b2, br[k] * br[k] + bz[k] * bz[k]);
  const double bs = std::sqrt(b2) * (1 + 1e-5) + 1e-6;
  Revolution<float> s;
  s.c = to_float(to_double(c));
  s.w = to_float(Vec3d{w.x / wl, w.y / wl, w.z / wl});
  for (int k = 0; k < 4; ++k) { s.rc[k] = float(r[k]); s.zc[k] = float(z[k]); }
  s.bs2 = float(bs * bs);
  return s;
}

// From a cubic Bezier in (r, z): control points (r_i, z_i), i = 0..3.
template <class T>
inline Revolution<float> make_revolution_bezier(Vec3<T> c, Vec3<T> axis, const std::array<std::array<double, 2>, 4>& P,
                                                std::string* why = nullptr) {
  auto power = [&](int a) {
    const double p0 = P[0][a], p1 = P[1][a], p2 = P[2][a], p3 = P[3][a];
    return std::array<double, 4>{p0, 3 * (p1 - p0), 3 * (p0 - 2 * p1 + p2), p3 - p0 + 3 * (p1 - p2)};
  };
  return make_revolution_poly(c, axis, power(0), power(1), why);
}

template <class F>
RB_INLINE Hit<F> intersect_revolution(const Ray<F>& ray, const Revolution<F>& S, IterCount* ic = nullptr) {
  const Vec3<F> q = ray.o - S.c;
  // The bounding sphere: the negative case (its span is not used further: the profile's roots
  // are found in the curve parameter s).
  if (none_of<F>(bounding_sphere_span(ray, q, S.bs2).valid[0])) return miss_hit<F>();
  const F qd = dot(q, ray.d), qq = dot(q, q);
  const F z0 = dot(q, S.w), z1 = dot(ray.d, S.w);
  const F e = qd - z0 * z1, b = dot(ray.d, ray.d) - z1 * z1, f = qq - z0 * z0;
  const F a = -(z1 * z1);
  const F c = F(2) * (z1 * e - z0 * b);
  const F d = z0 * (z0 * b - F(2) * z1 * e) + f * z1 * z1;
  // K*(s) = a r(s)^2 + b z(s)^2 + c z(s) + d
  F r2[7], z2[7];
  for (int k = 0; k < 7; ++k) { r2[k] = F(0); z2[k] = F(0); }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      r2[i + j] = r2[i + j] + S.rc[i] * S.rc[j];
      z2[i + j] = z2[i + j] + S.zc[i] * S.zc[j];
    }
  F K[7];
  for (int k = 0; k < 7; ++k) K[k] = a * r2[k] + b * z2[k];
  for (int k = 0; k < 4; ++k) K[k] = K[k] + c * S.zc[k];
  K[0] = K[0] + d;
  const F tol = F(8 * std::numeric_limits<scalar_t<F>>::epsilon());
  const mask_t<F> flat = vabs(z1) < cst<F>(kRevFlat);
  F tbest = F(kInf<F>), sbest = F(0);
  if (any_of<F>(mask_not<F>(flat))) {
    F s[6];
    mask_t<F> ok[6];
    poly_roots_in<6, F>(K, F(0), F(1), tol, s, ok, ic);
    const F inv_z1 = F(1) / z1;
    for (int k = 0; k < 6; ++k) {
      const F t = (poly_eval<3>(S.zc, s[k]) - z0) * inv_z1;
      const mask_t<F> good = mask_not<F>(flat) & ok[k] & (t >= ray.tmin) & (t <= ray.tmax) & (t < tbest);
      tbest = vselect(good, t, tbest);
      sbest = vselect(good, s[k], sbest);
    }
  }
  if (any_of<F>(flat)) {
    F zz[4] = {S.zc[0] - z0, S.zc[1], S.zc[2], S.zc[3]};
    F s[3];
    mask_t<F> ok[3];
    poly_roots_in<3, F>(zz, F(0), F(1), tol, s, ok, ic);
    const F inv_b = F(1) / b;
    for (int k = 0; k < 3; ++k) {
      const F rs = poly_eval<3>(S.rc, s[k]);
      const F disc = e * e - b * (f - rs * rs);
      const F sq = vsqrt(vmax(disc, F(0)));
      for (int sgn = 0; sgn < 2; ++sgn) {
        const F t = (-e + (sgn == 0 ? -sq : sq)) * inv_b;
        const mask_t<F> good = flat & ok[k] & (disc >= F(0)) & (t >= ray.tmin) & (t <= ray.tmax) & (t < tbest);
        tbest = vselect(good, t, tbest);
        sbest = vselect(good, s[k], sbest);
      }
    }
  }
  const mask_t<F> m = tbest < F(kInf<F>);
  return make_hit<F>(m, tbest, vselect(m, sbest, F(0)));
}

// Unit normal at a point p of the surface with profile parameter s (Hit.u).
template <class F>
RB_INLINE Vec3<F> revolution_normal(const Revolution<F>& S, const Vec3<F>& p, const F& s) {
  const Vec3<F> q = p - S.c;
  const F z = dot(q, S.w);
  const Vec3<F> radial = q - S.w * z;
  const F rl = length(radial);
  // On the axis (rl == 0) any radial direction is as good: the normal is then +-w anyway.
  const Vec3<F> ru = vselect3(rl > F(0), radial * (F(1) / rl), Vec3<F>{F(0), F(0), F(0)});
  const F dr = (F(3) * S.rc[3] * s + F(2) * S.rc[2]) * s + S.rc[1];
  const F dz = (F(3) * S.zc[3] * s + F(2) * S.zc[2]) * s + S.zc[1];
  return normalize(ru * dz - S.w * dr);
}

}  // namespace rb
