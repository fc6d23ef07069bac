// A fused multiply-add for xsimd 8.1's AVX-512 batches, included by core/num.hpp before xsimd in
// translation units compiled for AVX-512. xsimd 8.1 has no AVX-512 fma kernel: its generic one
// computes x * y + z, which rounds twice where the 8-lane AVX2 code (fma3) rounds once, so the
// kernels (vfma) and xsimd's own sin, cos and cbrt would give other results in 16 lanes than in 8
// (docs/DESIGN.md section 9). Declared before xsimd's API so that its calls
// kernel::fma(x, y, z, A{}) find it; defined after.
#pragma once

#include <immintrin.h>

namespace xsimd {
template <class T, class A>
class batch;
struct avx512f;
namespace kernel {
template <class A>
batch<float, A> fma(batch<float, A> const& x, batch<float, A> const& y, batch<float, A> const& z, avx512f const&) noexcept;
template <class A>
batch<double, A> fma(batch<double, A> const& x, batch<double, A> const& y, batch<double, A> const& z, avx512f const&) noexcept;
}  // namespace kernel
}  // namespace xsimd

#include <xsimd/xsimd.hpp>

namespace xsimd::kernel {
template <class A>
inline batch<float, A> fma(batch<float, A> const& x, batch<float, A> const& y, batch<float, A> const& z, avx512f const&) noexcept {
  return _mm512_fmadd_ps(x, y, z);
}
template <class A>
inline batch<double, A> fma(batch<double, A> const& x, batch<double, A> const& y, batch<double, A> const& z, avx512f const&) noexcept {
  return _mm512_fmadd_pd(x, y, z);
}
}  // namespace xsimd::kernel
