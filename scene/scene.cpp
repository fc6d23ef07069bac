#include "scene/scene.hpp"
#include "kernels/csg.hpp"

#include <cmath>

namespace rb::scene {

Bounds Scene::bounds() const {
  Bounds b;
  for (const auto& s : spheres) {
    b.grow(s.c - Vec3f{s.r, s.r, s.r});
    b.grow(s.c + Vec3f{s.r, s.r, s.r});
  }
  for (const auto& c : cones) {
    const float r = std::max(c.base_r, c.apex_r);
    for (const Vec3f& p : {c.base, c.apex}) {
      b.grow(p - Vec3f{r, r, r});
      b.grow(p + Vec3f{r, r, r});
    }
  }
  for (const auto& p : poly_verts) b.grow(p);
  for (const auto& t : triangles)
    for (auto i : t.v) b.grow(verts[i]);
  for (const auto& c : csgs)
    if (!c.tree->empty()) {
      const CsgNode& n = c.tree->nodes[c.tree->root];
      b.grow({n.lo[0], n.lo[1], n.lo[2]});
      b.grow({n.hi[0], n.hi[1], n.hi[2]});
    }
  return b;
}

std::size_t Scene::csg_tree_bytes() const {
  std::size_t b = 0;
  for (const auto& c : csgs) b += c.tree->bytes();
  return b;
}

}  // namespace rb::scene
