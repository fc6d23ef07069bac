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
#include <vector>

namespace rb::tracer {

using kinds::Kind;
using kinds::kKinds;

// The spacing of floats at magnitude x (ulp), for x >= 0; 2^-149 at 0.
double float_step(double x);

// The float step over a primitive's size below which float storage represents it well enough.
inline constexpr double kFloatTolerance = 0x1p-12;

// What the input's mesh coordinates hold (Scene::verts), read from the values themselves, whatever
// the file's format: a binary float PLY gives floats; decimal text gives the number its digits
// spell, which float reproduces within the text's own resolution (half a unit in the last of its
// shortest digits) when the text has no more digits than float holds; doubles computed by a
// generator or a transform hold more.
struct InputPrecision {
  std::size_t coords = 0;   // coordinates examined
  std::size_t floats = 0;   // exactly a float
  std::size_t decimal = 0;  // not a float, but the nearest float is within the text's own resolution
  std::size_t finer = 0;    // more than a float holds
  int digits_max = 0;       // the most significant decimal digits of a coordinate that is not a float
  std::string summary() const;  // one line: "float: every coordinate is a float", ...
};

struct KindProfile {
  std::size_t count = 0;
  // Primitives with no area or no size, or smaller than one float step where they lie (world):
  // left out of every figure below.
  std::size_t degenerate = 0;
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
  // The smallest object extent (1st percentile over the primitives' extents, so that a few
  // slivers do not decide; see make_profile): the scale at which the scene must stay right.
  double object_min = 0;
  // The box ray origins come from: the eye and every primitive but the huge ones (over a thousand
  // times the smallest object: a planet, a vast floor, whose far parts are not where the scene's
  // rays start). Lights are where shadow rays end, not where they start.
  scene::Bounds origins;
  std::size_t huge = 0;             // primitives left out of `origins`
  std::array<KindProfile, kKinds> kinds{};
  std::size_t primitives = 0;
  InputPrecision input;
  // Per vertex of Scene::verts: float storage in world coordinates reproduces it (all three
  // coordinates exact floats or within the input's own resolution).
  std::vector<std::uint8_t> vertex_as_input;

  nlohmann::json json() const;
};

Profile make_profile(const scene::Scene& s);

// The representation error of a frame with origin O. For every kind (`contact[k]`), the largest
// float step of its primitives' coordinates relative to O over the primitive's own extent (how far
// rounding to float in that frame moves its surface against its size), or over the scene's
// smallest object for a primitive a thousand times larger than that (a planet: small objects rest
// on it). For the eye (`eye`), the shift its rounding gives the whole view, in pixels (its float step
// over its distance to the nearest object, over the angle of a pixel).
//
// Every primitive falls in one class, by what float storage in that frame does to it:
//   as_input    the frame is the world's and float reproduces the input within its own precision
//               (a mesh read as floats): storing it in float changes nothing the data held;
//   fine        float step over its size at most kFloatTolerance;
//   coarse      above: float would move its surface visibly against its size, or collapse it when
//               it is smaller than one float step where it is (needs double, unless all the
//               coarse ones together can change a negligible share of the hits);
//   degenerate  no area or no size (collapsed and collinear triangles, zero radii): kept in the
//               tree as a slot no ray hits, which is the exact answer up to rays of measure zero;
//               never counted against the others (contact[k] is over the fine and coarse
//               primitives only).
// The share of a kind's hits that coarse primitives may change before they decide its storage:
// their perimeters times the float step where they lie, over the kind's area (a tenth of a hit per
// million).
inline constexpr double kNegligibleShare = 1e-7;

struct KindClasses {
  std::size_t as_input = 0, fine = 0, coarse = 0, degenerate = 0;
  // Of the coarse ones, those over a thousand times the smallest object (judged against it: no
  // origin of their own holds them in float).
  std::size_t coarse_huge = 0;
  // The coarse primitives' perimeters times their float step over the kind's area, and whether
  // that is at most kNegligibleShare: then the coarse ones stay in float with the rest (contact[k]
  // is over the fine primitives only).
  double moved_share = 0;
  bool negligible = false;
  std::uint32_t worst_coarse = UINT32_MAX;      // the primitive with the largest step over size
  double worst_coarse_ratio = 0;
  std::uint32_t worst_degenerate = UINT32_MAX;  // the smallest degenerate primitive (by extent)
  double worst_degenerate_extent = 0;
};
struct FrameError {
  std::array<double, kKinds> contact{};
  std::array<KindClasses, kKinds> classes{};
  // The coarse primitives of each kind (scene indices, ascending): the plan may store them in double
  // in a batch of their own (tracer/plan.hpp, KindPlan::split).
  std::array<std::vector<std::uint32_t>, kKinds> coarse_ids{};
  // The largest float step over size among each kind's fine and as-input primitives (those that
  // stay in float when the coarse ones are split off).
  std::array<double, kKinds> contact_fine{};
  double eye = 0;
  double worst(const std::array<bool, kKinds>& ignore) const;  // the largest contact[k] not ignored
};
FrameError frame_error(const scene::Scene& s, const Profile& p, const Vec3d& origin);

// The scale huge primitives are judged against: the smallest object (or the extent, or 1).
double smallest_object(const Profile& p);
// A primitive's float step over its size in the frame at `origin` (the ratio its class is decided
// by, against kFloatTolerance): the float step at its box's largest coordinate there, over its
// extent, or over `small` (smallest_object) for a primitive over a thousand times that.
double float_step_ratio(const scene::Bounds& b, const kinds::Feature& f, const Vec3d& origin, double small);

}  // namespace rb::tracer
