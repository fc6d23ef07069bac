#include "scene/scene.hpp"
#include "kernels/csg.hpp"

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

std::size_t Scene::csg_tree_bytes() const {
  std::size_t b = 0;
  for (const auto& c : csgs) b += c.tree->bytes();
  return b;
}

}  // namespace rb::scene
