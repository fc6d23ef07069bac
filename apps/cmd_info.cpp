// `raybench info SCENE`: what a scene holds and what it costs in memory.
#include "apps/cli.hpp"
#include "core/output_file.hpp"
#include "apps/commands.hpp"
#include "apps/scene_info.hpp"
#include "kernels/csg_ray.hpp"
#include "tracer/leaves.hpp"
#include "tracer/plan.hpp"
#include "tracer/profile.hpp"
#include "scene/csg_scene.hpp"
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
template <class T>
json vec(const Vec3<T>& v) { return json::array({v.x, v.y, v.z}); }
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
  // Every kind of the table (tracer/kinds.hpp), with the kernel batch the tracer stores for it:
  // the bytes of its primitives in float (and in double where the plan stores the kind in double),
  // and of the primitives it keeps apart (in local frames, or in double).
  const tracer::Profile profile = tracer::make_profile(s);
  const tracer::Plan plan = tracer::make_plan(s, profile, tracer::Model::automatic);
  j["input_precision"] = profile.input.summary();
  json kinds = json::array();
  kinds::AllKinds::each([&]<class K>() {
    const std::size_t n = K::count(s);
    if (!n) return;
    const tracer::KindPlan& kp = plan.kinds[std::size_t(K::id)];
    json k{{"kind", K::name}, {"count", n}};
    std::size_t batch = 0;
    std::string what;
    if constexpr (std::is_same_v<K, kinds::TriangleKind>) {
      k["vertices"] = s.verts.size();
      k["vertex_normals"] = !s.vert_normals.empty();
    } else if constexpr (std::is_same_v<K, kinds::PolygonKind>) {
      k["vertices"] = s.poly_verts.size();
    }
    json batches = json::array();
    if constexpr (K::custom) {
      batch = K::batch_bytes(s, what);
      batches.push_back({{"batch", what}, {"bytes", batch}});
    } else {
      // One slot per primitive (the BVH's leaves pad each group of 8; `trace` reports that).
      const bool d = kp.f64_storage;
      const std::size_t apart = kp.split.size();
      batch = (n - apart) * (d ? sizeof(typename K::template Prim<double>) : sizeof(typename K::template Prim<float>));
      batches.push_back({{"batch", fmt::format("PrimSoA<{}> in {}", K::name, d ? "double" : "float")}, {"bytes", batch}});
      // Apart in local frames: float, and an origin per leaf of 8 (a leaf that no origin of its own
      // holds in float takes its double form instead: `trace` counts them).
      if (apart && kp.split_local)
        batches.push_back({{"batch", fmt::format("PrimSoA<{}> in float, local frames: {} apart", K::name, apart)},
                           {"bytes", apart * sizeof(typename K::template Prim<float>) + (apart + 7) / 8 * sizeof(tracer::LocalFrame)}});
      else if (apart)
        batches.push_back({{"batch", fmt::format("PrimSoA<{}> in double: the {} stored apart", K::name, apart)},
                           {"bytes", apart * sizeof(typename K::template Prim<double>)}});
    }
    const std::size_t input = K::input_bytes(s);
    k["input_bytes"] = input;
    k["batches"] = batches;
    k["plan"] = fmt::format("{} in {}{}", K::methods[std::size_t(kp.method)].name, kp.f64 ? "double" : "float",
                            kp.f64_storage ? " (stored in double)" : "");
    k["classes"] = kp.classes_text();
    kinds.push_back(k);
  });
  j["kinds"] = kinds;
  j["input_bytes"] = s.memory_bytes();
  j["plan"] = plan.json();
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
  if (j.contains("input_precision")) o += wrap_words("input       " + j["input_precision"].get<std::string>(), 80, "            ");
  // Within 80 columns: a row per kind (input form), then its kernel batches indented below it.
  o += fmt::format("{:<10} {:>10} {:>10} {:>12}\n", "kind", "count", "vertices", "input form");
  o += "  kernel batch (SoA, padded to 8 lanes)                           memory\n";
  for (const auto& k : j["kinds"]) {
    o += fmt::format("{:<10} {:>10} {:>10} {:>12}\n", k["kind"].get<std::string>(), k["count"].get<std::size_t>(),
                     k.contains("vertices") ? std::to_string(k["vertices"].get<std::size_t>()) : "-", mib(k["input_bytes"]));
    if (k.contains("classes") && !k["classes"].get<std::string>().empty())
      o += wrap_words("  classes in float: " + k["classes"].get<std::string>(), 80, "    ");
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
  // How the tracer models the scene (the auto model; `raybench plan` gives the reasons).
  if (j.contains("plan")) {
    const auto& p = j["plan"];
    o += fmt::format("plan        frame {}", p["frame"]["kind"].get<std::string>());
    for (const auto& k : j["kinds"])
      if (k.contains("plan")) o += fmt::format("; {} {}", k["kind"].get<std::string>(), k["plan"].get<std::string>());
    o += fmt::format("; {} slab test; spawn {} (`raybench plan` explains)\n", p["slab"]["test"].get<std::string>(),
                     p["spawn"]["scheme"].get<std::string>());
  }
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
  bool empty = false;
  try {
    const auto t0 = std::chrono::steady_clock::now();
    const rb::scene::Scene s = rb::scene::load_scene(scene);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    j = scene_info(s);
    j["source"] = scene;
    j["load_ms"] = ms;
    empty = s.primitive_count() == 0;
  } catch (const std::exception& e) {
    // Loader errors name the file and line; a generator's name the scene.
    std::cerr << error_line("info", scene, e.what()) << "\n";
    return kExitError;
  }
  const int rc = write_result("info", out, [&] { return fit_columns(scene_info_text(j), 12); }, [&] { return j; }, "the scene description");
  if (rc != kExitOk || !empty) return rc;
  // Described, but nothing to trace or render: the convention's "nothing to do".
  std::cerr << error_line("info", scene, "the scene has no primitives") << "\n";
  return kExitNothing;
}

int run_dump_scene_command(const std::string& scene, const std::string& file) {
  if (!is_generated_scene(scene))
    if (const std::string why = check_input_file(scene); !why.empty()) {
      std::cerr << error_line("info", scene, why) << "\n";
      return kExitError;
    }
  std::string text;
  try {
    text = rb::scene::scene_json(rb::scene::load_scene(scene));
  } catch (const std::exception& e) {
    std::cerr << error_line("info", scene, e.what()) << "\n";
    return kExitError;
  }
  try {
    write_output(file.empty() ? "-" : file, text);  // core/output_file.hpp
  } catch (const std::exception& e) {
    std::cerr << error_line("info", "", e.what()) << "\n";
    return kExitError;
  }
  if (!file.empty() && !is_standard_output(file)) std::cerr << "raybench info: wrote " << file << "\n";
  return 0;
}

}  // namespace rb::app
