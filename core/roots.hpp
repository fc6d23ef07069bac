// Roots<F, N>: the one shape for "where along the ray" answers: the roots of a quadratic, the
// entry/exit span of a convex solid or a bounding sphere, every crossing of a torus or an
// algebraic surface, and the operands and results of CSG in 1D ray space (seed 000 "CSG":
// ordered t lists, combined by merging).
//
// N slots per lane: t[k] and valid[k]. Lane-generic like the kernels: each lane has its own
// count of valid slots (count_in_lane; per-lane masks valid[k]).
//
// Two states, by contract of the function that returns the list:
//   raw        t[k] means something only where valid[k] (the internal form kernels pass on to
//              their own final step without spending selects; e.g. stable_roots, span()).
//   canonical  ascending; the valid slots come first and every other slot holds +inf with a
//              clear mask. Every *_roots function a kernel file exports returns canonical lists,
//              and the CSG operations below take and give canonical lists.
// As a point set, a canonical list is the union of [t[2k], t[2k+1]] (the ray is inside the solid
// between an entry and the next exit; a tangent double root is an empty-interior interval).
#pragma once

#include "core/ray.hpp"

namespace rb {

// Ascending sort of a fixed-size array (insertion network: N(N-1)/2 compare-exchanges, each
// 1 min + 1 max; +inf sorts last). Used by every kernel that reports several roots.
template <int N, class F>
RB_INLINE void sort_net(F (&x)[N]) {
  for (int i = 1; i < N; ++i)
    for (int j = i; j >= 1; --j) {
      const F a = vmin(x[j - 1], x[j]), b = vmax(x[j - 1], x[j]);
      x[j - 1] = a;
      x[j] = b;
    }
}

template <class F, int N>
struct Roots {
  F t[N];
  mask_t<F> valid[N];

  // Canonical and empty.
  static RB_INLINE Roots none() {
    Roots r;
    for (int k = 0; k < N; ++k) { r.t[k] = F(kInf<F>); r.valid[k] = mask_false<F>(); }
    return r;
  }
  // Raw span [lo, hi] valid where m (N == 2): no operation.
  static RB_INLINE Roots span(const mask_t<F>& m, const F& lo, const F& hi) {
    static_assert(N == 2, "a span has two slots");
    Roots r;
    r.t[0] = lo;
    r.t[1] = hi;
    r.valid[0] = r.valid[1] = m;
    return r;
  }
  // Canonical span: +inf where m is clear (2 select). The caller guarantees lo <= hi where m.
  static RB_INLINE Roots closed_span(const mask_t<F>& m, const F& lo, const F& hi) {
    return span(m, vselect(m, lo, F(kInf<F>)), vselect(m, hi, F(kInf<F>)));
  }
  // Canonical list from slots holding +inf where there is no root: sorted ascending (sort_net),
  // valid = t < +inf (N cmp).
  static RB_INLINE Roots canonical(F (&t)[N]) {
    sort_net<N>(t);
    Roots r;
    for (int k = 0; k < N; ++k) {
      r.t[k] = t[k];
      r.valid[k] = t[k] < F(kInf<F>);
    }
    return r;
  }

  const F& lo() const { return t[0]; }
  const F& hi() const { return t[N - 1]; }
  // Number of valid slots in one lane (reads lanes: for tests and tools, not for kernels).
  int count_in_lane(int lane_index) const {
    int n = 0;
    for (int k = 0; k < N; ++k) n += lane_mask<F>(valid[k], lane_index) ? 1 : 0;
    return n;
  }
};

// The nearest root in [tmin, tmax] of a two-slot list (a quadratic's roots, or the entry/exit of
// a solid: the exit when the origin is inside), valid where t[0]'s mask is set.
//   3 cmp 2 select (with make_hit)
template <class F>
RB_INLINE Hit<F> first_hit(const Ray<F>& r, const Roots<F, 2>& s) {
  const F t = vselect(s.t[0] >= r.tmin, s.t[0], s.t[1]);       // 1 cmp 1 select
  const mask_t<F> m = s.valid[0] & (t >= r.tmin) & (t <= r.tmax);  // 2 cmp
  return make_hit<F>(m, t);                                     // 1 select
}

// ---- CSG in 1D ray space ------------------------------------------------------------------------
// The set operations on entry/exit lists. The merges themselves (a scalar two-pointer merge that
// can stop at the closest hit, and a lane-generic one for packets) live with the tagged interval
// list in core/intervals.hpp; these are the operation and its membership rule.
enum class SetOp { kUnion, kIntersection, kDifference };  // difference: A minus B

namespace detail {
template <class F>
RB_INLINE mask_t<F> set_op(SetOp op, const mask_t<F>& a, const mask_t<F>& b) {
  switch (op) {
    case SetOp::kUnion: return a | b;
    case SetOp::kIntersection: return a & b;
    default: return a & mask_not<F>(b);
  }
}
}  // namespace detail

}  // namespace rb
