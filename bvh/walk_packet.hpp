// The walk of a coherent packet (every ray in one direction octant: camera tiles, rays towards one
// light) of 8, 16, 64 or 256 rays in G groups of N lanes, as one: N = 8 (f8, AVX2) everywhere, or
// N = 16 (f16, in the AVX-512 translation unit tracer/traverse_mesh16.cpp) for packets of 16 or more
// rays. Per node:
//   - one 8-lane test of the 8 children against the packet's frustum (SlabFrustum: per axis the
//     ray whose origin and reciprocal direction bound every ray's entry distance from below and
//     exit distance from above; the same slab test on those extremes, so it is conservative exactly
//     as the per-ray test is: it never rejects a box one of the rays' tests would accept);
//   - packets of more than one group: one 8-lane test of the first active ray against the 8
//     children; an internal child that ray hits is taken with the parent's ray mask unchanged (no
//     per-ray test), as the rays of a coherent packet mostly share their boxes (one group of 16
//     rays tests every child exactly: one 16-lane test costs less than what the skipped tests
//     saved, measured 1.04-1.12x on 16-ray packets of the bunny and the dragon);
//   - every other child the frustum accepts (leaves always, so that a leaf sees exact ray masks)
//     gets the exact test of each active group of N rays; the rays that hit it form its mask.
// The node tests of the frustum and of one ray stay 8-lane (8 children); only the groups' tests,
// the leaves' rays-in-lanes loops and the packet's bookkeeping take the group's width.
// Closest hit visits children near to far by the frustum's entry distance (bvh/stack.hpp's
// order); any hit in slot order. The stack holds (child, entry distance, ray mask). At a leaf, the
// leaf source tests the masked rays. Any hit: rays that hit leave the packet; it ends when none
// remain; at a node with at most kAnySingleRays active rays, those go on one by one
// (any_hits_alone). Closest-hit packets stay packets to their last ray (going on alone measured
// slower on two of three meshes; see docs/DESIGN.md).
#pragma once

#include "bvh/walk_single.hpp"

namespace rb::bvh {

// An any-hit packet with at most this many active rays at a node goes on ray by ray from there.
inline constexpr int kAnySingleRays = 3;

// A ray mask of G groups of N rays: N bits per group (ray f = N g + l at bit f).
template <int G, int N = 8>
struct RayMask {
  static constexpr int W = (G * N + 63) / 64;
  static constexpr std::uint64_t kGroup = (std::uint64_t(1) << N) - 1;
  std::uint64_t w[W];
  static RayMask none() {
    RayMask m;
    for (auto& x : m.w) x = 0;
    return m;
  }
  unsigned group(int g) const { return unsigned(w[(N * g) >> 6] >> ((N * g) & 63) & kGroup); }
  void set(int g, unsigned bits) {
    const int s = (N * g) & 63;
    std::uint64_t& x = w[(N * g) >> 6];
    x = (x & ~(kGroup << s)) | (std::uint64_t(bits) << s);
  }
  bool empty() const {
    std::uint64_t o = 0;
    for (auto x : w) o |= x;
    return o == 0;
  }
  int first() const {  // the lowest ray (N g + lane); the mask is not empty
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

// The packet's rays as the walk tests them: per group the rays, their slab terms, closest distance
// so far, the rays a leaf is to test, and the hit primitive per ray with its aux datum (HitRec::aux);
// the slab terms also per ray as scalars (the first active ray's own test); the rays still looking
// for a hit.
template <class V, int G>
struct Packet {
  using Lanes = lanes::Group<V>;
  static constexpr int N = Lanes::N;
  using Mask = RayMask<G, N>;
  Ray<V> r[G];
  SlabSideT<V> side[G];
  V tbest[G];
  typename Lanes::mask act[G];
  std::uint32_t prim[N * G];
  V aux[G];
  alignas(64) float rd_s[3][N * G], ord_s[3][N * G], o_s[3][N * G], tmin_s[N * G];
  Mask alive;

  // Rays [i, i + N G) of the SoA; a ray with an empty interval is not alive (a miss).
  void load(const RaySoA& rays, std::size_t i) {
    alive = Mask::none();
    for (int g = 0; g < G; ++g) {
      r[g] = rays.packet<V>(i + N * std::size_t(g));
      const Vec3<V>& d = r[g].d;
      const V inv[3] = {safe_rcp_lanes(d.x, r[g].rd.x), safe_rcp_lanes(d.y, r[g].rd.y), safe_rcp_lanes(d.z, r[g].rd.z)};
      const V oo[3] = {r[g].o.x, r[g].o.y, r[g].o.z};
      for (int a = 0; a < 3; ++a) {
        side[g].rd[a] = inv[a];
        side[g].o[a] = oo[a];
        side[g].o_rd[a] = oo[a] * inv[a];
        inv[a].store_aligned(&rd_s[a][N * g]);
        side[g].o_rd[a].store_aligned(&ord_s[a][N * g]);
        oo[a].store_aligned(&o_s[a][N * g]);
      }
      r[g].tmin.store_aligned(&tmin_s[N * g]);
      tbest[g] = r[g].tmax;
      alive.set(g, Lanes::bits(r[g].tmin <= r[g].tmax));
    }
    for (auto& q : prim) q = kNoPrim;
  }
  void load_aux() {
    for (auto& a : aux) a = V(0);
  }
  // The frustum of the alive rays: per axis their extreme origins and reciprocal directions.
  SlabFrustum frustum() const {
    V lrd[3], hrd[3], lo[3], ho[3], tm(kInfF);
    for (int a = 0; a < 3; ++a) lrd[a] = lo[a] = V(kInfF), hrd[a] = ho[a] = V(-kInfF);
    for (int g = 0; g < G; ++g) {
      const auto v = Lanes::of(alive.group(g));
      for (int a = 0; a < 3; ++a) {
        lrd[a] = xsimd::min(lrd[a], xsimd::select(v, side[g].rd[a], V(kInfF)));
        hrd[a] = xsimd::max(hrd[a], xsimd::select(v, side[g].rd[a], V(-kInfF)));
        lo[a] = xsimd::min(lo[a], xsimd::select(v, side[g].o[a], V(kInfF)));
        ho[a] = xsimd::max(ho[a], xsimd::select(v, side[g].o[a], V(-kInfF)));
      }
      tm = xsimd::min(tm, xsimd::select(v, r[g].tmin, V(kInfF)));
    }
    SlabFrustum fr;
    const int f0 = alive.first();
    for (int a = 0; a < 3; ++a) {
      const float lo_rd = Lanes::hmin(lrd[a]), hi_rd = Lanes::hmax(hrd[a]), lo_o = Lanes::hmin(lo[a]), hi_o = Lanes::hmax(ho[a]);
      const bool neg = std::signbit(rd_s[a][f0]);
      fr.n[a] = neg;
      // positive axis: entry bounded by (lo plane, largest origin, smallest 1/d), exit by (hi plane,
      // smallest origin, largest 1/d); a negative axis swaps the planes and the origin/1/d pairs.
      const float rn = neg ? hi_rd : lo_rd, on = neg ? lo_o : hi_o;
      const float rf = neg ? lo_rd : hi_rd, of = neg ? hi_o : lo_o;
      fr.near.rd[a] = f8(rn); fr.near.o[a] = f8(on); fr.near.o_rd[a] = f8(on * rn);
      fr.far.rd[a] = f8(rf); fr.far.o[a] = f8(of); fr.far.o_rd[a] = f8(of * rf);
    }
    fr.tmin = f8(Lanes::hmin(tm));
    return fr;
  }
  // Ray f (N g + lane) alone, broadcast, for the test against a node's children.
  RB_INLINE SlabRay one(int f, const int (&n)[3]) const {
    SlabRay s;
    for (int a = 0; a < 3; ++a) {
      s.n[a] = n[a];
      s.s.rd[a] = f8(rd_s[a][f]);
      s.s.o_rd[a] = f8(ord_s[a][f]);
      s.s.o[a] = f8(o_s[a][f]);
    }
    s.tmin = f8(tmin_s[f]);
    return s;
  }
  // The largest closest distance among the rays of m (the frustum's tmax).
  RB_INLINE float tmax_of(const Mask& m) const {
    V x(-kInfF);
    for (int g = 0; g < G; ++g)
      if (const unsigned b = m.group(g)) x = xsimd::max(x, xsimd::select(Lanes::of(b), tbest[g], V(-kInfF)));
    return Lanes::hmax(x);
  }
  // The rays' hits into out[i, i + N G), with their aux data where the leaf source keeps them (Aux:
  // then load_aux ran after load).
  template <bool Aux>
  void finish(std::size_t i, HitRec* out) const {
    for (int g = 0; g < G; ++g) {
      alignas(64) float tt[N], ta[N];
      tbest[g].store_aligned(tt);
      if constexpr (Aux) aux[g].store_aligned(ta);
      for (int l = 0; l < N; ++l) {
        const std::uint32_t pr = prim[N * g + l];
        out[i + N * std::size_t(g) + std::size_t(l)] = {pr == kNoPrim ? kInfF : tt[l], pr, Aux ? ta[l] : 0.0f};
      }
    }
  }
};

// The few rays `left` of an any-hit packet at node `ref`, each on alone from there (the single-ray
// walk). The packet's frustum still spans every ray it started with, so it accepts children none
// of the few remaining rays meets, and each such child costs an 8-lane test with most lanes idle;
// alone, a ray tests a node's 8 children in one. Out of line (inlined, it changed the packet loop's
// register allocation and slowed shadow packets).
template <bool Robust, bool Count, class V, int G, class L>
[[gnu::noinline]] void any_hits_alone(const Bvh8& t, const L& leaves, const RaySoA& rays, std::size_t i, std::uint32_t ref,
                                      typename Packet<V, G>::Mask left, Packet<V, G>& p, TraceCounters& c) {
  constexpr int N = Packet<V, G>::N;
  Stack st(t);
  while (!left.empty()) {
    const int f = left.first(), g = f / N, l = f % N;
    left.set(g, left.group(g) & ~(1u << l));
    const HitRec h = single_loop<Robust, true, Count>(t, leaves, rays.get(i + std::size_t(f)), st, c, ref);
    if (h.prim == kNoPrim) continue;
    p.prim[f] = h.prim;
    p.tbest[g] = xsimd::select(Packet<V, G>::Lanes::of(1u << l), V(h.t), p.tbest[g]);
    if constexpr (carries_aux<L>) p.aux[g] = xsimd::select(Packet<V, G>::Lanes::of(1u << l), V(h.aux), p.aux[g]);
    p.alive.set(g, p.alive.group(g) & ~(1u << l));
  }
}

// The rays of `mask` against node n's children the frustum accepts (`bits`): each child's ray
// mask into cm, children no ray meets cleared from bits.
template <bool Robust, bool Count, class V, int G, class Mask>
RB_INLINE void child_masks(const WNode& n, const SlabFrustum& fr, const Packet<V, G>& p, const Mask& mask, unsigned& bits, Mask (&cm)[8],
                           [[maybe_unused]] std::uint64_t real, TraceCounters& c) {
  constexpr int N = Packet<V, G>::N;
  unsigned inherit = 0;
  if constexpr (G > 1) {
    // The first active ray against the 8 children: the internal children it meets keep the mask.
    const int f = mask.first();
    alignas(64) float tb[N];
    p.tbest[f / N].store_aligned(tb);
    f8 tn1;
    if constexpr (Count) c.boxes += real;
    const unsigned leaf_children = lanes::top_bits(n.child);  // kLeafBit is the top bit
    inherit = slab8<Robust>(n, p.one(f, fr.n), tb[f % N], tn1) & bits & ~leaf_children;
  }
  for (unsigned e = bits & ~inherit; e; e &= e - 1) {
    const int k = __builtin_ctz(e);
    const float near[3] = {n.b[0 + fr.n[0]][k], n.b[2 + fr.n[1]][k], n.b[4 + fr.n[2]][k]};
    const float far[3] = {n.b[1 - fr.n[0]][k], n.b[3 - fr.n[1]][k], n.b[5 - fr.n[2]][k]};
    Mask m = Mask::none();
    for (int g = 0; g < G; ++g) {
      const unsigned gb = mask.group(g);
      if (!gb) continue;
      if constexpr (Count) c.boxes += std::uint64_t(__builtin_popcount(gb));
      m.set(g, gb & slab_rays<Robust>(near, far, p.side[g], p.r[g].tmin, p.tbest[g]));
    }
    if (m.empty()) bits &= ~(1u << k);
    else cm[k] = m;
  }
  for (unsigned e = inherit; e; e &= e - 1) cm[__builtin_ctz(e)] = mask;
}

// Where the packet goes from a node: the hit children (bits, at least one) near to far (closest
// hit) or in slot order (any hit: sorting does not pay; docs/DESIGN.md section 12), the
// nearest next (ref, mask), the others pushed with their distance and mask.
template <bool Robust, bool Any, class Mask>
RB_INLINE void push_children(const WNode& n, const f8& tn, unsigned bits, const Mask (&cm)[8], std::uint32_t& ref, Mask& mask, Stack& st,
                             Mask* smask, std::size_t& sp) {
  if ((bits & (bits - 1)) == 0) {
    const int k = __builtin_ctz(bits);
    ref = n.child[k];
    mask = cm[k];
    return;
  }
  alignas(32) std::uint32_t slot[8];
  alignas(32) float dist[8];
  tn.store_aligned(dist);
  const int cnt = __builtin_popcount(bits);
  if constexpr (Any) lanes::store8_aligned(slot, lanes::compaction(bits));
  else if (cnt == 2) {
    const PairOrder o = pair_order(tn, bits);
    slot[0] = std::uint32_t(o.far);
    slot[1] = std::uint32_t(o.near);
  } else lanes::store8_aligned(slot, far_first<Robust>(tn, bits));
  for (int k = 0; k < cnt - 1; ++k) {
    st.ref[sp] = n.child[slot[k]];
    st.d[sp] = dist[slot[k]];
    smask[sp] = cm[slot[k]];
    ++sp;
  }
  RB_STACK_CHECK(sp, st.cap);
  ref = n.child[slot[cnt - 1]];
  mask = cm[slot[cnt - 1]];
}

// The rays of `mask` against leaf `ref` (the leaf source's packet function); any hit: the rays
// that hit leave `alive`; closest hit: tmax_all follows the rays' closest distances.
template <bool Any, bool Count, class V, int G, class L, class Mask, class Cache>
RB_INLINE void visit_packet_leaf(const L& leaves, std::uint32_t ref, const Mask& mask, Packet<V, G>& p, PacketRaysT<V>& view, Cache& cache,
                                 float& tmax_all, TraceCounters& c) {
  using Lanes = lanes::Group<V>;
  view.n = 0;
  for (int g = 0; g < G; ++g) {
    const unsigned gb = mask.group(g);
    p.act[g] = Lanes::of(gb);
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
      const unsigned hit = mask.group(g) & ~Lanes::bits(p.act[g]);  // the leaf cleared the rays that hit
      p.alive.set(g, p.alive.group(g) & ~hit);
    }
  } else if (view.improved) {
    tmax_all = p.tmax_of(p.alive);
  }
}

// Rays [i, i + N G) as one packet of G groups of V (N lanes each), into out. The leaf source gives
// its packet function for groups of V and its cache for them (L::PacketCacheFor<V>).
template <bool Robust, bool Any, bool Count, int G, class L, class V = f8>
void trace_packet(const Bvh8& t, const L& leaves, const RaySoA& rays, std::size_t i, HitRec* out, TraceCounters& c) {
  using Mask = typename Packet<V, G>::Mask;
  constexpr bool kAux = carries_aux<L>;
  Packet<V, G> p;
  p.load(rays, i);
  if constexpr (kAux) p.load_aux();
  if (p.alive.empty() || t.nodes.empty()) {
    p.template finish<kAux>(i, out);
    return;
  }
  const SlabFrustum fr = p.frustum();
  float tmax_all = p.tmax_of(p.alive);
  PacketRaysT<V> view;
  view.r = p.r;
  view.tbest = p.tbest;
  view.active = p.act;
  view.prim = p.prim;
  if constexpr (kAux) view.aux = p.aux;
  typename L::template PacketCacheFor<V> cache;
  Stack st(t);
  MaskStack<Mask> ms(t);
  std::size_t sp = 0;
  std::uint32_t ref = 0;
  Mask mask = p.alive;
  for (;;) {
    while (!is_leaf(ref)) {
      if constexpr (Any) {
        if (mask.count() <= kAnySingleRays) [[unlikely]] {
          any_hits_alone<Robust, Count, V, G>(t, leaves, rays, i, ref, mask, p, c);
          if (p.alive.empty()) goto done;
          goto pop;
        }
      }
      const WNode& n = t.nodes[ref];
      std::uint64_t real = 0;
      if constexpr (Count) {
        ++c.nodes;
        for (int k = 0; k < 8; ++k) real += n.child[k] != kEmpty;
        c.boxes += real;
      }
      f8 tn;
      unsigned bits = slab8<Robust>(n, fr, tmax_all, tn);
      if (bits == 0) goto pop;
      Mask cm[8];
      child_masks<Robust, Count>(n, fr, p, mask, bits, cm, real, c);
      if (bits == 0) goto pop;
      push_children<Robust, Any>(n, tn, bits, cm, ref, mask, st, ms.m, sp);
    }
    visit_packet_leaf<Any, Count>(leaves, ref, mask, p, view, cache, tmax_all, c);
    if (Any && p.alive.empty()) goto done;
  pop:
    for (;;) {
      if (sp == 0) goto done;
      --sp;
      const Mask m = Any ? ms.m[sp] & p.alive : ms.m[sp];
      if (m.empty()) continue;
      if (!Any && st.d[sp] > tmax_all) continue;
      ref = st.ref[sp];
      mask = m;
      break;
    }
  }
done:
  p.template finish<kAux>(i, out);
}

}  // namespace rb::bvh
