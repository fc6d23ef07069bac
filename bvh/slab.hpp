// The wide node's slab test: one ray against the 8 child boxes of a WNode in one 8-lane pass.
//   fast:   t = box * (1/d) - o * (1/d), one FMA per plane, o * (1/d) precomputed per ray;
//   robust: t = (box - o) * (1/d) and the far distance scaled by 1 + 2 gamma(3) (Ize 2013,
//           "Robust BVH Ray Traversal"), gamma(n) = n eps / (1 - n eps), eps = 2^-24.
// The near plane of each axis is chosen once per ray from the sign of 1/d, so the test is
// 6 FMAs (or 6 subtractions and 6 products), 4 max, 3 min, 1 compare per 8 boxes.
#pragma once

#include "bvh/bvh.hpp"
#include "core/ray.hpp"

#include <immintrin.h>

#include <cmath>
#include <limits>

namespace rb::bvh {

inline constexpr float kSlabEps = 0x1p-24f;
inline constexpr float kGamma3 = 3 * kSlabEps / (1 - 3 * kSlabEps);
inline constexpr float kRobustScale = 1 + 2 * kGamma3;
// A zero direction component would make 1/d infinite and o * (1/d) NaN at o = 0; as Embree
// does, components smaller than this are replaced by it (with their sign) for the slab test.
inline constexpr float kMinDir = 1e-18f;

inline float safe_rcp(float d) { return 1.0f / (std::fabs(d) < kMinDir ? std::copysign(kMinDir, d) : d); }

// Per-ray data of the slab test, broadcast to 8 lanes.
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

}  // namespace rb::bvh
