// Embree 3 beside raybench, in the same process, on the same float geometry and rays: the kinds
// whose table entry (tracer/kinds.hpp) maps to an Embree type, triangles (one
// RTC_GEOMETRY_TYPE_TRIANGLE geometry over the shared vertices) and spheres
// (RTC_GEOMETRY_TYPE_SPHERE_POINT), each with geomID = its kind and primID = its scene index, in the
// accel's frame (tracer/plan.hpp), at Embree's default build quality. A scene with a kind Embree
// does not model (cones, cylinders, polygons, tori, CSG: a tessellation would not be the same
// geometry) is not built: `ok` is false with the reason.
//
// Embree's best mode is the yardstick: the scene is built twice, on a device with Embree's native
// ISA (device config "", which picks the widest ISA both the CPU and the library support) and on
// one restricted to AVX2 (config "isa=avx2", the ISA raybench's kernels use). A run times every
// call Embree offers for the packet size (rtcIntersect1/8/16, rtcIntersect1M streams for 64 and
// 256; rtcOccluded* for any-hit) on both devices and compares with the fastest.
// Only this header and its .cpp (and bench/embree_build.cpp) see Embree; nothing else depends on it.
#pragma once

#include "tracer/accel.hpp"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace rb::trace {

struct EmbreeScene;

// The two devices: index 0 native ISA (config ""), 1 AVX2 (config "isa=avx2").
enum class EmbreeIsa { native = 0, avx2 = 1 };
inline constexpr int kEmbreeDevices = 2;
const char* embree_isa_label(EmbreeIsa d);    // "native", "avx2"
const char* embree_device_config(EmbreeIsa d);  // "", "isa=avx2" (before the threads setting)

// What a device runs with. Embree 3 has no device property naming its ISA: `isa` is parsed from
// the report a device with the same config prints with verbose=1 (the highest target that is both
// supported by the CPU under that config and compiled into the library), cross-checked with the
// native 16-wide packet property (only the AVX-512 kernels have it). "unknown" if the report could
// not be read.
struct EmbreeDeviceInfo {
  std::string config;         // as passed to rtcNewDevice (with threads=N)
  std::string isa;            // e.g. "AVX512", "AVX2"
  bool native_ray16 = false;  // RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED
  bool native_ray8 = false;
  double build_ms = 0;
};

struct EmbreeBuild {
  std::array<std::shared_ptr<EmbreeScene>, kEmbreeDevices> scenes;
  std::array<EmbreeDeviceInfo, kEmbreeDevices> devices;
  bool ok = false;
  std::string why;       // when !ok
  double build_ms = 0;   // rtcCommitScene (the BVH build) on the native device
  long long bvh_bytes = 0;   // memory-monitor bytes allocated by the native device's commit (BVH and its leaf copies)
  long long total_bytes = 0; // all memory the native device holds after the build (with the geometry buffers)
  const EmbreeScene& scene(EmbreeIsa d) const { return *scenes[std::size_t(d)]; }
};
bool embree_available();
// The geometry of a's scene in a's frame on both devices; `threads`: each device's threads.
EmbreeBuild embree_build(const tracer::SceneAccel& a, int threads);

// One way of calling Embree.
enum class EmbreeCall { one, eight, sixteen, stream };
struct EmbreeMode {
  EmbreeIsa isa = EmbreeIsa::native;
  EmbreeCall call = EmbreeCall::one;
  int stream = 0;  // rays per rtcIntersect1M / rtcOccluded1M call (call == stream)
  bool coherent = false;
  // "rtcIntersect8 avx2 coherent", "rtcOccluded1M(64) native incoherent"
  std::string name(bool any) const;
  std::string call_name(bool any) const;  // "rtcIntersect8", "rtcOccluded1M"
};
// The modes a run of `packet` rays per packet times, on both devices: packet 1 rtcIntersect1,
// 8 rtcIntersect8, 16 rtcIntersect16, 64 and 256 rtcIntersect1M over the packet's rays (the
// rtcOccluded forms for any-hit); `coherent` sets RTC_INTERSECT_CONTEXT_FLAG_COHERENT.
std::vector<EmbreeMode> embree_modes(int packet, bool coherent);

// Traces rays [begin, end) (begin a multiple of 16, and of mode.stream for streams) with `mode`.
// Results in the same form as tracer::SceneAccel::trace. A ray Embree would reject (origin or
// direction not finite or beyond its coordinate range, a zero direction, tnear < 0, NaN, or an
// empty interval) is never handed to it: it gets a miss, as raybench gives it. Single rays skip
// it, packets clear its lane in the valid mask, streams leave it out of the call.
void embree_trace(const EmbreeBuild& e, const EmbreeMode& mode, const RaySoA& rays, std::size_t begin, std::size_t end,
                  bvh::HitRec* out, bool any);
// Whether ray i of `rays` is one Embree accepts.
bool embree_valid(const RaySoA& rays, std::size_t i);

}  // namespace rb::trace
