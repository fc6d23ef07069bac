// Ray x plane with the [u,v] inverse mapping, and ray x parallelogram (seed 000 "Inverse
// transformation on the plane", "Parallelogram").
//   plane: PI(u,v) = PI0 + u U + v V, n = U x V;  t = -(n . P0 + D) / (n . p1)
//   [u,v]: the 2x2 system of two coordinates of P(t) - PI0 = u U + v V. The slide uses x and y;
//     here the two coordinates kept are the ones that drop the dominant axis of n, so the system
//     is never singular for a non-degenerate frame (the same choice as the lecture triangle).
//   parallelogram R(u,v) = R0 + u U + v V, hit iff 0 <= u, v <= 1 (4 comparisons).
// Both use the TriLecture data of kernels/triangle.hpp (n, D, R0/U/V on the two kept axes,
// the 2x2 determinant precomputed per primitive) and TriLectureSoA's grouping by dropped axis,
// so the axis is uniform over any aligned lane group: the same kernel runs rays in lanes
// (one primitive broadcast) and primitives in lanes (8 primitives of one axis group).
// Lecture counts: [u,v] solve 5+- 5* 2/; plane positive case 5+- 6* 1/; point 3+- 3*;
// parallelogram positive case total 13+- 14* 3/ 4<=.
#pragma once

#include "kernels/triangle.hpp"

namespace rb {

// The lecture data of the frame (PI0, U, V): make_lecture_frame (kernels/triangle.hpp).
template <class T>
inline TriLecture<float> make_plane_uv(Vec3<T> pi0, Vec3<T> u_dir, Vec3<T> v_dir, int& axis, std::string* why = nullptr) {
  return make_lecture_frame(to_double(pi0), to_double(u_dir), to_double(v_dir), axis, why);
}

// [u,v] of a point on the plane: the slide's "inverse transformation on the plane" with the
// determinant precomputed: 2+- (P - PI0) + 2x (1+- 2*) + 2/  =  4+- 4* 2/.
template <class F>
RB_INLINE void plane_uv_solve(const TriLecture<F>& q, const F& pa, const F& pb, F& u, F& v) {
  const F dx = pa - q.r0a, dy = pb - q.r0b;        // 2+-
  u = (dx * q.vb - dy * q.va) / q.det;             // 1+- 2* 1/
  v = (q.ua * dy - q.ub * dx) / q.det;             // 1+- 2* 1/
}

// [u,v] of a 3D point (the two kept coordinates are read, the dropped one is ignored).
template <class F>
RB_INLINE void plane_uv_of_point(const TriLecture<F>& q, int axis, const Vec3<F>& p, F& u, F& v) {
  plane_uv_solve(q, p[(axis + 1) % 3], p[(axis + 2) % 3], u, v);
}

namespace detail {
// Plane hit and [u,v]; returns false when every lane has already missed (early exit).
template <class F>
RB_INLINE bool plane_uv_core(const Ray<F>& r, const TriLecture<F>& q, int axis, mask_t<F>& m, F& t, F& u, F& v) {
  const F den = dot(q.n, r.d);                      // 2+- 3*
  m = den != F(0);                                  // 1 cmp  (negative case: parallel ray)
  if (none_of<F>(m)) return false;
  t = -(dot(q.n, r.o) + q.D) / den;                 // 3+- 3* 1/
  m = m & (t >= r.tmin) & (t <= r.tmax);            // 2 cmp
  if (none_of<F>(m)) return false;
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const F pa = r.o[a] + r.d[a] * t;                 // the two kept coordinates of [x,y,z]: 2+- 2*
  const F pb = r.o[b] + r.d[b] * t;
  plane_uv_solve(q, pa, pb, u, v);                  // 4+- 4* 2/
  return true;
}
}  // namespace detail

// Infinite plane with its [u,v] coordinates (u, v unbounded). Two-sided.
template <class F>
RB_INLINE Hit<F> intersect_plane_uv(const Ray<F>& r, const TriLecture<F>& q, int axis) {
  mask_t<F> m;
  F t, u, v;
  if (!detail::plane_uv_core(r, q, axis, m, t, u, v)) return miss_hit<F>();
  return make_hit<F>(m, t, u, v);                   // 1 select
}

// Parallelogram R0 + u U + v V, 0 <= u, v <= 1. Two-sided.
template <class F>
RB_INLINE Hit<F> intersect_parallelogram(const Ray<F>& r, const TriLecture<F>& q, int axis) {
  mask_t<F> m;
  F t, u, v;
  if (!detail::plane_uv_core(r, q, axis, m, t, u, v)) return miss_hit<F>();
  m = m & (u >= F(0)) & (u <= F(1)) & (v >= F(0)) & (v <= F(1));  // 4 cmp
  return make_hit<F>(m, t, u, v);                   // 1 select
}

// The parallelogram with corner R0 and adjacent corners R0 + U, R0 + V (the fourth is
// R0 + U + V): the lecture data of the triangle (R0, R0 + U, R0 + V).
template <class T>
inline TriLecture<float> make_parallelogram(Vec3<T> r0, Vec3<T> u_dir, Vec3<T> v_dir, int& axis, std::string* why = nullptr) {
  return make_plane_uv(r0, u_dir, v_dir, axis, why);
}

// Normal: triangle_normal(TriLecture) in kernels/triangle.hpp (n = U x V, not normalised).

}  // namespace rb
