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

EmbreeBuild embree_build(const scene::Scene& s, int threads) {
  EmbreeBuild b;
  if (!s.cones.empty() || !s.polygons.empty() || !s.csgs.empty()) {
    b.why = "the scene has cones, cylinders, polygons or CSG objects, which Embree does not model";
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
  if (!s.triangles.empty()) {
    RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), s.verts.size()));
    for (std::size_t i = 0; i < s.verts.size(); ++i) { v[3 * i] = s.verts[i].x; v[3 * i + 1] = s.verts[i].y; v[3 * i + 2] = s.verts[i].z; }
    auto* ix = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), s.triangles.size()));
    for (std::size_t i = 0; i < s.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) ix[3 * i + std::size_t(k)] = s.triangles[i].v[std::size_t(k)];
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(e->scene, g, 0);
    rtcReleaseGeometry(g);
  }
  if (!s.spheres.empty()) {
    RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), s.spheres.size()));
    for (std::size_t i = 0; i < s.spheres.size(); ++i) {
      v[4 * i] = s.spheres[i].c.x; v[4 * i + 1] = s.spheres[i].c.y; v[4 * i + 2] = s.spheres[i].c.z; v[4 * i + 3] = s.spheres[i].r;
    }
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(e->scene, g, 1);
    rtcReleaseGeometry(g);
  }
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
inline std::uint32_t code(unsigned geom, unsigned prim) {
  return bvh::prim_code(geom == 0 ? scene::Kind::triangle : scene::Kind::sphere, prim);
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
      if (!(rays.tmin[i] <= rays.tmax[i])) continue;
      if (any) {
        RTCRay r{};
        r.org_x = rays.ox[i]; r.org_y = rays.oy[i]; r.org_z = rays.oz[i];
        r.dir_x = rays.dx[i]; r.dir_y = rays.dy[i]; r.dir_z = rays.dz[i];
        r.tnear = rays.tmin[i]; r.tfar = rays.tmax[i]; r.mask = 0xFFFFFFFFu; r.flags = 0;
        rtcOccluded1(e.scene, &ctx, &r);
        if (r.tfar == -inf) out[i] = {0.f, bvh::prim_code(scene::Kind::triangle, 0)};
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
    for (int l = 0; l < 8; ++l) valid[l] = rays.tmin[i + std::size_t(l)] <= rays.tmax[i + std::size_t(l)] ? -1 : 0;
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
        out[i + std::size_t(l)] = valid[l] && r.tfar[l] == -inf ? HitRec{0.f, bvh::prim_code(scene::Kind::triangle, 0)} : HitRec{inf, kNoPrim};
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
