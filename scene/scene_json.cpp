// The JSON scene format written back (scene_json): a scene the format can hold, as indented JSON
// that loads back to the same scene (scene/json_scene.cpp reads it).
#include "scene/csg_scene.hpp"
#include "scene/parse_util.hpp"

#include <nlohmann/json.hpp>

#include <charconv>

namespace rb::scene {

using nlohmann::json;

namespace {
// A float as its shortest decimal form that reads back to the same float (0.9f -> 0.9).
json jfloat(float x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return json::parse(std::string(buf, r.ptr));
}
json jvec(const Vec3d& v) { return json::array({v.x, v.y, v.z}); }
json jvec(const Vec3f& v) { return json::array({jfloat(v.x), jfloat(v.y), jfloat(v.z)}); }

// Indented JSON for people: a value whose one-line form fits in 96 columns stays on one line
// (points, colours, CSG leaves), everything else opens one line per member.
void write_readable(const json& v, int indent, std::string& out) {
  std::string line = v.dump();
  // one-line form with spaces after ',' and ':' (outside strings; the format's strings hold no quotes)
  std::string spaced;
  bool in_str = false;
  for (char ch : line) {
    spaced += ch;
    if (ch == '"') in_str = !in_str;
    if (!in_str && (ch == ',' || ch == ':')) spaced += ' ';
  }
  if (!v.is_structured() || int(spaced.size()) + indent <= 96) {
    out += spaced;
    return;
  }
  const std::string pad(std::size_t(indent + 2), ' ');
  out += v.is_object() ? "{\n" : "[\n";
  std::size_t i = 0;
  for (auto it = v.begin(); it != v.end(); ++it, ++i) {
    out += pad;
    if (v.is_object()) out += json(it.key()).dump() + ": ";
    write_readable(it.value(), indent + 2, out);
    out += i + 1 < v.size() ? ",\n" : "\n";
  }
  out += std::string(std::size_t(indent), ' ') + (v.is_object() ? "}" : "]");
}
}  // namespace

std::string scene_json(const Scene& s) {
  std::string missing;
  auto cannot = [&](std::size_t n, const char* what) {
    if (n) missing += (missing.empty() ? "" : ", ") + std::to_string(n) + " " + what;
  };
  cannot(s.triangles.size(), "triangles (a mesh: keep it as OBJ or PLY)");
  cannot(s.cones.size(), "NFF cones");
  cannot(s.poly_normals.empty() ? 0 : s.polygons.size(), "polygons with per-vertex normals");
  std::size_t checker = 0;
  for (const auto& m : s.materials) checker += m.checker > 0;
  cannot(checker, "checkerboard materials");
  for (const auto& c : s.csgs) cannot(c.json.empty() ? 1 : 0, "CSG objects built without JSON");
  if (!missing.empty()) throw SceneError(s.name + ": the JSON scene format cannot represent " + missing);

  json root = json::object();
  const Camera& c = s.camera;
  root["camera"] = {{"from", jvec(c.from)}, {"at", jvec(c.at)}, {"up", jvec(c.up)}, {"angle", c.angle},
                    {"width", c.width},     {"height", c.height}, {"hither", c.hither}};
  root["background"] = jvec(s.background);
  json lights = json::array();
  for (const auto& l : s.lights) lights.push_back({{"position", jvec(l.pos)}, {"color", jvec(l.color)}});
  root["lights"] = lights;
  json mats = json::object();
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    const Material& m = s.materials[i];
    mats[detail::material_name(std::uint32_t(i), s.materials.size())] = {{"color", jvec(m.color)}, {"kd", jfloat(m.kd)}, {"ks", jfloat(m.ks)},
                                     {"shine", jfloat(m.shine)}, {"t", jfloat(m.t)}, {"ior", jfloat(m.ior)}};
  }
  root["materials"] = mats;
  json objs = json::array();
  auto with_mat = [&s](json o, std::uint32_t mat) {
    if (mat) o["material"] = detail::material_name(mat, s.materials.size());
    return o;
  };
  for (const auto& sp : s.spheres) objs.push_back(with_mat({{"type", "sphere"}, {"center", jvec(sp.c)}, {"radius", sp.r}}, sp.mat));
  for (const auto& t : s.tori)
    objs.push_back(with_mat({{"type", "torus"}, {"center", jvec(t.c)}, {"axis", jvec(t.axis)}, {"major", t.R}, {"minor", t.r}}, t.mat));
  for (const auto& p : s.polygons) {
    json v = json::array();
    for (std::uint32_t k = 0; k < p.count; ++k) v.push_back(jvec(s.poly_verts[p.first + k]));
    objs.push_back(with_mat({{"type", "polygon"}, {"vertices", v}}, p.mat));
  }
  for (const auto& g : s.csgs) objs.push_back(json::parse(g.json));
  root["objects"] = objs;
  std::string out;
  write_readable(root, 0, out);
  return out + "\n";
}

}  // namespace rb::scene
