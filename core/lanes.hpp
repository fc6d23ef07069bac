// Lane-level operations on the 8-lane float batch (and its halves as 4-lane doubles) that xsimd
// 8.1 does not offer: masks as bit sets, horizontal minimum and maximum, a lane read from the
// register, the integer order of float bits, a sort of 8 keys and the compaction of selected lanes.
// The traversal (bvh/) and the leaf functions (tracer/) use these instead of raw intrinsics; the
// number layer proper (core/num.hpp) stays what kernels call.
#pragma once

#include "core/num.hpp"
#include "core/ray.hpp"
#include "core/spawn.hpp"

#include <immintrin.h>

#include <cstdint>
#include <limits>

namespace rb::lanes {

// ---- masks as bit sets ---------------------------------------------------------------------------
// Bit l set when lane l of the mask is.
RB_INLINE unsigned bits(const f8_mask& m) { return unsigned(_mm256_movemask_ps(m)); }
RB_INLINE unsigned bits(const d4_mask& m) { return unsigned(_mm256_movemask_pd(m)); }
// Bit l set when lane l's sign bit is (-0.0 and negative NaNs included).
RB_INLINE unsigned sign_bits(const f8& x) { return unsigned(_mm256_movemask_ps(x)); }
// All ones in lane l when bit l of `b` is set (as integers, and as the float mask kernels take).
RB_INLINE __m256i int_lanes(unsigned b) {
  const __m256i lane = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  return _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(b)), lane), lane);
}
RB_INLINE f8_mask of(unsigned b) { return f8_mask(_mm256_castsi256_ps(int_lanes(b))); }
// Bit l set when lane l of the 8 integers at p (32-byte aligned or not) equals v.
RB_INLINE unsigned equal_bits(const std::uint32_t* p, std::uint32_t v) {
  const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
  return unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(x, _mm256_set1_epi32(int(v))))));
}

// Bit l set when the top bit of the l-th of 8 integers at p (32-byte aligned) is.
RB_INLINE unsigned top_bits(const std::uint32_t* p) { return unsigned(_mm256_movemask_ps(_mm256_load_ps(reinterpret_cast<const float*>(p)))); }

// ---- horizontal reductions and lane reads --------------------------------------------------------
// The smallest lane and its index (the lowest such lane); `ties` gets every lane holding that value.
RB_INLINE int argmin(const f8& t, float& best, unsigned& ties) {
  const __m256 v = t;
  __m256 m = _mm256_min_ps(v, _mm256_permute_ps(v, 0xB1));
  m = _mm256_min_ps(m, _mm256_permute_ps(m, 0x4E));
  m = _mm256_min_ps(m, _mm256_permute2f128_ps(m, m, 1));
  best = _mm256_cvtss_f32(m);
  ties = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(v, m, _CMP_EQ_OQ)));
  return ties ? __builtin_ctz(ties) : 0;
}
RB_INLINE float hmin(const f8& t) {
  float b;
  unsigned ties;
  argmin(t, b, ties);
  return b;
}
RB_INLINE float hmax(const f8& t) {
  const __m256 v = t;
  __m256 m = _mm256_max_ps(v, _mm256_permute_ps(v, 0xB1));
  m = _mm256_max_ps(m, _mm256_permute_ps(m, 0x4E));
  m = _mm256_max_ps(m, _mm256_permute2f128_ps(m, m, 1));
  return _mm256_cvtss_f32(m);
}
// Lane k of t, read from the register (a store and a load right after it would wait on the store).
RB_INLINE float at(const f8& t, int k) {
  return _mm256_cvtss_f32(_mm256_permutevar8x32_ps(t, _mm256_castsi128_si256(_mm_cvtsi32_si128(k))));
}

// ---- float bits as integers ----------------------------------------------------------------------
// Non-negative floats order as their bits do as signed integers, and a negative float's bits are a
// negative integer below all of them: a maximum or minimum of distances on the integer unit (one
// cycle instead of four) is right wherever one operand of a maximum is >= 0 (see bvh/slab.hpp).
RB_INLINE __m256i as_int(const f8& x) { return _mm256_castps_si256(x); }
RB_INLINE f8 as_float(__m256i x) { return f8(_mm256_castsi256_ps(x)); }
RB_INLINE __m256i int_max(__m256i a, __m256i b) { return _mm256_max_epi32(a, b); }
RB_INLINE __m256i int_min(__m256i a, __m256i b) { return _mm256_min_epi32(a, b); }
// Bit l set when lane l of a is not greater than lane l of b (as integers).
RB_INLINE unsigned int_le_bits(__m256i a, __m256i b) {
  return ~unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(a, b)))) & 0xFFu;
}
// Bit l set when a <= b in lane l (floats; false where either is NaN).
RB_INLINE unsigned le_bits(const f8& a, const f8& b) { return unsigned(_mm256_movemask_ps(_mm256_cmp_ps(a, b, _CMP_LE_OQ))); }
// Bit l set when !(a > b) in lane l (true where either is NaN).
RB_INLINE unsigned not_gt_bits(const f8& a, const f8& b) { return unsigned(_mm256_movemask_ps(_mm256_cmp_ps(a, b, _CMP_NGT_UQ))); }
// Float bits in an integer of the same order for every float (negative floats' magnitude flipped).
RB_INLINE __m256i ordered(__m256i b) { return _mm256_xor_si256(b, _mm256_srli_epi32(_mm256_srai_epi32(b, 31), 1)); }

// ---- rounding outward ----------------------------------------------------------------------------
// 8 coordinates each moved outward (up if Up, else down) by 4 u (|c| + O), u = 2^-24, in double
// (4 lanes at a time), rounded to float, and one float further in the lanes where that rounding went
// inward: the same arithmetic as one coordinate at a time (bvh::make_conservative's definition),
// 8 at once. Stepping only those lanes keeps -0 where no step is needed.
template <bool Up>
RB_INLINE f8 round_outward(const f8& row, double origin_bound) {
  const __m256d k4u = _mm256_set1_pd(4 * 0x1p-24), O = _mm256_set1_pd(origin_bound);
  const __m256d abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7FFFFFFFFFFFFFFF));
  const __m256i evens = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
  const __m256 r = row;
  const __m256d c[2] = {_mm256_cvtps_pd(_mm256_castps256_ps128(r)), _mm256_cvtps_pd(_mm256_extractf128_ps(r, 1))};
  __m128 f[2];
  __m128i inward[2];
  for (int h = 0; h < 2; ++h) {
    const __m256d d = _mm256_mul_pd(k4u, _mm256_add_pd(_mm256_and_pd(c[h], abs_mask), O));
    const __m256d moved = Up ? _mm256_add_pd(c[h], d) : _mm256_sub_pd(c[h], d);
    f[h] = _mm256_cvtpd_ps(moved);
    const __m256d back = _mm256_cvtps_pd(f[h]);
    const __m256d in = Up ? _mm256_cmp_pd(back, moved, _CMP_LT_OQ) : _mm256_cmp_pd(back, moved, _CMP_GT_OQ);
    inward[h] = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(in), evens));  // -1 where inward
  }
  const __m256i in8 = _mm256_set_m128i(inward[1], inward[0]);
  const __m256 rounded = _mm256_set_m128(f[1], f[0]);
  return f8(_mm256_blendv_ps(rounded, spawn::step_floats8(rounded, Up ? _mm256_sub_epi32(_mm256_setzero_si256(), in8) : in8),
                             _mm256_castsi256_ps(in8)));
}

// ---- sorting and compacting 8 lanes --------------------------------------------------------------
namespace detail {
// One layer of compare-exchanges: p = the partners, take_max = lanes that keep the larger key.
RB_INLINE __m256i exchange(__m256i v, __m256i p, __m256i take_max) {
  return _mm256_blendv_epi8(_mm256_min_epi32(v, p), _mm256_max_epi32(v, p), take_max);
}
}  // namespace detail
// 8 signed integer keys sorted descending in one register: Batcher's odd-even merge sort, 19
// comparators in 6 layers.
RB_INLINE __m256i sort_descending(__m256i v) {
  using detail::exchange;
  // (0,1)(2,3)(4,5)(6,7)
  v = exchange(v, _mm256_shuffle_epi32(v, 0xB1), _mm256_setr_epi32(-1, 0, -1, 0, -1, 0, -1, 0));
  // (0,2)(1,3)(4,6)(5,7)
  v = exchange(v, _mm256_shuffle_epi32(v, 0x4E), _mm256_setr_epi32(-1, -1, 0, 0, -1, -1, 0, 0));
  // (1,2)(5,6)
  v = exchange(v, _mm256_shuffle_epi32(v, 0xD8), _mm256_setr_epi32(0, -1, 0, 0, 0, -1, 0, 0));
  // (0,4)(1,5)(2,6)(3,7)
  v = exchange(v, _mm256_permute2x128_si256(v, v, 1), _mm256_setr_epi32(-1, -1, -1, -1, 0, 0, 0, 0));
  // (2,4)(3,5)
  v = exchange(v, _mm256_permutevar8x32_epi32(v, _mm256_setr_epi32(0, 1, 4, 5, 2, 3, 6, 7)), _mm256_setr_epi32(0, 0, -1, -1, 0, 0, 0, 0));
  // (1,2)(3,4)(5,6)
  v = exchange(v, _mm256_permutevar8x32_epi32(v, _mm256_setr_epi32(0, 2, 1, 4, 3, 6, 5, 7)), _mm256_setr_epi32(0, -1, 0, -1, 0, -1, 0, 0));
  return v;
}
// Keys made of an ordered float (its 3 low bits replaced by the lane's index) for the lanes of
// `b`, the smallest integer elsewhere: sorted, the indices come out in the floats' order.
RB_INLINE __m256i indexed_keys(__m256i key, unsigned b) {
  key = _mm256_or_si256(_mm256_and_si256(key, _mm256_set1_epi32(~7)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  return _mm256_blendv_epi8(_mm256_set1_epi32(std::numeric_limits<int>::min()), key, int_lanes(b));
}
RB_INLINE __m256i low3(__m256i v) { return _mm256_and_si256(v, _mm256_set1_epi32(7)); }

// The lanes of the set bits of a byte, lowest first (the rest 0): a permute by this table moves
// the selected lanes of a register to its front.
struct Compaction {
  alignas(32) std::uint32_t idx[256][8];
  constexpr Compaction() : idx{} {
    for (unsigned b = 0; b < 256; ++b) {
      unsigned k = 0;
      for (unsigned s = 0; s < 8; ++s)
        if (b >> s & 1u) idx[b][k++] = s;
    }
  }
};
inline constexpr Compaction kCompaction{};
RB_INLINE __m256i compaction(unsigned b) { return _mm256_load_si256(reinterpret_cast<const __m256i*>(kCompaction.idx[b])); }
// 8 integers or floats permuted: lane l of the result is lane idx[l] of v.
RB_INLINE __m256i permute(__m256i v, __m256i idx) { return _mm256_permutevar8x32_epi32(v, idx); }
RB_INLINE __m256 permute(__m256 v, __m256i idx) { return _mm256_permutevar8x32_ps(v, idx); }
RB_INLINE __m256i load8(const std::uint32_t* p) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)); }
RB_INLINE __m256i load8_aligned(const std::uint32_t* p) { return _mm256_load_si256(reinterpret_cast<const __m256i*>(p)); }
RB_INLINE void store8(std::uint32_t* p, __m256i v) { _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), v); }
RB_INLINE void store8_aligned(std::uint32_t* p, __m256i v) { _mm256_store_si256(reinterpret_cast<__m256i*>(p), v); }

// ---- a group of rays in one register, at either width ----------------------------------------------
// What the packet walk (bvh/walk_packet.hpp) does with a group of rays in lanes, for each width it
// runs at: 8 lanes here, 16 in core/lanes16.hpp (translation units compiled for AVX-512 only). The
// maxima and minima on floats' bits as integers are those of the fast slab test (bvh/slab.hpp).
template <class V>
struct Group;
template <>
struct Group<f8> {
  using mask = f8_mask;
  using ivec = __m256i;
  static constexpr int N = 8;
  static RB_INLINE unsigned bits(const mask& m) { return lanes::bits(m); }
  static RB_INLINE mask of(unsigned b) { return lanes::of(b); }
  static RB_INLINE float hmin(const f8& x) { return lanes::hmin(x); }
  static RB_INLINE float hmax(const f8& x) { return lanes::hmax(x); }
  static RB_INLINE ivec as_int(const f8& x) { return lanes::as_int(x); }
  static RB_INLINE f8 as_float(ivec x) { return lanes::as_float(x); }
  static RB_INLINE ivec int_max(ivec a, ivec b) { return lanes::int_max(a, b); }
  static RB_INLINE ivec int_min(ivec a, ivec b) { return lanes::int_min(a, b); }
  static RB_INLINE unsigned int_le_bits(ivec a, ivec b) { return lanes::int_le_bits(a, b); }
  static RB_INLINE unsigned le_bits(const f8& a, const f8& b) { return lanes::le_bits(a, b); }
};

// ---- 8 floats <-> two halves of 4 doubles --------------------------------------------------------
RB_INLINE d4 lo_d4(const f8& x) { return d4(_mm256_cvtps_pd(_mm256_castps256_ps128(x))); }
RB_INLINE d4 hi_d4(const f8& x) { return d4(_mm256_cvtps_pd(_mm256_extractf128_ps(x, 1))); }
RB_INLINE f8 join_f8(const d4& lo, const d4& hi) { return f8(_mm256_set_m128(_mm256_cvtpd_ps(hi), _mm256_cvtpd_ps(lo))); }

// ---- rays made eight at a time -------------------------------------------------------------------
// make_ray (core/ray.hpp) for eight rays from t = 0 without end, origins and directions in double as
// two 4-lane halves: lane l of the result is make_ray(o[l], d[l]) bit for bit, invalid rays included
// (|d| with the same fused multiply-adds, the same correctly rounded square root and divisions).
// The renderer's eye rays: made one at a time, their square root and six divisions in a row cost
// about as much as tracing them.
RB_INLINE Ray<f8> make_rays(const Vec3<d4> (&o)[2], const Vec3<d4> (&d)[2]) {
  const d4 inf(std::numeric_limits<double>::infinity());
  auto finite = [&](const d4& x) { return vabs(x) < inf; };  // false for NaN
  Vec3<d4> u[2];
  unsigned good = 0;
  for (int h = 0; h < 2; ++h) {
    const d4 len = vsqrt(dot_fma(d[h], d[h]));
    const d4_mask ok = finite(o[h].x) && finite(o[h].y) && finite(o[h].z) && finite(d[h].x) && finite(d[h].y) &&
                       finite(d[h].z) && finite(len) && len > d4(0.0);
    good |= bits(ok) << (4 * h);
    u[h] = {d[h].x / len, d[h].y / len, d[h].z / len};
  }
  auto join = [](const Vec3<d4>& lo, const Vec3<d4>& hi) {
    return Vec3<f8>{join_f8(lo.x, hi.x), join_f8(lo.y, hi.y), join_f8(lo.z, hi.z)};
  };
  const f8_mask valid = of(good);
  const f8 zero(0.0f), one(1.0f), finf(std::numeric_limits<float>::infinity());
  const Vec3<f8> dir = join(u[0], u[1]);
  Ray<f8> r;
  r.o = vselect3(valid, join(o[0], o[1]), Vec3<f8>{zero, zero, zero});
  r.d = vselect3(valid, dir, Vec3<f8>{zero, zero, one});
  r.rd = vselect3(valid, Vec3<f8>{one / dir.x, one / dir.y, one / dir.z}, Vec3<f8>{finf, finf, one});
  r.tmin = vselect(valid, zero, finf);
  r.tmax = vselect(valid, f8(std::numeric_limits<float>::max()), -finf);
  return r;
}

}  // namespace rb::lanes
