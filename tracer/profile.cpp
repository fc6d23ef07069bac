#include "tracer/profile.hpp"

#include "scene/camera.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace rb::tracer {

double float_step(double x) {
  x = std::fabs(x);
  if (!(x >= 0x1p-126)) return 0x1p-149;
  if (!std::isfinite(x)) return std::numeric_limits<double>::infinity();
  int e = 0;
  std::frexp(x, &e);  // x = m 2^e, m in [0.5, 1): floats there are 2^(e - 24) apart
  return std::ldexp(1.0, e - 24);
}

namespace {
double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return 0;
  const std::size_t k = std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}
double max_abs(const Vec3d& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }
// The largest distance from p to a point of box b.
double far_dist(const scene::Bounds& b, const Vec3d& p) {
  const Vec3d d{std::max(std::fabs(p.x - b.lo.x), std::fabs(p.x - b.hi.x)), std::max(std::fabs(p.y - b.lo.y), std::fabs(p.y - b.hi.y)),
                std::max(std::fabs(p.z - b.lo.z), std::fabs(p.z - b.hi.z))};
  return std::sqrt(dot(d, d));
}
// The distance from p to the nearest point of box b (0 inside).
double near_dist(const scene::Bounds& b, const Vec3d& p) {
  const Vec3d d{std::max({b.lo.x - p.x, 0.0, p.x - b.hi.x}), std::max({b.lo.y - p.y, 0.0, p.y - b.hi.y}),
                std::max({b.lo.z - p.z, 0.0, p.z - b.hi.z})};
  return std::sqrt(dot(d, d));
}
}  // namespace

Profile make_profile(const scene::Scene& s) {
  Profile p;
  p.scene = s.name;
  const scene::View v = scene::view_of(s);
  p.camera = v.from;
  p.stated_camera = v.stated;
  std::vector<double> extents_all;
  struct Acc {
    std::vector<double> size, extent;
  };
  std::array<Acc, kKinds> acc;
  kinds::AllKinds::each([&]<class K>() {
    KindProfile& kp = p.kinds[std::size_t(K::id)];
    Acc& a = acc[std::size_t(K::id)];
    K::each(s, [&](std::uint32_t i) {
      ++kp.count;
      const scene::Bounds b = K::bounds(s, i);
      if (b.empty()) return;
      p.bounds.grow(b);
      kp.coord_max = std::max({kp.coord_max, max_abs(b.lo), max_abs(b.hi)});
      const kinds::Feature f = K::feature(s, i);
      if (!(f.size > 0) || !(f.extent > 0)) return;
      a.size.push_back(f.size);
      a.extent.push_back(f.extent);
      extents_all.push_back(f.extent);
      kp.aspect_max = std::max(kp.aspect_max, f.extent / f.size);
    });
    p.primitives += kp.count;
  });
  p.extent = p.bounds.empty() ? 0 : p.bounds.max_extent();
  p.coord_max = p.bounds.empty() ? 0 : std::max(max_abs(p.bounds.lo), max_abs(p.bounds.hi));
  p.object_min = quantile(extents_all, 0.01);
  const scene::Camera& cam = s.camera;
  p.pixel_angle = v.angle * M_PI / 180.0 / double(std::max({cam.width, cam.height, 1}));
  // Ray origins: the eye and every primitive that is not huge; the eye's distance to the nearest box.
  p.origins.grow(p.camera);
  double near = 1e300;
  kinds::AllKinds::each([&]<class K>() {
    K::each(s, [&](std::uint32_t i) {
      const scene::Bounds b = K::bounds(s, i);
      if (b.empty()) return;
      near = std::min(near, near_dist(b, p.camera));
      if (K::feature(s, i).extent > 1e3 * p.object_min) {
        ++p.huge;
        return;
      }
      p.origins.grow(b);
    });
  });
  p.camera_distance = near < 1e300 ? near : 0;
  for (const auto& L : s.lights)
    if (!p.bounds.empty()) p.light_distance_max = std::max(p.light_distance_max, std::sqrt(dot(L.pos - p.bounds.centre(), L.pos - p.bounds.centre())));

  kinds::AllKinds::each([&]<class K>() {
    KindProfile& kp = p.kinds[std::size_t(K::id)];
    Acc& a = acc[std::size_t(K::id)];
    if (a.size.empty()) return;
    std::vector<double> sz = a.size, ex = a.extent;
    kp.size_min = *std::min_element(sz.begin(), sz.end());
    kp.size_max = *std::max_element(sz.begin(), sz.end());
    kp.size_median = quantile(sz, 0.5);
    kp.extent_min = *std::min_element(ex.begin(), ex.end());
    kp.extent_max = *std::max_element(ex.begin(), ex.end());
    kp.extent_p01 = quantile(ex, 0.01);
    // How far the kind is seen from: the farthest ray origin (a corner of the origins' box) from
    // each primitive's centre, over its size.
    double far = 0;
    K::each(s, [&](std::uint32_t i) {
      const kinds::Feature f = K::feature(s, i);
      if (f.size > 0) far = std::max(far, far_dist(p.origins, f.centre) / f.size);
    });
    kp.far_ratio = far;
    kp.scale_ratio = p.object_min > 0 ? kp.extent_max / p.object_min : 0;
    kp.world_step_ratio = kp.size_min > 0 ? float_step(kp.coord_max) / kp.size_min : 0;
  });
  return p;
}

double FrameError::worst(const std::array<bool, kKinds>& ignore) const {
  double w = 0;
  for (int k = 0; k < kKinds; ++k)
    if (!ignore[std::size_t(k)]) w = std::max(w, contact[std::size_t(k)]);
  return w;
}

FrameError frame_error(const scene::Scene& s, const Profile& p, const Vec3d& origin) {
  FrameError e;
  const double small = p.object_min > 0 ? p.object_min : (p.extent > 0 ? p.extent : 1.0);
  kinds::AllKinds::each([&]<class K>() {
    double worst = 0;
    K::each(s, [&](std::uint32_t i) {
      const scene::Bounds b = K::bounds(s, i);
      if (b.empty()) return;
      // The largest coordinate the primitive stores in this frame (its box corners relative to
      // the origin), its float step against its own extent; a primitive over a thousand times the
      // smallest object (a planet, a vast floor) against that object: small objects rest on it.
      const double m = std::max(max_abs(b.lo - origin), max_abs(b.hi - origin));
      const double ext = K::feature(s, i).extent;
      const double scale = ext > 1e3 * small || !(ext > 0) ? small : ext;
      worst = std::max(worst, float_step(m) / scale);
    });
    e.contact[std::size_t(K::id)] = worst;
  });
  const double dist = std::max(p.camera_distance, small);
  e.eye = p.pixel_angle > 0 ? float_step(max_abs(p.camera - origin)) * std::sqrt(3.0) / dist / p.pixel_angle : 0;
  return e;
}

nlohmann::json Profile::json() const {
  using nlohmann::json;
  auto v3 = [](const Vec3d& v) { return json::array({v.x, v.y, v.z}); };
  json k = json::object();
  for (int i = 0; i < kKinds; ++i) {
    const KindProfile& q = kinds[std::size_t(i)];
    if (!q.count) continue;
    k[kinds::kind_name(Kind(i))] = {{"count", q.count},
                                    {"size_min", q.size_min},
                                    {"size_median", q.size_median},
                                    {"size_max", q.size_max},
                                    {"extent_min", q.extent_min},
                                    {"extent_max", q.extent_max},
                                    {"aspect_max", q.aspect_max},
                                    {"coord_max", q.coord_max},
                                    {"far_ratio", q.far_ratio},
                                    {"scale_ratio", q.scale_ratio},
                                    {"world_float_step_over_size", q.world_step_ratio}};
  }
  return {{"scene", scene},
          {"primitives", primitives},
          {"bounds_lo", bounds.empty() ? json(nullptr) : v3(bounds.lo)},
          {"bounds_hi", bounds.empty() ? json(nullptr) : v3(bounds.hi)},
          {"extent", extent},
          {"coord_max", coord_max},
          {"world_float_step", float_step(coord_max)},
          {"camera", v3(camera)},
          {"camera_stated", stated_camera},
          {"camera_distance", camera_distance},
          {"pixel_angle", pixel_angle},
          {"huge_primitives", huge},
          {"light_distance_max", light_distance_max},
          {"object_min", object_min},
          {"kinds", k}};
}

}  // namespace rb::tracer
