// Traversal of the 8-wide BVH: which walk a range of rays takes. Single rays walk alone
// (bvh/walk_single.hpp); coherent packets of 8, 16, 64 or 256 rays walk as one in groups of 8
// lanes (bvh/walk_packet.hpp); incoherent packets of 8 walk as single rays, two at a time when
// they start apart. Closest or any hit, counted or not. Every walk uses the one box test of
// bvh/slab.hpp, the stack and child order of bvh/stack.hpp and the hit rules of bvh/hit.hpp.
// Templates over a leaf source, so the BVH knows nothing of primitives: whatever intersects the
// leaves (tracer/leaves.hpp for a scene) is instantiated into the walk, chosen once per scene,
// never switched per ray.
//
// A leaf source L provides:
//   using RayCache;      per single ray (constructed from it): whatever its leaves precompute; with
//                        a member `aux`, the aux datum of the ray's closest hit (HitRec::aux)
//   using PacketCache;   the same per group of a packet
//   bool single(ref, const Ray<float>& r, RayCache&, Closest& h) const;
//       the ray against leaf `ref`'s primitives with tmax = h.t (inclusive); true when h was
//       improved by the canonical order (`nearer`: a lesser t, or a lesser code at an equal t);
//       never called with an empty leaf
//   template <bool Any> void packet(ref, PacketRays& p, PacketCache&) const;
//       the listed groups' active rays against the leaf: improves p.tbest and p.prim per lane
//       (packet_update, and p.aux where the source carries aux data); with Any, clears p.active
//       of rays that hit
//   std::uint32_t slots(ref) const;   real primitives in the leaf (for the counted traversal)
#pragma once

#include "bvh/walk_packet.hpp"
#include "bvh/walk_single.hpp"

#include <cstddef>
#include <stdexcept>
#include <type_traits>

namespace rb::bvh {

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

// ---- a range of rays -----------------------------------------------------------------------------
// Rays [begin, end) (begin a multiple of 8, the SoA padded to 8) into out. packet 1: one ray at a
// time; 8, 16, 64 or 256: packets of that many consecutive rays when they share a direction
// octant (coherent: camera tiles, rays towards one light); a packet of more than 8 whose rays do
// not goes on in packets of 8, and an incoherent packet of 8 as single rays (its rays would part
// ways at the first nodes): one at a time when they start near each other, two at a time when
// they start apart (trace_pairs). A packet takes the robust slab test when one of its rays needs
// it (trace_single's rule). `wide`, when given, takes the coherent packets of 16 or more rays in
// place of the 8-lane walk: wide(robust, i, P) traces rays [i, i + P) as one packet (the 16-lane
// walk of tracer/traverse_mesh16.cpp).
inline bool valid_packet_size(int packet) { return packet == 1 || packet == 8 || packet == 16 || packet == 64 || packet == 256; }

// Whether the valid rays of [i, i + n) share a direction octant (8 rays per step, from the SoA).
inline bool shared_octant(const RaySoA& rays, std::size_t i, std::size_t n) {
  int oct = -1;
  for (std::size_t k = i; k < i + n; k += 8) {
    const unsigned valid = lanes::bits(f8::load_unaligned(&rays.tmin[k]) <= f8::load_unaligned(&rays.tmax[k]));
    const unsigned sx = lanes::sign_bits(f8::load_unaligned(&rays.dx[k])) & valid, sy = lanes::sign_bits(f8::load_unaligned(&rays.dy[k])) & valid,
                   sz = lanes::sign_bits(f8::load_unaligned(&rays.dz[k])) & valid;
    if (!((sx == 0 || sx == valid) && (sy == 0 || sy == valid) && (sz == 0 || sz == valid))) return false;
    if (!valid) continue;
    const int q = (sx != 0) | (sy != 0) << 1 | (sz != 0) << 2;  // the group's octant
    if (oct >= 0 && q != oct) return false;
    oct = q;
  }
  return true;
}

// Whether one of the valid rays of [i, i + n) needs the robust slab test (trace_single's rule).
template <Slab S>
bool needs_robust(const Bvh8& t, const RaySoA& rays, std::size_t i, std::size_t n) {
  if constexpr (S == Slab::robust) return true;
  const f8 bound(t.origin_bound);
  for (std::size_t k = i; k < i + n; k += 8) {
    const f8 tmin = f8::load_unaligned(&rays.tmin[k]);
    const unsigned valid = lanes::bits(tmin <= f8::load_unaligned(&rays.tmax[k]));
    unsigned need = lanes::bits(~(tmin >= f8(0.0f)));  // NaN included
    if constexpr (S == Slab::conservative) {
      for (const float* o : {&rays.ox[k], &rays.oy[k], &rays.oz[k]}) need |= lanes::bits(~(xsimd::abs(f8::load_unaligned(o)) <= bound));
    }
    if (need & valid) return true;
  }
  return false;
}

// Whether the valid rays of [k, k + 8) start far apart: their origins' box is wider than
// `near_side` along some axis.
inline bool starts_apart(const RaySoA& rays, std::size_t k, float near_side) {
  const f8_mask valid = f8::load_unaligned(&rays.tmin[k]) <= f8::load_unaligned(&rays.tmax[k]);
  float side = 0;
  for (const float* o : {&rays.ox[k], &rays.oy[k], &rays.oz[k]}) {
    const f8 v = f8::load_unaligned(o);
    side = std::max(side, lanes::hmax(xsimd::select(valid, v, f8(-kInfF))) - lanes::hmin(xsimd::select(valid, v, f8(kInfF))));
  }
  return side > near_side;
}

template <Slab S, bool Any, bool Count, class L, class Wide = std::nullptr_t>
void trace_range(const Bvh8& t, const L& leaves, const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, int packet,
                 TraceCounters& c, Wide wide = nullptr) {
  if (!valid_packet_size(packet)) throw std::invalid_argument("packet size must be 1, 8, 16, 64 or 256");
  if (packet == 1) {
    trace_singles<S, Any, Count>(t, leaves, rays, begin, end, out, c);
    return;
  }
  auto run = [&]<int G>(std::size_t i) {
    if (needs_robust<S>(t, rays, i, 8 * G)) trace_packet<true, Any, Count, G>(t, leaves, rays, i, out, c);
    else trace_packet<false, Any, Count, G>(t, leaves, rays, i, out, c);
  };
  // Rays that start apart (over 1/16 of the scene's box) share no nodes, so two of them walk at
  // once; rays that start near each other walk one after another on the nodes the previous one
  // brought in.
  const float near_side = largest_side(t) * (1.0f / 16);
  auto eights = [&](std::size_t i, std::size_t e) {
    for (; i < e; i += 8) {
      if (shared_octant(rays, i, 8)) run.template operator()<1>(i);
      else if (!starts_apart(rays, i, near_side))
        trace_singles<S, Any, Count>(t, leaves, rays, i, i + 8, out, c);
      else if (needs_robust<S>(t, rays, i, 8)) trace_pairs<true, Any, Count>(t, leaves, rays, i, out, c);
      else trace_pairs<false, Any, Count>(t, leaves, rays, i, out, c);
    }
  };
  const std::size_t P = std::size_t(packet);
  std::size_t i = begin;
  for (; i + P <= end; i += P) {
    if (P == 8 || !shared_octant(rays, i, P)) eights(i, i + P);
    else if constexpr (!std::is_null_pointer_v<Wide>) wide(needs_robust<S>(t, rays, i, P), i, P);
    else if (P == 16) run.template operator()<2>(i);
    else if (P == 64) run.template operator()<8>(i);
    else run.template operator()<32>(i);
  }
  eights(i, end);
}

}  // namespace rb::bvh
