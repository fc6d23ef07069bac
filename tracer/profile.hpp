// The numerical profile of a scene: the quantities that decide whether float arithmetic and float
// coordinates represent it, per primitive kind. tracer/plan.cpp reads it to choose the frame of
// reference, each kind's storage, method and precision, and the spawn offset.
//
// Every length is in the scene's units; "float step at x" is the spacing of floats near |x|
// (2^-23 |x| up to a factor 2).
#pragma once

#include "tracer/kinds.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <optional>
#include <string>

namespace rb::tracer {

using kinds::Kind;
using kinds::kKinds;

// The spacing of floats at magnitude x (ulp), for x >= 0; 2^-149 at 0.
double float_step(double x);

struct KindProfile {
  std::size_t count = 0;
  // Feature sizes (Feature::size: the smallest length that matters for a primitive) and extents
  // (its largest dimension), over the kind's non-degenerate primitives.
  double size_min = 0, size_median = 0, size_max = 0;
  double extent_min = 0, extent_p01 = 0, extent_max = 0;
  double aspect_max = 0;   // largest extent / size: needles, thin tubes, long cylinders
  double coord_max = 0;    // largest |coordinate| of the kind's boxes (world)
  // The largest distance from any ray origin the scene can produce (its bounds, camera, lights)
  // to a primitive's centre, over the primitive's size: how far away the kind is seen from.
  double far_ratio = 0;
  // The largest size of the kind over the smallest object extent of the scene: a planet under
  // small objects (their rays start close to its surface).
  double scale_ratio = 0;
  // Float step at the kind's largest coordinate over its smallest feature size (world frame).
  double world_step_ratio = 0;
};

struct Profile {
  std::string scene;
  scene::Bounds bounds;             // all primitives (world)
  double extent = 0;                // largest side of the bounds
  double coord_max = 0;             // largest |coordinate| of the bounds
  Vec3d camera{0, 0, 0};            // the eye (scene/camera.hpp: the scene's, or the stated one)
  bool stated_camera = false;
  double camera_distance = 0;       // from the eye to the nearest primitive's box (0 inside one)
  double pixel_angle = 0;           // the view's angle per pixel (radians)
  double light_distance_max = 0;    // from the bounds' centre to the farthest light
  // The smallest object extent (1st percentile over every primitive's extent, so that a few
  // slivers do not decide): the scale at which the scene must stay right.
  double object_min = 0;
  // The box ray origins come from: the eye and every primitive but the huge ones (over a thousand
  // times the smallest object: a planet, a vast floor, whose far parts are not where the scene's
  // rays start). Lights are where shadow rays end, not where they start.
  scene::Bounds origins;
  std::size_t huge = 0;             // primitives left out of `origins`
  std::array<KindProfile, kKinds> kinds{};
  std::size_t primitives = 0;

  nlohmann::json json() const;
};

Profile make_profile(const scene::Scene& s);

// The representation error of a frame with origin O. For every kind (`contact[k]`), the largest
// float step of its primitives' coordinates relative to O over the primitive's own extent (how far
// rounding to float in that frame moves its surface against its size), or over the scene's
// smallest object for a primitive a thousand times larger than that (a planet: small objects rest
// on it). For the eye (`eye`), the shift its rounding gives the whole view, in pixels (its float step
// over its distance to the nearest object, over the angle of a pixel).
struct FrameError {
  std::array<double, kKinds> contact{};
  double eye = 0;
  double worst(const std::array<bool, kKinds>& ignore) const;  // the largest contact[k] not ignored
};
FrameError frame_error(const scene::Scene& s, const Profile& p, const Vec3d& origin);

}  // namespace rb::tracer
