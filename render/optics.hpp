// The optics of RT_shade, one template over the number type (one hit, or one hit per lane): the
// mirror reflection, the refraction by Snell's law, sin(theta_I) / sin(theta_T) = eta_T / eta_I,
// with total internal reflection when no transmitted direction exists, and the local light of one
// light (Lambert diffuse plus Phong specular). The renderer runs them on SoA lanes of a whole
// generation's hits (render.cpp). Every multiply-add is an explicit FMA (dot_fma, vfma), so that
// the compiler's contraction, which differs between scalar and SIMD code, cannot change a bit: each
// lane gives the scalar instantiation's result (tests/test_render.cpp).
#pragma once

#include "core/vec3.hpp"

#include <cmath>
#include <optional>

namespace rb::render {

// d (unit, towards the surface) mirrored about the unit normal n (either side): d - 2 (d.n) n.
template <class F>
RB_INLINE Vec3<F> reflect(const Vec3<F>& d, const Vec3<F>& n) {
  const F s = F(-2) * dot_fma(d, n);
  return {vfma(n.x, s, d.x), vfma(n.y, s, d.y), vfma(n.z, s, d.z)};
}

// The transmitted direction t of the unit incident direction d at a surface with unit normal n
// facing the incident side (d.n <= 0), with eta = eta_i / eta_t, in double (D: double or double
// lanes): cos_i = -d.n, k = 1 - eta^2 (1 - cos_i^2), t = eta d + (eta cos_i - sqrt(k)) n, a unit
// vector. Returns k: k >= 0 where t exists; elsewhere (total internal reflection, or NaN input)
// t is not a direction.
template <class D>
RB_INLINE D refract_k(const Vec3<D>& d, const Vec3<D>& n, const D& eta, Vec3<D>& t) {
  const D cos_i = -dot_fma(d, n);
  const D k = vfma(-(eta * eta), vfma(-cos_i, cos_i, D(1)), D(1));
  const D s = vfma(eta, cos_i, -vsqrt(k));
  t = {vfma(n.x, s, d.x * eta), vfma(n.y, s, d.y * eta), vfma(n.z, s, d.z * eta)};
  return k;
}

// The same for one float direction, going from index eta_i into eta_t: nothing on total internal
// reflection.
inline std::optional<Vec3f> refract(const Vec3f& d, const Vec3f& n, float eta_i, float eta_t) {
  Vec3d t;
  const double k = refract_k(to_double(d), to_double(n), double(eta_i) / double(eta_t), t);
  if (!(k >= 0.0)) return std::nullopt;
  return to_float(t);
}

// ks * rv^shine where `want`, else 0: the Phong lobe, through libm's powf lane by lane (xsimd's pow
// is not bit-identical to it, and images must not depend on the lane count).
template <class F>
RB_INLINE F phong(const mask_t<F>& want, const F& ks, const F& rv, const F& shine) {
  if constexpr (lanes_v<F> == 1) {
    return want ? ks * std::pow(rv, shine) : F(0);
  } else {
    F out(0.0f);
    if (none_of<F>(want)) return out;
    alignas(kSimdAlign) float k[lanes_v<F>], r[lanes_v<F>], s[lanes_v<F>], o[lanes_v<F>];
    store(k, ks), store(r, rv), store(s, shine), store(o, out);
    for (int i = 0; i < lanes_v<F>; ++i)
      if (lane_mask<F>(want, i)) o[i] = k[i] * std::pow(r[i], s[i]);
    return load<F>(o);
  }
}

// The local light of one light at a hit: the unit direction L to the light, the normal nl of the
// light test, the direction `view` to the eye, the material's kd, ks and Phong exponent and the
// surface colour. Returns n.L (the light counts only where it is > 0: NaN from a light at the hit
// point does not) and writes base kd (n.L) + ks (r.v)^shine, r the mirror of -L, into `local`.
template <class F>
RB_INLINE F local_light(const Vec3<F>& L, const Vec3<F>& nl, const Vec3<F>& view, const F& kd, const F& ks,
                        const F& shine, const Vec3<F>& base, Vec3<F>& local) {
  const F ndl = dot_fma(nl, L);
  const F rv = dot_fma(reflect(-L, nl), view);
  const F spec = phong<F>((ndl > F(0)) & (ks > F(0)) & (rv > F(0)), ks, rv, shine);
  const F diffuse = kd * ndl;
  local = {vfma(base.x, diffuse, spec), vfma(base.y, diffuse, spec), vfma(base.z, diffuse, spec)};
  return ndl;
}

}  // namespace rb::render
