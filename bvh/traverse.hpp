// Traversal of the 8-wide BVH: one slab test (fast or robust, a template switch), one loop per
// ray mode (single rays; coherent packets of 8, 16, 64 or 256 rays in groups of 8 lanes;
// incoherent packets of 8 as single rays, two at a time when they start apart, through the same
// node and leaf visits as a single ray), closest or any hit, counted or not. Templates over a
// leaf source, so the BVH knows nothing of primitives: whatever intersects the leaves
// (tracer/leaves.hpp for a scene) is instantiated into the loop, chosen once per scene, never
// switched per ray.
//
// A leaf source L provides:
//   using RayCache;      per single ray (constructed from it): whatever its leaves precompute
//   using PacketCache;   the same per group of a packet
//   bool single(ref, const Ray<float>& r, RayCache&, HitRec& h) const;
//       the ray against leaf `ref`'s primitives with tmax = h.t (inclusive); true when h was
//       improved by the canonical order (`nearer`: a lesser t, or a lesser code at an equal t);
//       never called with an empty leaf
//   template <bool Any> void packet(ref, PacketRays& p, PacketCache&) const;
//       the listed groups' active rays against the leaf: improves p.tbest and p.prim per lane
//       (packet_update); with Any, clears p.active of rays that hit
//   std::uint32_t slots(ref) const;   real primitives in the leaf (for the counted traversal)
//
// The slab test: t = box * (1/d) - o * (1/d), one FMA per plane with o * (1/d) precomputed per
// ray; the near plane per axis is chosen once per ray from the sign of 1/d. It is exact enough
// when the boxes were made conservative for the ray's origin (bvh::make_conservative: boxes
// widened at build time); a ray whose origin lies beyond that bound, or whose tmin is negative,
// is traced with the robust test instead (Ize 2013, "Robust BVH Ray Traversal": t = (box - o) *
// (1/d), the far distance scaled by 1 + 2 gamma(3)). The choice is made once per ray (per packet).
//
// The stack holds at most 7 entries per wide level (Bvh8::stack_entries) plus 8 of headroom for
// the 8-lane pushes, sized from the built tree, so a push can never overrun it.
#pragma once

#include "bvh/bvh.hpp"
#include "core/ray.hpp"
#include "soa/rays.hpp"

#include <immintrin.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

namespace rb::bvh {

// The slab test a traversal uses:
//   conservative  the fast test where the boxes were made conservative for the ray's origin
//                 (make_conservative), the robust test for a ray (packet) from beyond that bound:
//                 loses no hit; the default
//   fast          the fast test whatever the boxes (on boxes as built it can cull the box of the
//                 closest hit for a ray through a shared vertex or edge: measured in the lab)
//   robust        Ize's test for every ray
enum class Slab { conservative, fast, robust };
inline const char* slab_name(Slab s) {
  return s == Slab::conservative ? "conservative" : s == Slab::fast ? "fast" : "robust";
}

inline constexpr float kSlabEps = 0x1p-24f;
inline constexpr float kGamma3 = 3 * kSlabEps / (1 - 3 * kSlabEps);
inline constexpr float kRobustScale = 1 + 2 * kGamma3;
// A zero direction component would make 1/d infinite and o * (1/d) NaN at o = 0; as Embree does,
// components smaller than this are replaced by it (with their sign) for the slab test.
// The ray already carries rd = 1/d (the ray contract: make_ray divides in float, as here), so the
// safe reciprocal is rd itself except on those components: no division per ray or packet.
inline constexpr float kMinDir = 1e-18f;
inline float safe_rcp(float d) { return 1.0f / (std::fabs(d) < kMinDir ? std::copysign(kMinDir, d) : d); }
inline float safe_rcp(float d, float rd) { return std::fabs(d) < kMinDir ? std::copysign(1.0f / kMinDir, d) : rd; }
inline f8 safe_rcp8(const f8& d, const f8& rd) {
  return xsimd::select(xsimd::abs(d) < f8(kMinDir), xsimd::copysign(f8(1.0f / kMinDir), d), rd);
}

namespace detail {

inline constexpr float kInfF = std::numeric_limits<float>::infinity();

inline unsigned movemask(const f8_mask& m) { return unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_castps_si256(m)))); }
// Smallest lane and its index; `ties` gets every lane holding that value (bit l for lane l).
inline int argmin8(const f8& t, float& best, unsigned& ties) {
  const __m256 v = t;
  __m256 m = _mm256_min_ps(v, _mm256_permute_ps(v, 0xB1));
  m = _mm256_min_ps(m, _mm256_permute_ps(m, 0x4E));
  m = _mm256_min_ps(m, _mm256_permute2f128_ps(m, m, 1));
  best = _mm256_cvtss_f32(m);
  ties = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(v, m, _CMP_EQ_OQ)));
  return ties ? __builtin_ctz(ties) : 0;
}
// Lane k of t, read from the register.
RB_INLINE float lane_value(const f8& t, int k) {
  return _mm256_cvtss_f32(_mm256_permutevar8x32_ps(t, _mm256_castsi128_si256(_mm_cvtsi32_si128(k))));
}
inline float hmin8(const f8& t) {
  float b;
  unsigned ties;
  argmin8(t, b, ties);
  return b;
}
inline float hmax8(const f8& t) {
  const __m256 v = t;
  __m256 m = _mm256_max_ps(v, _mm256_permute_ps(v, 0xB1));
  m = _mm256_max_ps(m, _mm256_permute_ps(m, 0x4E));
  m = _mm256_max_ps(m, _mm256_permute2f128_ps(m, m, 1));
  return _mm256_cvtss_f32(m);
}

// Child order (single rays; packets order by the frustum's distances the same way). A hit
// child's key is its entry distance's bits with the child's slot in the 3 low bits (distances >=
// 0, so the integer order is the float order; the 3 bits cost at most 7 ulp of ordering
// precision, which only changes which of two nearly equidistant children is visited first).
// Misses get INT_MIN. The 8 keys are sorted descending by a 19-comparator network (Batcher's
// odd-even merge sort) in one register, so the nearest hit child ends in lane n - 1 and the
// others lie farthest first below it: one store pushes them.
RB_INLINE __m256i as_int(const f8& x) { return _mm256_castps_si256(x); }
RB_INLINE f8 as_float(__m256i x) { return f8(_mm256_castsi256_ps(x)); }
// Float bits as an integer of the same order (negative floats' magnitude bits flipped).
RB_INLINE __m256i ordered(__m256i b) { return _mm256_xor_si256(b, _mm256_srli_epi32(_mm256_srai_epi32(b, 31), 1)); }
// One layer of compare-exchanges: p = the partners, take_max = lanes that keep the larger key.
RB_INLINE __m256i exchange(__m256i v, __m256i p, __m256i take_max) {
  return _mm256_blendv_epi8(_mm256_min_epi32(v, p), _mm256_max_epi32(v, p), take_max);
}
RB_INLINE __m256i sort8_descending(__m256i v) {
  // (0,1)(2,3)(4,5)(6,7)
  v = exchange(v, _mm256_shuffle_epi32(v, 0xB1), _mm256_setr_epi32(-1, 0, -1, 0, -1, 0, -1, 0));
  // (0,2)(1,3)(4,6)(5,7)
  v = exchange(v, _mm256_shuffle_epi32(v, 0x4E), _mm256_setr_epi32(-1, -1, 0, 0, -1, -1, 0, 0));
  // (1,2)(5,6)
  v = exchange(v, _mm256_shuffle_epi32(v, 0xD8), _mm256_setr_epi32(0, -1, 0, 0, 0, -1, 0, 0));
  // (0,4)(1,5)(2,6)(3,7)
  v = exchange(v, _mm256_permute2x128_si256(v, v, 1), _mm256_setr_epi32(-1, -1, -1, -1, 0, 0, 0, 0));
  // (2,4)(3,5)
  v = exchange(v, _mm256_permutevar8x32_epi32(v, _mm256_setr_epi32(0, 1, 4, 5, 2, 3, 6, 7)), _mm256_setr_epi32(0, 0, -1, -1, 0, 0, 0, 0));
  // (1,2)(3,4)(5,6)
  v = exchange(v, _mm256_permutevar8x32_epi32(v, _mm256_setr_epi32(0, 2, 1, 4, 3, 6, 5, 7)), _mm256_setr_epi32(0, -1, 0, -1, 0, -1, 0, 0));
  return v;
}

// Lanes of a 4-bit or 8-bit set as a mask: all ones in lane l when bit l is set (as integers, and
// as the float mask the kernels take).
RB_INLINE __m256i lane_bits(unsigned bits) {
  const __m256i lane = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  return _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(bits)), lane), lane);
}
RB_INLINE f8_mask lanes_of(unsigned bits) { return f8_mask(_mm256_castsi256_ps(lane_bits(bits))); }

// The hit children's slots sorted far to near by `tn` (a node's hit children, for single rays and packets).
template <bool Robust>
RB_INLINE __m256i order_far_first(const f8& tn, unsigned bits) {
  __m256i key = Robust ? ordered(as_int(tn)) : as_int(tn);
  key = _mm256_or_si256(_mm256_and_si256(key, _mm256_set1_epi32(~7)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  key = _mm256_blendv_epi8(_mm256_set1_epi32(std::numeric_limits<int>::min()), key, lane_bits(bits));
  return _mm256_and_si256(sort8_descending(key), _mm256_set1_epi32(7));
}

// The slots of the set bits of a byte, lowest first (the rest 0): pushes the hit children of an
// any-hit visit, or keeps 8 stack entries, with one permute.
struct Compaction {
  alignas(32) std::uint32_t idx[256][8];
  constexpr Compaction() : idx{} {
    for (unsigned b = 0; b < 256; ++b) {
      unsigned k = 0;
      for (unsigned s = 0; s < 8; ++s)
        if (b >> s & 1u) idx[b][k++] = s;
    }
  }
};
inline constexpr Compaction kCompaction{};

// The traversal stack: child references and entry distances in two arrays, so that a node visit
// pushes its children with two 8-lane stores (8 slots of headroom above the bound). Sized from the
// built tree: a node visit pushes at most 7 entries per level, so Bvh8::stack_entries() (7 per
// level of the tree's depth) is never exceeded, and collapse8 refuses trees deeper than
// kMaxTreeDepth. A local array when the bound fits it (every tree up to depth 73), else one heap
// array of the bound's size per trace call. In builds with assertions (the `debug` preset, under
// ASan) the stack is always a heap array of exactly the bound plus the headroom, so that ASan sees
// an overrun, and every push checks the bound (RB_STACK_CHECK); the optimised builds rely on the
// depth bound and check nothing per push.
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

// A ray with an empty interval (or a NaN bound), or any ray in an empty tree, misses without a walk.
RB_INLINE bool cannot_hit(const Bvh8& t, const Ray<float>& r) { return !(r.tmin <= r.tmax) || t.nodes.empty(); }

// Whether a ray with this origin needs the robust slab test (its origin is beyond the bound the
// boxes were made conservative for).
inline bool beyond_bound(const Bvh8& t, const Vec3f& o) {
  return !(std::max({std::fabs(o.x), std::fabs(o.y), std::fabs(o.z)}) <= t.origin_bound);
}

// The largest side of the scene's box (the union of the root's child boxes; 0 for an empty tree).
inline float largest_side(const Bvh8& t) {
  if (t.nodes.empty()) return 0;
  const WNode& n = t.nodes[0];
  float side = 0;
  for (int a = 0; a < 3; ++a) {
    float lo = kInfF, hi = -kInfF;
    for (int k = 0; k < 8; ++k)
      if (n.child[k] != kEmpty) lo = std::min(lo, n.b[2 * a][k]), hi = std::max(hi, n.b[2 * a + 1][k]);
    side = std::max(side, hi - lo);
  }
  return side;
}

}  // namespace detail

// ---- the slab test of one ray against a node's 8 child boxes ------------------------------------
struct SlabRay {
  f8 rdx, rdy, rdz, ox, oy, oz, orx, ory, orz, tmin;
  int nx, ny, nz;  // 1 where 1/d < 0: the near plane is the box's hi
  static SlabRay make(const Ray<float>& r) {
    SlabRay s;
    const float x = safe_rcp(r.d.x, r.rd.x), y = safe_rcp(r.d.y, r.rd.y), z = safe_rcp(r.d.z, r.rd.z);
    s.rdx = f8(x); s.rdy = f8(y); s.rdz = f8(z);
    s.ox = f8(r.o.x); s.oy = f8(r.o.y); s.oz = f8(r.o.z);
    s.orx = f8(r.o.x * x); s.ory = f8(r.o.y * y); s.orz = f8(r.o.z * z);
    s.tmin = f8(r.tmin);
    s.nx = x < 0; s.ny = y < 0; s.nz = z < 0;
    return s;
  }
};

// Bit k set when the ray's [tmin, tmax] interval meets child k's box; tn receives the entry
// distances. The fast form needs tmin >= 0: its maxima and minima run on the floats' bits as
// integers (one cycle each instead of four on the node's critical path), which orders
// non-negative floats as floats; every entry distance is a maximum with tmin >= 0, and a negative
// exit distance (a box behind the ray) is a negative integer, below every entry: rejected, as it
// must be. The robust form (any tmin) compares floats.
template <bool Robust>
RB_INLINE unsigned slab8(const WNode& n, const SlabRay& r, float tmax, f8& tn) {
  if constexpr (!Robust) {
    using detail::as_int;
    const __m256i tnx = as_int(xsimd::fms(f8::load_aligned(n.b[0 + r.nx]), r.rdx, r.orx));
    const __m256i tfx = as_int(xsimd::fms(f8::load_aligned(n.b[1 - r.nx]), r.rdx, r.orx));
    const __m256i tny = as_int(xsimd::fms(f8::load_aligned(n.b[2 + r.ny]), r.rdy, r.ory));
    const __m256i tfy = as_int(xsimd::fms(f8::load_aligned(n.b[3 - r.ny]), r.rdy, r.ory));
    const __m256i tnz = as_int(xsimd::fms(f8::load_aligned(n.b[4 + r.nz]), r.rdz, r.orz));
    const __m256i tfz = as_int(xsimd::fms(f8::load_aligned(n.b[5 - r.nz]), r.rdz, r.orz));
    const __m256i near = _mm256_max_epi32(_mm256_max_epi32(tnx, tny), _mm256_max_epi32(tnz, as_int(r.tmin)));
    const __m256i far = _mm256_min_epi32(_mm256_min_epi32(tfx, tfy), _mm256_min_epi32(tfz, _mm256_castps_si256(_mm256_set1_ps(tmax))));
    tn = detail::as_float(near);
    return ~unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(near, far)))) & 0xFFu;
  } else {
    const f8 tnx = (f8::load_aligned(n.b[0 + r.nx]) - r.ox) * r.rdx;
    const f8 tfx = (f8::load_aligned(n.b[1 - r.nx]) - r.ox) * r.rdx;
    const f8 tny = (f8::load_aligned(n.b[2 + r.ny]) - r.oy) * r.rdy;
    const f8 tfy = (f8::load_aligned(n.b[3 - r.ny]) - r.oy) * r.rdy;
    const f8 tnz = (f8::load_aligned(n.b[4 + r.nz]) - r.oz) * r.rdz;
    const f8 tfz = (f8::load_aligned(n.b[5 - r.nz]) - r.oz) * r.rdz;
    tn = xsimd::max(xsimd::max(tnx, tny), xsimd::max(tnz, r.tmin));
    const f8 tf = xsimd::min(xsimd::min(xsimd::min(tfx, tfy), tfz) * f8(kRobustScale), f8(tmax));
    return unsigned(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
  }
}

// The finished hit: t = +inf when nothing was hit (the contract of Hit).
RB_INLINE HitRec finished(HitRec h) {
  if (h.prim == kNoPrim) h.t = detail::kInfF;
  return h;
}

// The closest hit is canonical: the least t, and at an equal t the least hit code (the kind, then
// the scene index). So which of two faces meeting the ray at the same distance (a shared edge or
// vertex) is reported does not depend on the order in which the leaves and their lanes are
// tested: single rays, packets of every size and the brute-force loop give the same hits. Node
// tests and the stack keep boxes whose entry equals the closest t (the tests are inclusive), so
// the other face's leaf is still visited.
RB_INLINE bool nearer(float t, std::uint32_t code, const HitRec& h) { return t < h.t || (t == h.t && code < h.prim); }

// A leaf's hit lanes (t = +inf on the others, at least one hit) against h: the least t, at an
// equal t the least code among the lanes and h. code_of(lane) gives a lane's code; it is read for
// the nearest lane and, only when several lanes share its t, for each of them. True, with h
// updated, when the leaf gives a nearer hit by `nearer`.
template <class CodeOf>
RB_INLINE bool take_nearest(const f8& t8, HitRec& h, CodeOf&& code_of) {
  float t;
  unsigned ties;
  const int lane = detail::argmin8(t8, t, ties);
  std::uint32_t code = code_of(lane);
  for (ties &= ties - 1; ties; ties &= ties - 1) code = std::min(code, std::uint32_t(code_of(__builtin_ctz(ties))));
  if (!nearer(t, code, h)) return false;
  h = {t, code};
  return true;
}

// ---- single ray ----------------------------------------------------------------------------------
// One node visit of a single ray: ref becomes the next node (or leaf) to visit and the other hit
// children are pushed; false when no child was hit (the next comes from the stack).
template <bool Robust, bool Any, bool Count>
RB_INLINE bool visit_node(const WNode* nodes, const SlabRay& sr, float tmax, std::uint32_t& ref, std::uint32_t* sref, float* sd, std::size_t& sp,
                          [[maybe_unused]] std::size_t cap, TraceCounters& c) {
  using namespace detail;
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
  const __m256i child = _mm256_load_si256(reinterpret_cast<const __m256i*>(n.child));
  const int cnt = __builtin_popcount(bits);
  if constexpr (Any) {
    const __m256i refs = _mm256_permutevar8x32_epi32(child, _mm256_load_si256(reinterpret_cast<const __m256i*>(kCompaction.idx[bits])));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(sref + sp), refs);
    sp += std::size_t(cnt - 1);
    RB_STACK_CHECK(sp, cap);
    ref = sref[sp];
    return true;
  } else {
    if (cnt == 2) {
      const int a = __builtin_ctz(bits), b = __builtin_ctz(bits & (bits - 1));
      // The two distances taken from the register (a store and two loads of it right away
      // would wait for the store on every such node).
      const float da = lane_value(tn, a), db = lane_value(tn, b);
      const bool a_first = da <= db;
      const int near = a_first ? a : b, far = a_first ? b : a;
      sref[sp] = n.child[far];
      sd[sp] = a_first ? db : da;
      ++sp;
      RB_STACK_CHECK(sp, cap);
      ref = n.child[near];
      return true;
    }
    const __m256i slot = order_far_first<Robust>(tn, bits);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(sref + sp), _mm256_permutevar8x32_epi32(child, slot));
    _mm256_storeu_ps(sd + sp, _mm256_permutevar8x32_ps(tn, slot));
    sp += std::size_t(cnt - 1);
    RB_STACK_CHECK(sp, cap);
    ref = sref[sp];
    return true;
  }
}

// One leaf visit of a single ray: true when the leaf improved h. With closest hit, the stack
// entries now beyond h.t are dropped at once (8 at a time, with the compaction table; NaN
// distances are kept), so every entry on the stack lies within the closest hit and a pop needs no
// test (children are pushed only when their box starts before it).
template <bool Any, bool Count, class L>
RB_INLINE bool visit_leaf(const L& leaves, std::uint32_t ref, const Ray<float>& r, typename L::RayCache& cache, HitRec& h,
                          std::uint32_t* sref, float* sd, std::size_t& sp, TraceCounters& c) {
  using namespace detail;
  if constexpr (Count) {
    const std::uint32_t s = leaves.slots(ref);
    c.prims += s;
    c.kind_prims[leaf_kind(ref)] += s;
  }
  if (!leaves.single(ref, r, cache, h)) return false;
  if constexpr (!Any) {
    const __m256 ht = _mm256_set1_ps(h.t);
    std::size_t w = 0;
    for (std::size_t i = 0; i < sp; i += 8) {
      const __m256 d = _mm256_loadu_ps(sd + i);
      const unsigned live = (1u << std::min<std::size_t>(8, sp - i)) - 1u;
      const unsigned keep = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(d, ht, _CMP_NGT_UQ))) & live;
      const __m256i idx = _mm256_load_si256(reinterpret_cast<const __m256i*>(kCompaction.idx[keep]));
      const __m256i refs = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(sref + i));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(sref + w), _mm256_permutevar8x32_epi32(refs, idx));
      _mm256_storeu_ps(sd + w, _mm256_permutevar8x32_ps(d, idx));
      w += std::size_t(__builtin_popcount(keep));
    }
    sp = w;
  }
  return true;
}

// Closest hit: the hit children in near-to-far order (one child: no ordering; two: one compare;
// more: the sorting network), the nearest next, the others pushed with their entry distance and
// dropped from the stack when a leaf brings the closest hit nearer than it. Any hit: no
// distances, no order (the hit children pushed in slot order, the last one next), return at the
// first hit. The walk starts at node `ref` (the root, or where an any-hit packet left the ray).
template <bool Robust, bool Any, bool Count, class L>
RB_INLINE HitRec single_loop(const Bvh8& t, const L& leaves, const Ray<float>& r, detail::Stack& st, TraceCounters& c,
                             std::uint32_t ref = 0) {
  using namespace detail;
  HitRec h{r.tmax, kNoPrim};
  const SlabRay sr = SlabRay::make(r);
  typename L::RayCache cache(r);
  std::uint32_t* const sref = st.ref;
  float* const sd = st.d;
  std::size_t sp = 0;
  const WNode* const nodes = t.nodes.data();
  for (;;) {
    while (!is_leaf(ref))
      if (!visit_node<Robust, Any, Count>(nodes, sr, h.t, ref, sref, sd, sp, st.cap, c)) goto pop;
    if (visit_leaf<Any, Count>(leaves, ref, r, cache, h, sref, sd, sp, c) && Any) return h;
  pop:
    if (sp == 0) return finished(h);
    ref = sref[--sp];
  }
}

// Negative tmin (the fast form's integer ordering needs tmin >= 0) and, for the conservative slab
// test, an origin beyond the bound the boxes were widened for take the robust form.
template <Slab S, bool Any, bool Count, class L>
RB_INLINE HitRec trace_single(const Bvh8& t, const L& leaves, const Ray<float>& r, detail::Stack& st, TraceCounters& c) {
  using namespace detail;
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
  detail::Stack st(t);
  for (std::size_t i = begin; i < end; ++i) out[i] = trace_single<S, Any, Count>(t, leaves, rays.get(i), st, c);
}

// ---- packets: G groups of 8 rays in lanes ---------------------------------------------------------
// A coherent packet (every ray in one direction octant: camera tiles, rays towards one light) of
// 8, 16, 64 or 256 rays traverses as one. Per node:
//   - one 8-lane test of the 8 children against the packet's frustum: per axis the ray whose origin
//     and reciprocal direction bound every ray's entry distance from below and exit distance from
//     above (the same slab test on those extremes, so it is conservative exactly as the per-ray
//     test is: it never rejects a box one of the rays' tests would accept);
//   - packets of 16 or more rays: one 8-lane test of the first active ray against the 8 children;
//     an internal child that ray hits is taken with the parent's ray mask unchanged (no per-ray
//     test), as the rays of a coherent packet mostly share their boxes;
//   - every other child the frustum accepts (leaves always, so that a leaf sees exact ray masks)
//     gets the exact test of each active group of 8 rays; the rays that hit it form its mask.
// Closest hit visits children near to far by the frustum's entry distance (the sorting network of
// the single-ray loop); any hit in slot order. The stack holds (child, entry distance, ray mask).
// At a leaf, the leaf source tests the masked rays. Any hit: rays that hit leave the packet; it
// ends when none remain; at a node with at most kAnySingleRays active rays, those go on one by one
// (any_hits_alone). Closest-hit packets stay packets to their last ray (going on alone measured
// slower on two of three meshes; see the design notes).
inline constexpr int kMaxGroups = 32;
// An any-hit packet with at most this many active rays at a node goes on ray by ray from there.
inline constexpr int kAnySingleRays = 3;

// What a leaf source sees of a packet: the groups with rays to test at this leaf (list[0..n)),
// each group's rays, current closest distance (tbest, lowered by hits) and the rays to test
// (active: a leaf clears, with Any, the rays that hit), and the primitive hit per ray.
struct PacketRays {
  int n = 0;
  std::uint8_t list[kMaxGroups];
  Ray<f8>* r = nullptr;
  f8* tbest = nullptr;
  f8_mask* active = nullptr;
  std::uint32_t* prim = nullptr;
  bool improved = false;  // set by packet_update when a ray's tbest fell
};

// Records a leaf's hits for the 8 rays of group k: lanes of `hit` that are active take t (at most
// their tbest: the kernel ran with tmax = tbest; at an equal t only a lesser code, as `nearer`) and
// the primitive `code`; with Any, the rays that hit leave the packet.
template <bool Any>
RB_INLINE void packet_update(PacketRays& p, int k, const f8_mask& hit, const f8& t, std::uint32_t code) {
  f8_mask m = hit & p.active[k];
  unsigned bits = detail::movemask(m);
  if (!bits) return;
  if constexpr (!Any) {
    // A hit at a ray's closest t so far replaces it only with a lesser code (`nearer`).
    if (unsigned ties = bits & detail::movemask(t == p.tbest[k])) {
      for (; ties; ties &= ties - 1) {
        const int l = __builtin_ctz(ties);
        if (code >= p.prim[8 * k + l]) bits &= ~(1u << l);
      }
      if (!bits) return;
      m = m & detail::lanes_of(bits);
    }
  }
  p.tbest[k] = xsimd::select(m, t, p.tbest[k]);
  p.improved = true;
  while (bits) {
    const int l = __builtin_ctz(bits);
    bits &= bits - 1;
    p.prim[8 * k + l] = code;
  }
  if constexpr (Any) p.active[k] = p.active[k] & ~m;
}

namespace detail {

// A ray mask of G groups: 8 bits per group.
template <int G>
struct RayMask {
  static constexpr int W = (G + 7) / 8;
  std::uint64_t w[W];
  static RayMask none() {
    RayMask m;
    for (auto& x : m.w) x = 0;
    return m;
  }
  unsigned group(int g) const { return unsigned(w[g >> 3] >> (8 * (g & 7))) & 0xFFu; }
  void set(int g, unsigned bits) {
    const int s = 8 * (g & 7);
    w[g >> 3] = (w[g >> 3] & ~(std::uint64_t(0xFF) << s)) | (std::uint64_t(bits) << s);
  }
  bool empty() const {
    std::uint64_t o = 0;
    for (auto x : w) o |= x;
    return o == 0;
  }
  int first() const {  // the lowest ray (g * 8 + lane); the mask is not empty
    for (int k = 0; k < W; ++k)
      if (w[k]) return 64 * k + __builtin_ctzll(w[k]);
    return -1;
  }
  int count() const {
    int c = 0;
    for (auto x : w) c += __builtin_popcountll(x);
    return c;
  }
  RayMask operator&(const RayMask& o) const {
    RayMask m;
    for (int k = 0; k < W; ++k) m.w[k] = w[k] & o.w[k];
    return m;
  }
};

// The slab test of one box against 8 rays (the box's near and far planes per axis given by the
// packet's octant), the fast or the robust form; bit l set when ray l's interval meets it.
template <bool Robust>
RB_INLINE unsigned slab_rays(const float* near, const float* far, const f8* rd, const f8* org_rd, const f8* o, const f8& tmin,
                             const f8& tmax) {
  if constexpr (!Robust) {
    const __m256i nx = as_int(xsimd::fms(f8(near[0]), rd[0], org_rd[0])), fx = as_int(xsimd::fms(f8(far[0]), rd[0], org_rd[0]));
    const __m256i ny = as_int(xsimd::fms(f8(near[1]), rd[1], org_rd[1])), fy = as_int(xsimd::fms(f8(far[1]), rd[1], org_rd[1]));
    const __m256i nz = as_int(xsimd::fms(f8(near[2]), rd[2], org_rd[2])), fz = as_int(xsimd::fms(f8(far[2]), rd[2], org_rd[2]));
    const __m256i tn = _mm256_max_epi32(_mm256_max_epi32(nx, ny), _mm256_max_epi32(nz, as_int(tmin)));
    const __m256i tf = _mm256_min_epi32(_mm256_min_epi32(fx, fy), _mm256_min_epi32(fz, as_int(tmax)));
    return ~unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(tn, tf)))) & 0xFFu;
  } else {
    const f8 nx = (f8(near[0]) - o[0]) * rd[0], fx = (f8(far[0]) - o[0]) * rd[0];
    const f8 ny = (f8(near[1]) - o[1]) * rd[1], fy = (f8(far[1]) - o[1]) * rd[1];
    const f8 nz = (f8(near[2]) - o[2]) * rd[2], fz = (f8(far[2]) - o[2]) * rd[2];
    const f8 tn = xsimd::max(xsimd::max(nx, ny), xsimd::max(nz, tmin));
    const f8 tf = xsimd::min(xsimd::min(xsimd::min(fx, fy), fz) * f8(kRobustScale), tmax);
    return unsigned(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
  }
}

// The 8 children of a node against one "ray" given per axis by its near-plane and far-plane
// parameters (a real ray: the same values twice; the frustum: the extreme rays per plane).
struct ChildTest {
  f8 rdn[3], orn[3], on[3], rdf[3], orf[3], of[3], tmin;
  int n[3];  // 1 where the near plane is the box's hi (the octant's negative axes)
};
template <bool Robust>
RB_INLINE unsigned slab_children(const WNode& node, const ChildTest& c, float tmax, f8& tn) {
  f8 near[3], far[3];
  for (int a = 0; a < 3; ++a) {
    const f8 bn = f8::load_aligned(node.b[2 * a + c.n[a]]), bf = f8::load_aligned(node.b[2 * a + 1 - c.n[a]]);
    if constexpr (!Robust) {
      near[a] = xsimd::fms(bn, c.rdn[a], c.orn[a]);
      far[a] = xsimd::fms(bf, c.rdf[a], c.orf[a]);
    } else {
      near[a] = (bn - c.on[a]) * c.rdn[a];
      far[a] = (bf - c.of[a]) * c.rdf[a];
    }
  }
  if constexpr (!Robust) {
    const __m256i n = _mm256_max_epi32(_mm256_max_epi32(as_int(near[0]), as_int(near[1])), _mm256_max_epi32(as_int(near[2]), as_int(c.tmin)));
    const __m256i f = _mm256_min_epi32(_mm256_min_epi32(as_int(far[0]), as_int(far[1])),
                                       _mm256_min_epi32(as_int(far[2]), _mm256_castps_si256(_mm256_set1_ps(tmax))));
    tn = as_float(n);
    return ~unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(n, f)))) & 0xFFu;
  } else {
    tn = xsimd::max(xsimd::max(near[0], near[1]), xsimd::max(near[2], c.tmin));
    const f8 tf = xsimd::min(xsimd::min(xsimd::min(far[0], far[1]), far[2]) * f8(kRobustScale), f8(tmax));
    return unsigned(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
  }
}

}  // namespace detail

// The few rays `left` of an any-hit packet at node `ref`, each on alone from there (the single-ray
// walk). The packet's frustum still spans every ray it started with, so it accepts children none
// of the few remaining rays meets, and each such child costs an 8-lane test with most lanes idle;
// alone, a ray tests a node's 8 children in one. Out of line: inlined, it changed the packet
// loop's register allocation and cost the bunny's shadow packets 7-8 %.
template <bool Robust, bool Count, int G, class L>
[[gnu::noinline]] void any_hits_alone(const Bvh8& t, const L& leaves, const RaySoA& rays, std::size_t i, std::uint32_t ref,
                                      detail::RayMask<G> left, f8* tbest, std::uint32_t* prim, detail::RayMask<G>& alive,
                                      TraceCounters& c) {
  using namespace detail;
  Stack st(t);
  while (!left.empty()) {
    const int f = left.first(), g = f >> 3, l = f & 7;
    left.set(g, left.group(g) & ~(1u << l));
    const HitRec h = single_loop<Robust, true, Count>(t, leaves, rays.get(i + std::size_t(f)), st, c, ref);
    if (h.prim == kNoPrim) continue;
    prim[f] = h.prim;
    tbest[g] = xsimd::select(lanes_of(1u << l), f8(h.t), tbest[g]);
    alive.set(g, alive.group(g) & ~(1u << l));
  }
}

template <bool Robust, bool Any, bool Count, int G, class L>
void trace_packet(const Bvh8& t, const L& leaves, const RaySoA& rays, std::size_t i, HitRec* out, TraceCounters& c) {
  using namespace detail;
  using Mask = RayMask<G>;
  Ray<f8> r[G];
  f8 tbest[G];
  f8_mask act[G];
  std::uint32_t prim[8 * G];
  f8 rd[G][3], org_rd[G][3], org[G][3];
  alignas(32) float rd_s[3][8 * G], ord_s[3][8 * G], o_s[3][8 * G], tmin_s[8 * G];
  Mask alive = Mask::none();
  for (int g = 0; g < G; ++g) {
    r[g] = rays.packet<f8>(i + 8 * std::size_t(g));
    const Vec3<f8>& d = r[g].d;
    const f8 inv[3] = {safe_rcp8(d.x, r[g].rd.x), safe_rcp8(d.y, r[g].rd.y), safe_rcp8(d.z, r[g].rd.z)};
    const f8 oo[3] = {r[g].o.x, r[g].o.y, r[g].o.z};
    for (int a = 0; a < 3; ++a) {
      rd[g][a] = inv[a];
      org[g][a] = oo[a];
      org_rd[g][a] = oo[a] * inv[a];
      rd[g][a].store_aligned(&rd_s[a][8 * g]);
      org_rd[g][a].store_aligned(&ord_s[a][8 * g]);
      oo[a].store_aligned(&o_s[a][8 * g]);
    }
    r[g].tmin.store_aligned(&tmin_s[8 * g]);
    tbest[g] = r[g].tmax;
    alive.set(g, movemask(r[g].tmin <= r[g].tmax));
  }
  for (auto& q : prim) q = kNoPrim;
  if (!alive.empty() && !t.nodes.empty()) {
    // The frustum: per axis, the extreme origins and reciprocal directions of the valid rays.
    ChildTest fr;
    const int f0 = alive.first();
    float lo_rd[3], hi_rd[3], lo_o[3], hi_o[3], tmin_min;
    {
      f8 lrd[3], hrd[3], lo[3], ho[3], tm(kInfF);
      for (int a = 0; a < 3; ++a) lrd[a] = lo[a] = f8(kInfF), hrd[a] = ho[a] = f8(-kInfF);
      for (int g = 0; g < G; ++g) {
        const f8_mask v = lanes_of(alive.group(g));
        for (int a = 0; a < 3; ++a) {
          lrd[a] = xsimd::min(lrd[a], xsimd::select(v, rd[g][a], f8(kInfF)));
          hrd[a] = xsimd::max(hrd[a], xsimd::select(v, rd[g][a], f8(-kInfF)));
          lo[a] = xsimd::min(lo[a], xsimd::select(v, org[g][a], f8(kInfF)));
          ho[a] = xsimd::max(ho[a], xsimd::select(v, org[g][a], f8(-kInfF)));
        }
        tm = xsimd::min(tm, xsimd::select(v, r[g].tmin, f8(kInfF)));
      }
      for (int a = 0; a < 3; ++a) lo_rd[a] = hmin8(lrd[a]), hi_rd[a] = hmax8(hrd[a]), lo_o[a] = hmin8(lo[a]), hi_o[a] = hmax8(ho[a]);
      tmin_min = hmin8(tm);
    }
    for (int a = 0; a < 3; ++a) {
      const bool neg = std::signbit(rd_s[a][f0]);
      fr.n[a] = neg;
      // positive axis: entry bounded by (lo plane, largest origin, smallest 1/d), exit by (hi plane,
      // smallest origin, largest 1/d); a negative axis swaps the planes and the origin/1/d pairs.
      const float rn = neg ? hi_rd[a] : lo_rd[a], on = neg ? lo_o[a] : hi_o[a];
      const float rf = neg ? lo_rd[a] : hi_rd[a], of = neg ? hi_o[a] : lo_o[a];
      fr.rdn[a] = f8(rn); fr.on[a] = f8(on); fr.orn[a] = f8(on * rn);
      fr.rdf[a] = f8(rf); fr.of[a] = f8(of); fr.orf[a] = f8(of * rf);
    }
    fr.tmin = f8(tmin_min);
    auto tmax_of = [&](const Mask& m) {
      f8 x(-kInfF);
      for (int g = 0; g < G; ++g)
        if (const unsigned b = m.group(g)) x = xsimd::max(x, xsimd::select(lanes_of(b), tbest[g], f8(-kInfF)));
      return hmax8(x);
    };
    float tmax_all = tmax_of(alive);

    PacketRays view;
    view.r = r;
    view.tbest = tbest;
    view.active = act;
    view.prim = prim;
    typename L::PacketCache cache;
    Stack st(t);
    std::uint32_t* const sref = st.ref;
    float* const sd = st.d;
    Mask local_mask[kLocalStack + 8];
    std::unique_ptr<Mask[]> heap_mask;
    Mask* smask = local_mask;
    if (kCheckedStack || t.stack_entries() > kLocalStack) {
      heap_mask.reset(new Mask[t.stack_entries() + 8]);
      smask = heap_mask.get();
    }
    std::size_t sp = 0;
    std::uint32_t ref = 0;
    Mask mask = alive;
    for (;;) {
      while (!is_leaf(ref)) {
        if constexpr (Any) {
          if (mask.count() <= kAnySingleRays) [[unlikely]] {
            any_hits_alone<Robust, Count>(t, leaves, rays, i, ref, mask, tbest, prim, alive, c);
            if (alive.empty()) goto done;
            goto pop;
          }
        }
        const WNode& n = t.nodes[ref];
        if constexpr (Count) ++c.nodes;
        std::uint64_t real = 0;
        if constexpr (Count)
          for (int k = 0; k < 8; ++k) real += n.child[k] != kEmpty;
        if constexpr (Count) c.boxes += real;
        f8 tn;
        unsigned bits = slab_children<Robust>(n, fr, tmax_all, tn);
        if (bits == 0) goto pop;
        {
          const unsigned leaf_children = unsigned(_mm256_movemask_ps(_mm256_load_ps(reinterpret_cast<const float*>(n.child))));
          unsigned inherit = 0;
          if constexpr (G > 1) {
            // The first active ray against the 8 children.
            const int f = mask.first(), g = f >> 3, l = f & 7;
            ChildTest one;
            for (int a = 0; a < 3; ++a) {
              one.n[a] = fr.n[a];
              one.rdn[a] = one.rdf[a] = f8(rd_s[a][f]);
              one.orn[a] = one.orf[a] = f8(ord_s[a][f]);
              one.on[a] = one.of[a] = f8(o_s[a][f]);
            }
            one.tmin = f8(tmin_s[f]);
            alignas(32) float tb[8];
            tbest[g].store_aligned(tb);
            f8 tn1;
            if constexpr (Count) c.boxes += real;
            inherit = slab_children<Robust>(n, one, tb[l], tn1) & bits & ~leaf_children;
          }
          Mask cm[8];
          for (unsigned e = bits & ~inherit; e; e &= e - 1) {
            const int k = __builtin_ctz(e);
            const float near[3] = {n.b[0 + fr.n[0]][k], n.b[2 + fr.n[1]][k], n.b[4 + fr.n[2]][k]};
            const float far[3] = {n.b[1 - fr.n[0]][k], n.b[3 - fr.n[1]][k], n.b[5 - fr.n[2]][k]};
            Mask m = Mask::none();
            for (int g = 0; g < G; ++g) {
              const unsigned gb = mask.group(g);
              if (!gb) continue;
              if constexpr (Count) c.boxes += std::uint64_t(__builtin_popcount(gb));
              m.set(g, gb & slab_rays<Robust>(near, far, rd[g], org_rd[g], org[g], r[g].tmin, tbest[g]));
            }
            if (m.empty()) bits &= ~(1u << k);
            else cm[k] = m;
          }
          for (unsigned e = inherit; e; e &= e - 1) cm[__builtin_ctz(e)] = mask;
          if (bits == 0) goto pop;
          if ((bits & (bits - 1)) == 0) {
            const int k = __builtin_ctz(bits);
            ref = n.child[k];
            mask = cm[k];
            continue;
          }
          alignas(32) std::uint32_t slot[8];
          alignas(32) float dist[8];
          tn.store_aligned(dist);
          // Any hit: no order (as for single rays: the highest slot next, the rest popped downwards);
          // sorting shadow packets' children cost 4-14 % of their rate.
          const int cnt = __builtin_popcount(bits);
          if constexpr (Any) _mm256_store_si256(reinterpret_cast<__m256i*>(slot), _mm256_load_si256(reinterpret_cast<const __m256i*>(kCompaction.idx[bits])));
          else if (cnt == 2) {
            const std::uint32_t a = std::uint32_t(__builtin_ctz(bits)), b = std::uint32_t(__builtin_ctz(bits & (bits - 1)));
            const bool a_first = dist[a] <= dist[b];
            slot[0] = a_first ? b : a;
            slot[1] = a_first ? a : b;
          } else _mm256_store_si256(reinterpret_cast<__m256i*>(slot), order_far_first<Robust>(tn, bits));
          for (int k = 0; k < cnt - 1; ++k) {
            sref[sp] = n.child[slot[k]];
            sd[sp] = dist[slot[k]];
            smask[sp] = cm[slot[k]];
            ++sp;
          }
          RB_STACK_CHECK(sp, st.cap);
          ref = n.child[slot[cnt - 1]];
          mask = cm[slot[cnt - 1]];
        }
      }
      {
        view.n = 0;
        for (int g = 0; g < G; ++g) {
          const unsigned gb = mask.group(g);
          act[g] = lanes_of(gb);
          if (gb) view.list[view.n++] = std::uint8_t(g);
        }
        if constexpr (Count) {
          const std::uint64_t s = leaves.slots(ref), k = std::uint64_t(mask.count());
          c.prims += s * k;
          c.kind_prims[leaf_kind(ref)] += s * k;
        }
        view.improved = false;
        leaves.template packet<Any>(ref, view, cache);
        if constexpr (Any) {
          for (int k = 0; k < view.n; ++k) {
            const int g = view.list[k];
            const unsigned hit = mask.group(g) & ~movemask(act[g]);  // the leaf cleared the rays that hit
            alive.set(g, alive.group(g) & ~hit);
          }
          if (alive.empty()) goto done;
        } else if (view.improved) {
          tmax_all = tmax_of(alive);
        }
      }
    pop:
      for (;;) {
        if (sp == 0) goto done;
        --sp;
        const Mask m = Any ? smask[sp] & alive : smask[sp];
        if (m.empty()) continue;
        if (!Any && sd[sp] > tmax_all) continue;
        ref = sref[sp];
        mask = m;
        break;
      }
    }
  }
done:
  for (int g = 0; g < G; ++g) {
    alignas(32) float tt[8];
    tbest[g].store_aligned(tt);
    for (int l = 0; l < 8; ++l) {
      const std::size_t k = i + 8 * std::size_t(g) + std::size_t(l);
      const std::uint32_t pr = prim[8 * g + l];
      out[k] = {pr == kNoPrim ? kInfF : tt[l], pr};
    }
  }
}

// ---- incoherent packets: two rays walked at once -------------------------------------------------
// Rays that start far apart share no nodes, and one ray's walk waits on each node and leaf it
// loads. Two rays of the packet walk at once, a node or a leaf each in turn, so that one ray's
// loads are under way while the other computes; a ray that ends hands its walker to the packet's
// next ray.
template <bool Robust, bool Any, bool Count, class L>
void trace_pairs(const Bvh8& t, const L& leaves, const RaySoA& rays, std::size_t i, HitRec* out, TraceCounters& c) {
  using namespace detail;
  struct Walker {
    Ray<float> r;
    SlabRay sr;
    std::optional<typename L::RayCache> cache;
    HitRec h{kInfF, kNoPrim};  // set by start(); initialised so that no path reads an indeterminate value
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
    out[v.k] = finished(v.h);
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

// ---- a range of rays -----------------------------------------------------------------------------
// Rays [begin, end) (begin a multiple of 8, the SoA padded to 8) into out. packet 1: one ray at a
// time; 8, 16, 64 or 256: packets of that many consecutive rays when they share a direction
// octant (coherent: camera tiles, rays towards one light); a packet of more than 8 whose rays do
// not goes on in packets of 8, and an incoherent packet of 8 as single rays (its rays would part
// ways at the first nodes): one at a time when they start near each other, two at a time when
// they start apart (trace_pairs). A packet takes the robust slab test when one of its rays needs
// it (trace_single's rule).
inline bool valid_packet_size(int packet) { return packet == 1 || packet == 8 || packet == 16 || packet == 64 || packet == 256; }

template <Slab S, bool Any, bool Count, class L>
void trace_range(const Bvh8& t, const L& leaves, const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, int packet,
                 TraceCounters& c) {
  if (!valid_packet_size(packet)) throw std::invalid_argument("packet size must be 1, 8, 16, 64 or 256");
  if (packet == 1) {
    trace_singles<S, Any, Count>(t, leaves, rays, begin, end, out, c);
    return;
  }
  // Whether the valid rays of [i, i + n) share a direction octant, and whether one of them needs
  // the robust slab test: 8 rays per step, from the SoA lanes.
  auto coherent = [&](std::size_t i, std::size_t n) {
    int oct = -1;
    for (std::size_t k = i; k < i + n; k += 8) {
      const int valid = _mm256_movemask_ps(_mm256_cmp_ps(_mm256_loadu_ps(&rays.tmin[k]), _mm256_loadu_ps(&rays.tmax[k]), _CMP_LE_OQ));
      const int sx = _mm256_movemask_ps(_mm256_loadu_ps(&rays.dx[k])) & valid, sy = _mm256_movemask_ps(_mm256_loadu_ps(&rays.dy[k])) & valid,
                sz = _mm256_movemask_ps(_mm256_loadu_ps(&rays.dz[k])) & valid;
      if (!((sx == 0 || sx == valid) && (sy == 0 || sy == valid) && (sz == 0 || sz == valid))) return false;
      if (!valid) continue;
      const int q = (sx != 0) | (sy != 0) << 1 | (sz != 0) << 2;  // the group's octant
      if (oct >= 0 && q != oct) return false;
      oct = q;
    }
    return true;
  };
  auto robust = [&](std::size_t i, std::size_t n) {
    if constexpr (S == Slab::robust) return true;
    const __m256 zero = _mm256_setzero_ps(), bound = _mm256_set1_ps(t.origin_bound);
    const __m256 abs_mask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    for (std::size_t k = i; k < i + n; k += 8) {
      const __m256 tmin = _mm256_loadu_ps(&rays.tmin[k]);
      const int valid = _mm256_movemask_ps(_mm256_cmp_ps(tmin, _mm256_loadu_ps(&rays.tmax[k]), _CMP_LE_OQ));
      int need = _mm256_movemask_ps(_mm256_cmp_ps(tmin, zero, _CMP_NGE_UQ));  // !(tmin >= 0)
      if constexpr (S == Slab::conservative) {
        auto beyond = [&](const float* o) {  // !(|o| <= bound), NaN included
          return _mm256_movemask_ps(_mm256_cmp_ps(_mm256_and_ps(_mm256_loadu_ps(o), abs_mask), bound, _CMP_NLE_UQ));
        };
        need |= beyond(&rays.ox[k]) | beyond(&rays.oy[k]) | beyond(&rays.oz[k]);
      }
      if (need & valid) return true;
    }
    return false;
  };
  auto run = [&]<int G>(std::size_t i) {
    if (robust(i, 8 * G)) trace_packet<true, Any, Count, G>(t, leaves, rays, i, out, c);
    else trace_packet<false, Any, Count, G>(t, leaves, rays, i, out, c);
  };
  // Whether the valid rays of [i, i + 8) start far apart: their origins' box is over 1/16 of the
  // scene's box along some axis. Such rays share no nodes, so two of them walk at once; rays that
  // start near each other walk one after another on the nodes the previous one brought in.
  const float near_side = detail::largest_side(t) * (1.0f / 16);
  auto apart = [&](std::size_t k) {
    const f8_mask valid = f8::load_unaligned(&rays.tmin[k]) <= f8::load_unaligned(&rays.tmax[k]);
    float side = 0;
    for (const float* o : {&rays.ox[k], &rays.oy[k], &rays.oz[k]}) {
      const f8 v = f8::load_unaligned(o);
      side = std::max(side, detail::hmax8(xsimd::select(valid, v, f8(-detail::kInfF))) - detail::hmin8(xsimd::select(valid, v, f8(detail::kInfF))));
    }
    return side > near_side;
  };
  auto eights = [&](std::size_t i, std::size_t e) {
    for (; i < e; i += 8) {
      if (coherent(i, 8)) run.template operator()<1>(i);
      else if (!apart(i))
        trace_singles<S, Any, Count>(t, leaves, rays, i, i + 8, out, c);
      else if (robust(i, 8)) trace_pairs<true, Any, Count>(t, leaves, rays, i, out, c);
      else trace_pairs<false, Any, Count>(t, leaves, rays, i, out, c);
    }
  };
  const std::size_t P = std::size_t(packet);
  std::size_t i = begin;
  for (; i + P <= end; i += P) {
    if (P == 8 || !coherent(i, P)) eights(i, i + P);
    else if (P == 16) run.template operator()<2>(i);
    else if (P == 64) run.template operator()<8>(i);
    else run.template operator()<32>(i);
  }
  eights(i, end);
}

}  // namespace rb::bvh
