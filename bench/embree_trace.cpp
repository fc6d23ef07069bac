#include "bench/embree_trace.hpp"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <vector>

#include <unistd.h>

namespace rb::trace {

using bvh::HitRec;
using bvh::kNoPrim;

struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::atomic<long long> bytes{0};
  long long before_commit = 0;
  double build_ms = 0;
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

const char* embree_isa_label(EmbreeIsa d) { return d == EmbreeIsa::native ? "native" : "avx2"; }
const char* embree_device_config(EmbreeIsa d) { return d == EmbreeIsa::native ? "" : "isa=avx2"; }

namespace {

// The report a device of config `cfg` prints with verbose=1 (Embree writes it to stdout: fd 1 goes
// to a temporary file while the probe device lives).
std::string verbose_report(const std::string& cfg) {
  std::fflush(stdout);
  std::cout.flush();
  std::FILE* tmp = std::tmpfile();
  if (!tmp) return {};
  const int saved = dup(1);
  if (saved < 0) { std::fclose(tmp); return {}; }
  dup2(fileno(tmp), 1);
  const std::string c = cfg.empty() ? "verbose=1" : cfg + ",verbose=1";
  if (RTCDevice d = rtcNewDevice(c.c_str())) rtcReleaseDevice(d);
  std::cout.flush();
  std::fflush(stdout);
  dup2(saved, 1);
  close(saved);
  std::string text;
  std::rewind(tmp);
  char buf[4096];
  std::size_t k;
  while ((k = std::fread(buf, 1, sizeof buf, tmp)) > 0) text.append(buf, k);
  std::fclose(tmp);
  return text;
}

// The ISA a device runs: in the report's "Config" part, the highest target listed both as
// "(supported)" (by the CPU under the config) and "(compile time enabled)".
std::string isa_from_report(const std::string& text) {
  const std::size_t cfg = text.find("Config");
  if (cfg == std::string::npos) return "unknown";
  auto line_with = [&](const char* tag) {
    const std::size_t at = text.find(tag, cfg);
    if (at == std::string::npos) return std::string();
    const std::size_t b = text.rfind('\n', at);
    return text.substr(b == std::string::npos ? 0 : b + 1, at - (b == std::string::npos ? 0 : b + 1));
  };
  // (fmt::format, not operator+ chains: GCC 12 warns falsely about those, -Wrestrict.)
  const std::string sup = fmt::format(" {} ", line_with("(supported)")), comp = fmt::format(" {} ", line_with("(compile time enabled)"));
  for (const char* isa : {"AVX512SKX", "AVX512KNL", "AVX512", "AVX2", "AVXI", "AVX", "SSE4.2", "SSE2"}) {
    const std::string w = fmt::format(" {} ", isa);
    if (sup.find(w) != std::string::npos && comp.find(w) != std::string::npos) return isa;
  }
  return "unknown";
}

// How Embree models a kind (the tracer's kinds know nothing of Embree): as a triangle mesh (the shared
// vertex array, each primitive's three indices), as point spheres (centre and radius), or not at all.
enum class EmbreeGeometry { none, triangles, spheres };
template <class K>
struct EmbreeOf {
  static constexpr EmbreeGeometry geometry = EmbreeGeometry::none;
};
template <>
struct EmbreeOf<kinds::TriangleKind> {
  static constexpr EmbreeGeometry geometry = EmbreeGeometry::triangles;
  static const std::vector<Vec3d>& vertices(const scene::Scene& s) { return s.verts; }
  static std::array<std::uint32_t, 3> indices(const scene::Scene& s, std::uint32_t i) { return s.triangles[i].v; }
};
template <>
struct EmbreeOf<kinds::SphereKind> {
  static constexpr EmbreeGeometry geometry = EmbreeGeometry::spheres;
  static void sphere(const scene::Scene& s, std::uint32_t i, Vec3d& c, double& r) { c = s.spheres[i].c, r = s.spheres[i].r; }
};

// One device and the scene on it.
bool build_on(EmbreeScene& e, const tracer::SceneAccel& a, const std::string& cfg) {
  const scene::Scene& s = a.scene();
  e.device = rtcNewDevice(cfg.c_str());
  if (!e.device) return false;
  rtcSetDeviceMemoryMonitorFunction(e.device, monitor, &e);
  e.scene = rtcNewScene(e.device);
  kinds::AllKinds::each([&]<class K>() {
    const std::size_t n = K::count(s);
    if (!n) return;
    if constexpr (EmbreeOf<K>::geometry == EmbreeGeometry::triangles) {
      const std::vector<Vec3d>& verts = EmbreeOf<K>::vertices(s);
      RTCGeometry g = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), verts.size()));
      for (std::size_t i = 0; i < verts.size(); ++i) {
        const Vec3f f = a.to_frame(verts[i]);
        v[3 * i] = f.x; v[3 * i + 1] = f.y; v[3 * i + 2] = f.z;
      }
      auto* ix = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
      for (std::uint32_t i = 0; i < n; ++i) {
        const auto t = EmbreeOf<K>::indices(s, i);
        for (int k = 0; k < 3; ++k) ix[3 * std::size_t(i) + std::size_t(k)] = t[std::size_t(k)];
      }
      rtcCommitGeometry(g);
      rtcAttachGeometryByID(e.scene, g, unsigned(K::id));
      rtcReleaseGeometry(g);
    } else if constexpr (EmbreeOf<K>::geometry == EmbreeGeometry::spheres) {
      RTCGeometry g = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), n));
      for (std::uint32_t i = 0; i < n; ++i) {
        Vec3d c;
        double r;
        EmbreeOf<K>::sphere(s, i, c, r);
        const Vec3f f = a.to_frame(c);
        v[4 * i] = f.x; v[4 * i + 1] = f.y; v[4 * i + 2] = f.z; v[4 * i + 3] = float(r);
      }
      rtcCommitGeometry(g);
      rtcAttachGeometryByID(e.scene, g, unsigned(K::id));
      rtcReleaseGeometry(g);
    }
  });
  e.before_commit = e.bytes.load();
  const auto t0 = std::chrono::steady_clock::now();
  rtcCommitScene(e.scene);
  e.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return rtcGetDeviceError(e.device) == RTC_ERROR_NONE;
}

}  // namespace

EmbreeBuild embree_build(const tracer::SceneAccel& a, int threads) {
  EmbreeBuild b;
  const scene::Scene& s = a.scene();
  std::string missing;
  kinds::AllKinds::each([&]<class K>() {
    if (EmbreeOf<K>::geometry == EmbreeGeometry::none && K::count(s) > 0) missing += std::string(missing.empty() ? "" : ", ") + K::name;
  });
  if (!missing.empty()) {
    b.why = "the scene has primitives Embree does not model (" + missing + ")";
    return b;
  }
  for (int d = 0; d < kEmbreeDevices; ++d) {
    const std::string isa_cfg = embree_device_config(EmbreeIsa(d));
    const std::string cfg = (isa_cfg.empty() ? "" : isa_cfg + ",") + "threads=" + std::to_string(std::max(1, threads));
    auto e = std::make_shared<EmbreeScene>();
    if (!build_on(*e, a, cfg)) {
      b.why = std::string("Embree reported an error while building on the ") + embree_isa_label(EmbreeIsa(d)) + " device";
      return b;
    }
    EmbreeDeviceInfo& info = b.devices[std::size_t(d)];
    info.config = cfg;
    info.build_ms = e->build_ms;
    info.native_ray16 = rtcGetDeviceProperty(e->device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) != 0;
    info.native_ray8 = rtcGetDeviceProperty(e->device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) != 0;
    info.isa = isa_from_report(verbose_report(isa_cfg));
    // Only the AVX-512 kernels trace 16-ray packets natively: a report that disagrees is not trusted.
    if (info.native_ray16 != (info.isa.rfind("AVX512", 0) == 0)) info.isa = "unknown";
    b.scenes[std::size_t(d)] = e;
  }
  const EmbreeScene& n = *b.scenes[0];
  b.build_ms = n.build_ms;
  b.bvh_bytes = n.bytes.load() - n.before_commit;
  b.total_bytes = n.bytes.load();
  b.ok = true;
  return b;
}

namespace {
inline std::uint32_t code(unsigned geom, unsigned prim) { return bvh::prim_code(int(geom), prim); }
// Embree asserts on rays outside its valid range (origin and direction finite and below 1.844e18 in
// magnitude, 0 <= tnear <= tfar): such a ray is a miss here, never a call.
constexpr float kEmbreeLarge = 1.844e18f;
inline bool fits(float x) { return x > -kEmbreeLarge && x < kEmbreeLarge; }
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr HitRec kMiss{kInf, kNoPrim};

template <class R>
void fill_ray(R& r, const RaySoA& rays, std::size_t i) {
  r.org_x = rays.ox[i]; r.org_y = rays.oy[i]; r.org_z = rays.oz[i];
  r.dir_x = rays.dx[i]; r.dir_y = rays.dy[i]; r.dir_z = rays.dz[i];
  r.tnear = rays.tmin[i]; r.tfar = rays.tmax[i]; r.mask = 0xFFFFFFFFu; r.flags = 0; r.time = 0; r.id = 0;
}

// Lane l of an Embree packet: ray k, or (invalid: its valid-mask lane is 0) a harmless ray
// (origin 0, direction +z, empty interval at 0) so that no lane holds a NaN.
template <class RK>
void fill_lane(RK& r, int l, const RaySoA& rays, std::size_t k, bool valid) {
  if (valid) {
    r.org_x[l] = rays.ox[k]; r.org_y[l] = rays.oy[k]; r.org_z[l] = rays.oz[k];
    r.dir_x[l] = rays.dx[k]; r.dir_y[l] = rays.dy[k]; r.dir_z[l] = rays.dz[k];
    r.tnear[l] = rays.tmin[k]; r.tfar[l] = rays.tmax[k];
  } else {
    r.org_x[l] = r.org_y[l] = r.org_z[l] = 0.f;
    r.dir_x[l] = r.dir_y[l] = 0.f; r.dir_z[l] = 1.f;
    r.tnear[l] = r.tfar[l] = 0.f;
  }
  r.mask[l] = 0xFFFFFFFFu; r.flags[l] = 0; r.time[l] = 0; r.id[l] = 0;
}

template <int K, class Ray, class RayHit, class Isect, class Occl>
void packets(RTCScene sc, RTCIntersectContext* ctx, const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, bool any,
             Isect isect, Occl occl) {
  for (std::size_t i = begin; i < end; i += K) {
    alignas(64) int valid[K];
    bool anyv = false;
    for (int l = 0; l < K; ++l) {
      const std::size_t k = i + std::size_t(l);
      valid[l] = k < end && embree_valid(rays, k) ? -1 : 0;
      anyv = anyv || valid[l];
    }
    const int n = int(std::min<std::size_t>(K, end - i));
    if (!anyv) {
      for (int l = 0; l < n; ++l) out[i + std::size_t(l)] = kMiss;
      continue;
    }
    if (any) {
      alignas(64) Ray r;
      for (int l = 0; l < K; ++l) fill_lane(r, l, rays, i + std::size_t(l), valid[l] != 0);
      occl(valid, sc, ctx, &r);
      for (int l = 0; l < n; ++l) out[i + std::size_t(l)] = valid[l] && r.tfar[l] == -kInf ? HitRec{0.f, bvh::prim_code(0, 0)} : kMiss;
    } else {
      alignas(64) RayHit rh;
      for (int l = 0; l < K; ++l) {
        fill_lane(rh.ray, l, rays, i + std::size_t(l), valid[l] != 0);
        rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
      }
      isect(valid, sc, ctx, &rh);
      for (int l = 0; l < n; ++l)
        out[i + std::size_t(l)] = valid[l] && rh.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID
                                      ? HitRec{rh.ray.tfar[l], code(rh.hit.geomID[l], rh.hit.primID[l])}
                                      : kMiss;
    }
  }
}
}  // namespace

bool embree_valid(const RaySoA& r, std::size_t i) {
  return r.tmin[i] <= r.tmax[i] && r.tmin[i] >= 0.0f && fits(r.tmin[i]) && fits(r.ox[i]) && fits(r.oy[i]) && fits(r.oz[i]) &&
         fits(r.dx[i]) && fits(r.dy[i]) && fits(r.dz[i]) && (r.dx[i] != 0.0f || r.dy[i] != 0.0f || r.dz[i] != 0.0f);
}

std::string EmbreeMode::call_name(bool any) const {
  const char* base = any ? "rtcOccluded" : "rtcIntersect";
  switch (call) {
    case EmbreeCall::one: return std::string(base) + "1";
    case EmbreeCall::eight: return std::string(base) + "8";
    case EmbreeCall::sixteen: return std::string(base) + "16";
    case EmbreeCall::stream: return std::string(base) + "1M";
  }
  return base;
}
std::string EmbreeMode::name(bool any) const {
  return fmt::format("{}{} {} {}", call_name(any), call == EmbreeCall::stream ? fmt::format("({})", stream) : std::string(),
                     embree_isa_label(isa), coherent ? "coherent" : "incoherent");
}

std::vector<EmbreeMode> embree_modes(int packet, bool coherent) {
  EmbreeCall c = EmbreeCall::one;
  int stream = 0;
  if (packet == 8) c = EmbreeCall::eight;
  else if (packet == 16) c = EmbreeCall::sixteen;
  else if (packet > 16) { c = EmbreeCall::stream; stream = packet; }
  std::vector<EmbreeMode> m;
  for (int d = 0; d < kEmbreeDevices; ++d) m.push_back({EmbreeIsa(d), c, stream, coherent});
  return m;
}

void embree_trace(const EmbreeBuild& e, const EmbreeMode& mode, const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out,
                  bool any) {
  RTCScene sc = e.scene(mode.isa).scene;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = mode.coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  switch (mode.call) {
    case EmbreeCall::one:
      for (std::size_t i = begin; i < end; ++i) {
        out[i] = kMiss;
        if (!embree_valid(rays, i)) continue;
        if (any) {
          RTCRay r;
          fill_ray(r, rays, i);
          rtcOccluded1(sc, &ctx, &r);
          if (r.tfar == -kInf) out[i] = {0.f, bvh::prim_code(0, 0)};
        } else {
          RTCRayHit rh;
          fill_ray(rh.ray, rays, i);
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(sc, &ctx, &rh);
          if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) out[i] = {rh.ray.tfar, code(rh.hit.geomID, rh.hit.primID)};
        }
      }
      return;
    case EmbreeCall::eight:
      packets<8, RTCRay8, RTCRayHit8>(sc, &ctx, rays, begin, end, out, any, rtcIntersect8, rtcOccluded8);
      return;
    case EmbreeCall::sixteen:
      packets<16, RTCRay16, RTCRayHit16>(sc, &ctx, rays, begin, end, out, any, rtcIntersect16, rtcOccluded16);
      return;
    case EmbreeCall::stream: {
      // The valid rays of each group of `stream` rays, in one rtcIntersect1M / rtcOccluded1M call.
      const std::size_t m = std::size_t(std::max(1, mode.stream));
      thread_local std::vector<RTCRayHit> buf;
      thread_local std::vector<std::uint32_t> which;
      buf.resize(m);
      which.resize(m);
      for (std::size_t i = begin; i < end; i += m) {
        const std::size_t e2 = std::min(end, i + m);
        unsigned n = 0;
        for (std::size_t k = i; k < e2; ++k) {
          out[k] = kMiss;
          if (!embree_valid(rays, k)) continue;
          RTCRayHit& rh = buf[n];
          fill_ray(rh.ray, rays, k);
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          which[n++] = std::uint32_t(k - i);
        }
        if (!n) continue;
        if (any) {
          // RTCRayHit begins with its RTCRay: a stride of sizeof(RTCRayHit) walks the rays.
          rtcOccluded1M(sc, &ctx, &buf[0].ray, n, sizeof(RTCRayHit));
          for (unsigned k = 0; k < n; ++k)
            if (buf[k].ray.tfar == -kInf) out[i + which[k]] = {0.f, bvh::prim_code(0, 0)};
        } else {
          rtcIntersect1M(sc, &ctx, buf.data(), n, sizeof(RTCRayHit));
          for (unsigned k = 0; k < n; ++k)
            if (buf[k].hit.geomID != RTC_INVALID_GEOMETRY_ID) out[i + which[k]] = {buf[k].ray.tfar, code(buf[k].hit.geomID, buf[k].hit.primID)};
        }
      }
      return;
    }
  }
}

}  // namespace rb::trace
