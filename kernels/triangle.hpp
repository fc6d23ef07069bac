// Ray x triangle.
//   lecture (seed 000 "Triangle"): R(u,v) = R0 + u U + v V, 0 <= u, v, u + v <= 1. The plane
//     n = U x V, D = -n . R0 is intersected (t), the point [x,y,z] found, and [u,v] solved from
//     the 2x2 system of the two coordinates that drop the dominant axis of n ("inverse
//     transformation on the plane"). Lecture positive case: 14+- 14* 3/ 3<=.
//     The dropped axis is a per-primitive constant; batches group primitives by it so it is
//     uniform over the lanes of a SIMD call (TriLectureSoA).
//   Moller-Trumbore (1997): the same system by Cramer's rule with the triple products shared.
// Both are two-sided and return [u,v] (the barycentric coordinates of v1 and v2).
#pragma once

#include "core/ray.hpp"
#include "core/why.hpp"
#include "soa/axis_grouped.hpp"

#include <algorithm>
#include <vector>

namespace rb {

// ---- lecture method ---------------------------------------------------------------------------
template <class F>
struct TriLecture {
  Vec3<F> n;               // U x V (not normalised)
  F D;                     // -n . R0
  F r0a, r0b, ua, ub, va, vb, det;  // R0, U, V projected on the two kept axes; det = ua vb - va ub
  auto fields() { return std::tie(n.x, n.y, n.z, D, r0a, r0b, ua, ub, va, vb, det); }
  static TriLecture never() { return {{F(0), F(0), F(0)}, F(0), F(0), F(0), F(0), F(0), F(0), F(0), F(1)}; }
};

// The lecture data of the frame R0 + u U + v V (triangle, parallelogram, plane with [u,v]): the
// dropped axis is dominant_axis(n) (core/vec3.hpp). Zero area (U x V == 0, also after rounding
// to float), non-finite input, or n, D or the determinant not representable in float:
// TriLecture::never() (n = 0: parallel to every ray), axis 2, the reason in *why. `axis` receives
// the dropped axis.
inline TriLecture<float> make_lecture_frame(const Vec3d& R0, const Vec3d& U, const Vec3d& V, int& axis,
                                            std::string* why = nullptr) {
  using L = TriLecture<float>;
  const Vec3d n = cross(U, V);
  axis = 2;
  if (!finite3(R0) || !finite3(U) || !finite3(V) || !finite3(n)) return never_because<L>(why, "frame: a vertex or edge is not finite");
  if (dot(n, n) == 0.0) return never_because<L>(why, "frame: zero area (the edges are parallel)");
  const int ax = dominant_axis(n);
  const int a = (ax + 1) % 3, b = (ax + 2) % 3;
  TriLecture<float> t;
  t.n = to_float(n);
  t.D = float(-dot(n, R0));
  t.r0a = float(R0[a]); t.r0b = float(R0[b]);
  t.ua = float(U[a]); t.ub = float(U[b]); t.va = float(V[a]); t.vb = float(V[b]);
  const double det = double(t.ua) * double(t.vb) - double(t.va) * double(t.ub);
  if (!std::isfinite(t.D) || !finite3(t.n) || dot(to_double(t.n), to_double(t.n)) == 0.0 || det == 0.0 ||
      !std::isfinite(float(det)) || float(det) == 0.f)
    return never_because<L>(why, "frame: normal, offset or determinant not representable in float");
  t.det = float(det);
  axis = ax;
  return t;
}

// The lecture form of triangle (v0, v1, v2) (parallelogram: same data, different test).
template <class T>
inline TriLecture<float> make_tri_lecture(Vec3<T> v0, Vec3<T> v1, Vec3<T> v2, int& axis, std::string* why = nullptr) {
  const Vec3d R0 = to_double(v0);
  return make_lecture_frame(R0, to_double(v1) - R0, to_double(v2) - R0, axis, why);
}

template <class F>
RB_INLINE Hit<F> intersect_triangle_lecture(const Ray<F>& r, const TriLecture<F>& q, int axis) {
  const F den = dot(q.n, r.d);                      // 2+- 3*
  mask_t<F> m = den != F(0);                        // 1 cmp
  if (none_of<F>(m)) return miss_hit<F>();
  const F t = -(dot(q.n, r.o) + q.D) / den;         // 3+- 3* 1/
  m = m & (t >= r.tmin) & (t <= r.tmax);            // 2 cmp
  if (none_of<F>(m)) return miss_hit<F>();
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const F pa = r.o[a] + r.d[a] * t;                 // the two kept coordinates of [x,y,z]: 2+- 2*
  const F pb = r.o[b] + r.d[b] * t;
  const F dx = pa - q.r0a, dy = pb - q.r0b;         // 2+-
  const F u = (dx * q.vb - dy * q.va) / q.det;      // 1+- 2* 1/
  const F v = (q.ua * dy - q.ub * dx) / q.det;      // 1+- 2* 1/
  m = m & (u >= F(0)) & (v >= F(0)) & (u + v <= F(1));  // 1+- 3 cmp
  return make_hit<F>(m, t, u, v);                   // 1 select
}

// Batch of lecture triangles grouped by dropped axis (soa/axis_grouped.hpp), so that
// `axis_of(i)` is uniform over any aligned lane group.
struct TriLectureSoA : AxisGrouped<TriLecture> {
  // From already built lecture primitives and their dropped axes (parallelograms, planes with uv).
  static TriLectureSoA from(const std::vector<TriLecture<float>>& prims, const std::vector<int>& axes) {
    TriLectureSoA s;
    s.assign(prims, axes);
    return s;
  }
  template <class T>
  static TriLectureSoA build(const std::vector<std::array<Vec3<T>, 3>>& tris) {
    std::vector<TriLecture<float>> t(tris.size());
    std::vector<int> ax(tris.size());
    for (std::size_t i = 0; i < tris.size(); ++i) t[i] = make_tri_lecture(tris[i][0], tris[i][1], tris[i][2], ax[i]);
    return from(t, ax);
  }
};

// ---- Moller-Trumbore --------------------------------------------------------------------------
template <class F>
struct Triangle {
  Vec3<F> v0, e1, e2;
  auto fields() { return std::tie(v0.x, v0.y, v0.z, e1.x, e1.y, e1.z, e2.x, e2.y, e2.z); }
  static Triangle never() {
    const F nan = F(std::numeric_limits<scalar_t<F>>::quiet_NaN());
    return {{nan, nan, nan}, {nan, nan, nan}, {nan, nan, nan}};
  }
};

// Edges are formed in double and rounded once. Zero area or non-finite input: never() (the reason
// in *why).
template <class T>
inline Triangle<float> make_triangle(Vec3<T> a, Vec3<T> b, Vec3<T> c, std::string* why = nullptr) {
  const Vec3d A = to_double(a), e1 = to_double(b) - A, e2 = to_double(c) - A;
  const Vec3d n = cross(e1, e2);
  if (!finite3(A) || !finite3(e1) || !finite3(e2) || !finite3(n))
    return never_because<Triangle<float>>(why, "triangle: a vertex is not finite");
  if (dot(n, n) == 0.0) return never_because<Triangle<float>>(why, "triangle: zero area");
  const Triangle<float> t{to_float(A), to_float(e1), to_float(e2)};
  const Vec3d nr = cross(to_double(t.e1), to_double(t.e2));  // the rounded edges may be parallel
  if (dot(nr, nr) == 0.0)
    return never_because<Triangle<float>>(why, "triangle: zero area after rounding to float");
  return t;
}

template <class F>
RB_INLINE Hit<F> intersect_triangle_mt(const Ray<F>& r, const Triangle<F>& q) {
  const Vec3<F> p = cross(r.d, q.e2);               // 3+- 6*
  const F det = dot(q.e1, p);                       // 2+- 3*
  mask_t<F> m = det != F(0);                        // 1 cmp
  if (none_of<F>(m)) return miss_hit<F>();
  const F inv = F(1) / det;                         // 1/
  const Vec3<F> s = r.o - q.v0;                     // 3+-
  const F u = dot(s, p) * inv;                      // 2+- 4*
  m = m & (u >= F(0)) & (u <= F(1));                // 2 cmp
  if (none_of<F>(m)) return miss_hit<F>();
  const Vec3<F> qv = cross(s, q.e1);                // 3+- 6*
  const F v = dot(r.d, qv) * inv;                   // 2+- 4*
  m = m & (v >= F(0)) & (u + v <= F(1));            // 1+- 2 cmp
  if (none_of<F>(m)) return miss_hit<F>();
  const F t = dot(q.e2, qv) * inv;                  // 2+- 4*
  m = m & (t >= r.tmin) & (t <= r.tmax);            // 2 cmp
  return make_hit<F>(m, t, u, v);                   // 1 select
}

// Geometric normal (not normalised), e1 x e2: 3+- 6*.
template <class F>
RB_INLINE Vec3<F> triangle_normal(const Triangle<F>& q) { return cross(q.e1, q.e2); }
template <class F>
RB_INLINE Vec3<F> triangle_normal(const TriLecture<F>& q) { return q.n; }

}  // namespace rb
