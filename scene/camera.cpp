#include "scene/camera.hpp"

#include <algorithm>
#include <cmath>

namespace rb::scene {

namespace {
Vec3d unit_or(const Vec3d& a, const Vec3d& fallback) {
  const double l = std::sqrt(dot(a, a));
  return l > 0 && std::isfinite(l) ? a * (1.0 / l) : fallback;
}
}  // namespace

bool has_camera(const Scene& s) {
  const Camera d{};
  const Camera& c = s.camera;
  return !(c.from.x == d.from.x && c.from.y == d.from.y && c.from.z == d.from.z && c.at.x == d.at.x && c.at.y == d.at.y &&
           c.at.z == d.at.z);
}

View view_of(const Scene& s) {
  View v;
  if (has_camera(s)) {
    v.from = s.camera.from;
    v.w = unit_or(s.camera.at - v.from, Vec3d{0, 0, -1});
    v.angle = s.camera.angle;
    Vec3d u = cross(v.w, s.camera.up);
    if (!(dot(u, u) > 0)) u = cross(v.w, Vec3d{0, 1, 0});
    if (!(dot(u, u) > 0)) u = cross(v.w, Vec3d{1, 0, 0});
    v.u = unit_or(u, Vec3d{1, 0, 0});
  } else {
    v.stated = true;
    const Bounds b = s.bounds();
    Vec3d lo{-1, -1, -1}, hi{1, 1, 1};
    if (!b.empty()) lo = b.lo, hi = b.hi;
    const Vec3d centre = (lo + hi) * 0.5;
    const Vec3d dir = unit_or(Vec3d{0.3, 0.4, -1.0}, Vec3d{0, 0, 1});
    const double h = 0.5 * std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    v.angle = 45;
    v.from = centre + dir * (h / std::tan(v.angle * M_PI / 360.0) + h);
    v.w = dir * -1.0;
    v.u = unit_or(cross(v.w, Vec3d{0, 1, 0}), Vec3d{1, 0, 0});
  }
  if (!(v.angle > 0 && v.angle < 180)) v.angle = 45;
  v.half = std::tan(v.angle * M_PI / 360.0);
  v.v = cross(v.u, v.w);
  return v;
}

}  // namespace rb::scene
