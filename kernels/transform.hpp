// Transformed instances (seed 000 "CSG representation" / "Implementation"): any primitive placed
// by an affine matrix M (world = M local). The ray is carried into the primitive's frame by the
// stored inverse, the primitive's own kernel runs there, and normals come back by (M^-1)^T.
//
//   P0' = M^-1 [P0; 1]   9* 9+- (3x3 product and the translation)
//   p1' = M^-1 [p1; 0]   9* 6+-
//   together the slide's "1 transformation: 15+, 18*"; the normal: n = (M^-1)^T n' (9* 6+-),
//   then normalised.
//
// t in world units: the local ray P0' + t p1' is the image of P0 + t p1 under M^-1 for the same t
// (affine maps preserve the line parameter). p1' is NOT unit length, but t is never rescaled: the
// world direction is unit, so the t the local kernel returns is already the world distance, and
// [tmin, tmax] carry over unchanged. Consequently the wrapped kernel must accept a direction of
// any length: the stable sphere, the general quadric, the quadric of revolution, the cylinder and
// the cone here do; the geometric and Hearn-Baker spheres (which assume |d| = 1) do not.
// rd = 1/p1' is formed only on request (kRecip = true: +3/); otherwise it is NaN, so a kernel
// that wrongly reads it reports misses, never plausible hits.
//
// Construction (docs/DESIGN.md section 7): a non-finite or singular M, or one whose inverse
// overflows float, gives never() (zero inverse, never() primitive: misses every ray), the reason
// in *why. Affine3d::frame and Affine3d::inverse return std::nullopt for such input.
#pragma once

#include "core/ray.hpp"
#include "core/why.hpp"
#include "soa/prims.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <tuple>

namespace rb {

// An affine map in double precision: y = A x + b, rows m[i] = (A_i0, A_i1, A_i2, b_i).
struct Affine3d {
  double m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

  static Affine3d identity() { return {}; }
  static Affine3d translate(Vec3d t) {
    Affine3d a;
    a.m[0][3] = t.x; a.m[1][3] = t.y; a.m[2][3] = t.z;
    return a;
  }
  static Affine3d scale(Vec3d s) {
    Affine3d a;
    a.m[0][0] = s.x; a.m[1][1] = s.y; a.m[2][2] = s.z;
    return a;
  }
  // Rotation by `angle` radians about `axis` (Rodrigues); the axis is normalised.
  static Affine3d rotate(Vec3d axis, double angle) {
    const double l = std::sqrt(dot(axis, axis));
    const Vec3d k = axis * (1.0 / l);
    const double c = std::cos(angle), s = std::sin(angle), C = 1.0 - c;
    Affine3d a;
    a.m[0][0] = c + k.x * k.x * C;       a.m[0][1] = k.x * k.y * C - k.z * s; a.m[0][2] = k.x * k.z * C + k.y * s;
    a.m[1][0] = k.y * k.x * C + k.z * s; a.m[1][1] = c + k.y * k.y * C;       a.m[1][2] = k.y * k.z * C - k.x * s;
    a.m[2][0] = k.z * k.x * C - k.y * s; a.m[2][1] = k.z * k.y * C + k.x * s; a.m[2][2] = c + k.z * k.z * C;
    return a;
  }
  // A rigid frame taking +z to `axis` and the origin to `o`: world = frame(o, axis) local.
  // std::nullopt (the reason in *why) for a zero or non-finite axis or a non-finite origin.
  static std::optional<Affine3d> frame(Vec3d o, Vec3d axis, std::string* why = nullptr) {
    const double l = std::sqrt(dot(axis, axis));
    if (!(l > 0) || !std::isfinite(l)) {
      tell_why(why, "axis must be a non-zero finite vector");
      return std::nullopt;
    }
    if (!finite3(o)) {
      tell_why(why, "origin must be finite");
      return std::nullopt;
    }
    axis = axis * (1.0 / l);
    const Vec3d z{0, 0, 1};
    const Vec3d k = cross(z, axis);
    const double s = std::sqrt(dot(k, k)), c = dot(z, axis);
    Affine3d R;
    if (s > 1e-12) R = rotate(k, std::atan2(s, c));
    else if (c < 0) R = rotate({1, 0, 0}, 3.14159265358979323846);
    return translate(o) * R;
  }
  // this * o (apply o first).
  Affine3d operator*(const Affine3d& o) const {
    Affine3d r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) {
        double s = j == 3 ? m[i][3] : 0.0;
        for (int k = 0; k < 3; ++k) s += m[i][k] * o.m[k][j];
        r.m[i][j] = s;
      }
    return r;
  }
  Vec3d point(Vec3d p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3], m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
  }
  Vec3d vector(Vec3d v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  bool finite() const {
    for (const auto& r : m)
      for (double x : r)
        if (!std::isfinite(x)) return false;
    return true;
  }
  double det() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
  // The inverse; std::nullopt (the reason in *why) for a non-finite or (numerically) singular
  // matrix: |det| <= 1e-12 |A_0| |A_1| |A_2| (the row norms: a scale-free test of the 3x3 part).
  std::optional<Affine3d> inverse(std::string* why = nullptr) const {
    if (!finite()) {
      tell_why(why, "affine transform: matrix has a non-finite entry");
      return std::nullopt;
    }
    const double d = det();
    double rn = 1.0;
    for (const auto& r : m) rn *= std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (!(std::fabs(d) > 1e-12 * rn)) {
      tell_why(why, "affine transform: matrix is singular (det ~ 0)");
      return std::nullopt;
    }
    Affine3d v;
    const double id = 1.0 / d;
    v.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * id;
    v.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * id;
    v.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * id;
    v.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * id;
    v.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * id;
    v.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * id;
    v.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * id;
    v.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * id;
    v.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * id;
    for (int i = 0; i < 3; ++i) v.m[i][3] = -(v.m[i][0] * m[0][3] + v.m[i][1] * m[1][3] + v.m[i][2] * m[2][3]);
    return v;
  }
};

// The stored inverse, 12 numbers of type F (row-major 3x4).
template <class F>
struct Affine34 {
  F m00, m01, m02, m03, m10, m11, m12, m13, m20, m21, m22, m23;
};

// Transformed<P>::T<F>: a primitive of kind P<F> in its own frame plus the world-to-local matrix.
// A primitive kind in the sense of soa/prims.hpp (fields(), never()), so PrimSoA and both SIMD
// mappings work unchanged: PrimSoA<Transformed<Sphere>::T>.
template <template <class> class P>
struct Transformed {
  template <class F>
  struct T {
    Affine34<F> inv;
    P<F> prim;
    auto fields() {
      return std::tuple_cat(std::tie(inv.m00, inv.m01, inv.m02, inv.m03, inv.m10, inv.m11, inv.m12, inv.m13, inv.m20, inv.m21,
                                     inv.m22, inv.m23),
                            prim.fields());
    }
    static T never() {
      const F z = F(0);
      return {{z, z, z, z, z, z, z, z, z, z, z, z}, P<F>::never()};
    }
  };
};

// Places `prim` (built in its own frame) by M: world = M local. never() (the reason in *why) for
// a non-finite or singular M, one whose inverse is not representable in float, or a missing M
// (a frame that could not be built).
template <template <class> class P>
inline typename Transformed<P>::template T<float> make_transformed(const Affine3d& M, const P<float>& prim, std::string* why = nullptr) {
  using X = typename Transformed<P>::template T<float>;
  const std::optional<Affine3d> inv = M.inverse(why);
  if (!inv) return X::never();
  const Affine3d& v = *inv;
  X x;
  float* dst[12] = {&x.inv.m00, &x.inv.m01, &x.inv.m02, &x.inv.m03, &x.inv.m10, &x.inv.m11,
                    &x.inv.m12, &x.inv.m13, &x.inv.m20, &x.inv.m21, &x.inv.m22, &x.inv.m23};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) {
      const float f = float(v.m[i][j]);
      if (!std::isfinite(f)) return never_because<X>(why, "affine transform: inverse overflows float");
      *dst[i * 4 + j] = f;
    }
  x.prim = prim;
  return x;
}

// The same from a placement that may be missing (Affine3d::frame, Affine3d::inverse): no M gives
// never(), *why as the function that failed to build M left it.
template <template <class> class P>
inline typename Transformed<P>::template T<float> make_transformed(const std::optional<Affine3d>& M, const P<float>& prim,
                                                                   std::string* why = nullptr) {
  if (!M) return Transformed<P>::template T<float>::never();
  return make_transformed(*M, prim, why);
}

// The ray in the primitive's frame: 15+- 18* (the slide's count); kRecip adds rd = 1/p1' (3/).
template <bool kRecip = false, class F>
RB_INLINE Ray<F> transform_ray(const Ray<F>& r, const Affine34<F>& a) {
  Ray<F> l;
  l.o = {a.m00 * r.o.x + a.m01 * r.o.y + a.m02 * r.o.z + a.m03,   // 9* 9+-
         a.m10 * r.o.x + a.m11 * r.o.y + a.m12 * r.o.z + a.m13,
         a.m20 * r.o.x + a.m21 * r.o.y + a.m22 * r.o.z + a.m23};
  l.d = {a.m00 * r.d.x + a.m01 * r.d.y + a.m02 * r.d.z,           // 9* 6+-
         a.m10 * r.d.x + a.m11 * r.d.y + a.m12 * r.d.z,
         a.m20 * r.d.x + a.m21 * r.d.y + a.m22 * r.d.z};
  if constexpr (kRecip) {
    const F one = F(1);
    l.rd = {one / l.d.x, one / l.d.y, one / l.d.z};
  } else {
    const F nan = F(std::numeric_limits<scalar_t<F>>::quiet_NaN());
    l.rd = {nan, nan, nan};
  }
  l.tmin = r.tmin;  // same parameter in both frames: no rescaling
  l.tmax = r.tmax;
  return l;
}

// Runs kernel(local ray, primitive) on a transformed instance; t (and u, v) come back unchanged:
// t is the world distance (see the header comment).
template <bool kRecip = false, class F, class X, class K>
RB_INLINE auto intersect_transformed(const Ray<F>& r, const X& x, K&& kernel) {
  return kernel(transform_ray<kRecip>(r, x.inv), x.prim);
}

// The same with the ray re-centred first: a ray from far away is transformed with its origin's
// rounding error (the float step at the distance, times the map's scale), which moves the ray
// by a visible fraction of a small primitive seen from 1e2 of its sizes and more. So the origin is
// first moved along the ray to the point nearest `centre` (a point of the primitive in its own
// frame: t0 = -(o' - centre) . d' / d' . d', in the local frame), p0 = o + t0 d by one FMA per
// coordinate (a point on the ray within one rounding of its own, small, magnitude), and p0 is
// transformed; the kernel runs on [tmin - t0, tmax - t0] and t0 is added back to its t (a miss
// stays +inf). About 15* 14+- 3 fma 1/ more than intersect_transformed.
template <class F, class X, class K>
RB_INLINE Hit<F> intersect_transformed_recentred(const Ray<F>& r, const X& x, const Vec3<F>& centre, K&& kernel) {
  Ray<F> l = transform_ray(r, x.inv);
  const Vec3<F> q = l.o - centre;
  const F t0 = -dot(q, l.d) / dot(l.d, l.d);
  const Vec3<F> p0{vfma(t0, r.d.x, r.o.x), vfma(t0, r.d.y, r.o.y), vfma(t0, r.d.z, r.o.z)};
  const auto& a = x.inv;
  l.o = {a.m00 * p0.x + a.m01 * p0.y + a.m02 * p0.z + a.m03, a.m10 * p0.x + a.m11 * p0.y + a.m12 * p0.z + a.m13,
         a.m20 * p0.x + a.m21 * p0.y + a.m22 * p0.z + a.m23};
  l.tmin = r.tmin - t0;
  l.tmax = r.tmax - t0;
  Hit<F> h = kernel(l, x.prim);
  h.t = vselect(h.mask, h.t + t0, F(kInf<F>));
  return h;
}

// A local normal back to world space by (M^-1)^T, normalised: 9* 6+- then 3* 2+- 1 sqrt 1/ 3*.
template <class F>
RB_INLINE Vec3<F> transform_normal(const Affine34<F>& a, const Vec3<F>& n) {
  const Vec3<F> w{a.m00 * n.x + a.m10 * n.y + a.m20 * n.z, a.m01 * n.x + a.m11 * n.y + a.m21 * n.z,
                  a.m02 * n.x + a.m12 * n.y + a.m22 * n.z};
  return normalize(w);
}

// World normal of a transformed instance at world point p, given the local normal function.
template <class F, class X, class N>
RB_INLINE Vec3<F> transformed_normal(const X& x, const Vec3<F>& p, N&& local_normal) {
  const auto& a = x.inv;
  const Vec3<F> pl{a.m00 * p.x + a.m01 * p.y + a.m02 * p.z + a.m03, a.m10 * p.x + a.m11 * p.y + a.m12 * p.z + a.m13,
                   a.m20 * p.x + a.m21 * p.y + a.m22 * p.z + a.m23};
  return transform_normal(a, local_normal(x.prim, pl));
}

}  // namespace rb
