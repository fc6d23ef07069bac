// The leaves of a scene's BVH: each kind's batch in leaf order (every leaf one 8-slot group of its
// kind's batch, padded with never-hit slots) and the leaf functions that run the kind's kernel on a
// group, for one ray (the 8 primitives in lanes) or a packet (8 rays in lanes, one primitive at a
// time), in the method and precision the plan chose:
//   float              the kernel in 8 float lanes on the float batch;
//   double             the kernel in 4 double lanes (two calls per group) on the float batch
//                      widened: the arithmetic of double on the same stored primitive;
//   double storage     the same on a batch stored in double (the primitive made relative to the
//                      frame origin in double, never rounded to float).
// A kind has a second batch when the plan stores some of its primitives apart, in double
// (KindPlan::split): leaves of kind k carry the tag k, leaves of its apart batch the tag kKinds + k.
// The leaf sources that the walks of bvh/traverse.hpp instantiate: TableLeaves here (any scene: one function
// pointer per tag, chosen once per scene) and MeshLeaves in tracer/mesh_leaves.hpp (a
// triangle-only scene traced with Woop in float: the kernel inlined into the traversal loop;
// triangles stored apart in double by the double kernel).
#pragma once

#include "bvh/hit.hpp"
#include "core/spawn.hpp"
#include "soa/groups.hpp"
#include "tracer/kinds.hpp"

#include <immintrin.h>

#include <array>
#include <tuple>
#include <vector>

namespace rb::tracer {

using bvh::HitRec;
using bvh::kNoPrim;
using kinds::AllKinds;
using kinds::Kind;
using kinds::kKinds;
using kinds::MethodInfo;

// Leaf tags: kind k's batch is tag k, its primitives stored apart (in double) tag kKinds + k.
inline constexpr int kLeafKinds = 2 * kKinds;
static_assert(kLeafKinds <= bvh::kMaxKinds);
inline constexpr int apart_tag(Kind k) { return kKinds + int(k); }
inline constexpr Kind tag_kind(int tag) { return Kind(tag % kKinds); }

// ---- the double kernels on float rays -----------------------------------------------------------
namespace detail {
template <class D>
RB_INLINE Vec3<D> half3(const Vec3<f8>& v, bool hi) {
  using lanes::hi_d4, lanes::lo_d4;
  return hi ? Vec3<D>{hi_d4(v.x), hi_d4(v.y), hi_d4(v.z)} : Vec3<D>{lo_d4(v.x), lo_d4(v.y), lo_d4(v.z)};
}
// The double kernels' tmax for a closest t so far of `t` (float): the next float up, so that every
// double t that rounds to `t` reaches the float comparison (`bvh::nearer`) and a tie is decided
// by the code, whichever primitive came first. The largest float stays the largest float (a ray's
// tmax is finite).
inline double tmax64(float t) { return double(std::min(spawn::step_floats(t, 1), std::numeric_limits<float>::max())); }
inline f8 tmax64(const f8& t) {
  return xsimd::min(f8(spawn::step_floats8(t, 1)), f8(std::numeric_limits<float>::max()));
}
RB_INLINE Ray<d4> half_ray(const Ray<f8>& r, const f8& tmax, bool hi) {
  using lanes::hi_d4, lanes::lo_d4;
  return {half3<d4>(r.o, hi), half3<d4>(r.d, hi), half3<d4>(r.rd, hi), hi ? hi_d4(r.tmin) : lo_d4(r.tmin), hi ? hi_d4(tmax) : lo_d4(tmax)};
}
}  // namespace detail

// ---- per-ray and per-packet state the leaves prepare lazily --------------------------------------
// (User-provided constructors: the caches are made once per ray, and value-initialising their
// vectors would zero a few kilobytes each time.)
template <class K>
struct PreSlot {
  bool ready = false;
  typename K::template Pre<f8> v;
  PreSlot() {}
};
template <class... K>
struct PreTuple {
  std::tuple<PreSlot<K>...> slots;
};
template <class L>
struct PreTupleOf;
template <class... K>
struct PreTupleOf<kinds::KindList<K...>> {
  using type = PreTuple<K...>;
};
using AllPre = PreTupleOf<AllKinds>::type;

// One ray broadcast to 8 lanes and each kind's precompute on it (Woop's shear), made at the first
// leaf of that kind the ray reaches (most rays of a sparse view never reach one); and the aux datum
// of the ray's closest hit (HitRec::aux), written by the kinds that keep one (CSG: the leaf tag).
struct RayCache {
  Ray<f8> rb;
  bool ready = false;
  float aux = 0;
  AllPre pre;
  explicit RayCache(const Ray<float>&) {}
  RB_INLINE Ray<f8>& ray8(const Ray<float>& r) {
    if (!ready) {
      rb = Ray<f8>::broadcast(r);
      ready = true;
    }
    return rb;
  }
  template <class K>
  RB_INLINE const typename K::template Pre<f8>& pre8(const Ray<f8>& r) {
    auto& s = std::get<PreSlot<K>>(pre.slots);
    if (!s.ready) {
      s.v = K::pre(r);
      s.ready = true;
    }
    return s.v;
  }
};
// Each kind's precompute per group of a packet (up to bvh::kMaxGroups groups), made at the first
// leaf of that kind the group reaches.
struct PacketCache {
  template <class K>
  struct Slot {
    std::uint32_t ready = 0;  // bit g: group g's entry is made
    typename K::template Pre<f8> v[bvh::kMaxGroups];
    Slot() {}
  };
  template <class... K>
  struct Tuple {
    std::tuple<Slot<K>...> t;
  };
  template <class L>
  struct Of;
  template <class... K>
  struct Of<kinds::KindList<K...>> {
    using type = Tuple<K...>;
  };
  typename Of<AllKinds>::type slots;
  template <class K>
  RB_INLINE const typename K::template Pre<f8>& pre8(const bvh::PacketRays& p, int k) {
    auto& s = std::get<Slot<K>>(slots.t);
    if (!(s.ready >> k & 1u)) {
      s.v[k] = K::pre(p.r[k]);
      s.ready |= 1u << k;
    }
    return s.v[k];
  }
};

// ---- a standard kind's batch ---------------------------------------------------------------------
// A group of a batch in local frames (the primitives a plan stores apart, KindPlan::split_local):
// its primitives in float relative to an origin of its own (frame coordinates, in double), or, where
// no origin near them holds them in float to the plan's tolerance, in double: `deep` is then the
// group's index in the batch's double storage.
struct LocalFrame {
  Vec3d origin{0, 0, 0};
  std::uint32_t deep = UINT32_MAX;
};

template <class K>
struct StdBatch {
  PrimGroups<K::template Prim, float> f32;   // float storage, a leaf's group in one block
  PrimGroups<K::template Prim, double> f64;  // double storage (when the plan chose it)
  kinds::SlotIds id;                         // per slot: the scene index (UINT32_MAX: padding)
  // Per group, in a batch in local frames (empty otherwise), and the largest coordinate a float
  // group holds relative to its origin (the rounding its surfaces carry: SceneAccel::surface).
  std::vector<LocalFrame> local;
  double local_reach = 0;
  std::size_t bytes() const {
    return f32.bytes() + f64.bytes() + id.size() * sizeof(std::uint32_t) + local.size() * sizeof(LocalFrame);
  }
};
template <class K, bool Custom = K::custom>
struct BatchOf {
  using type = StdBatch<K>;
};
template <class K>
struct BatchOf<K, true> {
  using type = typename K::Batch;
};
template <class K>
using Batch = typename BatchOf<K>::type;

template <class L>
struct BatchTupleOf;
template <class... K>
struct BatchTupleOf<kinds::KindList<K...>> {
  using type = std::tuple<Batch<K>...>;
};
using Batches = BatchTupleOf<AllKinds>::type;

// The scene indices of a group are read only once a slot is hit, after the kernel: fetched when the
// leaf is entered, their cache miss overlaps the vertices' instead of following the kernel
// (docs/DESIGN.md section 8).
template <class B>
RB_INLINE void prefetch_ids(const B& b, std::size_t base) {
  __builtin_prefetch(b.id.data() + base, 0, 3);
}

// ---- the generic leaf functions of a standard kind -------------------------------------------------
// In double: the kernel in 4 double lanes, two calls per group, on the batch stored in double
// (Store64) or on the float batch widened. Needs no per-ray cache.
// `at`: the group's first slot in the double storage (base, but for a deep group of a batch in local
// frames).
template <class K, int M, bool Store64>
RB_INLINE bool std_single64(const StdBatch<K>& b, std::size_t base, const Ray<float>& r, bvh::Closest& h, std::size_t at) {
  Ray<d4> rd = Ray<d4>::broadcast(r);
  rd.tmax = d4(detail::tmax64(h.t));
  const auto pre = K::pre(rd);
  bool any = false;
  for (std::size_t half = 0; half < 2; ++half) {
    const std::size_t s = base + 4 * half;
    typename K::template Prim<d4> p;
    if constexpr (Store64) p = b.f64.template load<d4>(at + 4 * half);
    else p = b.f32.template load<d4>(s);
    const Hit<d4> hit = K::template hit<M>(rd, pre, p);
    const unsigned bits = lanes::bits(hit.mask);
    if (!bits) continue;
    alignas(32) double t[4];
    hit.t.store_aligned(t);
    for (int l = 0; l < 4; ++l) {
      if (!(bits >> l & 1u)) continue;
      const std::uint32_t code = kinds::code(K::id, b.id[s + std::size_t(l)]);
      if (bvh::nearer(float(t[l]), code, h)) {
        h = {float(t[l]), code};
        rd.tmax = d4(detail::tmax64(h.t));
        any = true;
      }
    }
  }
  return any;
}

template <class K, int M, bool F64, bool Store64>
RB_INLINE bool std_single(const StdBatch<K>& b, std::size_t base, const Ray<float>& r, RayCache& c, bvh::Closest& h) {
  prefetch_ids(b, base);
  if constexpr (!F64) {
    Ray<f8>& rb = c.ray8(r);
    rb.tmax = f8(h.t);
    const Hit<f8> hit = K::template hit<M>(rb, c.template pre8<K>(rb), b.f32.template load<f8>(base));
    if (none_of<f8>(hit.mask)) return false;
    return bvh::take_nearest(hit.t, h, [&](int lane) { return kinds::code(K::id, b.id[base + std::size_t(lane)]); });
  } else {
    return std_single64<K, M, Store64>(b, base, r, h, base);
  }
}

// A packet against one group in double: each primitive against the packet's rays in two 4-lane
// halves.
template <class K, int M, bool Store64, bool Any>
RB_INLINE void std_packet64(const StdBatch<K>& b, std::size_t base, bvh::PacketRays& p, std::size_t at) {
  for (std::size_t j = base; j < base + 8; ++j) {
    const std::uint32_t sid = b.id[j];
    if (sid == UINT32_MAX) continue;
    const std::uint32_t code = kinds::code(K::id, sid);
    typename K::template Prim<d4> prim;
    if constexpr (Store64) prim = b.f64.template broadcast<d4>(at + (j - base));
    else prim = b.f32.template broadcast<d4>(j);
    for (int q = 0; q < p.n; ++q) {
      const int k = p.list[q];
      if (none_of<f8>(p.active[k])) continue;
      const f8 tmax = detail::tmax64(p.tbest[k]);
      const Ray<d4> lo = detail::half_ray(p.r[k], tmax, false), hi = detail::half_ray(p.r[k], tmax, true);
      const Hit<d4> hl = K::template hit<M>(lo, K::pre(lo), prim), hh = K::template hit<M>(hi, K::pre(hi), prim);
      unsigned bits = lanes::bits(hl.mask) | lanes::bits(hh.mask) << 4;
      if (!bits) continue;
      // The kernel ran up to the next float above tbest: keep the hits whose float t is within it.
      const f8 t = lanes::join_f8(hl.t, hh.t);
      bits &= lanes::bits(t <= p.tbest[k]);
      if (!bits) continue;
      bvh::packet_update<Any>(p, k, lanes::of(bits), t, code);
    }
  }
}

template <class K, int M, bool F64, bool Store64, bool Any>
RB_INLINE void std_packet(const StdBatch<K>& b, std::size_t base, bvh::PacketRays& p, PacketCache& c) {
  if constexpr (F64) {
    std_packet64<K, M, Store64, Any>(b, base, p, base);
  } else {
    for (std::size_t j = base; j < base + 8; ++j) {
      const std::uint32_t sid = b.id[j];
      if (sid == UINT32_MAX) continue;
      const std::uint32_t code = kinds::code(K::id, sid);
      const auto prim = b.f32.template broadcast<f8>(j);
      for (int q = 0; q < p.n; ++q) {
        const int k = p.list[q];
        if (none_of<f8>(p.active[k])) continue;
        Ray<f8> rr = p.r[k];
        rr.tmax = p.tbest[k];
        const Hit<f8> hit = K::template hit<M>(rr, c.template pre8<K>(p, k), prim);
        bvh::packet_update<Any>(p, k, hit.mask, hit.t, code);
      }
    }
  }
}

// ---- a batch in local frames ------------------------------------------------------------------------
// A frame ray re-based at a group's origin g: its origin moved along the ray to the point nearest g,
// made relative to g in double and then rounded, so that the rounding is that of a vector of the
// group's size however far the ray came from. A t in the group's frame plus `shift` is the t on the
// ray; tmin and tmax are widened by a float step there, and the hits kept by their t on the ray.
struct LocalRay {
  Ray<float> r;
  double shift = 0;
};
// The re-basing itself, for one ray (D = double) or four (D = d4): o becomes the point of the ray
// nearest g, relative to g; returns the shift along the ray.
template <class D>
RB_INLINE D rebase(Vec3<D>& o, const Vec3<D>& d, const Vec3<D>& g) {
  const D s = dot(g - o, d) / dot(d, d);
  o = o + d * s - g;
  return s;
}
// A local t of 8 lanes back on the ray: plus the shifts of its two halves, in double.
RB_INLINE f8 ray_t(const f8& t, const d4& shift_lo, const d4& shift_hi) {
  return lanes::join_f8(lanes::lo_d4(t) + shift_lo, lanes::hi_d4(t) + shift_hi);
}
RB_INLINE LocalRay local_ray(const Ray<float>& r, const Vec3d& g, float tmax) {
  Vec3d o = to_double(r.o);
  const double s = rebase(o, to_double(r.d), g);
  LocalRay l{r, s};
  l.r.o = to_float(o);
  l.r.tmin = spawn::step_floats(float(double(r.tmin) - s), -1);
  l.r.tmax = spawn::step_floats(float(double(tmax) - s), 1);
  return l;
}

// Ray lane l of a group of 8.
RB_INLINE Ray<float> lane_ray(const Ray<f8>& r, int l) {
  alignas(32) float v[11][8];
  const f8* f[11] = {&r.o.x, &r.o.y, &r.o.z, &r.d.x, &r.d.y, &r.d.z, &r.rd.x, &r.rd.y, &r.rd.z, &r.tmin, &r.tmax};
  for (int i = 0; i < 11; ++i) f[i]->store_aligned(v[i]);
  return {{v[0][l], v[1][l], v[2][l]}, {v[3][l], v[4][l], v[5][l]}, {v[6][l], v[7][l], v[8][l]}, v[9][l], v[10][l]};
}

// One ray against a float group in its local frame at g: the kernel on the re-based ray, each hit's
// t brought back to the ray in double and kept within [r.tmin, h.t].
template <class K, int M>
RB_INLINE bool local_single(const StdBatch<K>& b, std::size_t base, const Vec3d& g, const Ray<float>& r, bvh::Closest& h) {
  const LocalRay l = local_ray(r, g, h.t);
  const Ray<f8> rb = Ray<f8>::broadcast(l.r);
  const Hit<f8> hit = K::template hit<M>(rb, K::pre(rb), b.f32.template load<f8>(base));
  if (none_of<f8>(hit.mask)) return false;
  const f8 t = ray_t(hit.t, d4(l.shift), d4(l.shift));
  const f8_mask ok = hit.mask & (t >= f8(r.tmin)) & (t <= f8(h.t));
  if (none_of<f8>(ok)) return false;
  return bvh::take_nearest(xsimd::select(ok, t, f8(bvh::kInfF)), h,
                           [&](int lane) { return kinds::code(K::id, b.id[base + std::size_t(lane)]); });
}

// The leaf functions of a batch in local frames (a whole batch in double when it has no frames).
template <class K, int M>
RB_INLINE bool apart_single(const StdBatch<K>& b, std::size_t base, const Ray<float>& r, bvh::Closest& h) {
  prefetch_ids(b, base);
  if (b.local.empty()) return std_single64<K, M, true>(b, base, r, h, base);
  const LocalFrame& f = b.local[base / 8];
  if (f.deep != UINT32_MAX) [[unlikely]]
    return std_single64<K, M, true>(b, base, r, h, std::size_t(f.deep) * 8);
  return local_single<K, M>(b, base, f.origin, r, h);
}
// A packet against a float group in its local frame at g, whichever needs fewer kernel calls (as
// the mesh leaves choose): with fewer active rays than primitive x group pairs, each ray re-based on
// its own against the primitives in lanes (local_single); otherwise each group of 8 rays re-based in
// lanes (the shifts in two 4-lane doubles) against one primitive at a time. The same arithmetic
// either way.
template <class K, int M, bool Any>
RB_INLINE void apart_packet(const StdBatch<K>& b, std::size_t base, bvh::PacketRays& p) {
  if (b.local.empty()) return std_packet64<K, M, true, Any>(b, base, p, base);
  const LocalFrame& f = b.local[base / 8];
  if (f.deep != UINT32_MAX) [[unlikely]]
    return std_packet64<K, M, true, Any>(b, base, p, std::size_t(f.deep) * 8);
  prefetch_ids(b, base);
  int rays = 0;
  for (int q = 0; q < p.n; ++q) rays += count_true<f8>(p.active[p.list[q]]);
  const int prims = int(real_slots(b, base));
  if (rays >= prims * p.n) {
    using lanes::hi_d4, lanes::lo_d4, lanes::join_f8;
    const Vec3<d4> gl{d4(f.origin.x), d4(f.origin.y), d4(f.origin.z)};
    for (int q = 0; q < p.n; ++q) {
      const int k = p.list[q];
      if (none_of<f8>(p.active[k])) continue;
      Ray<f8> lr = p.r[k];
      d4 shift[2];
      Vec3<d4> o[2];
      for (int h = 0; h < 2; ++h) {
        auto half = [&](const f8& v) { return h ? hi_d4(v) : lo_d4(v); };
        o[h] = {half(lr.o.x), half(lr.o.y), half(lr.o.z)};
        shift[h] = rebase(o[h], Vec3<d4>{half(lr.d.x), half(lr.d.y), half(lr.d.z)}, gl);
      }
      lr.o = {join_f8(o[0].x, o[1].x), join_f8(o[0].y, o[1].y), join_f8(o[0].z, o[1].z)};
      lr.tmin = f8(spawn::step_floats8(join_f8(lo_d4(lr.tmin) - shift[0], hi_d4(lr.tmin) - shift[1]), -1));
      lr.tmax = f8(spawn::step_floats8(join_f8(lo_d4(p.tbest[k]) - shift[0], hi_d4(p.tbest[k]) - shift[1]), 1));
      const auto pre = K::pre(lr);
      for (std::size_t j = base; j < base + 8; ++j) {
        const std::uint32_t sid = b.id[j];
        if (sid == UINT32_MAX) continue;
        const Hit<f8> hit = K::template hit<M>(lr, pre, b.f32.template broadcast<f8>(j));
        if (none_of<f8>(hit.mask)) continue;
        const f8 t = ray_t(hit.t, shift[0], shift[1]);
        bvh::packet_update<Any>(p, k, hit.mask & (t >= p.r[k].tmin) & (t <= p.tbest[k]), t, kinds::code(K::id, sid));
      }
    }
    return;
  }
  for (int q = 0; q < p.n; ++q) {
    const int g = p.list[q];
    unsigned bits = lanes::bits(p.active[g]);
    if (!bits) continue;
    alignas(32) float tb[8];
    p.tbest[g].store_aligned(tb);
    unsigned hit = 0;
    while (bits) {
      const int l = __builtin_ctz(bits);
      bits &= bits - 1;
      bvh::Closest h{tb[l], p.prim[8 * g + l]};
      if (!local_single<K, M>(b, base, f.origin, lane_ray(p.r[g], l), h)) continue;
      tb[l] = h.t;
      p.prim[8 * g + l] = h.prim;
      hit |= 1u << l;
    }
    if (!hit) continue;
    p.tbest[g] = f8::load_aligned(tb);
    p.improved = true;
    if constexpr (Any) p.active[g] = p.active[g] & ~lanes::of(hit);
  }
}

// ---- one function pointer set per kind ------------------------------------------------------------
struct LeafFns {
  bool (*single)(const void* batch, std::size_t base, const Ray<float>& r, RayCache& c, bvh::Closest& h) = nullptr;
  void (*packet[2])(const void* batch, std::size_t base, bvh::PacketRays& p, PacketCache& c) = {nullptr, nullptr};  // [Any]
};

// Every kind's functions for its chosen method and precision (tracer/leaves.cpp instantiates each
// kind's kernels once, in every method and precision the kind supports).
struct LeafChoice {
  int method = 0;
  bool f64 = false, f64_storage = false;
};
std::array<LeafFns, kKinds> leaf_table(const std::array<LeafChoice, kKinds>& c);
// The leaves of each kind's primitives stored apart, in the method given (apart_single, apart_packet).
std::array<LeafFns, kKinds> apart_table(const std::array<int, kKinds>& method);

// The number of real slots of a group (for the counted traversal, and for the mesh packet leaf's
// choice of loop on every visit): a whole group by one 8-lane compare with the padding's index.
template <class B>
inline std::uint32_t real_slots(const B& b, std::size_t base) {
  if (base + 8 <= b.id.size()) {
    return 8u - unsigned(__builtin_popcount(lanes::equal_bits(b.id.data() + base, UINT32_MAX)));
  }
  std::uint32_t n = 0;
  for (std::size_t j = base; j < b.id.size(); ++j) n += b.id[j] != UINT32_MAX;
  return n;
}

// ---- the leaf sources of bvh/traverse.hpp -----------------------------------------------------------
struct TableLeaves {
  const void* batch[kLeafKinds] = {};
  const LeafFns* fns = nullptr;  // kLeafKinds entries
  std::uint32_t (*slots_fn[kLeafKinds])(const void*, std::size_t) = {};
  using RayCache = tracer::RayCache;
  using PacketCache = tracer::PacketCache;
  template <class V>  // groups of 8 lanes only: every kind's leaf functions are 8-lane
  using PacketCacheFor = PacketCache;
  RB_INLINE bool single(std::uint32_t ref, const Ray<float>& r, RayCache& c, bvh::Closest& h) const {
    const int k = bvh::leaf_kind(ref);
    return fns[k].single(batch[k], std::size_t(bvh::leaf_group(ref)) * 8, r, c, h);
  }
  template <bool Any>
  RB_INLINE void packet(std::uint32_t ref, bvh::PacketRays& p, PacketCache& c) const {
    const int k = bvh::leaf_kind(ref);
    fns[k].packet[Any](batch[k], std::size_t(bvh::leaf_group(ref)) * 8, p, c);
  }
  std::uint32_t slots(std::uint32_t ref) const {
    const int k = bvh::leaf_kind(ref);
    return slots_fn[k](batch[k], std::size_t(bvh::leaf_group(ref)) * 8);
  }
};

}  // namespace rb::tracer
