// Where scenes come from: files (OBJ, PLY, NFF) and embedded generators, by one name.
//   path/to/file.obj | .ply | .nff        a file, by extension
//   spd:NAME[:SIZE]                       Haines' SPD generators: balls gears mount rings teapot tetra tree
//   lecture:NAME                          the lecture's scenes (seed 004's images)
//   path/to/scene.json                    the JSON scene format: CSG trees and analytic primitives (scene/csg.hpp)
//   csg:NAME                              embedded CSG scenes (scene/csg.hpp)
//   precision:NAME                        scenes that test a tracer's precision (scene/precision_scenes.cpp)
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

Scene load_scene(const std::string& source);          // scene/load.cpp (dispatch)

// Embedded generators (scene/spd/*.cpp, scene/lecture_scenes.cpp).
std::vector<std::string> spd_names();                  // {"balls", "gears", ...}
int spd_default_size(const std::string& name);         // Haines' default size factor
Scene generate_spd(const std::string& name, int size); // throws SceneError on an unknown name or size < 1
std::vector<std::string> lecture_scene_names();
Scene lecture_scene(const std::string& name);
std::vector<std::string> precision_scene_names();
Scene precision_scene(const std::string& name);

}  // namespace rb::scene
