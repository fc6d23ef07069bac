// Spans<F>: the interval list of CSG in 1D ray space, on top of Roots<F, N> (core/roots.hpp).
//
// A list is an ascending sequence of boundaries t[0] <= t[1] <= ...; the ray is inside the solid
// between t[2k] and t[2k+1]. Each boundary carries a tag naming the surface it lies on: +(leaf + 1)
// for a leaf's own surface, negated when the normal there must be flipped (a subtracted solid's
// surface bounds the result from outside the subtrahend, so its outward normal points into the
// subtrahend). Lane-generic like Roots: slot k of every lane; a slot at or beyond a lane's count
// holds t = +inf and tag 0; n is the largest count of any lane (exactly the count for scalars).
//
// Set operations are the generalised merge of two ordered lists (seed 000 "Set operations on the
// ray"). The rule at touching and coincident boundaries (stated once, both merges obey it):
//   boundaries at the same t, of either list, are applied together: the result has a boundary
//   at t iff its membership just before t differs from its membership just after t. So the
//   result is the regularised set on the line: intervals that touch (one's exit at the other's
//   entry) fuse into one, zero-length intervals (a tangent double root, two solids touching at a
//   point) and zero-length gaps vanish, and a coincident surface is reported once. Comparisons
//   are exact: boundaries that differ by one ulp are two boundaries (CSG of solids sharing a face
//   through different float arithmetic may leave a sliver there).
// The tag of a kept boundary is the first list's when that list has a boundary at t, else the
// second's (flipped for a difference).
//
// Two merges, one result (tests check they agree):
//   merge_linear   scalar: the two-pointer merge, O(N + M), about 3 compares per boundary; it
//                  can stop at the first result boundary at or after a given t (the closest-hit
//                  early exit: the rest of the list is never formed).
//   merge_lanes    any number type, lane by lane without branches (SIMD packets): each boundary
//                  is kept or dropped from the parities of both lists just before and just after
//                  it, then the kept ones are sorted; O((N + M)^2) compares and selects.
#pragma once

#include "core/roots.hpp"

#include <cstdint>

namespace rb {

// Slots per list: the sum over a tree's leaves of their slots (2 per convex leaf, 4 per torus)
// is at most this (the CSG builder refuses larger trees), so no list can overflow.
inline constexpr int kSpanCap = 64;

template <class F>
struct Spans {
  int n = 0;
  F t[kSpanCap];
  F tag[kSpanCap];

  // From a canonical root list, in place: slot k keeps t[k] where valid, +inf elsewhere; every
  // valid slot gets the tag `surface` (+(leaf + 1)).
  template <int N>
  RB_INLINE void assign(const Roots<F, N>& r, scalar_t<F> surface) {
    n = 0;
    for (int k = 0; k < N; ++k) {
      if (none_of<F>(r.valid[k])) break;  // canonical: valid slots first
      t[k] = vselect(r.valid[k], r.t[k], F(kInf<F>));
      tag[k] = vselect(r.valid[k], F(surface), F(0));
      n = k + 1;
    }
  }
  // Copies the used slots of s.
  RB_INLINE void copy_from(const Spans& s) {
    n = s.n;
    for (int k = 0; k < n; ++k) {
      t[k] = s.t[k];
      tag[k] = s.tag[k];
    }
  }
  // Number of valid slots in one lane (tests and tools).
  int count_in_lane(int lane_index) const {
    int c = 0;
    for (int k = 0; k < n; ++k) c += lane(t[k], lane_index) < kInf<F> ? 1 : 0;
    return c;
  }
};

namespace detail {
inline bool set_op_scalar(SetOp op, bool a, bool b) {
  switch (op) {
    case SetOp::kUnion: return a || b;
    case SetOp::kIntersection: return a && b;
    default: return a && !b;
  }
}
}  // namespace detail

// Scalar merge (F = float, double or Counted of those). Writes op(A, B) into out (which must not
// alias A or B). stop_at: the merge ends after the first result boundary with t >= stop_at (pass
// +inf for the full list); the return value is that boundary's slot, or -1.
//   per consumed boundary: 1 cmp to pick the smaller head, 1-2 cmp to gather equal ones;
//   per kept boundary: 1 cmp against stop_at (when finite).
template <class F>
RB_INLINE int merge_linear(SetOp op, const Spans<F>& A, const Spans<F>& B, Spans<F>& out, bool stop = false,
                           const F& stop_at = F(kInf<F>)) {
  static_assert(lanes_v<F> == 1, "merge_linear is the scalar merge; packets use merge_lanes");
  int i = 0, j = 0;
  bool inA = false, inB = false, cur = false;
  out.n = 0;
  const bool flip = op == SetOp::kDifference;
  while (i < A.n || j < B.n) {
    const bool takeA = j >= B.n || (i < A.n && A.t[i] <= B.t[j]);  // 1 cmp when both have one
    const F t = takeA ? A.t[i] : B.t[j];
    F tag = F(0);
    bool fromA = false;
    while (i < A.n && A.t[i] == t) {  // A's boundaries at t (1 cmp each, 1 more to stop)
      tag = fromA ? tag : A.tag[i];
      fromA = true;
      inA = !inA;
      ++i;
    }
    bool fromB = false;
    while (j < B.n && B.t[j] == t) {
      if (!fromA && !fromB) tag = flip ? -B.tag[j] : B.tag[j];  // sign flips are free
      fromB = true;
      inB = !inB;
      ++j;
    }
    const bool now = detail::set_op_scalar(op, inA, inB);
    if (now == cur) continue;
    cur = now;
    out.t[out.n] = t;
    out.tag[out.n] = tag;
    ++out.n;
    if (stop && t >= stop_at) return out.n - 1;
  }
  return -1;
}

// Lane-generic merge (any F, SIMD packets): the same result as merge_linear in every lane.
template <class F>
RB_INLINE void merge_lanes(SetOp op, const Spans<F>& A, const Spans<F>& B, Spans<F>& out) {
  const F inf = F(kInf<F>);
  const bool flip = op == SetOp::kDifference;
  int n = 0;
  // Membership of L just before x (parity of boundaries < x) and just after (<= x).
  auto parity = [](const Spans<F>& L, const F& x, mask_t<F>& before, mask_t<F>& after) {
    before = mask_false<F>();
    after = mask_false<F>();
    for (int k = 0; k < L.n; ++k) {
      before = mask_xor<F>(before, L.t[k] < x);
      after = mask_xor<F>(after, L.t[k] <= x);
    }
  };
  auto changes = [&](const F& x) {
    mask_t<F> ab, aa, bb, ba;
    parity(A, x, ab, aa);
    parity(B, x, bb, ba);
    return mask_xor<F>(detail::set_op<F>(op, ab, bb), detail::set_op<F>(op, aa, ba));
  };
  for (int k = 0; k < A.n; ++k) {
    const F x = A.t[k];
    mask_t<F> keep = (x < inf) & changes(x);
    if (k > 0) keep = keep & mask_not<F>(A.t[k - 1] == x);  // the first of equal boundaries only
    out.t[n] = vselect(keep, x, inf);
    out.tag[n] = vselect(keep, A.tag[k], F(0));
    ++n;
  }
  for (int k = 0; k < B.n; ++k) {
    const F x = B.t[k];
    mask_t<F> keep = (x < inf) & changes(x);
    if (k > 0) keep = keep & mask_not<F>(B.t[k - 1] == x);
    for (int q = 0; q < A.n; ++q) keep = keep & mask_not<F>(A.t[q] == x);  // A's copy represents it
    out.t[n] = vselect(keep, x, inf);
    out.tag[n] = vselect(keep, flip ? -B.tag[k] : B.tag[k], F(0));
    ++n;
  }
  // Insertion network on (t, tag): +inf (dropped) slots sort last.
  for (int a = 1; a < n; ++a)
    for (int b = a; b >= 1; --b) {
      const mask_t<F> sw = out.t[b] < out.t[b - 1];
      const F t0 = vselect(sw, out.t[b], out.t[b - 1]), t1 = vselect(sw, out.t[b - 1], out.t[b]);
      const F g0 = vselect(sw, out.tag[b], out.tag[b - 1]), g1 = vselect(sw, out.tag[b - 1], out.tag[b]);
      out.t[b - 1] = t0;
      out.t[b] = t1;
      out.tag[b - 1] = g0;
      out.tag[b] = g1;
    }
  while (n > 0 && none_of<F>(out.t[n - 1] < inf)) --n;
  out.n = n;
}

// The first boundary of a list in [tmin, tmax] (scan from the end: the smallest t >= tmin wins),
// with its tag; mask clear and t = +inf where none.
template <class F>
RB_INLINE Hit<F> first_span_hit(const Ray<F>& r, const Spans<F>& s, F& tag) {
  F t = F(kInf<F>);
  tag = F(0);
  for (int k = s.n - 1; k >= 0; --k) {
    const mask_t<F> m = s.t[k] >= r.tmin;
    t = vselect(m, s.t[k], t);
    tag = vselect(m, s.tag[k], tag);
  }
  const mask_t<F> hit = t <= r.tmax;
  tag = vselect(hit, tag, F(0));
  return make_hit<F>(hit, t);
}

}  // namespace rb
