// `raybench info SCENE`: what a scene holds and what it costs in memory.
#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "apps/scene_info.hpp"
#include "kernels/csg.hpp"
#include "scene/batches.hpp"
#include "scene/sources.hpp"

#include <fmt/format.h>

#include <chrono>
#include <fstream>
#include <iostream>
#include <malloc.h>
#include <map>

namespace rb::app {

namespace {
using nlohmann::json;
json vec(const Vec3f& v) { return json::array({v.x, v.y, v.z}); }
double status_mib(const char* key) {
  std::ifstream f("/proc/self/status");
  std::string line;
  const std::string k = std::string(key) + ":";
  while (std::getline(f, line))
    if (line.rfind(k, 0) == 0) return std::stod(line.substr(k.size())) / 1024.0;  // kB
  return 0;
}
}  // namespace

void PeakRss::reset() {
  malloc_trim(0);
  std::ofstream f("/proc/self/clear_refs");
  f << "5";
  f.close();
  ok = bool(f);
  base_mib = status_mib("VmRSS");
  if (ok && status_mib("VmHWM") > base_mib + 1.0) ok = false;  // the reset did not take
}
double PeakRss::peak_mib() const { return status_mib("VmHWM") - base_mib; }

json scene_info(const rb::scene::Scene& s) {
  json j;
  j["name"] = s.name;
  const auto b = s.bounds();
  j["bounds"] = b.empty() ? json(nullptr) : json{{"lo", vec(b.lo)}, {"hi", vec(b.hi)}};
  const auto& c = s.camera;
  j["camera"] = {{"from", vec(c.from)}, {"at", vec(c.at)}, {"up", vec(c.up)}, {"angle", c.angle}, {"hither", c.hither},
                 {"width", c.width}, {"height", c.height}};
  j["lights"] = s.lights.size();
  j["materials"] = s.materials.size();
  j["primitives"] = s.primitive_count();
  json kinds = json::array();
  // Every batch comes from scene/batches.hpp, the builder the BVH uses too.
  // Spheres: PrimSoA<Sphere> (c, r^2, 1/r).
  if (!s.spheres.empty()) {
    const auto soa = rb::scene::sphere_batch(s);
    kinds.push_back({{"kind", "sphere"}, {"count", s.spheres.size()}, {"input_bytes", s.spheres.size() * sizeof(rb::scene::SphereIn)},
                     {"batches", json::array({{{"batch", "PrimSoA<Sphere>"}, {"bytes", soa.prims.bytes()}}})}});
  }
  // NFF cones and cylinders (open shells between two circles): placed instances of the unit
  // cylinder or unit cone, PrimSoA<Transformed<Cylinder|Cone>::T> (12 inverse-matrix floats each).
  if (!s.cones.empty()) {
    const auto cyl = rb::scene::cylinder_batch(s);
    const auto cone = rb::scene::cone_batch(s);
    json batches = json::array();
    if (cyl.prims.size()) batches.push_back({{"batch", fmt::format("PrimSoA<Transformed<Cylinder>> ({} equal radii)", cyl.prims.count)}, {"bytes", cyl.prims.bytes()}});
    if (cone.prims.size()) batches.push_back({{"batch", fmt::format("PrimSoA<Transformed<Cone>> ({} frusta)", cone.prims.count)}, {"bytes", cone.prims.bytes()}});
    kinds.push_back({{"kind", "cone"}, {"count", s.cones.size()}, {"input_bytes", s.cones.size() * sizeof(rb::scene::ConeIn)},
                     {"batches", batches}});
  }
  // Polygons: PolygonSoA (plane per polygon and projected vertices interleaved per group of 8).
  if (!s.polygons.empty()) {
    const PolygonSoA soa = rb::scene::polygon_batch(s);
    kinds.push_back({{"kind", "polygon"}, {"count", s.polygons.size()}, {"vertices", s.poly_verts.size()},
                     {"input_bytes", s.polygons.size() * sizeof(rb::scene::PolygonIn) + (s.poly_verts.size() + s.poly_normals.size()) * sizeof(Vec3f)},
                     {"batches", json::array({{{"batch", fmt::format("PolygonSoA ({} degenerate kept as never-hit slots)", soa.degenerate)},
                                               {"bytes", soa.bytes()}}})}});
  }
  if (!s.triangles.empty()) {
    const auto mt = rb::scene::triangle_mt_batch(s);
    const auto woop = rb::scene::triangle_verts_batch(s);
    const TriLectureSoA lec = rb::scene::triangle_lecture_batch(s);
    const std::size_t lec_bytes = lec.prims.bytes() + lec.axis.size() * sizeof(std::int8_t) + lec.id.size() * sizeof(std::uint32_t);
    kinds.push_back({{"kind", "triangle"}, {"count", s.triangles.size()}, {"vertices", s.verts.size()},
                     {"vertex_normals", !s.vert_normals.empty()},
                     {"input_bytes", s.triangles.size() * sizeof(rb::scene::TriangleIn) + (s.verts.size() + s.vert_normals.size()) * sizeof(Vec3f)},
                     {"batches", json::array({{{"batch", "PrimSoA<Triangle> (Moller-Trumbore)"}, {"bytes", mt.prims.bytes()}},
                                              {{"batch", "PrimSoA<TriVerts> (Woop, watertight)"}, {"bytes", woop.prims.bytes()}},
                                              {{"batch", "TriLectureSoA (lecture, by dropped axis)"}, {"bytes", lec_bytes}}})}});
  }
  // CSG objects: each a tree (kernels/csg.hpp) of nodes with world boxes and leaves with their
  // composed inverse transforms; no SoA batch (a tree is queried as a whole).
  if (!s.csgs.empty()) {
    std::size_t nodes = 0, leaves = 0, tree_bytes = 0;
    int depth = 0;
    std::map<std::string, std::size_t> by_kind;
    for (const auto& obj : s.csgs) {
      nodes += obj.tree->nodes.size();
      leaves += obj.tree->leaves.size();
      tree_bytes += obj.tree->bytes();
      depth = std::max(depth, obj.tree->depth);
      for (const auto& l : obj.tree->leaves) ++by_kind[std::string(csg_leaf_name(l.kind)) + (l.placed ? " (transformed)" : "")];
    }
    std::string mix;
    for (const auto& [k, n] : by_kind) mix += fmt::format("{}{} {}", mix.empty() ? "" : ", ", n, k);
    kinds.push_back({{"kind", "csg"}, {"count", s.csgs.size()}, {"nodes", nodes}, {"leaves", leaves}, {"depth", depth},
                     {"leaf_kinds", by_kind}, {"input_bytes", s.csgs.size() * sizeof(rb::scene::CsgIn) + tree_bytes},
                     {"batches", json::array({{{"batch", fmt::format("CSG trees ({} nodes, depth {}; leaves: {})", nodes, depth, mix)},
                                               {"bytes", tree_bytes}}})}});
  }
  j["kinds"] = kinds;
  j["input_bytes"] = s.memory_bytes();
  return j;
}

namespace {
std::string mib(std::size_t bytes) {
  return bytes < 1024 * 1024 ? fmt::format("{:.1f} KiB", double(bytes) / 1024.0) : fmt::format("{:.2f} MiB", double(bytes) / (1024.0 * 1024.0));
}
std::string v3(const json& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v[0].get<double>(), v[1].get<double>(), v[2].get<double>()); }
}  // namespace

std::string scene_info_text(const json& j) {
  std::string o = fmt::format("scene       {}\n", j["name"].get<std::string>());
  o += fmt::format("primitives  {}\n", j["primitives"].get<std::size_t>());
  if (j["bounds"].is_null()) o += "bounds      empty\n";
  else o += fmt::format("bounds      {} .. {}\n", v3(j["bounds"]["lo"]), v3(j["bounds"]["hi"]));
  const auto& c = j["camera"];
  o += fmt::format("camera      from {} at {} up {}, angle {} deg, hither {}, {}x{}\n", v3(c["from"]), v3(c["at"]), v3(c["up"]),
                   c["angle"].get<double>(), c["hither"].get<double>(), c["width"].get<int>(), c["height"].get<int>());
  o += fmt::format("lights      {}\nmaterials   {}\n", j["lights"].get<std::size_t>(), j["materials"].get<std::size_t>());
  // Within 80 columns: a row per kind (input form), then its kernel batches indented below it.
  o += fmt::format("{:<10} {:>10} {:>10} {:>12}\n", "kind", "count", "vertices", "input form");
  o += "  kernel batch (SoA, padded to 8 lanes)                           memory\n";
  for (const auto& k : j["kinds"]) {
    o += fmt::format("{:<10} {:>10} {:>10} {:>12}\n", k["kind"].get<std::string>(), k["count"].get<std::size_t>(),
                     k.contains("vertices") ? std::to_string(k["vertices"].get<std::size_t>()) : "-", mib(k["input_bytes"]));
    if (k.contains("note")) {
      o += wrap_words("  " + k["note"].get<std::string>(), 80, "    ");
      continue;
    }
    for (const auto& b : k["batches"]) {
      const std::string name = b["batch"].get<std::string>(), size = mib(b["bytes"]);
      if (display_width(name) + 2 + 1 + 12 <= 80) o += fmt::format("  {:<63} {:>12}\n", name, size);
      else o += wrap_words("  " + name, 80, "    ") + fmt::format("{:>78}\n", size);
    }
  }
  o += fmt::format("{:<10} {:>10} {:>10} {:>12}\n", "total", j["primitives"].get<std::size_t>(), "", mib(j["input_bytes"]));
  if (j.contains("load_ms")) o += fmt::format("loaded in   {:.1f} ms\n", j["load_ms"].get<double>());
  return o;
}

std::string scene_info_markdown(const json& j) {
  const std::string label = j.contains("source") ? j["source"].get<std::string>() : j["name"].get<std::string>();
  std::string o = fmt::format("**{}**: {} primitives, {} lights, {} materials", label, j["primitives"].get<std::size_t>(),
                              j["lights"].get<std::size_t>(), j["materials"].get<std::size_t>());
  if (!j["bounds"].is_null()) o += fmt::format(", bounds {} .. {}", v3(j["bounds"]["lo"]), v3(j["bounds"]["hi"]));
  o += "\n\n| kind | count | vertices | input form | kernel batch |\n|---|---:|---:|---:|---|\n";
  for (const auto& k : j["kinds"]) {
    std::string batches;
    for (const auto& b : k["batches"]) batches += fmt::format("{}{}: {}", batches.empty() ? "" : "<br>", b["batch"].get<std::string>(), mib(b["bytes"]));
    if (k.contains("note")) batches = k["note"].get<std::string>();
    o += fmt::format("| {} | {} | {} | {} | {} |\n", k["kind"].get<std::string>(), k["count"].get<std::size_t>(),
                     k.contains("vertices") ? std::to_string(k["vertices"].get<std::size_t>()) : "-", mib(k["input_bytes"]), batches);
  }
  return o + "\n";
}

int run_info_command(const std::string& scene, const JsonOut& out) {
  json j;
  if (!is_generated_scene(scene))
    if (const std::string why = check_input_file(scene); !why.empty()) {
      std::cerr << error_line("info", scene, why) << "\n";
      return kExitError;
    }
  try {
    const auto t0 = std::chrono::steady_clock::now();
    const rb::scene::Scene s = rb::scene::load_scene(scene);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    j = scene_info(s);
    j["source"] = scene;
    j["load_ms"] = ms;
  } catch (const std::exception& e) {
    // Loader errors name the file and line; a generator's name the scene.
    std::cerr << error_line("info", scene, e.what()) << "\n";
    return kExitError;
  }
  return write_result("info", out, [&] { return fit_columns(scene_info_text(j), 12); }, [&] { return j; }, "the scene description");
}

}  // namespace rb::app
