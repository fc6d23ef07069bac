// Report section "Rendering": the recursive ray tracer on Haines' seven SPD scenes (his protocol,
// his published counts beside ours) and on the lecture's four scenes, with images, the time
// split, Mrays/s and the ratio to primary-ray tracing throughput on the same scene and threads.
#include "apps/render_run.hpp"
#include "apps/report.hpp"
#include "apps/report_sections.hpp"
#include "apps/trace_run.hpp"
#include "scene/sources.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <iostream>

namespace rb::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string dev(std::uint64_t got, const json& ref) {
  if (ref.is_null()) return "-";
  const double r = ref.get<double>();
  if (r == 0) return got == 0 ? "equal" : "-";
  return fmt::format("{:+.1f} %", 100.0 * (double(got) - r) / r);
}
std::string numd(const json& h, const char* k) {
  return h.is_object() && h.contains(k) ? fmt::format("{:L}", std::uint64_t(h[k].get<double>())) : "-";
}
std::uint64_t poly_like(const json& j) {
  return j["prim_tests"]["polygon"].get<std::uint64_t>() + j["prim_tests"]["triangle"].get<std::uint64_t>();
}

}  // namespace

std::string report_section_render(const ReportOptions& o, const fs::path& out, json& summary) {
  (void)o;
  const int threads = 2;
  std::string md = "## Rendering: the recursive ray tracer\n\n";
  md += "The lecture's RT_trace / RT_shade over the 8-wide BVH (`raybench render`): the closest hit, an ambient term, per light "
        "a shadow ray (none when the normal faces away from the light; opaque occluders block, transmitting ones scale the "
        "light by their T per surface crossed), Lambert diffuse and Phong specular, a reflection ray for Ks > 0 and a "
        "refraction ray by Snell's law for T > 0 (on total internal reflection the reflection ray takes the transmitted share), "
        "up to a depth limit. Each 16 x 16 tile of samples is traced generation by generation: all rays of one generation "
        "go through the BVH as one SoA batch in 8-ray packets (a packet whose rays do not share a direction octant falls "
        "back to single rays), their shadow rays as another batch. Tiles run on TBB threads (and under `mpirun` on MPI ranks).\n\n";
  md += "SPD scenes follow Haines' protocol (`--spd`): 513 x 513 rays through the pixel corners of a 512 x 512 image, each "
        "pixel the mean of its four corners, depth 5 with the eye ray at depth 1, every ray hitting a reflector or a "
        "transmitter spawns a reflection ray, positional lights, smooth shading of `pp` patches, opaque surfaces one-sided "
        "(the light test uses the normal as given) except the teapot's. Scenes at the generators' default size factors. "
        "Haines' published counts are for a classical ray tracer; he expects others within about 10 %.\n\n";

  json rows = json::array();
  std::string img_md;
  const auto names = scene::spd_names();
  std::size_t step = 0;
  const std::size_t total = names.size() + scene::lecture_scene_names().size();
  auto render_one = [&](const std::string& src, bool spd, const std::string& png) {
    std::cerr << fmt::format("[report render {}/{}] {}\n", ++step, total, src);
    RenderRunOptions ro;
    ro.scene = src;
    ro.out = (out / png).string();
    ro.threads = threads;
    ro.spd = spd;
    ro.width = ro.height = 512;
    json j = run_render(ro, nullptr);
    TraceRunOptions t;
    t.scene = src;
    t.ray_set = "primary";
    t.threads = threads;
    t.packet = 8;
    t.count = 512 * 512;
    t.repetitions = 3;
    t.brute_rays = 0;
    t.embree = false;
    const json tj = run_trace(t, false);
    j["trace_primary_mrays_per_s"] = tj["mrays_per_s"];
    j["png"] = png;
    rows.push_back(j);
    return j;
  };

  std::vector<json> spd, lect;
  for (const auto& n : names) spd.push_back(render_one("spd:" + n, true, "render_spd_" + n + ".png"));
  for (const auto& n : scene::lecture_scene_names()) lect.push_back(render_one("lecture:" + n, false, "render_lecture_" + n + ".png"));

  md += "### Rays: ours beside Haines'\n\n| scene | prims | eye | eye hits | Haines | reflection | Haines | refraction | Haines | "
        "shadow | Haines |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& j : spd) {
    const json h = j.contains("haines") ? j["haines"] : json(nullptr);
    auto cell = [&](const char* k) {
      const auto v = j[k].get<std::uint64_t>();
      return h.is_null() ? fmt::format("{:L} | -", v) : fmt::format("{:L} | {} ({})", v, numd(h, k), dev(v, h[k]));
    };
    md += fmt::format("| {} | {:L} | {:L} | {} | {} | {} | {} |\n", j["scene"].get<std::string>(), j["primitives"].get<std::uint64_t>(),
                      j["eye_rays"].get<std::uint64_t>(), cell("eye_hit_rays"), cell("reflect_rays"), cell("refract_rays"),
                      cell("shadow_rays"));
  }
  md += "\nHaines' table in the task gives four of the seven scenes; the other three are rendered with the same protocol.\n\n";

  md += "### Intersection tests: ours beside Haines' hierarchy\n\nBox tests count every child box a node visit tests (8 per "
        "wide node, fewer where a node has fewer children); primitive tests count every real primitive slot a leaf visit "
        "tests, by kind.\n\n| scene | box tests | Haines | polygon + triangle tests | Haines (polygons) | sphere tests | "
        "Haines | cylinder + cone tests |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& j : spd) {
    const json h = j.contains("haines") ? j["haines"] : json(nullptr);
    md += fmt::format("| {} | {:L} | {} | {:L} | {} | {:L} | {} | {:L} |\n", j["scene"].get<std::string>(), j["box_tests"].get<std::uint64_t>(),
                      numd(h, "box_tests"), poly_like(j), numd(h, "polygon_tests"), j["prim_tests"]["sphere"].get<std::uint64_t>(),
                      numd(h, "sphere_tests"),
                      j["prim_tests"]["cylinder"].get<std::uint64_t>() + j["prim_tests"]["cone"].get<std::uint64_t>());
  }

  md += fmt::format("\n### Time and throughput ({} threads)\n\nPreprocessing is the scene's generation and the BVH build; tracing "
                    "is every ray of the image (eye, reflection, refraction, shadow, with the counting traversal that gives the "
                    "test counts above). The last column divides the render's rate (all rays) by the primary-ray rate of "
                    "`raybench trace SCENE --rays primary --packet 8 --threads {} --count 262144 --no-embree` (median of 3) in the "
                    "same run.\n\n| scene | rays | load ms | BVH ms | trace ms | Mrays/s | primary trace Mrays/s | render / primary |\n"
                    "|---|---:|---:|---:|---:|---:|---:|---:|\n", threads, threads);
  for (const auto* group : {&spd, &lect})
    for (const auto& j : *group) {
      const double a = j["mrays_per_s"].get<double>();
      const json& p = j["trace_primary_mrays_per_s"];
      md += fmt::format("| {} | {:L} | {:.1f} | {:.1f} | {:.1f} | {:.2f} | {} | {} |\n", j["scene"].get<std::string>(),
                        j["total_rays"].get<std::uint64_t>(), j["load_ms"].get<double>(), j["build_ms"].get<double>(),
                        j["trace_ms"].get<double>(), a, p.is_null() ? "-" : fmt::format("{:.2f}", p.get<double>()),
                        p.is_null() || p.get<double>() <= 0 ? "-" : fmt::format("{:.2f}", a / p.get<double>()));
    }

  md += "\n### The lecture's scenes\n\n512 x 512, one ray per pixel centre, depth 5, two-sided surfaces.\n\n| scene | eye hits | "
        "reflection | refraction | shadow | box tests | primitive tests |\n|---|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& j : lect) {
    std::uint64_t pt = 0;
    for (const auto& [k, v] : j["prim_tests"].items()) pt += v.get<std::uint64_t>();
    md += fmt::format("| {} | {:L} | {:L} | {:L} | {:L} | {:L} | {:L} |\n", j["scene"].get<std::string>(), j["eye_hit_rays"].get<std::uint64_t>(),
                      j["reflect_rays"].get<std::uint64_t>(), j["refract_rays"].get<std::uint64_t>(),
                      j["shadow_rays"].get<std::uint64_t>(), j["box_tests"].get<std::uint64_t>(), pt);
  }
  md += "\n### Images\n\n";
  for (const auto* group : {&spd, &lect})
    for (const auto& j : *group) md += fmt::format("`{}`\n\n![{}]({})\n\n", j["scene"].get<std::string>(), j["scene"].get<std::string>(),
                                                   j["png"].get<std::string>());
  summary["render"] = rows;
  return md;
}

}  // namespace rb::app
