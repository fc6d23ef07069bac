// Ray x axis-aligned box by the slab test (seed 004 "Ray Box Intersection", Kay-Kajiya).
// The slide divides by the direction per axis and exits early per axis; here the reciprocal
// direction is a per-ray precompute (Ray::rd), the three slabs are intersected without
// branches, and one comparison decides. A NaN from 0 * inf (a ray parallel to an axis with its
// origin exactly on that axis' slab plane) sits in the first argument of min/max, which then
// return the other value (minps semantics): t stays finite or +inf, never NaN; such a ray
// lies in the box's face plane, a boundary case that may report a miss.
//   t_lo = (lo - P0) * rd, t_hi = (hi - P0) * rd        6+- 6*
//   t_near = max of the per-axis mins, t_far = min of the per-axis maxes   10 min/max
//   t = t_near if t_near >= tmin, else t_far            1 cmp 1 select
//   hit: t_near <= t_far and tmin <= t <= tmax          3 cmp
// Returns the first surface crossing in [tmin, tmax], as every closed primitive does: the entry,
// or the exit when the origin is inside (the sphere's far root). intersect_box_overlap keeps the
// cheaper clamped form (t = max(t_near, tmin), so tmin when the origin is inside), which is what
// a traversal wants: the distance at which the segment enters the box.
#pragma once

#include "core/ray.hpp"
#include "core/roots.hpp"
#include "core/why.hpp"

namespace rb {

template <class F>
struct Box {
  Vec3<F> lo, hi;
  auto fields() { return std::tie(lo.x, lo.y, lo.z, hi.x, hi.y, hi.z); }
  // Both corners at +inf: every slab interval is (+inf, +inf) or (-inf, -inf), never overlapping.
  static Box never() { return {{F(kInf<F>), F(kInf<F>), F(kInf<F>)}, {F(kInf<F>), F(kInf<F>), F(kInf<F>)}}; }
};

// Inverted (lo > hi on any axis) or non-finite boxes: never() (the reason in *why). A flat box
// (lo == hi) is kept.
template <class T>
inline Box<float> make_box(Vec3<T> lo, Vec3<T> hi, std::string* why = nullptr) {
  if (!finite3(lo) || !finite3(hi)) return never_because<Box<float>>(why, "box: a corner is not finite");
  if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z) return never_because<Box<float>>(why, "box: min is above max on an axis");
  return {to_float(to_double(lo)), to_float(to_double(hi))};
}

template <class F>
RB_INLINE Hit<F> intersect_box(const Ray<F>& r, const Box<F>& b) {
  const F x0 = (b.lo.x - r.o.x) * r.rd.x, x1 = (b.hi.x - r.o.x) * r.rd.x;   // 2+- 2*
  const F y0 = (b.lo.y - r.o.y) * r.rd.y, y1 = (b.hi.y - r.o.y) * r.rd.y;   // 2+- 2*
  const F z0 = (b.lo.z - r.o.z) * r.rd.z, z1 = (b.hi.z - r.o.z) * r.rd.z;   // 2+- 2*
  // A NaN axis (origin on both planes of a flat box, ray in them) makes tn or tf NaN: a miss.
  const F tn = vmax(vmin(z0, z1), vmax(vmin(x0, x1), vmin(y0, y1)));      // 5 min/max
  const F tf = vmin(vmax(z0, z1), vmin(vmax(x0, x1), vmax(y0, y1)));      // 5 min/max
  const F t = vselect(tn >= r.tmin, tn, tf);                                // 1 cmp 1 select
  const mask_t<F> m = (tn <= tf) & (t >= r.tmin) & (t <= r.tmax);           // 3 cmp
  return make_hit<F>(m, t);                                                 // 1 select
}

// The overlap form for traversal: hit when the box meets [tmin, tmax]; t = the clamped entry
// max(t_near, tmin) (tmin when the origin is inside). 6+- 6* 12 min/max 1 cmp 1 select.
template <class F>
RB_INLINE Hit<F> intersect_box_overlap(const Ray<F>& r, const Box<F>& b) {
  const F x0 = (b.lo.x - r.o.x) * r.rd.x, x1 = (b.hi.x - r.o.x) * r.rd.x;   // 2+- 2*
  const F y0 = (b.lo.y - r.o.y) * r.rd.y, y1 = (b.hi.y - r.o.y) * r.rd.y;   // 2+- 2*
  const F z0 = (b.lo.z - r.o.z) * r.rd.z, z1 = (b.hi.z - r.o.z) * r.rd.z;   // 2+- 2*
  const F tn = vmax(vmax(vmin(x0, x1), vmin(y0, y1)), vmax(vmin(z0, z1), r.tmin));  // 6 min/max
  const F tf = vmin(vmin(vmax(x0, x1), vmax(y0, y1)), vmin(vmax(z0, z1), r.tmax));  // 6 min/max
  const mask_t<F> m = tn <= tf;                                             // 1 cmp
  return make_hit<F>(m, tn);                                                // 1 select
}

// Entry and exit of the closed box along the whole line (not clipped to [tmin, tmax]: CSG
// combines intervals first), canonical. 6+- 6* 10 min/max 1 cmp 2 select. Reads Ray::rd: under a
// transformation use transform_ray<true>.
template <class F>
RB_INLINE Roots<F, 2> box_roots(const Ray<F>& r, const Box<F>& b) {
  const F x0 = (b.lo.x - r.o.x) * r.rd.x, x1 = (b.hi.x - r.o.x) * r.rd.x;
  const F y0 = (b.lo.y - r.o.y) * r.rd.y, y1 = (b.hi.y - r.o.y) * r.rd.y;
  const F z0 = (b.lo.z - r.o.z) * r.rd.z, z1 = (b.hi.z - r.o.z) * r.rd.z;
  const F tn = vmax(vmin(z0, z1), vmax(vmin(x0, x1), vmin(y0, y1)));
  const F tf = vmin(vmax(z0, z1), vmin(vmax(x0, x1), vmax(y0, y1)));
  return Roots<F, 2>::closed_span(tn <= tf, tn, tf);
}

// Outward normal of the face at point p: the axis where p is closest to a face (selects only).
template <class F>
RB_INLINE Vec3<F> box_normal(const Box<F>& b, const Vec3<F>& p) {
  const F c = F(0.5);
  const Vec3<F> ctr = (b.lo + b.hi) * c, half = (b.hi - b.lo) * c;
  const Vec3<F> q = p - ctr;
  const F ax = vabs(q.x) / half.x, ay = vabs(q.y) / half.y, az = vabs(q.z) / half.z;
  const mask_t<F> mx = (ax >= ay) & (ax >= az), my = mask_not<F>(mx) & (ay >= az);
  const mask_t<F> mz = mask_not<F>(mx | my);
  const F one = F(1), zero = F(0);
  return {vselect(mx, vcopysign(one, q.x), zero), vselect(my, vcopysign(one, q.y), zero), vselect(mz, vcopysign(one, q.z), zero)};
}

}  // namespace rb
