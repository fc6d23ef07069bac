// The box test of the traversal, one body for every walk: the distances at which a ray crosses a
// box's six planes, then the interval [max(entries, tmin), min(exits, tmax)] non-empty or not. It
// runs as one ray against a node's 8 child boxes (single rays; the first ray of a packet), as a
// packet's frustum against them (per axis the extreme ray of the packet for each plane), and as one
// box against 8 rays in lanes (a packet's groups).
//
// Two forms (a template switch):
//   fast    t = plane * (1/d) - o * (1/d): one FMA per plane with o * (1/d) made once per ray. It
//           is exact enough when the boxes were made conservative for the ray's origin
//           (bvh::make_conservative widens them at build time). Its maxima and minima run on the
//           floats' bits as integers (lanes::int_max: one cycle instead of four on the node's
//           critical path). That needs tmin >= 0: every entry distance is then a maximum with a
//           non-negative float, and a negative exit distance (a box behind the ray) is a negative
//           integer, below every entry: rejected, as it must be.
//   robust  t = (plane - o) * (1/d), the exit distance scaled by 1 + 2 gamma(3) (Ize 2013, "Robust
//           BVH Ray Traversal"); any tmin; float comparisons.
// The walks choose the form once per ray (per packet); bvh/walk_single.hpp says when.
#pragma once

#include "bvh/bvh.hpp"
#include "core/lanes.hpp"
#include "core/ray.hpp"

#include <cmath>

namespace rb::bvh {

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
template <class V>
RB_INLINE V safe_rcp_lanes(const V& d, const V& rd) {
  return xsimd::select(xsimd::abs(d) < V(kMinDir), xsimd::copysign(V(1.0f / kMinDir), d), rd);
}

// What the test needs of a ray for one kind of plane (near or far), per axis: 1/d, o and o * (1/d),
// each in 8 lanes (one ray broadcast, or 8 rays), or in 16 (16 rays, core/lanes16.hpp).
template <class V>
struct SlabSideT {
  V rd[3], o[3], o_rd[3];
};
using SlabSide = SlabSideT<f8>;

// The distance to the plane at `plane` along axis a.
template <bool Robust, class V>
RB_INLINE V plane_distance(const V& plane, const SlabSideT<V>& s, int a) {
  if constexpr (Robust) return (plane - s.o[a]) * s.rd[a];
  else return xsimd::fms(plane, s.rd[a], s.o_rd[a]);
}

// Bit l set when lane l's interval [max(near x, y, z, tmin), min(far x, y, z, tmax)] is not empty;
// tn receives the entry distances (the fast form's are exact as floats: integer maxima of floats
// of which one is >= 0).
template <bool Robust, class V>
RB_INLINE unsigned slab_interval(const V& nx, const V& ny, const V& nz, const V& fx, const V& fy, const V& fz, const V& tmin, const V& tmax,
                                 V& tn) {
  using G = lanes::Group<V>;
  if constexpr (!Robust) {
    const auto n = G::int_max(G::int_max(G::as_int(nx), G::as_int(ny)), G::int_max(G::as_int(nz), G::as_int(tmin)));
    const auto f = G::int_min(G::int_min(G::as_int(fx), G::as_int(fy)), G::int_min(G::as_int(fz), G::as_int(tmax)));
    tn = G::as_float(n);
    return G::int_le_bits(n, f);
  } else {
    tn = xsimd::max(xsimd::max(nx, ny), xsimd::max(nz, tmin));
    const V tf = xsimd::min(xsimd::min(xsimd::min(fx, fy), fz) * V(kRobustScale), tmax);
    return G::le_bits(tn, tf);
  }
}

// One ray broadcast to 8 lanes, for the test against a node's 8 children.
struct SlabRay {
  SlabSide s;
  f8 tmin;
  int n[3];  // 1 where 1/d < 0: the near plane is the box's hi
  static RB_INLINE SlabRay make(const Ray<float>& r) {
    SlabRay x;
    const float rd[3] = {safe_rcp(r.d.x, r.rd.x), safe_rcp(r.d.y, r.rd.y), safe_rcp(r.d.z, r.rd.z)};
    const float o[3] = {r.o.x, r.o.y, r.o.z};
    for (int a = 0; a < 3; ++a) {
      x.s.rd[a] = f8(rd[a]);
      x.s.o[a] = f8(o[a]);
      x.s.o_rd[a] = f8(o[a] * rd[a]);
      x.n[a] = rd[a] < 0;
    }
    x.tmin = f8(r.tmin);
    return x;
  }
};
// A packet's frustum: per axis, the near planes tested with the ray that enters them last and the
// far planes with the ray that leaves them first (conservative exactly as each ray's own test is).
struct SlabFrustum {
  SlabSide near, far;
  f8 tmin;
  int n[3];
};

// The 8 children of node `nd` against a ray given by its near-plane and far-plane sides: bit k set
// when child k's box meets [tmin, tmax]; tn receives the entry distances.
template <bool Robust>
RB_INLINE unsigned slab_node(const WNode& nd, const SlabSide& ns, const SlabSide& fs, const int (&n)[3], const f8& tmin, float tmax, f8& tn) {
  auto near = [&](int a) RB_INLINE_LAMBDA { return plane_distance<Robust>(f8::load_aligned(nd.b[2 * a + n[a]]), ns, a); };
  auto far = [&](int a) RB_INLINE_LAMBDA { return plane_distance<Robust>(f8::load_aligned(nd.b[2 * a + 1 - n[a]]), fs, a); };
  return slab_interval<Robust>(near(0), near(1), near(2), far(0), far(1), far(2), tmin, f8(tmax), tn);
}
template <bool Robust>
RB_INLINE unsigned slab8(const WNode& nd, const SlabRay& r, float tmax, f8& tn) {
  return slab_node<Robust>(nd, r.s, r.s, r.n, r.tmin, tmax, tn);
}
template <bool Robust>
RB_INLINE unsigned slab8(const WNode& nd, const SlabFrustum& f, float tmax, f8& tn) {
  return slab_node<Robust>(nd, f.near, f.far, f.n, f.tmin, tmax, tn);
}

// One box, given by its near and far planes per axis (the packet's octant chooses them), against
// 8 (or 16) rays in lanes: bit l set when ray l's interval meets it.
template <bool Robust, class V>
RB_INLINE unsigned slab_rays(const float (&near)[3], const float (&far)[3], const SlabSideT<V>& rays, const V& tmin, const V& tmax) {
  auto n = [&](int a) RB_INLINE_LAMBDA { return plane_distance<Robust>(V(near[a]), rays, a); };
  auto f = [&](int a) RB_INLINE_LAMBDA { return plane_distance<Robust>(V(far[a]), rays, a); };
  V tn;
  return slab_interval<Robust>(n(0), n(1), n(2), f(0), f(1), f(2), tmin, tmax, tn);
}

}  // namespace rb::bvh
