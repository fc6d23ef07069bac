// The report's CSG section, also printed by `raybench csg`: operations per CSG query (from the ops
// table's csg rows) and CSG queries per second on the embedded CSG scenes, one float ray at a time
// (csg_hit: linear merges, closest-hit stop) against 8 rays in lanes (csg_hit8: branch-free
// merges), on the same rays, one thread.
#include "core/median.hpp"
#include "core/output_file.hpp"
#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "apps/results/machine.hpp"
#include "apps/progress.hpp"
#include "apps/report/report.hpp"
#include "apps/report/report_record.hpp"
#include "apps/report/report_sections.hpp"
#include "bench/ops_table.hpp"
#include "bench/timed_csg.hpp"
#include "scene/csg_scene.hpp"
#include "soa/rays.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <iostream>

namespace rb::app {

namespace {
using nlohmann::json;
}  // namespace

json measure_csg_speed(int repetitions, std::size_t nrays, ProgressBar* bar = nullptr, const std::string& filter = "") {
  json out = json::array();
  auto names = scene::csg_scene_names();
  if (!filter.empty()) {
    const std::regex re = filter_regex(filter);
    std::erase_if(names, [&](const std::string& n) { return !filter_matches(re, "csg:" + n); });
    if (names.empty()) throw NothingToDo("--filter '" + filter + "' selects no CSG scene (csg:NAME, e.g. die or ^csg:lens$)");
  }
  for (const std::string& name : names) {
    if (bar) bar->update(double(out.size()) / double(names.size()), "csg:" + name);
    const scene::Scene sc = scene::csg_scene(name);
    const CsgTree& T = *sc.csgs[0].tree;
    const bench::CsgSpeed a = bench::time_csg_queries(T, bench::csg_rays(T, nrays, 1234), repetitions);
    const int side = std::max(8, int(std::sqrt(double(nrays))) / 8 * 8);
    const bench::CsgSpeed c = bench::time_csg_queries(T, bench::camera_rays(sc.camera, side, side), repetitions);
    int placed = 0;
    for (const auto& l : T.leaves) placed += l.placed;
    out.push_back({{"scene", "csg:" + name}, {"leaves", T.leaves.size()}, {"transformed_leaves", placed}, {"nodes", T.nodes.size()},
                   {"rays", a.n}, {"hit_fraction", double(a.hits) / double(a.n)}, {"hits_scalar", a.hits}, {"hits_simd8", a.hits8},
                   {"scalar_queries_per_s", a.scalar}, {"simd8_queries_per_s", a.simd}, {"speedup", a.simd / a.scalar},
                   {"camera_rays", c.n}, {"camera_hit_fraction", double(c.hits) / double(c.n)},
                   {"camera_scalar_queries_per_s", c.scalar}, {"camera_simd8_queries_per_s", c.simd},
                   {"camera_speedup", c.simd / c.scalar}, {"checksum", a.sink + c.sink}});
  }
  return out;
}

std::string csg_markdown(const json& speed, const std::vector<opstable::Row>& rows) {
  std::string md = "## CSG in 1D ray space\n\n"
                   "Each CSG object is a tree of closed solids (sphere, box, convex polyhedron, capped cylinder and cone, torus, "
                   "ellipsoid) under union, intersection and difference; every leaf gives its entry/exit list along the ray, the "
                   "tree merges the lists, and transforms are composed into each leaf (one ray transformation, the slide's "
                   "15\u00b1 18*, per transformed leaf). Scenes: `raybench info csg:NAME`; trace them with `raybench trace csg:NAME`.\n\n"
                   "### Operations per CSG query\n\n"
                   "Counted<float> (one ray, with the early exits: a node box the ray misses, an empty left operand of an "
                   "intersection or a difference, and the root's merge stopping at the answer) and the per-lane count of an 8-ray "
                   "packet (Counted<simd8>; `uniform`: all 8 lanes take this case).\n\n"
                   "| scene | case | float | simd8 per lane (mixed / uniform) | what it counts |\n|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    if (r.kernel != "csg" || r.number != "float") continue;
    std::string simd = "-";
    for (const auto& q : rows)
      if (q.kernel == "csg" && q.method == r.method && q.kase == r.kase && q.number == "simd8")
        simd = q.measured.str() + " / " + (q.uniform ? q.uniform->str() : "-");
    md += fmt::format("| {} | {} | {} | {} | {} |\n", r.method, r.kase, r.measured.str(), simd, r.note);
  }
  md += "\n### CSG queries per second, scalar against SIMD\n\n"
        "Closest hit per ray; rays from a sphere twice the object's size towards random points of its box; one thread; "
        "median of the repetitions of the thread's CPU time. `scalar`: `csg_hit` (float, linear merges with the closest-hit stop); `simd8`: `csg_hit8` "
        "(8 rays in lanes, lane-generic merges).\n\n"
        "Two ray sets per scene: `random` (from a sphere around the object to random points of its box: incoherent packets) "
        "and `camera` (the scene's camera over a square image, 8 neighbouring pixels per packet: coherent packets, most "
        "missing the object).\n\n"
        "| scene | leaves (transformed) | rays | hit fraction | scalar Mqueries/s | simd8 Mqueries/s | SIMD / scalar | camera: hit fraction | scalar | simd8 | SIMD / scalar |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& s : speed)
    md += fmt::format("| {} | {} ({}) | {} | {:.2f} | {:.2f} | {:.2f} | {:.2f}x{} | {:.2f} | {:.2f} | {:.2f} | {:.2f}x |\n", s["scene"].get<std::string>(), s["leaves"].get<int>(),
                      s["transformed_leaves"].get<int>(), s["rays"].get<std::size_t>(), s["hit_fraction"].get<double>(),
                      s["scalar_queries_per_s"].get<double>() / 1e6, s["simd8_queries_per_s"].get<double>() / 1e6,
                      s["speedup"].get<double>(),
                      s["hits_scalar"] == s["hits_simd8"] ? std::string()
                                                          : fmt::format(" ({} vs {} hits: rounding differs between the scalar and the SIMD instantiation)",
                                                                        s["hits_scalar"].get<std::size_t>(), s["hits_simd8"].get<std::size_t>()),
                      s["camera_hit_fraction"].get<double>(), s["camera_scalar_queries_per_s"].get<double>() / 1e6,
                      s["camera_simd8_queries_per_s"].get<double>() / 1e6, s["camera_speedup"].get<double>());
  md += "\nWhere SIMD falls short of 8x (more so on the random rays than on the camera rays): a packet pays every lane's work (a subtree is skipped only when all 8 rays miss its box "
        "or its left operand), the lane-generic merge costs O((N+M)^2) compares against the scalar merge's ~3 per boundary and "
        "cannot stop at the answer, and the torus leaf's root isolation iterates as long as its slowest lane.\n\n";
  return md;
}

std::string report_section_csg(const ReportOptions& o, Record& rec, const std::filesystem::path& out, json& summary,
                               const std::vector<opstable::Row>& ops) {
  const json speed = rec.take("csg", [&] {
    ProgressBar bar("  CSG scenes");
    json j = measure_csg_speed(o.quick ? 1 : std::max(3, o.repetitions), o.quick ? 1 << 11 : 1 << 15, &bar);
    bar.done();
    return j;
  });
  write_output((out / "csg.json").string(), speed.dump(2) + "\n");
  summary["csg"] = speed;
  return csg_markdown(speed, ops);
}

namespace {
// The terminal table of `raybench csg`, within 80 columns.
std::string csg_text(const json& speed) {
  const char* const kRow = "{:<28} {:>7} {:>6} {:>11} {:>11} {:>11}\n";
  std::string t = fmt::format(fmt::runtime(kRow), "scene / rays", "rays", "hit %", "scalar Mq/s", "simd8 Mq/s", "SIMD/scalar");
  for (const auto& s : speed) {
    t += fmt::format(fmt::runtime(kRow), s["scene"].get<std::string>(), s["rays"].get<std::size_t>(),
                     fmt::format("{:.1f}", 100 * s["hit_fraction"].get<double>()), fmt::format("{:.3f}", s["scalar_queries_per_s"].get<double>() / 1e6),
                     fmt::format("{:.3f}", s["simd8_queries_per_s"].get<double>() / 1e6), fmt::format("{:.2f}x", s["speedup"].get<double>()));
    t += fmt::format(fmt::runtime(kRow), "  camera rays", s["camera_rays"].get<std::size_t>(),
                     fmt::format("{:.1f}", 100 * s["camera_hit_fraction"].get<double>()),
                     fmt::format("{:.3f}", s["camera_scalar_queries_per_s"].get<double>() / 1e6),
                     fmt::format("{:.3f}", s["camera_simd8_queries_per_s"].get<double>() / 1e6), fmt::format("{:.2f}x", s["camera_speedup"].get<double>()));
  }
  return t + wrap_words("Closest hit per ray, one thread, median of the repetitions of the thread's CPU time. Rays: from a sphere "
                        "twice the object's size to random points of its box; camera rays: the scene's camera, 8 neighbouring "
                        "pixels per packet. Operations per query and the reasons: --markdown (the report's CSG section).");
}
}  // namespace

int run_csg_command(int repetitions, std::size_t rays, bool markdown, const std::string& filter, const JsonOut& out) {
  ProgressBar bar("raybench csg");
  const json speed = measure_csg_speed(repetitions, rays, &bar, filter);
  bar.done();
  return write_result("csg", out, [&] { return markdown ? csg_markdown(speed, opstable::build()) : csg_text(speed); },
                      [&] { return json{{"machine", machine().json()}, {"repetitions", repetitions}, {"rays", rays}, {"rows", speed}}; },
                      "the CSG figures");
}

}  // namespace rb::app
