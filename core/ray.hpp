// Ray<F> and Hit<F>: what every kernel takes and returns.
//
// Ray contract (enforced by make_ray and soa::RaySoA, the only ways rays enter the engine):
//   - d has unit length, rd = 1/d per component (per-ray precompute, as Embree does);
//   - t is a distance along d and a hit must satisfy tmin <= t <= tmax; tmax is finite (an
//     infinite tmax is stored as the largest float), so a hit always has a finite t;
//   - an invalid ray (NaN or inf anywhere, zero direction, tmin > tmax, NaN bounds) is stored
//     with the empty interval tmin = +inf, tmax = -inf, so every kernel's positive-form range
//     test fails: a defined miss, never a NaN t, never a crash.
// Hit contract: `mask` is the hit mask; t is +inf on lanes that missed (never NaN);
// u, v are the method's surface parameters where the lecture defines them (0 otherwise).
#pragma once

#include "core/vec3.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rb {

template <class F>
struct Ray {
  Vec3<F> o, d, rd;
  F tmin, tmax;

  template <class G>
  static RB_INLINE Ray broadcast(const Ray<G>& r) {
    return {Vec3<F>::from(r.o), Vec3<F>::from(r.d), Vec3<F>::from(r.rd), F(r.tmin), F(r.tmax)};
  }
  RB_INLINE Vec3<F> at(const F& t) const { return o + d * t; }
};

template <class F>
struct Hit {
  mask_t<F> mask;
  F t, u, v;
};

template <class F>
RB_INLINE Hit<F> miss_hit() {
  return {mask_false<F>(), F(kInf<F>), F(0), F(0)};
}

// Final step of every kernel: t where the mask is set, +inf elsewhere (1 select).
template <class F>
RB_INLINE Hit<F> make_hit(const mask_t<F>& m, const F& t, const F& u = F(0), const F& v = F(0)) {
  return {m, vselect(m, t, F(kInf<F>)), u, v};
}

// The hit point [x, y, z] = P0 + t p1 (seed 000: 3+- 3*).
template <class F>
RB_INLINE Vec3<F> hit_point(const Ray<F>& r, const F& t) { return r.at(t); }

// Builds a validated ray from user input (any float type). See the contract above.
template <class T = float>
RB_INLINE Ray<float> make_ray(Vec3<T> o, Vec3<T> d, T tmin = T(0), T tmax = std::numeric_limits<T>::infinity()) {
  // |d| with its fused multiply-adds spelled out (dot_fma): the same bits as lanes::make_rays under
  // any -ffp-contract.
  const double len = std::sqrt(dot_fma(to_double(d), to_double(d)));
  Ray<float> r;
  const bool ok = finite3(o) && finite3(d) && std::isfinite(len) && len > 0.0 && !std::isnan(tmin) &&
                  !std::isnan(tmax) && tmin <= tmax && !std::isinf(tmin);
  if (!ok) {
    const float inf = std::numeric_limits<float>::infinity();
    return {{0.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, {inf, inf, 1.f}, inf, -inf};
  }
  // Normalise in double, round once; tmin/tmax scale with |d| so the same segment is kept.
  r.o = to_float(to_double(o));
  r.d = to_float(Vec3d{double(d.x) / len, double(d.y) / len, double(d.z) / len});
  r.rd = {1.0f / r.d.x, 1.0f / r.d.y, 1.0f / r.d.z};
  r.tmin = float(double(tmin) * len);
  r.tmax = float(std::min(double(tmax) * len, double(std::numeric_limits<float>::max())));
  return r;
}

}  // namespace rb
