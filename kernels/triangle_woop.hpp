// Watertight ray x triangle (Woop, Benthin, Wald, "Watertight Ray/Triangle Intersection",
// JCGT 2(1), 2013).
//   Per ray, once (WoopRay, make_woop_ray): kz = the axis of the largest |d|, kx = kz+1, ky = kx+1
//   (mod 3), kx and ky swapped when d[kz] < 0 (keeps the winding); the shear
//   Sx = d[kx]/d[kz], Sy = d[ky]/d[kz], Sz = 1/d[kz].
//   Per test: vertices relative to the origin, permuted and sheared so the ray is the +z axis:
//   Ax = A[kx] - Sx A[kz], Ay = A[ky] - Sy A[kz] (B, C alike); the 2D edge functions
//   U = Cx By - Cy Bx, V = Ax Cy - Ay Cx, W = Bx Ay - By Ax; a hit when U, V, W have one sign
//   (zero allowed on either side: two-sided); det = U + V + W != 0; t = (U Az + V Bz + W Cz)/det
//   with Az = Sz A[kz]. A shared edge is evaluated with the same operations on the same floats by
//   both of its triangles (reversed, the value is exactly negated), so no ray passes between them.
//   That needs both products of each edge function rounded separately: with -ffp-contract=fast
//   the compiler would form fma(Cx, By, -(Cy Bx)), which is not the negation of the reversed
//   edge's fma(By, Cx, -(Bx Cy)) (one product exact, the other rounded), and rays exactly through
//   shared edges passed between both faces. vrounded (core/num.hpp) forces the separate rounding
//   without an instruction; it holds in every build (the double fallback's products of floats
//   are exact in double, contracted or not).
//   When an edge function is exactly 0.0 in float, U, V, W are recomputed in double from the
//   float sheared coordinates (a product of two floats is exact in double, so the sign is right).
//
// SIMD: the fallback runs per lane, only for the lanes that have a zero (scalar double code on the
// extracted lanes, written back), so every SIMD lane equals the scalar float result bit for bit.
// The double instantiations do no fallback (no wider type is available for d4; the paper's
// recomputation is defined for single precision). Fallback operations are not counted (rare
// path: only rays exactly through an edge or vertex in float).
//
// Permutation: a broadcast ray (primitives in lanes, scalar) has one (kx, ky, kz) and indexes the
// vertices directly. A packet of rays (rays in lanes) whose lanes share the permutation does the
// same; a mixed packet permutes with 2 selects per coordinate (6 per vertex), bit-identical since
// selects only move values.
// [u,v] = [V/det, W/det] (the barycentric coordinates of b and c, as Moller-Trumbore returns).
#pragma once

#include "core/ray.hpp"
#include "core/why.hpp"

#include <type_traits>

namespace rb {

template <class F>
struct TriVerts {
  Vec3<F> a, b, c;
  auto fields() { return std::tie(a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z); }
  // NaN vertices: U, V, W and t are NaN, every positive-form test fails.
  static TriVerts never() {
    const F nan = F(std::numeric_limits<scalar_t<F>>::quiet_NaN());
    return {{nan, nan, nan}, {nan, nan, nan}, {nan, nan, nan}};
  }
};

// Vertices are kept exactly as given (watertightness needs shared vertices bit-identical).
// Zero area (cross product zero in double) or non-finite input: never() (the reason in *why).
template <class T>
inline TriVerts<float> make_tri_verts(Vec3<T> a, Vec3<T> b, Vec3<T> c, std::string* why = nullptr) {
  const Vec3d A = to_double(a), B = to_double(b), C = to_double(c);
  const Vec3d n = cross(B - A, C - A);
  if (!finite3(A) || !finite3(B) || !finite3(C) || !finite3(n))
    return never_because<TriVerts<float>>(why, "triangle: a vertex is not finite");
  if (dot(n, n) == 0.0) return never_because<TriVerts<float>>(why, "triangle: zero area");
  const TriVerts<float> t{to_float(A), to_float(B), to_float(C)};
  const Vec3d nr = cross(to_double(t.b) - to_double(t.a), to_double(t.c) - to_double(t.a));
  if (dot(nr, nr) == 0.0) return never_because<TriVerts<float>>(why, "triangle: zero area after rounding to float");
  return t;
}

// The per-ray precompute.
template <class F>
struct WoopRay {
  F Sx, Sy, Sz;
  // Per-lane permutation: kx == 0 (x0), kx == 1 (x1), else 2; likewise ky, kz.
  mask_t<F> x0, x1, y0, y1, z0, z1;
  int kx, ky, kz;  // valid when `uniform`
  bool uniform;    // every lane has the same permutation
};

template <class F>
RB_INLINE WoopRay<F> make_woop_ray(const Ray<F>& r) {
  WoopRay<F> w;
  const F ax = vabs(r.d.x), ay = vabs(r.d.y), az = vabs(r.d.z);
  w.z0 = (ax >= ay) & (ax >= az);                                   // 2 cmp
  w.z1 = mask_not<F>(w.z0) & (ay >= az);                            // 1 cmp
  const mask_t<F> z2 = mask_not<F>(w.z0 | w.z1);
  const F dkz = vselect(w.z0, r.d.x, vselect(w.z1, r.d.y, r.d.z));  // 2 select
  const mask_t<F> neg = dkz < F(0);                                 // 1 cmp
  const mask_t<F> pos = mask_not<F>(neg);
  // kz = 0: (kx, ky) = (1, 2), kz = 1: (2, 0), kz = 2: (0, 1); swapped when d[kz] < 0.
  w.x0 = (z2 & pos) | (w.z1 & neg);
  w.x1 = (w.z0 & pos) | (z2 & neg);
  w.y0 = (w.z1 & pos) | (z2 & neg);
  w.y1 = (z2 & pos) | (w.z0 & neg);
  const F dkx = vselect(w.x0, r.d.x, vselect(w.x1, r.d.y, r.d.z));  // 2 select
  const F dky = vselect(w.y0, r.d.x, vselect(w.y1, r.d.y, r.d.z));  // 2 select
  w.Sx = dkx / dkz;                                                 // 1/
  w.Sy = dky / dkz;                                                 // 1/
  w.Sz = F(1) / dkz;                                                // 1/
  const bool uz0 = all_of<F>(w.z0) || none_of<F>(w.z0), uz1 = all_of<F>(w.z1) || none_of<F>(w.z1);
  const bool un = all_of<F>(neg) || none_of<F>(neg);
  w.uniform = uz0 && uz1 && un;
  w.kz = lane_mask<F>(w.z0, 0) ? 0 : lane_mask<F>(w.z1, 0) ? 1 : 2;
  w.kx = lane_mask<F>(w.x0, 0) ? 0 : lane_mask<F>(w.x1, 0) ? 1 : 2;
  w.ky = lane_mask<F>(w.y0, 0) ? 0 : lane_mask<F>(w.y1, 0) ? 1 : 2;
  return w;
}

// (a[kx], a[ky], a[kz]) per lane.
template <class F>
RB_INLINE Vec3<F> woop_permute(const WoopRay<F>& w, const Vec3<F>& a) {
  if (w.uniform) return {a[w.kx], a[w.ky], a[w.kz]};
  return {vselect(w.x0, a.x, vselect(w.x1, a.y, a.z)), vselect(w.y0, a.x, vselect(w.y1, a.y, a.z)),
          vselect(w.z0, a.x, vselect(w.z1, a.y, a.z))};
}

namespace detail {
// Recomputes U, V, W in double on the lanes of `zero` (float lanes only; see the header).
template <class F>
inline void woop_double_fallback(const mask_t<F>& zero, const F& Ax, const F& Ay, const F& Bx, const F& By, const F& Cx,
                                 const F& Cy, F& U, F& V, F& W) {
  if constexpr (std::is_same_v<scalar_t<F>, float>) {
    constexpr int L = lanes_v<F>;
    alignas(kSimdAlign) float ax[L], ay[L], bx[L], by[L], cx[L], cy[L], u[L], v[L], w[L];
    store(ax, Ax); store(ay, Ay); store(bx, Bx); store(by, By); store(cx, Cx); store(cy, Cy);
    store(u, U); store(v, V); store(w, W);
    for (int k = 0; k < L; ++k) {
      if (!lane_mask<F>(zero, k)) continue;
      u[k] = float(double(cx[k]) * double(by[k]) - double(cy[k]) * double(bx[k]));
      v[k] = float(double(ax[k]) * double(cy[k]) - double(ay[k]) * double(cx[k]));
      w[k] = float(double(bx[k]) * double(ay[k]) - double(by[k]) * double(ax[k]));
    }
    U = load<F>(u); V = load<F>(v); W = load<F>(w);
  } else {
    (void)zero; (void)Ax; (void)Ay; (void)Bx; (void)By; (void)Cx; (void)Cy; (void)U; (void)V; (void)W;
  }
}
}  // namespace detail

// The test on the vertices already relative to the origin and permuted ((a - o)[kx], [ky], [kz]):
// a batch stored by coordinate can load them in that order (tracer/leaves.hpp does, for one ray
// against 8 triangles), with the same result bit for bit.
template <class F>
RB_INLINE Hit<F> intersect_triangle_woop_permuted(const WoopRay<F>& w, const Ray<F>& r, const Vec3<F>& A, const Vec3<F>& B,
                                                  const Vec3<F>& C) {
  const F Ax = A.x - w.Sx * A.z, Ay = A.y - w.Sy * A.z;  // 2+- 2*
  const F Bx = B.x - w.Sx * B.z, By = B.y - w.Sy * B.z;  // 2+- 2*
  const F Cx = C.x - w.Sx * C.z, Cy = C.y - w.Sy * C.z;  // 2+- 2*
  // Each product rounded on its own (vrounded): a contracted fma(Cx, By, -Cy Bx) is not the exact
  // negation of the other face's fma(By, Cx, -Bx Cy), and rays through the shared edge leaked.
  F U = vrounded(Cx * By) - vrounded(Cy * Bx);           // 1+- 2*
  F V = vrounded(Ax * Cy) - vrounded(Ay * Cx);           // 1+- 2*
  F W = vrounded(Bx * Ay) - vrounded(By * Ax);           // 1+- 2*
  const mask_t<F> zero = (U == F(0)) | (V == F(0)) | (W == F(0));  // 3 cmp
  if (any_of<F>(zero)) detail::woop_double_fallback<F>(zero, Ax, Ay, Bx, By, Cx, Cy, U, V, W);
  const F z = F(0);
  mask_t<F> m = ((U >= z) & (V >= z) & (W >= z)) | ((U <= z) & (V <= z) & (W <= z));  // 6 cmp
  const F det = U + V + W;                               // 2+-
  m = m & (det != z);                                    // 1 cmp
  if (none_of<F>(m)) return miss_hit<F>();
  const F Az = w.Sz * A.z, Bz = w.Sz * B.z, Cz = w.Sz * C.z;  // 3*
  const F T = U * Az + V * Bz + W * Cz;                  // 2+- 3*
  const F inv = F(1) / det;                              // 1/
  const F t = T * inv;                                   // 1*
  m = m & (t >= r.tmin) & (t <= r.tmax);                 // 2 cmp
  return make_hit<F>(m, t, V * inv, W * inv);            // 2* 1 select
}

template <class F>
RB_INLINE Hit<F> intersect_triangle_woop(const WoopRay<F>& w, const Ray<F>& r, const TriVerts<F>& q) {
  const Vec3<F> A = woop_permute(w, q.a - r.o);          // 3+-
  const Vec3<F> B = woop_permute(w, q.b - r.o);          // 3+-
  const Vec3<F> C = woop_permute(w, q.c - r.o);          // 3+-
  return intersect_triangle_woop_permuted(w, r, A, B, C);
}

// Convenience: precompute and test (use intersect_triangle_woop with a stored WoopRay when one
// ray meets many triangles).
template <class F>
RB_INLINE Hit<F> intersect_triangle_woop(const Ray<F>& r, const TriVerts<F>& q) {
  return intersect_triangle_woop(make_woop_ray(r), r, q);
}

// Geometric normal (not normalised), (b - a) x (c - a): 9+- 6*.
template <class F>
RB_INLINE Vec3<F> triangle_normal(const TriVerts<F>& q) { return cross(q.b - q.a, q.c - q.a); }

}  // namespace rb
