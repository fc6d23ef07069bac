// A scene moved or scaled as a whole (camera, lights and every primitive; CSG trees placed by the
// same map), computed in double: a far-away or rescaled copy of a scene for `--move`/`--scale` and
// the invariance tests. Scaling also scales the checkerboard's cell size, so the copy looks the same.
#pragma once

#include "scene/scene.hpp"

namespace rb::scene {

Scene translated(const Scene& s, const Vec3d& by);
// s > 0 and finite (else std::invalid_argument).
Scene scaled(const Scene& s, double by);

}  // namespace rb::scene
