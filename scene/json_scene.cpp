// The JSON scene format (scene/csg_scene.hpp): camera, background, lights, named materials and objects
// (spheres, tori and polygons as primitives of their own; everything else a CSG object, built by
// scene/csg_scene.cpp), each error naming the file and the JSON path.
#include "scene/csg_scene.hpp"
#include "scene/json_read.hpp"
#include "scene/parse_util.hpp"

#include <nlohmann/json.hpp>

#include <map>
#include <memory>

namespace rb::scene {

namespace {
using nlohmann::json;
using namespace json_read;

Material parse_material(const json& m, const std::string& path) {
  if (!m.is_object()) fail(path, "expected an object");
  only_keys(m, path, {"color", "kd", "ks", "shine", "t", "ior"});
  Material mat;
  if (m.contains("color")) mat.color = to_float(vec(m, path, "color"));
  auto opt = [&](const char* k, float& dst) {
    if (m.contains(k)) {
      const double v = num(m, path, k);
      if (v < 0) fail(key_path(path, k), "expected a non-negative number");
      dst = float(v);
    }
  };
  opt("kd", mat.kd);
  opt("ks", mat.ks);
  opt("shine", mat.shine);
  opt("t", mat.t);
  opt("ior", mat.ior);
  return mat;
}

// The node with every "material": NAME renamed "m<index>" (scene_json writes materials so).
json canonical_materials(const json& node, const std::map<std::string, std::uint32_t>& mats, std::size_t n) {
  if (node.is_array()) {
    json a = json::array();
    for (const auto& v : node) a.push_back(canonical_materials(v, mats, n));
    return a;
  }
  if (!node.is_object()) return node;
  json o = json::object();
  for (auto it = node.begin(); it != node.end(); ++it)
    if (it.key() == "material" && it.value().is_string()) {
      const auto m = mats.find(it.value().get<std::string>());
      o["material"] = m == mats.end() ? it.value() : json(detail::material_name(m->second, n));
    } else if (it.key() == "left" || it.key() == "right" || it.key() == "children") {
      o[it.key()] = canonical_materials(it.value(), mats, n);
    } else {
      o[it.key()] = it.value();
    }
  return o;
}

Scene build_scene(const json& root, const std::string& name) {
  Scene s;
  s.name = name;
  if (!root.is_object()) fail("(top level)", "expected an object with \"objects\"");
  only_keys(root, "", {"camera", "background", "lights", "materials", "objects"});
  if (root.contains("camera")) {
    const json& c = root["camera"];
    if (!c.is_object()) fail("camera", "expected an object");
    only_keys(c, "camera", {"from", "at", "up", "angle", "hither", "width", "height"});
    if (c.contains("from")) s.camera.from = vec(c, "camera", "from");
    if (c.contains("at")) s.camera.at = vec(c, "camera", "at");
    if (c.contains("up")) s.camera.up = nonzero(c, "camera", "up");
    if (c.contains("angle")) {
      const double a = num(c, "camera", "angle");
      if (!(a > 0 && a < 180)) fail("camera.angle", "expected degrees in (0, 180)");
      s.camera.angle = a;
    }
    if (c.contains("hither")) s.camera.hither = num(c, "camera", "hither");
    for (const char* k : {"width", "height"})
      if (c.contains(k)) {
        const json& v = c[k];
        if (!v.is_number_integer() || v.get<long long>() < 1 || v.get<long long>() > 16384)
          fail(std::string("camera.") + k, "expected an integer in 1..16384");
        (std::string(k) == "width" ? s.camera.width : s.camera.height) = int(v.get<long long>());
      }
  }
  if (root.contains("background")) s.background = to_float(vec3(root["background"], "background"));
  if (root.contains("lights")) {
    const json& l = root["lights"];
    if (!l.is_array()) fail("lights", "expected an array");
    for (std::size_t i = 0; i < l.size(); ++i) {
      const std::string p = "lights[" + std::to_string(i) + "]";
      if (!l[i].is_object()) fail(p, "expected {\"position\": [..], \"color\": [..]}");
      only_keys(l[i], p, {"position", "color"});
      Light L;
      L.pos = vec(l[i], p, "position");
      if (l[i].contains("color")) L.color = to_float(vec(l[i], p, "color"));
      s.lights.push_back(L);
    }
  }
  std::map<std::string, std::uint32_t> mats;
  s.materials.push_back(Material{});  // 0: the default
  if (root.contains("materials")) {
    const json& m = root["materials"];
    if (!m.is_object()) fail("materials", "expected an object of named materials");
    for (auto it = m.begin(); it != m.end(); ++it) {
      // "default": the material of every object that names none (material 0).
      if (it.key() == "default") {
        mats[it.key()] = 0;
        s.materials[0] = parse_material(it.value(), "materials.default");
        continue;
      }
      mats[it.key()] = std::uint32_t(s.materials.size());
      s.materials.push_back(parse_material(it.value(), "materials." + it.key()));
    }
  }
  const json& objs = need(root, "", "objects");
  if (!objs.is_array()) fail("objects", "expected an array");
  if (objs.size() > 1000000) fail("objects", "more than 1000000 objects");
  for (std::size_t i = 0; i < objs.size(); ++i) {
    const std::string p = "objects[" + std::to_string(i) + "]";
    const json& o = objs[i];
    const std::uint32_t mat = node_material(o, p, &mats, 0);
    const std::string type = o.is_object() && o.contains("type") && o["type"].is_string() ? o["type"].get<std::string>() : "";
    if (type == "sphere" && !o.contains("transform")) {
      only_keys(o, p, {"type", "center", "radius", "material"});
      const Vec3d c = vec(o, p, "center");
      const double r = positive(o, p, "radius");
      s.spheres.push_back({c, r, mat});
      continue;
    }
    if (type == "torus" && !o.contains("transform")) {
      // A plain torus (a primitive kind of its own); with a transform it is a one-leaf CSG object.
      // The same checks as the CSG leaf: a ring torus (R > r) with a non-zero axis.
      only_keys(o, p, {"type", "center", "axis", "major", "minor", "material"});
      const Vec3d c = vec(o, p, "center"), w = nonzero(o, p, "axis");
      const double R = positive(o, p, "major"), r = positive(o, p, "minor");
      if (!(R > r)) fail(key_path(p, "minor"), "expected a number below \"major\" (a ring torus)");
      std::string why;
      make_torus(c, w, R, r, Vec3d{1, 0, 0}, &why);
      if (!why.empty()) fail(p, why);
      s.tori.push_back({c, w, R, r, mat});
      continue;
    }
    if (type == "polygon") {
      only_keys(o, p, {"type", "vertices", "material"});
      const json& v = need(o, p, "vertices");
      const std::string vp = p + ".vertices";
      if (!v.is_array() || v.size() < 3 || v.size() > 100000) fail(vp, "expected an array of 3 to 100000 points");
      PolygonIn pg{std::uint32_t(s.poly_verts.size()), std::uint32_t(v.size()), mat};
      for (std::size_t k = 0; k < v.size(); ++k) s.poly_verts.push_back(vec3(v[k], vp + "[" + std::to_string(k) + "]"));
      s.polygons.push_back(pg);
      continue;
    }
    CsgTree tree = csg_tree(o, p, Affine3d{}, &mats, mat);
    // The same tree relative to a frame origin: the root placed by translate(-origin), composed
    // in double into every leaf's placement before it is rounded (the JSON is checked already).
    auto node = std::make_shared<const json>(o);
    auto names = std::make_shared<const std::map<std::string, std::uint32_t>>(mats);
    auto in_frame = [node, names, p, mat](const Vec3d& origin) {
      return std::make_shared<const CsgTree>(csg_tree(*node, p, Affine3d::translate(origin * -1.0), names.get(), mat));
    };
    s.csgs.push_back({std::make_shared<const CsgTree>(std::move(tree)), mat, in_frame, canonical_materials(o, mats, s.materials.size()).dump()});
  }
  return s;
}

}  // namespace

namespace detail {
// Material i of n's name in scene_json's output: "default" for 0, else "m<i>", zero-padded to the digits of n - 1 so
// that the names sort in index order (the format's materials object is read in key order).
// Appended, not operator+: GCC 12 gives a false -Wrestrict on a short literal plus a temporary.
std::string material_name(std::uint32_t i, std::size_t n) {
  if (i == 0) return "default";
  const std::string d = std::to_string(i);
  const std::size_t width = std::to_string(n > 1 ? n - 1 : 1).size();
  std::string s = "m";
  s.append(width > d.size() ? width - d.size() : 0, '0');
  s += d;
  return s;
}
}  // namespace detail

Scene parse_json_scene(std::string_view text, const std::string& name) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    throw SceneError(name + ": malformed JSON at byte " + std::to_string(e.byte) + ": " + e.what());
  } catch (const json::exception& e) {  // e.g. out_of_range: a number beyond double (found by fuzz_json)
    throw SceneError(name + ": malformed JSON: " + e.what());
  }
  try {
    return build_scene(root, name);
  } catch (const PathError& e) {
    throw SceneError(name + ": " + e.what());
  }
}

Scene load_json_scene(const std::string& path) { return parse_json_scene(detail::read_file(path), path); }

}  // namespace rb::scene
