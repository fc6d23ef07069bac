// The camera every view of a scene uses (the renderer's image, `raybench trace`'s primary rays,
// the accuracy lab's whole-scene cases), in double and in world coordinates: the scene's own
// (NFF `v`, the JSON "camera"), or, for a scene without one (a bare mesh), the stated camera:
// looking at the bounds' centre from the direction (0.3, 0.4, -1), 45 degrees, at the distance
// h / tan(22.5 deg) + h from it (h the largest half extent of the bounds), so the bounds about
// fill the view.
#pragma once

#include "scene/scene.hpp"

namespace rb::scene {

struct View {
  Vec3d from;       // eye
  Vec3d w, u, v;    // unit forward, right, up (v = u x w)
  double half = 1;  // tan(angle / 2): the image plane at distance 1 spans [-half, half] across its larger side
  double angle = 45;
  bool stated = false;  // true: the scene had no camera

  // The direction through the image-plane point (x, y), in units of `half` (x right, y up): x = +-1
  // are the edges of the larger image side. Not normalised.
  Vec3d dir(double x, double y) const { return w + u * (x * half) + v * (y * half); }
};

// Whether the scene gives its own camera (any of from/at differs from the default Camera).
bool has_camera(const Scene& s);
// The view of the scene (see above). A degenerate camera (from == at) looks down -z.
View view_of(const Scene& s);

}  // namespace rb::scene
