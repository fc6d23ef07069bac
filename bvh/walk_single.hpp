// The walk of one ray through the 8-wide tree: a node visit tests the 8 children in one slab test
// (bvh/slab.hpp) and goes on to the nearest hit child, pushing the others (bvh/stack.hpp); a leaf
// visit hands the leaf to the leaf source. Closest hit: children near to far, stack entries beyond
// a new closest hit dropped. Any hit: no distances, no order (the hit children pushed in slot
// order, the last one next), return at the first hit. Also the incoherent packet's walk of two
// rays at once (trace_pairs), made of the same visits.
#pragma once

#include "bvh/hit.hpp"
#include "bvh/slab.hpp"
#include "bvh/stack.hpp"
#include "soa/rays.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace rb::bvh {

// A ray with an empty interval (or a NaN bound), or any ray in an empty tree, misses without a walk.
RB_INLINE bool cannot_hit(const Bvh8& t, const Ray<float>& r) { return !(r.tmin <= r.tmax) || t.nodes.empty(); }

// Whether a ray with this origin needs the robust slab test (its origin is beyond the bound the
// boxes were made conservative for).
inline bool beyond_bound(const Bvh8& t, const Vec3f& o) {
  return !(std::max({std::fabs(o.x), std::fabs(o.y), std::fabs(o.z)}) <= t.origin_bound);
}

// One node visit of a single ray: ref becomes the next node (or leaf) to visit and the other hit
// children are pushed; false when no child was hit (the next comes from the stack).
template <bool Robust, bool Any, bool Count>
RB_INLINE bool visit_node(const WNode* nodes, const SlabRay& sr, float tmax, std::uint32_t& ref, std::uint32_t* sref, float* sd, std::size_t& sp,
                          [[maybe_unused]] std::size_t cap, TraceCounters& c) {
  const WNode& n = nodes[ref];
  if constexpr (Count) {
    ++c.nodes;
    for (int k = 0; k < 8; ++k) c.boxes += n.child[k] != kEmpty;
  }
  f8 tn;
  const unsigned bits = slab8<Robust>(n, sr, tmax, tn);
  if (bits == 0) return false;
  if ((bits & (bits - 1)) == 0) {
    ref = n.child[__builtin_ctz(bits)];
    return true;
  }
  const __m256i child = lanes::load8_aligned(n.child);
  const int cnt = __builtin_popcount(bits);
  if constexpr (Any) {
    lanes::store8(sref + sp, lanes::permute(child, lanes::compaction(bits)));
  } else if (cnt == 2) {
    const PairOrder o = pair_order(tn, bits);
    sref[sp] = n.child[o.far];
    sd[sp] = o.far_d;
    ++sp;
    RB_STACK_CHECK(sp, cap);
    ref = n.child[o.near];
    return true;
  } else {
    const __m256i slot = far_first<Robust>(tn, bits);
    lanes::store8(sref + sp, lanes::permute(child, slot));
    f8(lanes::permute(__m256(tn), slot)).store_unaligned(sd + sp);
  }
  sp += std::size_t(cnt - 1);
  RB_STACK_CHECK(sp, cap);
  ref = sref[sp];
  return true;
}

// One leaf visit of a single ray: true when the leaf improved h. With closest hit, the stack
// entries now beyond h.t are dropped at once.
template <bool Any, bool Count, class L>
RB_INLINE bool visit_leaf(const L& leaves, std::uint32_t ref, const Ray<float>& r, typename L::RayCache& cache, Closest& h,
                          std::uint32_t* sref, float* sd, std::size_t& sp, TraceCounters& c) {
  if constexpr (Count) {
    const std::uint32_t s = leaves.slots(ref);
    c.prims += s;
    c.kind_prims[leaf_kind(ref)] += s;
  }
  if (!leaves.single(ref, r, cache, h)) return false;
  if constexpr (!Any) drop_beyond(h.t, sref, sd, sp);
  return true;
}

// The walk of one ray from node `ref` (the root, or where an any-hit packet left the ray).
template <bool Robust, bool Any, bool Count, class L>
RB_INLINE HitRec single_loop(const Bvh8& t, const L& leaves, const Ray<float>& r, Stack& st, TraceCounters& c, std::uint32_t ref = 0) {
  Closest h{r.tmax, kNoPrim};
  const SlabRay sr = SlabRay::make(r);
  typename L::RayCache cache(r);
  std::uint32_t* const sref = st.ref;
  float* const sd = st.d;
  std::size_t sp = 0;
  const WNode* const nodes = t.nodes.data();
  for (;;) {
    while (!is_leaf(ref))
      if (!visit_node<Robust, Any, Count>(nodes, sr, h.t, ref, sref, sd, sp, st.cap, c)) goto pop;
    if (visit_leaf<Any, Count>(leaves, ref, r, cache, h, sref, sd, sp, c) && Any) return finished(h, cache);
  pop:
    if (sp == 0) return finished(h, cache);
    ref = sref[--sp];
  }
}

// Negative tmin (the fast form's integer ordering needs tmin >= 0) and, for the conservative slab
// test, an origin beyond the bound the boxes were widened for take the robust form.
template <Slab S, bool Any, bool Count, class L>
RB_INLINE HitRec trace_single(const Bvh8& t, const L& leaves, const Ray<float>& r, Stack& st, TraceCounters& c) {
  if (cannot_hit(t, r)) return {kInfF, kNoPrim};
  if constexpr (S != Slab::robust) {
    if (!(r.tmin >= 0) || (S == Slab::conservative && beyond_bound(t, r.o))) return single_loop<true, Any, Count>(t, leaves, r, st, c);
    return single_loop<false, Any, Count>(t, leaves, r, st, c);
  } else {
    return single_loop<true, Any, Count>(t, leaves, r, st, c);
  }
}

// Rays [begin, end) one at a time: one stack for all of them, and each ray's walk inlined into the
// loop, so that the ray is read from the SoA into registers (a walk called per ray took the ray
// through memory) and what every ray uses (the node array, the leaf source) stays loaded.
template <Slab S, bool Any, bool Count, class L>
void trace_singles(const Bvh8& t, const L& leaves, const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, TraceCounters& c) {
  Stack st(t);
  for (std::size_t i = begin; i < end; ++i) out[i] = trace_single<S, Any, Count>(t, leaves, rays.get(i), st, c);
}

// ---- incoherent packets: two rays walked at once -------------------------------------------------
// Rays that start far apart share no nodes, and one ray's walk waits on each node and leaf it
// loads. Two rays of the packet walk at once, a node or a leaf each in turn, so that one ray's
// loads are under way while the other computes; a ray that ends hands its walker to the packet's
// next ray.
template <bool Robust, bool Any, bool Count, class L>
void trace_pairs(const Bvh8& t, const L& leaves, const RaySoA& rays, std::size_t i, HitRec* out, TraceCounters& c) {
  struct Walker {
    Ray<float> r;
    SlabRay sr;
    std::optional<typename L::RayCache> cache;
    Closest h{kInfF, kNoPrim};  // set by start(); initialised so that no path reads an indeterminate value
    std::uint32_t ref;
    std::size_t sp;
    std::size_t k = 0;  // the ray's index
  };
  Walker w[2];
  Stack st0(t), st1(t);
  std::size_t next = i;
  // The packet's next valid ray into walker v (an invalid ray is a miss); false when none is left.
  auto start = [&](Walker& v) RB_INLINE_LAMBDA {
    while (next < i + 8) {
      const std::size_t k = next++;
      const Ray<float> r = rays.get(k);
      if (cannot_hit(t, r)) {
        out[k] = {kInfF, kNoPrim};
        continue;
      }
      v.r = r;
      v.sr = SlabRay::make(r);
      v.cache.emplace(r);
      v.h = {r.tmax, kNoPrim};
      v.ref = 0;
      v.sp = 0;
      v.k = k;
      return true;
    }
    return false;
  };
  // One node or one leaf of walker v; false when its ray has ended (its hit written out).
  auto step = [&](Walker& v, Stack& s) RB_INLINE_LAMBDA {
    if (!is_leaf(v.ref)) {
      if (visit_node<Robust, Any, Count>(t.nodes.data(), v.sr, v.h.t, v.ref, s.ref, s.d, v.sp, s.cap, c)) return true;
    } else if (visit_leaf<Any, Count>(leaves, v.ref, v.r, *v.cache, v.h, s.ref, s.d, v.sp, c) && Any) {
      v.sp = 0;  // any hit: the ray ends at its first hit
    }
    if (v.sp) {
      v.ref = s.ref[--v.sp];
      return true;
    }
    out[v.k] = finished(v.h, *v.cache);
    return false;
  };
  bool a = start(w[0]), b = a && start(w[1]);
  while (a && b) {
    if (!step(w[0], st0)) a = start(w[0]);
    if (!step(w[1], st1)) b = start(w[1]);
  }
  while (a)
    if (!step(w[0], st0)) a = start(w[0]);
  while (b)
    if (!step(w[1], st1)) b = start(w[1]);
}

}  // namespace rb::bvh
