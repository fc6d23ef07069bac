// The JSON scene format (CSG trees, analytic primitives, materials, camera, lights) and the
// embedded CSG scenes `csg:NAME`. Model no more than a scene needs:
//
//   { "camera": {"from": [x,y,z], "at": [..], "up": [..], "angle": 45, "width": 512, "height": 512, "hither": 0.001},
//     "background": [r,g,b],
//     "lights": [{"position": [..], "color": [..]}],
//     "materials": {"NAME": {"color": [..], "kd": 1, "ks": 0, "shine": 0, "t": 0, "ior": 1}},
//                  (the name "default" sets the material of every object that names none)
//     "objects": [ NODE, ... ] }
//
// Every key but "objects" is optional. A NODE is
//   {"type": "union" | "intersection", "children": [NODE, NODE, ...]}      (or "left", "right")
//   {"type": "difference", "left": NODE, "right": NODE}                    (left minus right)
//   {"type": "sphere", "center", "radius"}          {"type": "box", "min", "max"}
//   {"type": "polyhedron", "planes": [{"normal", "point"}, ...]}   convex, bounded, 4..12 planes
//   {"type": "cylinder", "base", "axis", "radius", "height"}      capped
//   {"type": "cone", "apex", "axis", "radius", "height"}          capped; "radius" at "height"
//   {"type": "torus", "center", "axis", "major", "minor"}
//   {"type": "ellipsoid", "center", "radii"}
//   {"type": "quadric", "coefficients": [a,b,c,d,e,f,g,h,j,k]}    bounded (an ellipsoid), inside F <= 0
//   {"type": "polygon", "vertices": [[x,y,z], ...]}              top level only (a floor); not a solid
// and any node may have "material": "NAME" (inherited by the leaves below it) and
// "transform": {"translate": [..], "rotate": {"axis": [..], "degrees": d}, "scale": s | [sx,sy,sz]}
// (M = translate * rotate * scale) or {"matrix": [[4 numbers] x 3]}. A top-level sphere without
// transform is a plain sphere and a polygon a plain polygon; every other top-level node is one CSG
// object (a primitive kind of its own: scene/batches.hpp).
//
// Errors throw SceneError naming the file and the JSON path:
//   "scene.json: objects[2].right.radius: expected a positive number".
#pragma once

#include "kernels/csg_ray.hpp"
#include "scene/sources.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace rb::scene {

Scene load_json_scene(const std::string& path);
Scene parse_json_scene(std::string_view text, const std::string& name);

// The scene in the JSON scene format (pretty-printed), a starting point for a scene of one's own:
// parse_json_scene of the text gives the same scene (camera, background, lights, materials,
// spheres, polygons, tori and CSG objects, every number as stored). Material 0 is written as
// "default", material i as "m<i>". Throws SceneError naming what the format cannot
// represent: triangle meshes, NFF cones, per-vertex normals, checkerboard materials.
std::string scene_json(const Scene& s);

// One CSG node (a JSON object's text) as a tree; `where` prefixes the messages (e.g. "primitive").
// Materials are not resolved (every leaf gets material 0). Throws SceneError "WHERE.PATH: ...".
CsgTree csg_from_json_text(std::string_view node_json, const std::string& where);

// Embedded CSG scenes (scene/csg_scenes.cpp): csg:spheres_minus, csg:lens, csg:die, csg:torus_box,
// csg:ellipsoid_minus_cylinder.
std::vector<std::string> csg_scene_names();
std::string csg_scene_json(const std::string& name);  // the scene's JSON text (SceneError if unknown)
Scene csg_scene(const std::string& name);

// The CSG object hit by `r` at its closest hit in [tmin, tmax]: t, the outward normal (pointing
// out of the solid) and the material of the leaf surface hit. hit = false on a miss.
struct CsgSurface {
  bool hit = false;
  float t = 0;
  Vec3f normal{0, 0, 0};
  std::uint32_t material = 0;
};
CsgSurface csg_surface(const CsgTree& tree, const Ray<float>& r);
// The same at a hit already found: the point p on the surface of the leaf with `tag` (the closest-hit
// query's, kernels/csg_ray.hpp), t left 0; hit = false when the tag names no leaf.
CsgSurface csg_surface(const CsgTree& tree, float tag, Vec3f p);
// The material of that surface alone (csg_surface(tree, tag, p).material, no normal computed).
std::uint32_t csg_material(const CsgTree& tree, float tag);

}  // namespace rb::scene
