// Workloads for tracing a scene, without a yardstick: reproducible ray sets, and the ray-by-ray
// comparison of two engines' (or two runs') answers. Used by `raybench trace`, the report, the
// tests and the benchmarks (bench/timed_trace.hpp times them; bench/embree_trace.hpp traces them with
// Embree).
//
// Ray sets (all from one seed, rays stored so that 8, 16, 64 and 256 consecutive rays form a
// packet):
//   primary  camera rays through jittered pixel centres of a square image whose side is a multiple
//            of 16, in 16x16 pixel blocks made of 4x4 tiles in Z order (a 256-ray packet is a block,
//            64 rays an 8x8 quarter, 16 a tile, 8 half a tile); the scene's camera (NFF `v`), or for files
//            without one a stated camera: looking at the bounds' centre from the direction
//            (0.3, 0.4, -1), 45 degrees, at the distance h / tan(22.5 deg) + h from it (h the
//            largest half extent of the bounds), so the bounds about fill the view
//   shadow   from each primary hit point to the scene's first light (or, for scenes without
//            lights, a stated light at centre + 2 R (0.5, 1, -0.7)/|...|, R the bounds' radius),
//            segment [1e-4 R, 0.9999 |L - P|]: any-hit queries
//   diffuse  from each primary hit point, cosine-weighted about the geometric normal facing the
//            incoming ray (the kind's surface rule, tracer/kinds.hpp), tmin 1e-4 R
//   random   origin uniform in the bounds, direction uniform on the sphere
// Rays are made in world coordinates (double) and stored in the accel's frame (tracer/plan.hpp):
// both engines trace the same float rays against the same float geometry.
#pragma once

#include "tracer/accel.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace rb::tracer {

enum class RaySet { primary, shadow, diffuse, random };
const char* ray_set_name(RaySet s);
RaySet parse_ray_set(const std::string& s);  // throws std::invalid_argument
bool is_ray_set_name(const std::string& s);
inline const char* const kRaySetNames[] = {"primary", "shadow", "diffuse", "random"};

struct RaySetInfo {
  std::string camera;  // "scene" or "stated"
  std::string light;   // "scene" or "stated"
  int width = 0, height = 0;
};

// About `count` rays of the set (primary: a width x height image of about count pixels; shadow
// and diffuse: one per primary hit of an image of about count pixels). Uses `accel` for the
// primary hits.
RaySoA make_rays(const scene::Scene& s, const SceneAccel& accel, RaySet set, std::size_t count, std::uint64_t seed,
                 RaySetInfo* info = nullptr);

// Ray-by-ray comparison: a mismatch is a hit against a miss, or two hits whose t differ by more
// than rel_tol * max(1, |t|); `other_prim` counts hits at agreeing t on different primitives (ties
// at shared edges, vertices or coincident surfaces).
struct Compare {
  std::size_t rays = 0, mismatches = 0, other_prim = 0;
  double rate() const { return rays ? double(mismatches) / double(rays) : 0.0; }
};
Compare compare(const std::vector<HitRec>& a, const std::vector<HitRec>& b, std::size_t n, bool any, float rel_tol = 1e-4f);

}  // namespace rb::tracer
