// Where scenes come from: files (OBJ, PLY, NFF) and embedded generators, by one name.
//   path/to/file.obj | .ply | .nff        a file, by extension
//   spd:NAME[:SIZE]                       Haines' SPD generators: balls gears mount rings teapot tetra tree
//   lecture:NAME                          the lecture's scenes (seed 004's images)
//   path/to/scene.json                    the JSON scene format: CSG trees and analytic primitives (scene/csg_scene.hpp)
//   csg:NAME                              embedded CSG scenes (scene/csg_scene.hpp)
//   precision:NAME                        scenes that test a tracer's precision (scene/precision_scenes.cpp)
//   heightfield[:NXxNY]                   a wavy height field of NX x NY quads (default 708x707: 1,001,112 triangles)
// Errors (unknown name, unreadable or malformed file) throw rb::scene::SceneError whose
// message names the file, the line (or byte offset) and what was expected.
#pragma once

#include "scene/scene.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace rb::scene {

struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// scene/load.cpp (dispatch). Every scene it returns has passed check_numbers.
Scene load_scene(const std::string& source);

// Numbers the tracers can work with, checked before any use (camera framing, ray sets, the BVH):
// finite bounds within kMaxCoordinate of the origin (so that the extent, too, is at most twice
// that), a finite camera (from, at, up, angle) and finite lights (position within the same bound,
// colour). The tracers compute in float: products of three lengths of a scene's extent (triangle
// and quadric determinants, squared distances times a length) stay below float's 3.4e38 for
// extents up to about 7e12, so coordinates beyond 1e12 would turn rays and boxes into infinities.
// Throws SceneError naming `source`, the offending value and the bound.
inline constexpr double kMaxCoordinate = 1e12;
void check_numbers(const Scene& s, const std::string& source);

// Embedded generators (scene/spd/*.cpp, scene/lecture_scenes.cpp).
std::vector<std::string> spd_names();                  // {"balls", "gears", ...}
int spd_default_size(const std::string& name);         // Haines' default size factor
Scene generate_spd(const std::string& name, int size); // throws SceneError on an unknown name or size < 1
std::vector<std::string> lecture_scene_names();
Scene lecture_scene(const std::string& name);
std::vector<std::string> precision_scene_names();
Scene precision_scene(const std::string& name);
// Adds a closed icosphere of 20 * 4^levels triangles (shared vertices, consistent winding) of
// radius r at c to s's mesh (scene/precision_scenes.cpp).
void add_icosphere(Scene& s, const Vec3d& c, double r, int levels, std::uint32_t mat = 0);
// A wavy height field over [-1, 1]^2 (y up: 0.15 sin 7u cos 5v + 0.05 sin 31uv) of nx x ny quads,
// two triangles each: a generated mesh the size of a large scan (scene/heightfield.cpp). Throws
// SceneError on a side outside 1 .. kMaxHeightFieldSide.
inline constexpr int kMaxHeightFieldSide = 2048;
inline constexpr int kHeightFieldNx = 708, kHeightFieldNy = 707;  // `heightfield` alone
Scene height_field(int nx, int ny);

}  // namespace rb::scene
