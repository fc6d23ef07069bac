// What a walk of the tree and its leaves agree on: the closest-hit rule (`nearer`), how a leaf's
// hits update one ray (`take_nearest`) or a packet's rays (`packet_update`), the packet as a leaf
// sees it (`PacketRays`), and the choice of slab test (`Slab`). Leaf sources (tracer/leaves.hpp)
// and the plan (tracer/plan.hpp) need only this; the walks are in bvh/walk_single.hpp and
// bvh/walk_packet.hpp.
#pragma once

#include "bvh/bvh.hpp"
#include "core/lanes.hpp"
#include "core/ray.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>

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

inline constexpr float kInfF = std::numeric_limits<float>::infinity();

// Whether a leaf source's hits carry an aux datum (HitRec::aux): its ray cache keeps one, written by
// the leaf that gave the ray's closest hit.
template <class L>
inline constexpr bool carries_aux = requires(typename L::RayCache& c) { c.aux; };

// The finished hit: t = +inf when nothing was hit (the contract of Hit); the aux datum from the ray's
// cache where the leaf source keeps one.
template <class Cache>
RB_INLINE HitRec finished(const Closest& h, const Cache& c) {
  HitRec o{h.prim == kNoPrim ? kInfF : h.t, h.prim};
  if constexpr (requires { c.aux; }) o.aux = c.aux;
  return o;
}

// The closest hit is canonical: the least t, and at an equal t the least hit code (the kind, then
// the scene index). So which of two faces meeting the ray at the same distance (a shared edge or
// vertex) is reported does not depend on the order in which the leaves and their lanes are
// tested: single rays, packets of every size and the brute-force loop give the same hits. Node
// tests and the stack keep boxes whose entry equals the closest t (the tests are inclusive), so
// the other face's leaf is still visited.
RB_INLINE bool nearer(float t, std::uint32_t code, const Closest& h) { return t < h.t || (t == h.t && code < h.prim); }

// A leaf's hit lanes (t = +inf on the others, at least one hit) against h: the least t, at an
// equal t the least code among the lanes and h. code_of(lane) gives a lane's code; it is read for
// the nearest lane and, only when several lanes share its t, for each of them. True, with h
// updated, when the leaf gives a nearer hit by `nearer`.
template <class CodeOf>
RB_INLINE bool take_nearest(const f8& t8, Closest& h, CodeOf&& code_of) {
  float t;
  unsigned ties;
  const int lane = lanes::argmin(t8, t, ties);
  std::uint32_t code = code_of(lane);
  for (ties &= ties - 1; ties; ties &= ties - 1) code = std::min(code, std::uint32_t(code_of(__builtin_ctz(ties))));
  if (!nearer(t, code, h)) return false;
  h = {t, code};
  return true;
}

// ---- packets: G groups of 8 (or 16) rays in lanes --------------------------------------------------
inline constexpr int kMaxRays = 256;
inline constexpr int kMaxGroups = kMaxRays / 8;

// What a leaf source sees of a packet: the groups with rays to test at this leaf (list[0..n)),
// each group's rays, current closest distance (tbest, lowered by hits) and the rays to test
// (active: a leaf clears, with Any, the rays that hit), the primitive hit per ray (ray l of
// group k at prim[N k + l]) and the hit's aux datum per group (HitRec::aux; null where the walk keeps
// none). V: the group's register (f8; f16 in the 16-lane walk).
template <class V>
struct PacketRaysT {
  static constexpr int N = lanes::Group<V>::N;
  using mask = typename lanes::Group<V>::mask;
  int n = 0;
  std::uint8_t list[kMaxRays / N];
  Ray<V>* r = nullptr;
  V* tbest = nullptr;
  mask* active = nullptr;
  std::uint32_t* prim = nullptr;
  V* aux = nullptr;
  bool improved = false;  // set by packet_update when a ray's tbest fell
};
using PacketRays = PacketRaysT<f8>;

// Records a leaf's hits for the rays of group k: lanes of `hit` that are active take t (at most
// their tbest: the kernel ran with tmax = tbest; at an equal t only a lesser code, as `nearer`) and
// the primitive `code` (and, given, the aux datum per lane); with Any, the rays that hit leave the
// packet.
template <bool Any, class V>
RB_INLINE void packet_update(PacketRaysT<V>& p, int k, const typename PacketRaysT<V>::mask& hit, const V& t, std::uint32_t code,
                             const V* aux = nullptr) {
  using G = lanes::Group<V>;
  constexpr int N = G::N;
  auto m = hit & p.active[k];
  unsigned bits = G::bits(m);
  if (!bits) return;
  if constexpr (!Any) {
    // A hit at a ray's closest t so far replaces it only with a lesser code (`nearer`).
    if (unsigned ties = bits & G::bits(t == p.tbest[k])) {
      for (; ties; ties &= ties - 1) {
        const int l = __builtin_ctz(ties);
        if (code >= p.prim[N * k + l]) bits &= ~(1u << l);
      }
      if (!bits) return;
      m = m & G::of(bits);
    }
  }
  p.tbest[k] = xsimd::select(m, t, p.tbest[k]);
  if (aux && p.aux) p.aux[k] = xsimd::select(m, *aux, p.aux[k]);
  p.improved = true;
  while (bits) {
    const int l = __builtin_ctz(bits);
    bits &= bits - 1;
    p.prim[N * k + l] = code;
  }
  if constexpr (Any) p.active[k] = p.active[k] & ~m;
}

}  // namespace rb::bvh
