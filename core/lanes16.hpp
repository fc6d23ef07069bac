// The lane operations of core/lanes.hpp for a group of 16 rays in one AVX-512 register (Group<f16>),
// and the halves of such a group as two 8-lane groups. Only for translation units compiled for
// AVX-512 (RB_SIMD16): the 16-ray packet walk (tracer/traverse_mesh16.cpp).
#pragma once

#include "core/lanes.hpp"

#ifndef RB_SIMD16
#error "core/lanes16.hpp needs AVX-512 (F, DQ and BW): include it only in an AVX-512 translation unit"
#endif

namespace rb::lanes {

using f16_mask = xsimd::batch_bool<float, simd16_arch>;

template <>
struct Group<f16> {
  using mask = f16_mask;
  using ivec = __m512i;
  static constexpr int N = 16;
  static RB_INLINE unsigned bits(const mask& m) { return unsigned(__mmask16(m)); }
  static RB_INLINE mask of(unsigned b) { return mask(__mmask16(b)); }
  static RB_INLINE float hmin(const f16& x) { return _mm512_reduce_min_ps(x); }
  static RB_INLINE float hmax(const f16& x) { return _mm512_reduce_max_ps(x); }
  static RB_INLINE ivec as_int(const f16& x) { return _mm512_castps_si512(x); }
  static RB_INLINE f16 as_float(ivec x) { return f16(_mm512_castsi512_ps(x)); }
  static RB_INLINE ivec int_max(ivec a, ivec b) { return _mm512_max_epi32(a, b); }
  static RB_INLINE ivec int_min(ivec a, ivec b) { return _mm512_min_epi32(a, b); }
  static RB_INLINE unsigned int_le_bits(ivec a, ivec b) { return unsigned(_mm512_cmple_epi32_mask(a, b)); }
  static RB_INLINE unsigned le_bits(const f16& a, const f16& b) { return unsigned(_mm512_cmp_ps_mask(a, b, _CMP_LE_OQ)); }
  // Lanes 0-7 (h = 0) or 8-15 (h = 1) as an 8-lane group, and the group made of two such halves.
  static RB_INLINE f8 half(const f16& x, int h) { return f8(h ? _mm512_extractf32x8_ps(x, 1) : _mm512_castps512_ps256(x)); }
  static RB_INLINE f16 join(const f8& lo, const f8& hi) { return f16(_mm512_insertf32x8(_mm512_castps256_ps512(lo), hi, 1)); }
  // The same 8 lanes in both halves (one broadcast; from memory, one load).
  static RB_INLINE f16 twice(const f8& x) { return f16(_mm512_broadcast_f32x8(x)); }
};

}  // namespace rb::lanes
