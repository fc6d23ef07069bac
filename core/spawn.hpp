// Where a secondary ray starts: a point computed on a surface lies within rounding error of it, on
// either side, so a ray spawned there can hit its own surface again ("self-hit", shadow acne).
// Three schemes, all in float (the tracer's frame coordinates), measured by the accuracy lab
// (accuracy/secondary_cases.cpp: each one's self-hits and cost); the tracer (tracer/plan.hpp) runs
// the first (fast model) and the last (auto and exact):
//   - extent epsilon: the point moved along the normal by a fixed fraction of the scene's size
//     (simple and scale-aware, but at 6.4e6 from the origin a fraction of the extent is hundreds
//     of units, and near the origin of a large scene it is below one float step);
//   - Waechter and Binder's integer offset (Ray Tracing Gems, chapter 6): each coordinate moved
//     along the normal by a number of float ulps proportional to the normal component (256 for a
//     normal along the axis), or, where the coordinate is near zero (below 1/32), by a fixed
//     1/65536 (the published constants, for a scene of size about 1). Sized to the coordinates,
//     not to the point's error: far from the origin it lifts a ray past objects smaller than 256
//     float steps there;
//   - the error-bound offset (as pbrt-v4 spawns rays): a point recomputed in a form whose rounding
//     error has a known bound, moved along the normal by that bound, each coordinate rounded one
//     float further away.
#pragma once

#include "core/vec3.hpp"

#include <immintrin.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <cstdint>

namespace rb::spawn {

// Waechter-Binder on one coordinate (p, the unit normal's component n).
inline float wb_one(float p, float n) {
  const int of = int(256.0f * n);
  const float pi = std::bit_cast<float>(std::bit_cast<int>(p) + (p < 0 ? -of : of));
  return std::fabs(p) < 1.0f / 32.0f ? p + (1.0f / 65536.0f) * n : pi;
}
inline Vec3f wb_offset(const Vec3f& p, const Vec3f& n) { return {wb_one(p.x, n.x), wb_one(p.y, n.y), wb_one(p.z, n.z)}; }

// gamma_n = n u / (1 - n u), u = 2^-24: the bound of n float roundings (Higham).
constexpr float gamma_f(int n) {
  const float u = 0x1p-24f;
  return float(n) * u / (1.0f - float(n) * u);
}
inline Vec3f vabs3(const Vec3f& v) { return {std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}; }

// The next float up or down by its bit pattern (finite inputs; -0 is taken as +0 going up and +0
// as -0 going down): an integer step, no library call.
inline float next_up(float v) {
  if (v == 0.0f) return std::bit_cast<float>(1);
  const int b = std::bit_cast<int>(v);
  return std::bit_cast<float>(v > 0 ? b + 1 : b - 1);
}
inline float next_down(float v) { return -next_up(-v); }
// `n` floats up (n > 0) or down (n < 0) from a finite v, through the ordered integer key of the bit
// pattern (-x has key -key(x); +0 and -0 share key 0), so one step from 0 is the smallest subnormal
// and steps past the largest float stop at infinity (as n calls of next_up or next_down would give,
// but without their sign branch). Infinities and NaN stay as they are. The definition, one float at
// a time; frame boxes (three steps per side) use the 8-lane form below, tested equal to it.
inline float step_floats(float v, int n) {
  if (!(std::fabs(v) <= std::numeric_limits<float>::max())) return v;
  constexpr std::int32_t kInfKey = 0x7F800000;
  const std::int32_t b = std::bit_cast<std::int32_t>(v);
  std::int32_t key = b >= 0 ? b : std::numeric_limits<std::int32_t>::min() - b;
  key = std::clamp(key + n, -kInfKey, kInfKey);
  return std::bit_cast<float>(key >= 0 ? key : std::numeric_limits<std::int32_t>::min() - key);
}
// The same for 8 floats at once, lane i stepped n[i] floats (|n[i]| small).
inline __m256 step_floats8(__m256 v, __m256i n) {
  const __m256i kmin = _mm256_set1_epi32(std::numeric_limits<std::int32_t>::min()), kinf = _mm256_set1_epi32(0x7F800000);
  const __m256i b = _mm256_castps_si256(v);
  __m256i key = _mm256_blendv_epi8(b, _mm256_sub_epi32(kmin, b), _mm256_srai_epi32(b, 31));
  key = _mm256_max_epi32(_mm256_min_epi32(_mm256_add_epi32(key, n), kinf), _mm256_sub_epi32(_mm256_setzero_si256(), kinf));
  const __m256i r = _mm256_blendv_epi8(key, _mm256_sub_epi32(kmin, key), _mm256_srai_epi32(key, 31));
  const __m256 finite = _mm256_cmp_ps(_mm256_and_ps(v, _mm256_castsi256_ps(_mm256_set1_epi32(0x7FFFFFFF))),
                                      _mm256_set1_ps(std::numeric_limits<float>::max()), _CMP_LE_OQ);
  return _mm256_blendv_ps(v, _mm256_castsi256_ps(r), finite);
}
// Every lane stepped n floats.
inline __m256 step_floats8(__m256 v, int n) { return step_floats8(v, _mm256_set1_epi32(n)); }
// The box [lo, hi] relative to `origin`: each bound's difference rounded to the nearest float, then
// `steps` floats outward, all 6 in the lanes of one register.
inline void relative_box_outward(const Vec3d& lo, const Vec3d& hi, const Vec3d& origin, int steps, float out_lo[3], float out_hi[3]) {
  const __m256d o = _mm256_setr_pd(origin.x, origin.y, origin.z, 0.0);
  const __m128 l = _mm256_cvtpd_ps(_mm256_sub_pd(_mm256_setr_pd(lo.x, lo.y, lo.z, 0.0), o));
  const __m128 h = _mm256_cvtpd_ps(_mm256_sub_pd(_mm256_setr_pd(hi.x, hi.y, hi.z, 0.0), o));
  alignas(32) float v[8];
  _mm256_store_ps(v, step_floats8(_mm256_set_m128(h, l), _mm256_setr_epi32(-steps, -steps, -steps, 0, steps, steps, steps, 0)));
  for (int k = 0; k < 3; ++k) out_lo[k] = v[k], out_hi[k] = v[4 + k];
}
inline float away(float po, float off) { return off > 0 ? next_up(po) : off < 0 ? next_down(po) : po; }

// p (within err of the surface, per coordinate) moved along the unit normal n (on the outgoing
// side) by |n| . err, each moved coordinate rounded one float further. Fused explicitly (p + n d
// rounded once), so that the point is the same wherever this is inlined: left to
// -ffp-contract=fast, the compiler fused it in one caller and not in another.
inline Vec3f bound_offset(const Vec3f& p, const Vec3f& err, const Vec3f& n) {
  const float d = std::fma(std::fabs(n.x), err.x, std::fma(std::fabs(n.y), err.y, std::fabs(n.z) * err.z));
  const Vec3f po{std::fma(n.x, d, p.x), std::fma(n.y, d, p.y), std::fma(n.z, d, p.z)};
  return {away(po.x, n.x * d), away(po.y, n.y * d), away(po.z, n.z * d)};
}

// bound_offset for 8 points at once, lane for lane the same bits (the same fused operations, and
// one float step in the integer order of step_floats8, which is next_up / next_down on finite
// values).
inline Vec3<f8> bound_offset(const Vec3<f8>& p, const Vec3<f8>& err, const Vec3<f8>& n) {
  const f8 d = vfma(vabs(n.x), err.x, vfma(vabs(n.y), err.y, vabs(n.z) * err.z));
  auto away8 = [&](const f8& pn, const f8& nc) {
    const f8 po = vfma(nc, d, pn), off = nc * d;
    const __m256i up = _mm256_castps_si256(_mm256_cmp_ps(off, _mm256_setzero_ps(), _CMP_GT_OQ));
    const __m256i down = _mm256_castps_si256(_mm256_cmp_ps(off, _mm256_setzero_ps(), _CMP_LT_OQ));
    return f8(step_floats8(po, _mm256_sub_epi32(down, up)));  // +1 where off > 0, -1 where off < 0
  };
  return {away8(p.x, n.x), away8(p.y, n.y), away8(p.z, n.z)};
}

// The point moved along n by eps (the extent-epsilon scheme), fused (p + n eps rounded once) in
// one lane or eight.
template <class F>
RB_INLINE Vec3<F> eps_offset(const Vec3<F>& p, const Vec3<F>& n, const F& eps) {
  return {vfma(n.x, eps, p.x), vfma(n.y, eps, p.y), vfma(n.z, eps, p.z)};
}

}  // namespace rb::spawn
