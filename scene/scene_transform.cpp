#include "scene/scene_transform.hpp"

#include "kernels/csg_ray.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rb::scene {

namespace {
// The map p -> k p + t applied to every position of the scene; sizes scale by k.
Scene mapped(const Scene& in, double k, const Vec3d& t) {
  Scene s = in;
  auto P = [&](const Vec3d& p) { return p * k + t; };
  s.camera.from = P(s.camera.from);
  s.camera.at = P(s.camera.at);
  for (auto& L : s.lights) L.pos = P(L.pos);
  for (auto& sp : s.spheres) sp.c = P(sp.c), sp.r *= k;
  for (auto& c : s.cones) c.base = P(c.base), c.apex = P(c.apex), c.base_r *= k, c.apex_r *= k;
  for (auto& v : s.poly_verts) v = P(v);
  for (auto& v : s.verts) v = P(v);
  for (auto& tr : s.tori) tr.c = P(tr.c), tr.R *= k, tr.r *= k;
  for (auto& m : s.materials) m.checker = float(double(m.checker) * k);
  // CSG: the tree rebuilt in the frame of the inverse map (in_frame takes an origin: a pure
  // translation); a scaled CSG scene is not supported.
  if (!s.csgs.empty() && k != 1.0) throw std::invalid_argument(in.name + ": scaling a scene with CSG objects is not supported");
  for (auto& c : s.csgs)
    if (c.in_frame) {
      auto old = c.in_frame;
      c.tree = old(t * -1.0);
      c.in_frame = [old, t](const Vec3d& origin) { return old(origin - t); };
    }
  return s;
}
}  // namespace

Scene translated(const Scene& s, const Vec3d& by) {
  if (!finite3(by)) throw std::invalid_argument("move: the offset is not finite");
  Scene r = mapped(s, 1.0, by);
  r.name = s.name;
  return r;
}

Scene scaled(const Scene& s, double by) {
  if (!(by > 0) || !std::isfinite(by)) throw std::invalid_argument("scale: the factor must be positive and finite");
  Scene r = mapped(s, by, {0, 0, 0});
  r.name = s.name;
  return r;
}

}  // namespace rb::scene
