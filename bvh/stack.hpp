// The traversal stack and what goes on it in which order.
//
// The stack holds child references and entry distances in two arrays, so that a node visit pushes
// its children with two 8-lane stores (8 slots of headroom above the bound); a packet's walk keeps
// a third array of ray masks beside them (MaskStack). Sized from the built tree: a node visit
// pushes at most 7 entries per level, so Bvh8::stack_entries() (7 per level of the tree's depth)
// is never exceeded, and collapse8 refuses trees deeper than kMaxTreeDepth. A local array when the
// bound fits it (every tree up to depth 73), else one heap array of the bound's size per trace
// call. In builds with assertions (the `debug` preset, under ASan) the stack is always a heap
// array of exactly the bound plus the headroom, so that ASan sees an overrun, and every push
// checks the bound (RB_STACK_CHECK); the optimised builds rely on the depth bound and check
// nothing per push.
//
// Child order (closest hit): a node's hit children are visited near to far by their entry
// distance. Two children: one comparison (`pair_order`). More: each child's key is its entry
// distance's bits with the child's slot in the 3 low bits (distances >= 0 order as their bits;
// the robust form's may be negative and are made ordered first; the 3 bits cost at most 7 ulp of
// ordering precision, which only changes which of two nearly equidistant children is visited
// first), misses get the least key, and the sorting network orders the 8 keys descending in one
// register (`far_first`), so that the nearest hit child ends in lane n - 1 and the others lie
// farthest first below it: one store pushes them.
#pragma once

#include "bvh/bvh.hpp"
#include "core/lanes.hpp"

#include <cassert>
#include <cstdint>
#include <memory>

namespace rb::bvh {

inline constexpr std::size_t kLocalStack = 512;
#ifdef NDEBUG
inline constexpr bool kCheckedStack = false;
#define RB_STACK_CHECK(sp, cap) ((void)0)
#else
inline constexpr bool kCheckedStack = true;
#define RB_STACK_CHECK(sp, cap) assert((sp) <= (cap) && "traversal stack beyond the tree's depth bound")
#endif

struct Stack {
  alignas(32) std::uint32_t local_ref[kLocalStack + 8];
  alignas(32) float local_d[kLocalStack + 8];
  struct Heap {
    std::unique_ptr<std::uint32_t[]> ref;
    std::unique_ptr<float[]> d;
  };
  std::unique_ptr<Heap> heap;  // one pointer, so a stack on the local arrays ends with one test
  std::uint32_t* ref;
  float* d;
  std::size_t cap;  // entries below which sp stays (the 8 of headroom above it)
  explicit Stack(const Bvh8& t) : cap(t.stack_entries()) {
    if (!kCheckedStack && cap <= kLocalStack) {
      ref = local_ref;
      d = local_d;
    } else {
      heap.reset(new Heap{std::unique_ptr<std::uint32_t[]>(new std::uint32_t[cap + 8]), std::unique_ptr<float[]>(new float[cap + 8])});
      ref = heap->ref.get();
      d = heap->d.get();
    }
  }
};

// A packet's ray masks beside its Stack, under the same bound and the same local-or-heap rule.
template <class Mask>
struct MaskStack {
  Mask local[kLocalStack + 8];
  std::unique_ptr<Mask[]> heap;
  Mask* m = local;
  explicit MaskStack(const Bvh8& t) {
    if (kCheckedStack || t.stack_entries() > kLocalStack) {
      heap.reset(new Mask[t.stack_entries() + 8]);
      m = heap.get();
    }
  }
};

// Drops the entries whose distance is beyond t (closest hit, after a leaf brought t nearer), 8 at
// a time with the compaction table; NaN distances are kept. So every entry on the stack lies
// within the closest hit and a pop needs no test.
RB_INLINE void drop_beyond(float t, std::uint32_t* ref, float* d, std::size_t& sp) {
  const f8 ht(t);
  std::size_t w = 0;
  for (std::size_t i = 0; i < sp; i += 8) {
    const f8 di = f8::load_unaligned(d + i);
    const unsigned live = (1u << std::min<std::size_t>(8, sp - i)) - 1u;
    const unsigned keep = lanes::not_gt_bits(di, ht) & live;
    const __m256i idx = lanes::compaction(keep);
    lanes::store8(ref + w, lanes::permute(lanes::load8(ref + i), idx));
    f8(lanes::permute(__m256(di), idx)).store_unaligned(d + w);
    w += std::size_t(__builtin_popcount(keep));
  }
  sp = w;
}

// Two hit children a and b (a < b): which is nearer (the lower slot at equal distances) and the
// farther one's distance, read from the register.
struct PairOrder {
  int near, far;
  float far_d;
};
RB_INLINE PairOrder pair_order(const f8& tn, unsigned bits) {
  const int a = __builtin_ctz(bits), b = __builtin_ctz(bits & (bits - 1));
  const float da = lanes::at(tn, a), db = lanes::at(tn, b);
  return da <= db ? PairOrder{a, b, db} : PairOrder{b, a, da};
}
// The hit children's slots sorted far to near by `tn` (the nearest in lane popcount(bits) - 1).
template <bool Robust>
RB_INLINE __m256i far_first(const f8& tn, unsigned bits) {
  const __m256i key = Robust ? lanes::ordered(lanes::as_int(tn)) : lanes::as_int(tn);
  return lanes::low3(lanes::sort_descending(lanes::indexed_keys(key, bits)));
}

}  // namespace rb::bvh
