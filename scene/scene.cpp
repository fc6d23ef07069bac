#include "scene/scene.hpp"
#include "kernels/csg_ray.hpp"
#include "scene/sources.hpp"

#include <fmt/format.h>

#include <cmath>

namespace rb::scene {

Bounds Scene::bounds() const {
  Bounds b;
  for (const auto& s : spheres) {
    const double r = std::fabs(s.r);
    b.grow(s.c - Vec3d{r, r, r});
    b.grow(s.c + Vec3d{r, r, r});
  }
  for (const auto& c : cones) {
    const double r = std::max(std::fabs(c.base_r), std::fabs(c.apex_r));
    for (const Vec3d& p : {c.base, c.apex}) {
      b.grow(p - Vec3d{r, r, r});
      b.grow(p + Vec3d{r, r, r});
    }
  }
  for (const auto& t : tori) {
    const double r = std::fabs(t.R) + std::fabs(t.r);
    b.grow(t.c - Vec3d{r, r, r});
    b.grow(t.c + Vec3d{r, r, r});
  }
  for (const auto& p : poly_verts) b.grow(p);
  for (const auto& t : triangles)
    for (auto i : t.v) b.grow(verts[i]);
  for (const auto& c : csgs)
    if (!c.tree->empty()) {
      const CsgNode& n = c.tree->nodes[c.tree->root];
      b.grow(Vec3d{n.lo[0], n.lo[1], n.lo[2]});
      b.grow(Vec3d{n.hi[0], n.hi[1], n.hi[2]});
    }
  return b;
}

namespace {
bool all_finite(const Vec3d& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
double max_abs3(const Vec3d& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }
std::string show_vec(const Vec3d& v) { return fmt::format("({:g}, {:g}, {:g})", v.x, v.y, v.z); }
}  // namespace

void check_numbers(const Scene& s, const std::string& source) {
  auto fail = [&](const std::string& what) { throw SceneError(source + ": " + what); };
  const Bounds b = s.bounds();
  if (!b.empty()) {
    if (!all_finite(b.lo) || !all_finite(b.hi)) fail("the scene's bounds are not finite: " + show_vec(b.lo) + " to " + show_vec(b.hi));
    const double m = std::max(max_abs3(b.lo), max_abs3(b.hi));
    if (!(m <= kMaxCoordinate))
      fail(fmt::format("the scene's bounds reach {:g} ({} to {}), beyond the largest coordinate traced, {:g}: float arithmetic on "
                       "such extents overflows",
                       m, show_vec(b.lo), show_vec(b.hi), kMaxCoordinate));
  }
  const Camera& c = s.camera;
  if (!all_finite(c.from) || !all_finite(c.at) || !all_finite(c.up) || !std::isfinite(c.angle))
    fail("the camera is not finite: from " + show_vec(c.from) + ", at " + show_vec(c.at) + ", up " + show_vec(c.up) + fmt::format(", angle {:g}", c.angle));
  if (!(std::max(max_abs3(c.from), max_abs3(c.at)) <= kMaxCoordinate))
    fail(fmt::format("the camera (from {}, at {}) lies beyond the largest coordinate traced, {:g}", show_vec(c.from), show_vec(c.at), kMaxCoordinate));
  for (std::size_t i = 0; i < s.lights.size(); ++i) {
    const Light& l = s.lights[i];
    const Vec3d col{double(l.color.x), double(l.color.y), double(l.color.z)};
    if (!all_finite(l.pos) || !all_finite(col)) fail(fmt::format("light {} is not finite: position {}, colour {}", i + 1, show_vec(l.pos), show_vec(col)));
    if (!(max_abs3(l.pos) <= kMaxCoordinate))
      fail(fmt::format("light {} at {} lies beyond the largest coordinate traced, {:g}", i + 1, show_vec(l.pos), kMaxCoordinate));
  }
}

std::size_t Scene::csg_tree_bytes() const {
  std::size_t b = 0;
  for (const auto& c : csgs) b += c.tree->bytes();
  return b;
}

}  // namespace rb::scene
