#include "scene/scene.hpp"

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
  return b;
}

}  // namespace rb::scene
