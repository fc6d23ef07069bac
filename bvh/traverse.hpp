// Traversal of the 8-wide BVH: one slab test, one loop per ray mode (single rays, packets of 8 or
// 16 rays in lanes), closest or any hit, counted or not. Templates over a leaf source, so the BVH
// knows nothing of primitives: whatever intersects the leaves (tracer/leaves.hpp for a scene) is
// instantiated into the loop, chosen once per scene, never switched per ray.
//
// A leaf source L provides:
//   using RayCache;                   per single ray: whatever its leaves precompute, lazily
//   template <int H> using PacketCache;  the same for a packet of 8 x H rays
//   bool single(ref, const Ray<float>& r, RayCache&, HitRec& h) const;
//       the ray against leaf `ref`'s primitives with tmax = h.t; true when h was improved (h.t,
//       h.prim updated); never called with an empty leaf
//   template <bool Any, int H> void packet(ref, Packet<H>& p, PacketCache<H>&) const;
//       the packet's active rays against the leaf: improves p.tbest and p.prim per lane; with Any,
//       clears p.active of rays that hit
//   std::uint32_t slots(ref) const;   real primitives in the leaf (for the counted traversal)
//
// The slab test: t = box * (1/d) - o * (1/d), one FMA per plane with o * (1/d) precomputed per
// ray; the near plane per axis is chosen once per ray from the sign of 1/d. It is exact enough
// when the boxes were made conservative for the ray's origin (bvh::make_conservative: boxes
// widened at build time); a ray whose origin lies beyond that bound is traced with the robust
// test instead (Ize 2013, "Robust BVH Ray Traversal": t = (box - o) * (1/d), the far distance
// scaled by 1 + 2 gamma(3)). The choice is made once per ray (per packet), by a template switch.
//
// The stack holds at most 7 entries per wide level (Bvh8::stack_entries), sized from the built
// tree, so a push can never overrun it.
#pragma once

#include "bvh/bvh.hpp"
#include "core/ray.hpp"
#include "soa/rays.hpp"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <limits>
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
inline constexpr float kMinDir = 1e-18f;
inline float safe_rcp(float d) { return 1.0f / (std::fabs(d) < kMinDir ? std::copysign(kMinDir, d) : d); }
inline f8 safe_rcp8(const f8& d) {
  const f8 m = xsimd::select(xsimd::abs(d) < f8(kMinDir), xsimd::copysign(f8(kMinDir), d), d);
  return f8(1.0f) / m;
}

namespace detail {

inline constexpr float kInfF = std::numeric_limits<float>::infinity();

inline unsigned movemask(const f8_mask& m) { return unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_castps_si256(m)))); }
// Smallest lane and its index.
inline int argmin8(const f8& t, float& best) {
  const __m256 v = t;
  __m256 m = _mm256_min_ps(v, _mm256_permute_ps(v, 0xB1));
  m = _mm256_min_ps(m, _mm256_permute_ps(m, 0x4E));
  m = _mm256_min_ps(m, _mm256_permute2f128_ps(m, m, 1));
  best = _mm256_cvtss_f32(m);
  const unsigned bits = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(v, m, _CMP_EQ_OQ)));
  return bits ? __builtin_ctz(bits) : 0;
}
inline float hmin8(const f8& t) {
  float b;
  argmin8(t, b);
  return b;
}
inline float hmax8(const f8& t) {
  const __m256 v = t;
  __m256 m = _mm256_max_ps(v, _mm256_permute_ps(v, 0xB1));
  m = _mm256_max_ps(m, _mm256_permute_ps(m, 0x4E));
  m = _mm256_max_ps(m, _mm256_permute2f128_ps(m, m, 1));
  return _mm256_cvtss_f32(m);
}

struct Entry {
  std::uint32_t ref;
  float d;
};

// Sorts `n` (>= 2) entries by distance, farthest first (so the nearest is popped first).
inline void sort_far_first(Entry* e, int n) {
  for (int i = 1; i < n; ++i) {
    const Entry x = e[i];
    int j = i - 1;
    while (j >= 0 && e[j].d < x.d) { e[j + 1] = e[j]; --j; }
    e[j + 1] = x;
  }
}

// Pops entries until one is not beyond `t` (NaN distances are kept: `d > t` is false for them);
// false when the stack runs empty.
RB_INLINE bool pop_nearer(const Entry* stack, std::size_t& sp, float t, std::uint32_t& ref) {
  while (sp > 0) {
    --sp;
    if (!(stack[sp].d > t)) {
      ref = stack[sp].ref;
      return true;
    }
  }
  return false;
}

// The traversal stack: a local array when the tree's bound fits it (every tree up to depth 73),
// else a heap array of the bound's size.
inline constexpr std::size_t kLocalStack = 512;
struct Stack {
  Entry local[kLocalStack];
  std::vector<Entry> heap;
  Entry* data;
  explicit Stack(const Bvh8& t) {
    if (t.stack_entries() <= kLocalStack) {
      data = local;
    } else {
      heap.resize(t.stack_entries());
      data = heap.data();
    }
  }
};

// Whether a ray with this origin needs the robust slab test (its origin is beyond the bound the
// boxes were made conservative for).
inline bool beyond_bound(const Bvh8& t, const Vec3f& o) {
  return !(std::max({std::fabs(o.x), std::fabs(o.y), std::fabs(o.z)}) <= t.origin_bound);
}

}  // namespace detail

// ---- the slab test of one ray against a node's 8 child boxes ------------------------------------
struct SlabRay {
  f8 rdx, rdy, rdz, ox, oy, oz, orx, ory, orz, tmin;
  int nx, ny, nz;  // 1 where 1/d < 0: the near plane is the box's hi
  static SlabRay make(const Ray<float>& r) {
    SlabRay s;
    const float x = safe_rcp(r.d.x), y = safe_rcp(r.d.y), z = safe_rcp(r.d.z);
    s.rdx = f8(x); s.rdy = f8(y); s.rdz = f8(z);
    s.ox = f8(r.o.x); s.oy = f8(r.o.y); s.oz = f8(r.o.z);
    s.orx = f8(r.o.x * x); s.ory = f8(r.o.y * y); s.orz = f8(r.o.z * z);
    s.tmin = f8(r.tmin);
    s.nx = x < 0; s.ny = y < 0; s.nz = z < 0;
    return s;
  }
};

// Bit k set when the ray's [tmin, tmax] interval meets child k's box; tn receives the entry
// distances.
template <bool Robust>
RB_INLINE unsigned slab8(const WNode& n, const SlabRay& r, float tmax, f8& tn) {
  f8 tnx, tny, tnz, tfx, tfy, tfz;
  if constexpr (!Robust) {
    tnx = xsimd::fms(f8::load_aligned(n.b[0 + r.nx]), r.rdx, r.orx);
    tfx = xsimd::fms(f8::load_aligned(n.b[1 - r.nx]), r.rdx, r.orx);
    tny = xsimd::fms(f8::load_aligned(n.b[2 + r.ny]), r.rdy, r.ory);
    tfy = xsimd::fms(f8::load_aligned(n.b[3 - r.ny]), r.rdy, r.ory);
    tnz = xsimd::fms(f8::load_aligned(n.b[4 + r.nz]), r.rdz, r.orz);
    tfz = xsimd::fms(f8::load_aligned(n.b[5 - r.nz]), r.rdz, r.orz);
  } else {
    tnx = (f8::load_aligned(n.b[0 + r.nx]) - r.ox) * r.rdx;
    tfx = (f8::load_aligned(n.b[1 - r.nx]) - r.ox) * r.rdx;
    tny = (f8::load_aligned(n.b[2 + r.ny]) - r.oy) * r.rdy;
    tfy = (f8::load_aligned(n.b[3 - r.ny]) - r.oy) * r.rdy;
    tnz = (f8::load_aligned(n.b[4 + r.nz]) - r.oz) * r.rdz;
    tfz = (f8::load_aligned(n.b[5 - r.nz]) - r.oz) * r.rdz;
  }
  tn = xsimd::max(xsimd::max(tnx, tny), xsimd::max(tnz, r.tmin));
  f8 tf = xsimd::min(xsimd::min(tfx, tfy), tfz);
  if constexpr (Robust) tf = tf * f8(kRobustScale);
  tf = xsimd::min(tf, f8(tmax));
  return unsigned(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
}

// The finished hit: t = +inf when nothing was hit (the contract of Hit).
RB_INLINE HitRec finished(HitRec h) {
  if (h.prim == kNoPrim) h.t = detail::kInfF;
  return h;
}

// ---- single ray ----------------------------------------------------------------------------------
template <Slab S, bool Any, bool Count, class L>
HitRec trace_single(const Bvh8& t, const L& leaves, const Ray<float>& r, TraceCounters& c) {
  using namespace detail;
  if (!(r.tmin <= r.tmax) || t.nodes.empty()) return {kInfF, kNoPrim};
  if constexpr (S == Slab::conservative)
    if (beyond_bound(t, r.o)) return trace_single<Slab::robust, Any, Count>(t, leaves, r, c);
  constexpr bool Robust = S == Slab::robust;
  HitRec h{r.tmax, kNoPrim};
  const SlabRay sr = SlabRay::make(r);
  typename L::RayCache cache;
  Stack st(t);
  Entry* stack = st.data;
  std::size_t sp = 0;
  std::uint32_t ref = 0;
  for (;;) {
    if (!is_leaf(ref)) {
      const WNode& n = t.nodes[ref];
      if constexpr (Count) {
        ++c.nodes;
        for (int k = 0; k < 8; ++k) c.boxes += n.child[k] != kEmpty;
      }
      f8 tn;
      unsigned bits = slab8<Robust>(n, sr, h.t, tn);
      if (bits == 0) goto pop;
      if ((bits & (bits - 1)) == 0) {
        ref = n.child[__builtin_ctz(bits)];
        continue;
      }
      alignas(32) float dist[8];
      tn.store_aligned(dist);
      Entry e[8];
      int ne = 0;
      while (bits) {
        const int k = __builtin_ctz(bits);
        bits &= bits - 1;
        e[ne++] = {n.child[k], dist[k]};
      }
      sort_far_first(e, ne);
      for (int k = 0; k < ne - 1; ++k) stack[sp++] = e[k];
      ref = e[ne - 1].ref;
      continue;
    }
    if constexpr (Count) {
      const std::uint32_t s = leaves.slots(ref);
      c.prims += s;
      c.kind_prims[leaf_kind(ref)] += s;
    }
    if (leaves.single(ref, r, cache, h) && Any) return h;
  pop:
    if (!pop_nearer(stack, sp, h.t, ref)) return finished(h);
  }
}

// ---- packets of 8 x H rays (rays in lanes) -------------------------------------------------------
template <int H>
struct Packet {
  Ray<f8> r[H];
  f8 rdx[H], rdy[H], rdz[H], orx[H], ory[H], orz[H];
  f8 tbest[H];  // the ray's current tmax (the closest hit so far)
  f8_mask active[H];
  std::uint32_t prim[8 * H];
};

// Records a leaf's hits for the 8 rays of half k: lanes of `hit` that are active take t (already
// below their tbest: the kernel ran with tmax = tbest) and the primitive `code`; with Any, the rays
// that hit leave the packet.
template <bool Any, int H>
RB_INLINE void packet_update(Packet<H>& p, int k, const f8_mask& hit, const f8& t, std::uint32_t code) {
  const f8_mask m = hit & p.active[k];
  unsigned bits = detail::movemask(m);
  if (!bits) return;
  p.tbest[k] = xsimd::select(m, t, p.tbest[k]);
  while (bits) {
    const int l = __builtin_ctz(bits);
    bits &= bits - 1;
    p.prim[8 * k + l] = code;
  }
  if constexpr (Any) p.active[k] = p.active[k] & ~m;
}

template <int H>
RB_INLINE float packet_tmax(const Packet<H>& p) {
  f8 m = xsimd::select(p.active[0], p.tbest[0], f8(-detail::kInfF));
  for (int k = 1; k < H; ++k) m = xsimd::max(m, xsimd::select(p.active[k], p.tbest[k], f8(-detail::kInfF)));
  return detail::hmax8(m);
}

template <bool Robust, bool Any, bool Count, int H, class L>
void trace_packet(const Bvh8& t, const L& leaves, const RaySoA& rays, std::size_t i, HitRec* out, TraceCounters& c) {
  using namespace detail;
  Packet<H> p;
  bool live = false;
  for (int k = 0; k < H; ++k) {
    p.r[k] = rays.packet<f8>(i + 8 * std::size_t(k));
    p.rdx[k] = safe_rcp8(p.r[k].d.x);
    p.rdy[k] = safe_rcp8(p.r[k].d.y);
    p.rdz[k] = safe_rcp8(p.r[k].d.z);
    p.orx[k] = p.r[k].o.x * p.rdx[k];
    p.ory[k] = p.r[k].o.y * p.rdy[k];
    p.orz[k] = p.r[k].o.z * p.rdz[k];
    p.tbest[k] = p.r[k].tmax;
    p.active[k] = p.r[k].tmin <= p.r[k].tmax;
    live = live || any_of<f8>(p.active[k]);
  }
  for (auto& q : p.prim) q = kNoPrim;
  if (live && !t.nodes.empty()) {
    typename L::template PacketCache<H> cache;
    Stack st(t);
    Entry* stack = st.data;
    std::size_t sp = 0;
    std::uint32_t ref = 0;
    for (;;) {
      if (!is_leaf(ref)) {
        const WNode& n = t.nodes[ref];
        if constexpr (Count) ++c.nodes;
        Entry e[8];
        int ne = 0;
        for (int ch = 0; ch < 8; ++ch) {
          const std::uint32_t cr = n.child[ch];
          if (cr == kEmpty) break;
          const f8 lx(n.b[0][ch]), hx(n.b[1][ch]), ly(n.b[2][ch]), hy(n.b[3][ch]), lz(n.b[4][ch]), hz(n.b[5][ch]);
          float dmin = kInfF;
          for (int k = 0; k < H; ++k) {
            if constexpr (Count) c.boxes += std::uint64_t(count_true<f8>(p.active[k]));
            f8 x0, x1, y0, y1, z0, z1;
            if constexpr (!Robust) {
              x0 = xsimd::fms(lx, p.rdx[k], p.orx[k]); x1 = xsimd::fms(hx, p.rdx[k], p.orx[k]);
              y0 = xsimd::fms(ly, p.rdy[k], p.ory[k]); y1 = xsimd::fms(hy, p.rdy[k], p.ory[k]);
              z0 = xsimd::fms(lz, p.rdz[k], p.orz[k]); z1 = xsimd::fms(hz, p.rdz[k], p.orz[k]);
            } else {
              x0 = (lx - p.r[k].o.x) * p.rdx[k]; x1 = (hx - p.r[k].o.x) * p.rdx[k];
              y0 = (ly - p.r[k].o.y) * p.rdy[k]; y1 = (hy - p.r[k].o.y) * p.rdy[k];
              z0 = (lz - p.r[k].o.z) * p.rdz[k]; z1 = (hz - p.r[k].o.z) * p.rdz[k];
            }
            const f8 tn = xsimd::max(xsimd::max(xsimd::min(x0, x1), xsimd::min(y0, y1)), xsimd::max(xsimd::min(z0, z1), p.r[k].tmin));
            f8 tf = xsimd::min(xsimd::min(xsimd::max(x0, x1), xsimd::max(y0, y1)), xsimd::max(z0, z1));
            if constexpr (Robust) tf = tf * f8(kRobustScale);
            tf = xsimd::min(tf, p.tbest[k]);
            const f8_mask m = (tn <= tf) & p.active[k];
            if (any_of<f8>(m)) dmin = std::min(dmin, hmin8(xsimd::select(m, tn, f8(kInfF))));
          }
          if (dmin < kInfF) e[ne++] = {cr, dmin};
        }
        if (ne == 0) goto pop;
        if (ne > 1) {
          sort_far_first(e, ne);
          for (int k = 0; k < ne - 1; ++k) stack[sp++] = e[k];
        }
        ref = e[ne - 1].ref;
        continue;
      }
      if constexpr (Count) {
        const std::uint32_t s = leaves.slots(ref);
        std::uint64_t act = 0;
        for (int k = 0; k < H; ++k) act += std::uint64_t(count_true<f8>(p.active[k]));
        c.prims += s * act;
        c.kind_prims[leaf_kind(ref)] += s * act;
      }
      leaves.template packet<Any, H>(ref, p, cache);
      if constexpr (Any) {
        bool alive = false;
        for (int k = 0; k < H; ++k) alive = alive || any_of<f8>(p.active[k]);
        if (!alive) break;
      }
    pop:
      {
        const float tm = packet_tmax(p);
        do {
          if (sp == 0) goto done;
          --sp;
        } while (stack[sp].d > tm);
        ref = stack[sp].ref;
      }
    }
  }
done:
  for (int k = 0; k < H; ++k) {
    alignas(32) float tt[8];
    p.tbest[k].store_aligned(tt);
    for (int l = 0; l < 8; ++l) {
      const std::size_t r = i + 8 * std::size_t(k) + std::size_t(l);
      const std::uint32_t pr = p.prim[8 * k + l];
      out[r] = {pr == kNoPrim ? kInfF : tt[l], pr};
    }
  }
}

// ---- a range of rays -----------------------------------------------------------------------------
// Rays [begin, end) (begin a multiple of 8, the SoA padded to 8) into out. packet 1: one ray at a
// time; 8 or 16: packets of that many rays when they share a direction octant (coherent: camera
// tiles, rays towards one light); an incoherent packet's rays part ways at the first nodes, so
// they traverse one by one.
template <Slab S, bool Any, bool Count, class L>
void trace_range(const Bvh8& t, const L& leaves, const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, int packet,
                 TraceCounters& c) {
  if (packet != 1 && packet != 8 && packet != 16) throw std::invalid_argument("packet size must be 1, 8 or 16");
  if (packet == 1) {
    for (std::size_t i = begin; i < end; ++i) out[i] = trace_single<S, Any, Count>(t, leaves, rays.get(i), c);
    return;
  }
  auto coherent = [&](std::size_t i, std::size_t n) {
    int oct = -1;
    for (std::size_t k = i; k < i + n; ++k) {
      if (!(rays.tmin[k] <= rays.tmax[k])) continue;
      const int q = (rays.dx[k] < 0) | (rays.dy[k] < 0) << 1 | (rays.dz[k] < 0) << 2;
      if (oct >= 0 && q != oct) return false;
      oct = q;
    }
    return true;
  };
  // Conservative: the packet's fast test is conservative for every ray of it when every origin is
  // within the bound; otherwise the packet uses the robust test.
  auto robust = [&](std::size_t i, std::size_t n) {
    if constexpr (S == Slab::robust) return true;
    if constexpr (S == Slab::fast) return false;
    for (std::size_t k = i; k < i + n; ++k)
      if (rays.tmin[k] <= rays.tmax[k] && detail::beyond_bound(t, {rays.ox[k], rays.oy[k], rays.oz[k]})) return true;
    return false;
  };
  auto singles = [&](std::size_t i, std::size_t n) {
    for (std::size_t k = i; k < i + n; ++k) out[k] = trace_single<S, Any, Count>(t, leaves, rays.get(k), c);
  };
  std::size_t i = begin;
  if (packet == 16)
    for (; i + 16 <= end; i += 16) {
      if (!coherent(i, 16)) singles(i, 16);
      else if (robust(i, 16)) trace_packet<true, Any, Count, 2>(t, leaves, rays, i, out, c);
      else trace_packet<false, Any, Count, 2>(t, leaves, rays, i, out, c);
    }
  for (; i < end; i += 8) {
    if (!coherent(i, 8)) singles(i, 8);
    else if (robust(i, 8)) trace_packet<true, Any, Count, 1>(t, leaves, rays, i, out, c);
    else trace_packet<false, Any, Count, 1>(t, leaves, rays, i, out, c);
  }
}

}  // namespace rb::bvh
