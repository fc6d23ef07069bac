#include "bench/embree_trace.hpp"

#include <embree3/rtcore.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

namespace rb::trace {

using bvh::HitRec;
using bvh::kNoPrim;

struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::atomic<long long> bytes{0};
  ~EmbreeScene() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

bool embree_available() { return true; }

namespace {
bool monitor(void* user, ssize_t bytes, bool) {
  static_cast<EmbreeScene*>(user)->bytes += (long long)bytes;
  return true;
}
}  // namespace

EmbreeBuild embree_build(const tracer::SceneAccel& a, int threads) {
  EmbreeBuild b;
  const scene::Scene& s = a.scene();
  std::string missing;
  kinds::AllKinds::each([&]<class K>() {
    if (K::embree == kinds::EmbreeType::none && K::count(s) > 0) missing += std::string(missing.empty() ? "" : ", ") + K::name;
  });
  if (!missing.empty()) {
    b.why = "the scene has primitives Embree does not model (" + missing + ")";
    return b;
  }
  auto e = std::make_shared<EmbreeScene>();
  const std::string cfg = "threads=" + std::to_string(std::max(1, threads));
  e->device = rtcNewDevice(cfg.c_str());
  if (!e->device) {
    b.why = "rtcNewDevice failed";
    return b;
  }
  rtcSetDeviceMemoryMonitorFunction(e->device, monitor, e.get());
  e->scene = rtcNewScene(e->device);
  kinds::AllKinds::each([&]<class K>() {
    const std::size_t n = K::count(s);
    if (!n) return;
    if constexpr (K::embree == kinds::EmbreeType::triangle) {
      const std::vector<Vec3d>& verts = K::mesh_vertices(s);
      RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), verts.size()));
      for (std::size_t i = 0; i < verts.size(); ++i) {
        const Vec3f f = a.to_frame(verts[i]);
        v[3 * i] = f.x; v[3 * i + 1] = f.y; v[3 * i + 2] = f.z;
      }
      auto* ix = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
      for (std::uint32_t i = 0; i < n; ++i) {
        const auto t = K::mesh_indices(s, i);
        for (int k = 0; k < 3; ++k) ix[3 * std::size_t(i) + std::size_t(k)] = t[std::size_t(k)];
      }
      rtcCommitGeometry(g);
      rtcAttachGeometryByID(e->scene, g, unsigned(K::id));
      rtcReleaseGeometry(g);
    } else if constexpr (K::embree == kinds::EmbreeType::sphere) {
      RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), n));
      for (std::uint32_t i = 0; i < n; ++i) {
        Vec3d c;
        double r;
        K::sphere_of(s, i, c, r);
        const Vec3f f = a.to_frame(c);
        v[4 * i] = f.x; v[4 * i + 1] = f.y; v[4 * i + 2] = f.z; v[4 * i + 3] = float(r);
      }
      rtcCommitGeometry(g);
      rtcAttachGeometryByID(e->scene, g, unsigned(K::id));
      rtcReleaseGeometry(g);
    }
  });
  const long long before = e->bytes.load();
  const auto t0 = std::chrono::steady_clock::now();
  rtcCommitScene(e->scene);
  b.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (rtcGetDeviceError(e->device) != RTC_ERROR_NONE) {
    b.why = "Embree reported an error while building";
    return b;
  }
  b.bvh_bytes = e->bytes.load() - before;
  b.total_bytes = e->bytes.load();
  b.scene = e;
  b.ok = true;
  return b;
}

namespace {
inline std::uint32_t code(unsigned geom, unsigned prim) { return bvh::prim_code(int(geom), prim); }
// Embree asserts on rays outside its valid range (origin and direction finite and below 1.844e18 in
// magnitude, 0 <= tnear <= tfar): such a ray is a miss here, never a call.
constexpr float kEmbreeLarge = 1.844e18f;
inline bool fits(float x) { return x > -kEmbreeLarge && x < kEmbreeLarge; }
inline bool embree_valid(const RaySoA& r, std::size_t i) {
  return r.tmin[i] <= r.tmax[i] && r.tmin[i] >= 0.0f && fits(r.tmin[i]) && fits(r.ox[i]) && fits(r.oy[i]) && fits(r.oz[i]) &&
         fits(r.dx[i]) && fits(r.dy[i]) && fits(r.dz[i]) && (r.dx[i] != 0.0f || r.dy[i] != 0.0f || r.dz[i] != 0.0f);
}
}  // namespace

void embree_trace(const EmbreeScene& e, const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, bool any, int packet,
                  bool coherent) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  const float inf = std::numeric_limits<float>::infinity();
  if (packet == 1) {
    for (std::size_t i = begin; i < end; ++i) {
      out[i] = {inf, kNoPrim};
      if (!embree_valid(rays, i)) continue;
      if (any) {
        RTCRay r{};
        r.org_x = rays.ox[i]; r.org_y = rays.oy[i]; r.org_z = rays.oz[i];
        r.dir_x = rays.dx[i]; r.dir_y = rays.dy[i]; r.dir_z = rays.dz[i];
        r.tnear = rays.tmin[i]; r.tfar = rays.tmax[i]; r.mask = 0xFFFFFFFFu; r.flags = 0;
        rtcOccluded1(e.scene, &ctx, &r);
        if (r.tfar == -inf) out[i] = {0.f, bvh::prim_code(0, 0)};
      } else {
        RTCRayHit rh{};
        auto& r = rh.ray;
        r.org_x = rays.ox[i]; r.org_y = rays.oy[i]; r.org_z = rays.oz[i];
        r.dir_x = rays.dx[i]; r.dir_y = rays.dy[i]; r.dir_z = rays.dz[i];
        r.tnear = rays.tmin[i]; r.tfar = rays.tmax[i]; r.mask = 0xFFFFFFFFu; r.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(e.scene, &ctx, &rh);
        if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) out[i] = {r.tfar, code(rh.hit.geomID, rh.hit.primID)};
      }
    }
    return;
  }
  for (std::size_t i = begin; i < end; i += 8) {
    alignas(32) int valid[8];
    for (int l = 0; l < 8; ++l) valid[l] = embree_valid(rays, i + std::size_t(l)) ? -1 : 0;
    if (any) {
      RTCRay8 r;
      for (int l = 0; l < 8; ++l) {
        const std::size_t k = i + std::size_t(l);
        r.org_x[l] = rays.ox[k]; r.org_y[l] = rays.oy[k]; r.org_z[l] = rays.oz[k];
        r.dir_x[l] = rays.dx[k]; r.dir_y[l] = rays.dy[k]; r.dir_z[l] = rays.dz[k];
        r.tnear[l] = valid[l] ? rays.tmin[k] : 0.f; r.tfar[l] = valid[l] ? rays.tmax[k] : 0.f;
        r.mask[l] = 0xFFFFFFFFu; r.flags[l] = 0; r.time[l] = 0; r.id[l] = 0;
      }
      rtcOccluded8(valid, e.scene, &ctx, &r);
      for (int l = 0; l < 8; ++l)
        out[i + std::size_t(l)] = valid[l] && r.tfar[l] == -inf ? HitRec{0.f, bvh::prim_code(0, 0)} : HitRec{inf, kNoPrim};
    } else {
      RTCRayHit8 rh;
      for (int l = 0; l < 8; ++l) {
        const std::size_t k = i + std::size_t(l);
        rh.ray.org_x[l] = rays.ox[k]; rh.ray.org_y[l] = rays.oy[k]; rh.ray.org_z[l] = rays.oz[k];
        rh.ray.dir_x[l] = rays.dx[k]; rh.ray.dir_y[l] = rays.dy[k]; rh.ray.dir_z[l] = rays.dz[k];
        rh.ray.tnear[l] = valid[l] ? rays.tmin[k] : 0.f; rh.ray.tfar[l] = valid[l] ? rays.tmax[k] : 0.f;
        rh.ray.mask[l] = 0xFFFFFFFFu; rh.ray.flags[l] = 0; rh.ray.time[l] = 0; rh.ray.id[l] = 0;
        rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect8(valid, e.scene, &ctx, &rh);
      for (int l = 0; l < 8; ++l)
        out[i + std::size_t(l)] = valid[l] && rh.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID
                                      ? HitRec{rh.ray.tfar[l], code(rh.hit.geomID[l], rh.hit.primID[l])}
                                      : HitRec{inf, kNoPrim};
    }
  }
}

}  // namespace rb::trace
