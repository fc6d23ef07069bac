// Embree 3 beside raybench, in the same process, on the same float geometry and rays: triangles
// (one RTC_GEOMETRY_TYPE_TRIANGLE geometry, primID = scene triangle index) and spheres
// (RTC_GEOMETRY_TYPE_SPHERE_POINT, primID = scene sphere index); default build quality. Scenes
// with cones, cylinders or polygons are not modelled here (Embree has no such primitive; a
// tessellation would not be the same geometry): `ok` is false with the reason.
// Only this header and its .cpp see Embree; the BVH does not depend on it.
#pragma once

#include "bvh/accel.hpp"
#include "scene/scene.hpp"

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
// `threads`: the device's build threads.
EmbreeBuild embree_build(const scene::Scene& s, int threads);

// Traces rays [begin, end) (begin a multiple of 16): packet 1 = rtcIntersect1/rtcOccluded1,
// 8 = rtcIntersect8/rtcOccluded8, 16 = two rtcIntersect8 calls; `coherent` sets
// RTC_INTERSECT_CONTEXT_FLAG_COHERENT. Results in the same form as bvh::Accel::trace.
void embree_trace(const EmbreeScene& e, const RaySoA& rays, std::size_t begin, std::size_t end, bvh::HitRec* out, bool any,
                  int packet, bool coherent);

}  // namespace rb::trace
