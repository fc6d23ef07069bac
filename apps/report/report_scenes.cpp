// Report section: the embedded scenes (data/meshes and the generators), how long each takes to
// load or generate, its peak memory, and a `raybench info` table per scene.
#include "core/output_file.hpp"
#include "apps/paths.hpp"
#include "apps/report/report.hpp"
#include "apps/report/report_record.hpp"
#include "apps/report/report_sections.hpp"
#include "apps/scene_info.hpp"
#include "scene/sources.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>

namespace rb::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct Timed {
  json row;
  json info;
};

// Median of 5 runs of `make`; peak resident memory over the first run.
Timed measure(const std::string& source, const std::string& kind, const std::function<rb::scene::Scene()>& make) {
  Timed t;
  std::vector<double> ms;
  double peak = -1;
  rb::scene::Scene s;
  for (int i = 0; i < 5; ++i) {
    PeakRss probe;
    if (i == 0) probe.reset();
    const auto t0 = std::chrono::steady_clock::now();
    rb::scene::Scene x = make();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    if (i == 0 && probe.ok) peak = probe.peak_mib();
    if (i == 0) s = std::move(x);
  }
  std::sort(ms.begin(), ms.end());
  t.info = scene_info(s);
  t.info["source"] = source;
  t.row = {{"source", source}, {"kind", kind}, {"median_ms", ms[2]}, {"min_ms", ms[0]}, {"max_ms", ms[4]},
           {"peak_rss_mib", peak < 0 ? json(nullptr) : json(peak)}, {"input_mib", double(s.memory_bytes()) / (1024.0 * 1024.0)},
           {"spheres", s.spheres.size()}, {"cones", s.cones.size()}, {"polygons", s.polygons.size()},
           {"triangles", s.triangles.size()}, {"primitives", s.primitive_count()}};
  return t;
}

// A height-field grid of nx x ny quads (2 nx ny triangles) as a binary little-endian PLY with
// float x y z and uchar-count int-index faces: the shape of a large scanned mesh.
void write_grid_ply(const fs::path& p, std::uint32_t nx, std::uint32_t ny) {
  std::ofstream f(p, std::ios::binary);
  f << "ply\nformat binary_little_endian 1.0\ncomment raybench report: synthetic grid\n"
    << "element vertex " << std::uint64_t(nx + 1) * (ny + 1) << "\nproperty float x\nproperty float y\nproperty float z\n"
    << "element face " << std::uint64_t(2) * nx * ny << "\nproperty list uchar int vertex_indices\nend_header\n";
  auto put = [&f](const auto v) { f.write(reinterpret_cast<const char*>(&v), sizeof v); };  // x86: little-endian
  for (std::uint32_t j = 0; j <= ny; ++j)
    for (std::uint32_t i = 0; i <= nx; ++i) {
      put(float(i));
      put(float(j));
      put(0.25f * std::sin(0.05f * float(i)) * std::cos(0.07f * float(j)));
    }
  for (std::uint32_t j = 0; j < ny; ++j)
    for (std::uint32_t i = 0; i < nx; ++i) {
      const std::int32_t a = std::int32_t(j * (nx + 1) + i), b = a + 1, c = a + std::int32_t(nx + 1), d = c + 1;
      put(std::uint8_t(3)); put(a); put(b); put(d);
      put(std::uint8_t(3)); put(a); put(d); put(c);
    }
  if (!f) throw std::runtime_error("cannot write " + p.string());
}

// Loads and generates every embedded scene: {"loads", "scenes", "pending"}.
json measure_scenes(const fs::path& out) {
  std::vector<Timed> done;
  std::vector<std::string> pending;
  // Embedded meshes.
  const fs::path meshes = fs::path(data_dir()) / "meshes";
  std::vector<fs::path> files;
  if (fs::is_directory(meshes))
    for (const auto& e : fs::directory_iterator(meshes))
      if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    const std::string ext = f.extension().string();
    if (ext != ".obj" && ext != ".ply" && ext != ".nff") continue;
    const std::string src = "data/meshes/" + f.filename().string();
    std::cerr << "  load " << src << "\n";
    try {
      done.push_back(measure(src, "file", [p = f.string()] { return rb::scene::load_scene(p); }));
    } catch (const std::exception& e) {
      pending.push_back(src + ": " + e.what());
    }
  }
  // A 1M-triangle binary PLY, written here and removed after the measurement.
  {
    const fs::path big = out / "grid_1M_triangles.ply";
    const std::string src = "generated grid, 1,000,000 triangles, binary PLY";
    std::cerr << "  load " << src << "\n";
    try {
      write_grid_ply(big, 1000, 500);
      done.push_back(measure(src, "file", [p = big.string()] { return rb::scene::load_scene(p); }));
    } catch (const std::exception& e) {
      pending.push_back(src + ": " + e.what());
    }
    std::error_code ec;
    fs::remove(big, ec);
  }
  // Generators at their default sizes.
  std::vector<std::string> gens;
  try {
    for (const auto& n : rb::scene::spd_names()) gens.push_back("spd:" + n);
  } catch (const std::exception& e) {
    pending.push_back(std::string("spd generators: ") + e.what());
  }
  try {
    for (const auto& n : rb::scene::lecture_scene_names()) gens.push_back("lecture:" + n);
  } catch (const std::exception& e) {
    pending.push_back(std::string("lecture scenes: ") + e.what());
  }
  if (gens.empty()) pending.push_back("spd:* and lecture:* (generators not available in this build)");
  for (const auto& g : gens) {
    std::cerr << "  generate " << g << "\n";
    try {
      done.push_back(measure(g, "generator", [g] { return rb::scene::load_scene(g); }));
    } catch (const std::exception& e) {
      pending.push_back(g + ": " + e.what());
    }
  }

  json rows = json::array(), infos = json::array();
  for (const auto& t : done) {
    rows.push_back(t.row);
    infos.push_back(t.info);
  }
  return {{"loads", rows}, {"scenes", infos}, {"pending", pending}};
}

}  // namespace

std::string report_section_scenes(const ReportOptions&, Record& rec, const fs::path& out, json& summary) {
  const json doc = rec.take("scenes", [&] { return measure_scenes(out); });
  const json& rows = doc["loads"];
  const json& infos = doc["scenes"];
  const std::vector<std::string> pending = doc["pending"].get<std::vector<std::string>>();
  write_output((out / "scenes.json").string(), doc.dump(2) + "\n");
  summary["scenes"] = rows;

  std::string md = "## Scenes\n\n"
                   "Embedded meshes (`data/meshes`, see data/README.md for provenance) loaded from disk, and the embedded "
                   "generators at their default sizes. Time: median of 5 loads in this process (file in the page cache). "
                   "Peak memory: growth of the resident set's high-water mark during the first load (Linux "
                   "`/proc/self/clear_refs` reset; it includes the file buffer and the parser's scratch); input form: the "
                   "scene's arrays afterwards. Raw: [scenes.json](scenes.json).\n\n"
                   "| scene | spheres | cones | polygons | triangles | load or generate (ms, median of 5) | peak memory (MiB) | input form (MiB) |\n"
                   "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : rows)
    md += fmt::format("| {} | {} | {} | {} | {} | {:.3g} | {} | {:.2f} |\n", r["source"].get<std::string>(), r["spheres"].get<std::size_t>(),
                      r["cones"].get<std::size_t>(), r["polygons"].get<std::size_t>(), r["triangles"].get<std::size_t>(),
                      r["median_ms"].get<double>(),
                      r["peak_rss_mib"].is_null() ? std::string("n/a") : fmt::format("{:.1f}", r["peak_rss_mib"].get<double>()),
                      r["input_mib"].get<double>());
  if (!pending.empty()) {
    md += "\nPending or failed:\n\n";
    for (const auto& p : pending) md += "- " + p + "\n";
  }
  md += "\n### Scene details (`raybench info`)\n\n"
        "Memory per primitive kind: the input form (the scene's arrays) and the SoA kernel batch it builds, padded to 8 lanes.\n\n";
  for (const auto& i : infos) md += scene_info_markdown(i);
  return md;
}

}  // namespace rb::app
