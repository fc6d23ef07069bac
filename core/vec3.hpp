// Vec3<F>: three numbers of type F (a point or a direction, one lane or eight).
#pragma once

#include "core/num.hpp"

#include <cmath>
#include <cstddef>

namespace rb {

template <class F>
struct Vec3 {
  F x, y, z;

  // Lane-wise broadcast of a float vector into any number type.
  template <class G>
  static RB_INLINE Vec3 from(const Vec3<G>& v) { return {F(v.x), F(v.y), F(v.z)}; }
  RB_INLINE F operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

using Vec3f = Vec3<float>;
using Vec3d = Vec3<double>;

template <class F> RB_INLINE Vec3<F> operator+(const Vec3<F>& a, const Vec3<F>& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class F> RB_INLINE Vec3<F> operator-(const Vec3<F>& a, const Vec3<F>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class F> RB_INLINE Vec3<F> operator-(const Vec3<F>& a) { return {-a.x, -a.y, -a.z}; }
template <class F> RB_INLINE Vec3<F> operator*(const Vec3<F>& a, const F& s) { return {a.x * s, a.y * s, a.z * s}; }
template <class F> RB_INLINE Vec3<F> operator*(const F& s, const Vec3<F>& a) { return {s * a.x, s * a.y, s * a.z}; }
template <class F> RB_INLINE F dot(const Vec3<F>& a, const Vec3<F>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
// The dot product with each product rounded on its own (vrounded): no FMA contraction, so the
// scalar and every SIMD instantiation give the same bits under any -ffp-contract. The same
// operation count as dot.
template <class F> RB_INLINE F dot_rounded(const Vec3<F>& a, const Vec3<F>& b) {
  return vrounded(a.x * b.x) + vrounded(a.y * b.y) + vrounded(a.z * b.z);
}
// The dot product with its fused multiply-adds spelled out, fma(a.z, b.z, fma(a.y, b.y, a.x b.x)):
// the same bits in every instantiation under any -ffp-contract (the compiler fuses scalar and SIMD
// expressions differently). The same operation count as dot.
template <class F> RB_INLINE F dot_fma(const Vec3<F>& a, const Vec3<F>& b) {
  return vfma(a.z, b.z, vfma(a.y, b.y, a.x * b.x));
}
template <class F> RB_INLINE Vec3<F> cross(const Vec3<F>& a, const Vec3<F>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class F> RB_INLINE Vec3<F> vmin3(const Vec3<F>& a, const Vec3<F>& b) { return {vmin(a.x, b.x), vmin(a.y, b.y), vmin(a.z, b.z)}; }
template <class F> RB_INLINE Vec3<F> vmax3(const Vec3<F>& a, const Vec3<F>& b) { return {vmax(a.x, b.x), vmax(a.y, b.y), vmax(a.z, b.z)}; }
template <class F> RB_INLINE Vec3<F> vselect3(const mask_t<F>& m, const Vec3<F>& a, const Vec3<F>& b) {
  return {vselect(m, a.x, b.x), vselect(m, a.y, b.y), vselect(m, a.z, b.z)};
}
template <class F> RB_INLINE F length(const Vec3<F>& a) { return vsqrt(dot(a, a)); }
template <class F> RB_INLINE Vec3<F> normalize(const Vec3<F>& a) { return a * (F(1) / length(a)); }

// Construction-time helpers (float/double only: never in kernels).
template <class T> inline bool finite3(const Vec3<T>& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
template <class T> inline Vec3d to_double(const Vec3<T>& a) { return {double(a.x), double(a.y), double(a.z)}; }
inline Vec3f to_float(const Vec3d& a) { return {float(a.x), float(a.y), float(a.z)}; }
// Newell's normal of the closed polygon p[0], ..., p[n-1], in double and not normalised: twice its
// vector area, for either winding, robust to collinear runs and slightly non-planar input. Zero
// when the polygon has no area.
template <class T>
inline Vec3d newell_normal(const Vec3<T>* p, std::size_t n) {
  Vec3d nn{0, 0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3d a = to_double(p[i]), b = to_double(p[(i + 1) % n]);
    nn.x += (a.y - b.y) * (a.z + b.z);
    nn.y += (a.z - b.z) * (a.x + b.x);
    nn.z += (a.x - b.x) * (a.y + b.y);
  }
  return nn;
}
// The axis (0, 1, 2) of the largest |component| of n, x before y before z on ties: the axis a
// planar figure with normal n is projected along so that its projection keeps the most area.
inline int dominant_axis(const Vec3d& n) {
  const double ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
  return ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
}
template <class F> RB_INLINE Vec3<scalar_t<F>> lane3(const Vec3<F>& v, int i) { return {lane(v.x, i), lane(v.y, i), lane(v.z, i)}; }

}  // namespace rb
