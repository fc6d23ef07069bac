// The 8-wide node's box test (bvh/slab.hpp) in one 16-lane AVX-512 register: lanes 0-7 hold the
// distances to the 8 children's near planes of an axis, lanes 8-15 those to their far planes, so an
// axis costs one 16-lane FMA (fast) or subtract and multiply (robust) where the 8-lane test spends
// two. The far half is computed negated (the reciprocal's sign flipped: -t exactly), which turns its
// minimum into a maximum, so one 16-lane maximum per axis folds both halves; the halves meet once
// at the end, the entry distances against the exit distances.
//
//   fast    t = plane * (1/d) - o * (1/d) as in the 8-lane fast form (one FMA), float maxima where
//           that form takes integer ones: the same hit bits and entry distances, except that a zero
//           distance may differ in sign (a far plane at exactly -0 from the origin: the 8-lane
//           integer form counts the box as behind the ray, this one as touched).
//   robust  t = (plane - o) * (1/d), the exit scaled by 1 + 2 gamma(3) and clipped by tmax as in
//           the 8-lane robust form: the same hit bits; entry distances equal as floats.
//
// Measured against the 8-lane test on the same nodes and rays (bench/bench_wide_node.cpp; figures in
// docs/DESIGN.md section 12): the robust form gains a little, the fast form between a small loss
// and a small gain depending on how busy the host's core is (gathering a node's near and far rows
// into one register and splitting the result again costs most of what the halved arithmetic
// saves). The tracer keeps the 8-lane test; this one is the measurement. Only for translation
// units compiled for AVX-512 (RB_SIMD16): its entry points are in bench/simd16_node.cpp.
#pragma once

#include "bvh/slab.hpp"

#ifndef RB_SIMD16
#error "bvh/slab16.hpp needs AVX-512 (F, DQ and BW): include it only in an AVX-512 translation unit"
#endif

#include <immintrin.h>

#include <limits>

namespace rb::bvh {

// One ray for the 16-lane node test. Per axis: 1/d and o * (1/d) with their far halves (lanes
// 8-15) negated, and o; n[a] = 1 where the near plane of axis a is the box's hi.
struct SlabRay16 {
  __m512 rd_signed[3], o_rd_signed[3], o[3];
  float tmin;
  int n[3];
  static RB_INLINE SlabRay16 make(const Ray<float>& r) {
    SlabRay16 x;
    const float rd[3] = {safe_rcp(r.d.x, r.rd.x), safe_rcp(r.d.y, r.rd.y), safe_rcp(r.d.z, r.rd.z)};
    const float o[3] = {r.o.x, r.o.y, r.o.z};
    for (int a = 0; a < 3; ++a) {
      const float ord = o[a] * rd[a];
      x.rd_signed[a] = _mm512_insertf32x8(_mm512_set1_ps(rd[a]), _mm256_set1_ps(-rd[a]), 1);
      x.o_rd_signed[a] = _mm512_insertf32x8(_mm512_set1_ps(ord), _mm256_set1_ps(-ord), 1);
      x.o[a] = _mm512_set1_ps(o[a]);
      x.n[a] = rd[a] < 0;
    }
    x.tmin = r.tmin;
    return x;
  }
};

// The near planes of axis a (lanes 0-7) and its far planes (lanes 8-15): the node keeps lo and hi
// as two rows of 8, so one row is loaded and the other inserted.
RB_INLINE __m512 near_far16(const WNode& nd, int a, int n) {
  return _mm512_insertf32x8(_mm512_castps256_ps512(_mm256_load_ps(nd.b[2 * a + n])), _mm256_load_ps(nd.b[2 * a + 1 - n]), 1);
}

// Bit k set when child k's box meets [tmin, tmax]; tn receives the 8 entry distances (lanes 0-7).
template <bool Robust>
RB_INLINE unsigned slab16(const WNode& nd, const SlabRay16& r, float tmax, f8& tn) {
  if constexpr (!Robust) {
    auto axis = [&](int a) RB_INLINE_LAMBDA {
      return _mm512_fmsub_ps(near_far16(nd, a, r.n[a]), r.rd_signed[a], r.o_rd_signed[a]);
    };
    const __m512 lim = _mm512_insertf32x8(_mm512_set1_ps(r.tmin), _mm256_set1_ps(-tmax), 1);
    const __m512 m = _mm512_max_ps(_mm512_max_ps(axis(0), axis(1)), _mm512_max_ps(axis(2), lim));
    const __m256 entry = _mm512_castps512_ps256(m);
    tn = f8(entry);
    return unsigned(_mm256_cmp_ps_mask(entry, _mm256_xor_ps(_mm512_extractf32x8_ps(m, 1), _mm256_set1_ps(-0.0f)), _CMP_LE_OQ));
  } else {
    auto axis = [&](int a) RB_INLINE_LAMBDA { return _mm512_mul_ps(_mm512_sub_ps(near_far16(nd, a, r.n[a]), r.o[a]), r.rd_signed[a]); };
    const __m512 lim = _mm512_insertf32x8(_mm512_set1_ps(r.tmin), _mm256_set1_ps(-std::numeric_limits<float>::infinity()), 1);
    const __m512 m = _mm512_max_ps(_mm512_max_ps(axis(0), axis(1)), _mm512_max_ps(axis(2), lim));
    const __m256 entry = _mm512_castps512_ps256(m);
    const __m256 exit = _mm256_min_ps(_mm256_mul_ps(_mm256_xor_ps(_mm512_extractf32x8_ps(m, 1), _mm256_set1_ps(-0.0f)), _mm256_set1_ps(kRobustScale)),
                                      _mm256_set1_ps(tmax));
    tn = f8(entry);
    return unsigned(_mm256_cmp_ps_mask(entry, exit, _CMP_LE_OQ));
  }
}

}  // namespace rb::bvh
