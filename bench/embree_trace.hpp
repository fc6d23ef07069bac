// Embree 3 beside raybench, in the same process, on the same float geometry and rays: the kinds
// whose table entry (tracer/kinds.hpp) maps to an Embree type, triangles (one
// RTC_GEOMETRY_TYPE_TRIANGLE geometry over the shared vertices) and spheres
// (RTC_GEOMETRY_TYPE_SPHERE_POINT), each with geomID = its kind and primID = its scene index, in the
// accel's frame (tracer/plan.hpp), at Embree's default build quality. A scene with a kind Embree
// does not model (cones, cylinders, polygons, tori, CSG: a tessellation would not be the same
// geometry) is not built: `ok` is false with the reason.
// Only this header and its .cpp see Embree; nothing else depends on it.
#pragma once

#include "tracer/accel.hpp"

#include <memory>
#include <string>

namespace rb::trace {

struct EmbreeScene;
struct EmbreeBuild {
  std::shared_ptr<EmbreeScene> scene;
  bool ok = false;
  std::string why;       // when !ok
  double build_ms = 0;   // rtcCommitScene (the BVH build)
  long long bvh_bytes = 0;   // memory-monitor bytes allocated by the commit (BVH and its leaf copies)
  long long total_bytes = 0; // all memory the device holds after the build (with the geometry buffers)
};
bool embree_available();
// The geometry of a's scene in a's frame; `threads`: the device's build threads.
EmbreeBuild embree_build(const tracer::SceneAccel& a, int threads);

// Traces rays [begin, end) (begin a multiple of 16): packet 1 = rtcIntersect1/rtcOccluded1,
// 8 = rtcIntersect8/rtcOccluded8, 16 = two rtcIntersect8 calls; `coherent` sets
// RTC_INTERSECT_CONTEXT_FLAG_COHERENT. Results in the same form as tracer::SceneAccel::trace.
// A ray Embree would reject (not finite, beyond its coordinate range, tnear < 0 or an empty
// interval) is never handed to it: it gets a miss, as raybench gives it.
void embree_trace(const EmbreeScene& e, const RaySoA& rays, std::size_t begin, std::size_t end, bvh::HitRec* out, bool any,
                  int packet, bool coherent);

}  // namespace rb::trace
