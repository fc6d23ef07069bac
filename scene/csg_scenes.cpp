// The embedded CSG scenes (csg:NAME): JSON scenes of the format scene/json_scene.cpp reads, each a CSG
// object over a floor, with the lights and materials they share.
#include "core/suggest.hpp"
#include "scene/csg_scene.hpp"

#include <nlohmann/json.hpp>

#include <cmath>

namespace rb::scene {

using nlohmann::json;

namespace {
const char* kCommon = R"("camera": {"from": [0, 1.5, 6], "at": [0, 0, 0], "up": [0, 1, 0], "angle": 40, "width": 512, "height": 512, "hither": 0.001},
  "background": [0.078, 0.361, 0.753],
  "lights": [{"position": [-6, 10, 8], "color": [1, 1, 1]}, {"position": [8, 6, 6], "color": [0.5, 0.5, 0.5]}],
  "materials": {
    "red":   {"color": [0.9, 0.15, 0.1], "kd": 0.8, "ks": 0.2, "shine": 40},
    "white": {"color": [0.95, 0.95, 0.9], "kd": 0.8, "ks": 0.1, "shine": 20},
    "black": {"color": [0.05, 0.05, 0.05], "kd": 0.8, "ks": 0.1, "shine": 20},
    "glass": {"color": [0.9, 0.95, 1.0], "kd": 0.1, "ks": 0.3, "shine": 100, "t": 0.9, "ior": 1.5},
    "gold":  {"color": [0.9, 0.7, 0.2], "kd": 0.6, "ks": 0.4, "shine": 60},
    "floor": {"color": [0.6, 0.6, 0.6], "kd": 0.9}
  },
)";
const char* kFloor = R"({"type": "polygon", "material": "floor", "vertices": [[-20, -1.5, -20], [-20, -1.5, 20], [20, -1.5, 20], [20, -1.5, -20]]})";

// The die: a cube intersected with a sphere (rounded edges), minus short cylinders for the pips
// (1 opposite 6, 2 opposite 5, 3 opposite 4), each face's pips a union of their own.
std::string die_json() {
  json faces = json::array();
  // Face normal n, in-face axes u, v; pip positions in (u, v) units of 0.5.
  struct Face {
    Vec3d n, u, v;
    std::vector<std::pair<int, int>> pips;
  };
  const std::vector<Face> F = {
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {{0, 0}}},
      {{0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {{-1, -1}, {-1, 0}, {-1, 1}, {1, -1}, {1, 0}, {1, 1}}},
      {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}, {{-1, -1}, {1, 1}}},
      {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}, {{-1, -1}, {-1, 1}, {1, -1}, {1, 1}, {0, 0}}},
      {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {{-1, -1}, {0, 0}, {1, 1}}},
      {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}, {{-1, -1}, {-1, 1}, {1, -1}, {1, 1}}},
  };
  for (const Face& f : F) {
    json pips = json::array();
    for (auto [a, b] : f.pips) {
      const Vec3d c = f.n * 1.0 + f.u * (0.5 * a) + f.v * (0.5 * b);
      const Vec3d base = c - f.n * 0.12;
      pips.push_back({{"type", "cylinder"}, {"base", {base.x, base.y, base.z}}, {"axis", {f.n.x, f.n.y, f.n.z}}, {"radius", 0.14}, {"height", 0.3}});
    }
    if (pips.size() == 1) faces.push_back(pips[0]);
    else faces.push_back({{"type", "union"}, {"children", pips}});
  }
  json die = {{"type", "difference"},
              {"material", "white"},
              {"transform", {{"rotate", {{"axis", {1, 1, 0}}, {"degrees", 30}}}}},
              {"left", {{"type", "intersection"},
                        {"left", {{"type", "box"}, {"min", {-1, -1, -1}}, {"max", {1, 1, 1}}}},
                        {"right", {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.38}}}}},
              {"right", {{"type", "union"}, {"material", "black"}, {"children", faces}}}};
  return std::string("{\n  ") + kCommon + "  \"objects\": [\n    " + die.dump() + ",\n    " + kFloor + "\n  ]\n}\n";
}

std::string wrap(const char* objects) { return std::string("{\n  ") + kCommon + "  \"objects\": [\n" + objects + ",\n    " + kFloor + "\n  ]\n}\n"; }
}  // namespace

std::vector<std::string> csg_scene_names() { return {"spheres_minus", "lens", "die", "torus_box", "ellipsoid_minus_cylinder"}; }

std::string csg_scene_json(const std::string& name) {
  // The slide's A - B: a sphere with a bite taken out by a second one.
  if (name == "spheres_minus")
    return wrap(R"(    {"type": "difference", "material": "red",
     "left": {"type": "sphere", "center": [0, 0, 0], "radius": 1.2},
     "right": {"type": "sphere", "center": [0.7, 0.5, 0.8], "radius": 0.9}})");
  // A biconvex lens: the intersection of two spheres (seed 004's "Lens").
  if (name == "lens")
    return wrap(R"(    {"type": "intersection", "material": "glass",
     "left": {"type": "sphere", "center": [0, 0, -1.6], "radius": 2.0},
     "right": {"type": "sphere", "center": [0, 0, 1.6], "radius": 2.0}})");
  if (name == "die") return die_json();
  // A torus cut by a box: the half of a ring above a plane and inside a slab.
  if (name == "torus_box")
    return wrap(R"(    {"type": "intersection", "material": "gold",
     "transform": {"rotate": {"axis": [1, 0, 0], "degrees": 60}},
     "left": {"type": "torus", "center": [0, 0, 0], "axis": [0, 0, 1], "major": 1.2, "minor": 0.4},
     "right": {"type": "box", "min": [-2, -0.6, -1], "max": [2, 2, 1]}})");
  // A transformed difference: an ellipsoid with a tilted cylinder bored through, rotated and
  // moved as a whole.
  if (name == "ellipsoid_minus_cylinder")
    return wrap(R"(    {"type": "difference", "material": "red",
     "transform": {"translate": [0, 0.1, 0], "rotate": {"axis": [0, 1, 1], "degrees": 35}, "scale": [1, 1, 1.2]},
     "left": {"type": "ellipsoid", "center": [0, 0, 0], "radii": [1.4, 0.9, 0.7]},
     "right": {"type": "cylinder", "base": [0, -2, 0], "axis": [0.3, 1, 0], "radius": 0.4, "height": 4}})");
  std::string names;
  for (const auto& n : csg_scene_names()) names += (names.empty() ? "" : ", ") + n;
  throw SceneError("csg:" + name + ": unknown CSG scene (" + names + ")" + did_you_mean(name, csg_scene_names()));
}

Scene csg_scene(const std::string& name) { return parse_json_scene(csg_scene_json(name), "csg:" + name); }

}  // namespace rb::scene
