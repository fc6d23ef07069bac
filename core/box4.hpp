// The BVH builder's box: x, y, z in lanes 0-2 of two 4-lane SSE registers (lane 3 free for a tag
// the builder keeps there, such as a primitive's index), so that growing a box by another or by a
// point is one minimum and one maximum, and binning a centroid is one subtract, multiply and
// convert for all three axes. The builder (bvh/build.cpp) uses these instead of raw intrinsics.
#pragma once

#include <immintrin.h>

#include <array>
#include <cstdint>
#include <limits>

namespace rb {

// Four floats x, y, z, w.
inline __m128 f4(float x, float y, float z, float w = 0.f) { return _mm_setr_ps(x, y, z, w); }

// Lane `k` of v (0-3) by a variable permute: through memory a read waited on the store each time.
inline float lane4(__m128 v, int k) { return _mm_cvtss_f32(_mm_permutevar_ps(v, _mm_set1_epi32(k))); }

struct Box4 {
  __m128 lo = _mm_set1_ps(std::numeric_limits<float>::infinity()), hi = _mm_set1_ps(-std::numeric_limits<float>::infinity());

  // The box from lo[0..2] and hi[0..2], with `tag` in the low corner's fourth lane.
  static Box4 of(const float* l, const float* h, std::uint32_t tag) {
    Box4 b;
    b.lo = _mm_castsi128_ps(_mm_insert_epi32(_mm_castps_si128(f4(l[0], l[1], l[2])), int(tag), 3));
    b.hi = f4(h[0], h[1], h[2]);
    return b;
  }
  std::uint32_t tag() const { return std::uint32_t(_mm_cvtsi128_si32(_mm_castps_si128(_mm_shuffle_ps(lo, lo, 3)))); }

  void grow(const Box4& b) { lo = _mm_min_ps(lo, b.lo); hi = _mm_max_ps(hi, b.hi); }
  void grow(__m128 p) { lo = _mm_min_ps(lo, p); hi = _mm_max_ps(hi, p); }
  // A corner's coordinate k through memory (the builder reads all three of a node's at once, where
  // the store is paid once; lane4 is for a single read).
  float l(int k) const { alignas(16) float v[4]; _mm_store_ps(v, lo); return v[k]; }
  float h(int k) const { alignas(16) float v[4]; _mm_store_ps(v, hi); return v[k]; }
  // Twice the centre (lo + hi): where only the order of centres or their bins matter, the halving
  // cancels.
  __m128 centre2() const { return _mm_add_ps(lo, hi); }
  // The surface area; 0 for an empty box (lo above hi on x).
  float area() const {
    alignas(16) float d[4];
    _mm_store_ps(d, _mm_sub_ps(hi, lo));
    if (!(d[0] >= 0)) return 0.f;
    return 2.f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
  }
  // Lanes 0-2 finite (x - x == 0 fails for inf and NaN) and lo <= hi.
  bool usable() const {
    const __m128 zero = _mm_setzero_ps();
    const __m128 ok = _mm_and_ps(_mm_and_ps(_mm_cmpeq_ps(_mm_sub_ps(lo, lo), zero), _mm_cmpeq_ps(_mm_sub_ps(hi, hi), zero)), _mm_cmple_ps(lo, hi));
    return (_mm_movemask_ps(ok) & 7) == 7;
  }
};

// The bins of point p per axis: int((p - lo) * scale), clamped to [0, nb - 1] (lanes 0-2 used).
inline std::array<int, 4> bins4(__m128 p, __m128 lo, __m128 scale, int nb) {
  const __m128i b = _mm_min_epi32(_mm_max_epi32(_mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(p, lo), scale)), _mm_setzero_si128()),
                                  _mm_set1_epi32(nb - 1));
  alignas(16) std::array<int, 4> out;
  _mm_store_si128(reinterpret_cast<__m128i*>(out.data()), b);
  return out;
}

}  // namespace rb
