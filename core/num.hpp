// The number-type layer: every kernel is written once over a number type F and calls only the
// functions in this header (vmin, vmax, vselect, vsqrt, vabs, vfma, any_of, all_of, none_of,
// mask_xor, lane, load, ...). Each supported type is described once, by a specialisation of num<F>.
//
// Supported: float, double, the 8-lane float batch (AVX2+FMA), the 4-lane double batch, and
// Counted<T> over each of those (core/counted.hpp); in translation units compiled for AVX-512
// (RB_SIMD16: bench/bench_*_simd16.cpp) also the 16-lane float and 8-lane double batches.
//
// Names are deliberately not min/max/select/any/all: unqualified calls on xsimd batches would
// find xsimd's overloads by argument-dependent lookup and the result would depend on include
// order (docs/DESIGN.md section 3).
#pragma once

#if defined(__AVX512F__) && defined(__AVX512DQ__) && defined(__AVX512BW__)
#define RB_SIMD16 1
#include "core/xsimd_avx512_fma.hpp"  // before xsimd: a fused fma for its AVX-512 batches
#endif
#include <xsimd/xsimd.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

// Inlining policy. Forced inlining pays only in the timed benchmark loops, where a kernel must become
// one straight-line body inside the loop: the benchmark translation units define RB_FORCE_INLINE
// (bench/CMakeLists.txt) and there RB_INLINE forces every kernel and number-layer function inline.
// Everywhere else (the ops table's Counted copies, the tests, `raybench query`, the sanitizer build)
// the compiler decides: forcing whole solver kernels and their root isolation inline there only
// multiplied compile time (a test file under ASan took over 16 minutes) and changes no result the
// tests check.
#if defined(RB_FORCE_INLINE) && !defined(RB_SANITIZE)
#define RB_INLINE inline __attribute__((always_inline))
#define RB_INLINE_LAMBDA __attribute__((always_inline))  // after a lambda's parameter list
#else
#define RB_INLINE inline
#define RB_INLINE_LAMBDA
#endif

namespace rb {

// Pinned, never default_arch: that becomes 16 lanes on an AVX-512 host.
using simd_arch = xsimd::fma3<xsimd::avx2>;
using f8 = xsimd::batch<float, simd_arch>;
using d4 = xsimd::batch<double, simd_arch>;
using f8_mask = xsimd::batch_bool<float, simd_arch>;
using d4_mask = xsimd::batch_bool<double, simd_arch>;
// Alignment of SIMD data: a 16-lane float load (64 bytes) is aligned in every container.
inline constexpr std::size_t kSimdAlign = 64;
#ifdef RB_SIMD16
// AVX-512: xsimd's avx512dq batch (compiled with F, CD, DQ, BW and VL: 8.1 declares the avx512cd
// and avx512dq registers only with BW; not its avx512bw batch, whose integer select does not
// compile at -O0).
using simd16_arch = xsimd::avx512dq;
using f16 = xsimd::batch<float, simd16_arch>;
using d8 = xsimd::batch<double, simd16_arch>;
#endif

template <class F>
struct num;  // one specialisation per number type

// ---- plain IEEE scalars ---------------------------------------------------------------------
template <class T>
struct scalar_num {
  using type = T;
  using scalar = T;  // the IEEE type of one lane
  using mask = bool;
  static constexpr int lanes = 1;
  // a < b ? a : b, the semantics of minps/maxps: a NaN in the first argument yields the second.
  // (std::min and xsimd 8.1's scalar min differ: docs/DESIGN.md section 6.) With AVX these are the
  // minss/maxss instructions themselves: from the expression, a profile-guided build compiled the
  // scalar kernels' min/max as compares and conditional jumps, which mispredict on rays that go
  // either way (docs/DESIGN.md section 11).
  static RB_INLINE T min(T a, T b) {
#if defined(__AVX__) && defined(__GNUC__)
    if constexpr (std::is_same_v<T, float>) asm("vminss %2, %1, %0" : "=x"(a) : "x"(a), "x"(b));
    else if constexpr (std::is_same_v<T, double>) asm("vminsd %2, %1, %0" : "=x"(a) : "x"(a), "x"(b));
    else a = a < b ? a : b;
    return a;
#else
    return a < b ? a : b;
#endif
  }
  static RB_INLINE T max(T a, T b) {
#if defined(__AVX__) && defined(__GNUC__)
    if constexpr (std::is_same_v<T, float>) asm("vmaxss %2, %1, %0" : "=x"(a) : "x"(a), "x"(b));
    else if constexpr (std::is_same_v<T, double>) asm("vmaxsd %2, %1, %0" : "=x"(a) : "x"(a), "x"(b));
    else a = a > b ? a : b;
    return a;
#else
    return a > b ? a : b;
#endif
  }
  static RB_INLINE T select(bool m, T a, T b) { return m ? a : b; }
  static RB_INLINE T sqrt(T a) { return std::sqrt(a); }
  static RB_INLINE T abs(T a) { return std::fabs(a); }
  static RB_INLINE T fma(T a, T b, T c) { return std::fma(a, b, c); }
  static RB_INLINE T copysign(T a, T b) { return std::copysign(a, b); }
  // The value itself, through an empty asm that claims to modify it in its register: the compiler
  // can no longer fuse the operation that produced it into a following add (FMA contraction).
  static RB_INLINE T rounded(T a) {
    asm("" : "+x"(a));
    return a;
  }
  // Transcendentals (implicit surfaces, closed-form cubic/quartic roots, [u,v] angles).
  static RB_INLINE T sin(T a) { return std::sin(a); }
  static RB_INLINE T cos(T a) { return std::cos(a); }
  static RB_INLINE T acos(T a) { return std::acos(a); }
  static RB_INLINE T atan2(T a, T b) { return std::atan2(a, b); }
  static RB_INLINE T cbrt(T a) { return std::cbrt(a); }
  static RB_INLINE bool any(bool m) { return m; }
  static RB_INLINE bool all(bool m) { return m; }
  static RB_INLINE bool mnot(bool m) { return !m; }
  static RB_INLINE bool mconst(bool b) { return b; }
  static RB_INLINE bool lane_mask(bool m, int) { return m; }
  static RB_INLINE int count(bool m) { return m ? 1 : 0; }
  static RB_INLINE T lane(T v, int) { return v; }
  template <class S>
  static RB_INLINE T load(const S* p) { return static_cast<T>(*p); }
  template <class S>
  static RB_INLINE void store(S* p, T v) { *p = static_cast<S>(v); }
};
template <> struct num<float> : scalar_num<float> { static constexpr const char* name = "float"; };
template <> struct num<double> : scalar_num<double> { static constexpr const char* name = "double"; };

// ---- xsimd batches (AVX2 + FMA, pinned; AVX-512 where compiled for it) ----------------------------
template <class T, class Arch = simd_arch>
struct batch_num {
  using type = xsimd::batch<T, Arch>;
  using scalar = T;
  using mask = xsimd::batch_bool<T, Arch>;
  static constexpr int lanes = static_cast<int>(type::size);
  static constexpr bool wide = sizeof(type) == 64;  // AVX-512: masks are k registers
  static RB_INLINE type min(const type& a, const type& b) { return xsimd::min(a, b); }
  static RB_INLINE type max(const type& a, const type& b) { return xsimd::max(a, b); }
  static RB_INLINE type select(const mask& m, const type& a, const type& b) { return xsimd::select(m, a, b); }
  static RB_INLINE type sqrt(const type& a) { return xsimd::sqrt(a); }
  static RB_INLINE type abs(const type& a) { return xsimd::abs(a); }
  static RB_INLINE type fma(const type& a, const type& b, const type& c) { return xsimd::fma(a, b, c); }
  static RB_INLINE type copysign(const type& a, const type& b) { return xsimd::copysign(a, b); }
  static RB_INLINE type rounded(const type& a) {
    typename type::register_type v = a;
    if constexpr (wide) asm("" : "+v"(v));
    else asm("" : "+x"(v));
    return type(v);
  }
  static RB_INLINE type sin(const type& a) { return xsimd::sin(a); }
  static RB_INLINE type cos(const type& a) { return xsimd::cos(a); }
  static RB_INLINE type acos(const type& a) { return xsimd::acos(a); }
  static RB_INLINE type atan2(const type& a, const type& b) { return xsimd::atan2(a, b); }
  static RB_INLINE type cbrt(const type& a) { return xsimd::cbrt(a); }
  static RB_INLINE bool any(const mask& m) { return xsimd::any(m); }
  static RB_INLINE bool all(const mask& m) { return xsimd::all(m); }
  static RB_INLINE mask mnot(const mask& m) { return ~m; }
  static RB_INLINE mask mconst(bool b) { return mask(b); }
  static RB_INLINE int count(const mask& m) {  // set lanes: movemask (or the k register) + popcount
    if constexpr (wide) return __builtin_popcount(unsigned(typename mask::register_type(m)));
    else if constexpr (std::is_same_v<T, float>) return __builtin_popcount(unsigned(_mm256_movemask_ps(m)));
    else return __builtin_popcount(unsigned(_mm256_movemask_pd(m)));
  }
  static RB_INLINE bool lane_mask(const mask& m, int i) {
    if constexpr (wide) {
      return (unsigned(typename mask::register_type(m)) >> i) & 1u;
    } else {
      alignas(kSimdAlign) bool b[type::size];
      m.store_unaligned(b);
      return b[i];
    }
  }
  static RB_INLINE T lane(const type& v, int i) {
    alignas(kSimdAlign) T b[type::size];
    v.store_aligned(b);
    return b[i];
  }
  // Loads `lanes` consecutive values. Same type: an aligned load (the SoA containers align every
  // lane group to its width: kSimdAlign). Float data into a double batch: converted lane by lane.
  template <class S>
  static RB_INLINE type load(const S* p) {
    if constexpr (std::is_same_v<S, T>) {
      return type::load_aligned(p);
    } else {
      alignas(kSimdAlign) T b[type::size];
      for (std::size_t i = 0; i < type::size; ++i) b[i] = static_cast<T>(p[i]);
      return type::load_aligned(b);
    }
  }
  template <class S>
  static RB_INLINE void store(S* p, const type& v) {
    if constexpr (std::is_same_v<S, T>) {
      v.store_aligned(p);
    } else {
      alignas(kSimdAlign) T b[type::size];
      v.store_aligned(b);
      for (std::size_t i = 0; i < type::size; ++i) p[i] = static_cast<S>(b[i]);
    }
  }
};
template <> struct num<f8> : batch_num<float> { static constexpr const char* name = "simd8"; };
template <> struct num<d4> : batch_num<double> { static constexpr const char* name = "simd4d"; };
#ifdef RB_SIMD16
template <> struct num<f16> : batch_num<float, simd16_arch> { static constexpr const char* name = "simd16"; };
template <> struct num<d8> : batch_num<double, simd16_arch> { static constexpr const char* name = "simd8d"; };
#endif

// ---- the functions kernels call ---------------------------------------------------------------
template <class F> using mask_t = typename num<F>::mask;
template <class F> using scalar_t = typename num<F>::scalar;
template <class F> inline constexpr int lanes_v = num<F>::lanes;

template <class F> RB_INLINE F vmin(const F& a, const F& b) { return num<F>::min(a, b); }
template <class F> RB_INLINE F vmax(const F& a, const F& b) { return num<F>::max(a, b); }
template <class F> RB_INLINE F vselect(const mask_t<F>& m, const F& a, const F& b) { return num<F>::select(m, a, b); }
template <class F> RB_INLINE F vsqrt(const F& a) { return num<F>::sqrt(a); }
template <class F> RB_INLINE F vabs(const F& a) { return num<F>::abs(a); }
template <class F> RB_INLINE F vfma(const F& a, const F& b, const F& c) { return num<F>::fma(a, b, c); }
template <class F> RB_INLINE F vcopysign(const F& a, const F& b) { return num<F>::copysign(a, b); }
// a, as a separately rounded value: under -ffp-contract=fast, vrounded(a * b) - vrounded(c * d)
// rounds both products and then the difference (no FMA), so swapping the operand pairs negates
// the result exactly. Free (no instruction; not counted). For exact sign tests that must agree
// between two evaluations (shared triangle edges).
template <class F> RB_INLINE F vrounded(const F& a) { return num<F>::rounded(a); }
// Transcendentals: xsimd's vectorised sin/cos/acos/atan2/cbrt are not bit-identical to libm, so
// a SIMD lane may differ from the scalar result by a few ulps wherever these are used.
template <class F> RB_INLINE F vsin(const F& a) { return num<F>::sin(a); }
template <class F> RB_INLINE F vcos(const F& a) { return num<F>::cos(a); }
template <class F> RB_INLINE F vacos(const F& a) { return num<F>::acos(a); }
template <class F> RB_INLINE F vatan2(const F& y, const F& x) { return num<F>::atan2(y, x); }
template <class F> RB_INLINE F vcbrt(const F& a) { return num<F>::cbrt(a); }
template <class F> RB_INLINE F vclamp(const F& x, const F& lo, const F& hi) { return vmin(vmax(x, lo), hi); }
template <class F> RB_INLINE bool any_of(const mask_t<F>& m) { return num<F>::any(m); }
template <class F> RB_INLINE bool all_of(const mask_t<F>& m) { return num<F>::all(m); }
template <class F> RB_INLINE bool none_of(const mask_t<F>& m) { return !num<F>::any(m); }
template <class F> RB_INLINE mask_t<F> mask_not(const mask_t<F>& m) { return num<F>::mnot(m); }
template <class F> RB_INLINE mask_t<F> mask_xor(const mask_t<F>& a, const mask_t<F>& b) {
  return (a & mask_not<F>(b)) | (mask_not<F>(a) & b);
}
template <class F> RB_INLINE scalar_t<F> lane(const F& v, int i) { return num<F>::lane(v, i); }
template <class F> RB_INLINE bool lane_mask(const mask_t<F>& m, int i) { return num<F>::lane_mask(m, i); }
template <class F> RB_INLINE int count_true(const mask_t<F>& m) { return num<F>::count(m); }
template <class F, class S> RB_INLINE F load(const S* p) { return num<F>::load(p); }
template <class F, class S> RB_INLINE void store(S* p, const F& v) { num<F>::store(p, v); }
// A mask with every lane set / clear (free: no comparison is counted).
template <class F> RB_INLINE mask_t<F> mask_true() { return num<F>::mconst(true); }
template <class F> RB_INLINE mask_t<F> mask_false() { return num<F>::mconst(false); }

template <class F> inline constexpr scalar_t<F> kInf = std::numeric_limits<scalar_t<F>>::infinity();

// Whether all lanes of two values are identical bit patterns (NaNs included): the test of
// "scalar == SIMD bit for bit".
template <class S>
inline bool same_bits(S a, S b) {
  static_assert(std::is_floating_point_v<S>);
  return std::memcmp(&a, &b, sizeof(S)) == 0;
}

}  // namespace rb
