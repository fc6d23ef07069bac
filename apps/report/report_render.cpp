// Report section "Rendering": the recursive ray tracer on Haines' seven SPD scenes (his protocol,
// his published counts beside ours) and on the lecture's four scenes, with images, the time
// split, Mrays/s and the ratio to primary-ray tracing throughput on the same scene and threads.
#include "apps/render_run.hpp"
#include "apps/report/report.hpp"
#include "apps/report/report_record.hpp"
#include "apps/report/report_doc.hpp"
#include "apps/report/report_sections.hpp"
#include "apps/results/stats.hpp"
#include "scene/csg_scene.hpp"
#include "scene/sources.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <iostream>
#include <vector>

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
// 1234567 -> "1,234,567".
std::string sep(std::uint64_t v) {
  std::string d = std::to_string(v), r;
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (i && (d.size() - i) % 3 == 0) r += ',';
    r += d[i];
  }
  return r;
}
std::string numd(const json& h, const char* k) {
  return h.is_object() && h.contains(k) ? sep(std::uint64_t(h[k].get<double>())) : "-";
}
std::string u(const json& v) { return sep(v.get<std::uint64_t>()); }
// Primitives in Haines' SPD databases at their default sizes (his table; teapot: size 12).
std::string haines_prims(const std::string& src) {
  static const std::pair<const char*, int> k[] = {{"spd:balls", 7382}, {"spd:gears", 9345}, {"spd:mount", 8196}, {"spd:rings", 8401},
                                                  {"spd:teapot:12", 9264}, {"spd:tetra", 4096}, {"spd:tree", 8191}};
  for (const auto& [n, c] : k)
    if (src == n) return sep(std::uint64_t(c));
  return "-";
}
std::uint64_t poly_like(const json& j) {
  return j["prim_tests"]["polygon"].get<std::uint64_t>() + j["prim_tests"]["triangle"].get<std::uint64_t>();
}

// The SPD scenes' rays and intersection tests beside Haines' published counts.
std::string render_spd_tables(const std::vector<json>& spd) {
  std::string md;
  md += "### Rays: ours beside Haines'\n\n| scene | prims | Haines' prims | eye | eye hits | Haines | reflection | Haines | refraction | Haines | "
        "shadow | Haines |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& j : spd) {
    const json h = j.contains("haines") ? j["haines"] : json(nullptr);
    auto cell = [&](const char* k) {
      const auto v = j[k].get<std::uint64_t>();
      return h.is_null() ? fmt::format("{} | -", sep(v)) : fmt::format("{} | {} ({})", sep(v), numd(h, k), dev(v, h[k]));
    };
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", j["scene"].get<std::string>(), u(j["primitives"]),
                      haines_prims(j["scene"].get<std::string>()), u(j["eye_rays"]), cell("eye_hit_rays"), cell("reflect_rays"),
                      cell("refract_rays"), cell("shadow_rays"));
  }
  md += "\nHaines' published ray counts cover balls, teapot, tetra and tree; gears, mount and rings are rendered with the same "
        "protocol. The generators' default size factors give Haines' primitive counts except for the teapot: its default "
        "size 6 has 2,292 primitives, Haines' 9,264 are size 12, so the teapot is rendered at both (`spd:teapot:12`). The "
        "eye-hit, reflection and shadow counts hardly depend on the teapot's tessellation (the silhouette is the same).\n\n";

  md += "### Intersection tests: ours beside Haines' hierarchy\n\nBox tests count every child box a node visit tests (8 per "
        "wide node, fewer where a node has fewer children); primitive tests count every real primitive slot a leaf visit "
        "tests, by kind.\n\n| scene | box tests | Haines | polygon + triangle tests | Haines (polygons) | sphere tests | "
        "Haines | cylinder + cone tests |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& j : spd) {
    const json h = j.contains("haines") ? j["haines"] : json(nullptr);
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", j["scene"].get<std::string>(), u(j["box_tests"]),
                      numd(h, "box_tests"), sep(poly_like(j)), numd(h, "polygon_tests"), u(j["prim_tests"]["sphere"]),
                      numd(h, "sphere_tests"),
                      sep(j["prim_tests"]["cylinder"].get<std::uint64_t>() + j["prim_tests"]["cone"].get<std::uint64_t>()));
  }

  md += "\nThe two hierarchies differ in shape, so the totals do not compare one to one: each of our leaves is one 8-slot lane "
        "group of one kind, tested by one SIMD kernel call, and a wide node tests its up to 8 child boxes in one 8-lane slab "
        "test. Primitive tests therefore count up to 8 per leaf visit (more than a hierarchy with a primitive or two per "
        "leaf) and box tests count 8 per node visit; the kernel calls are about an eighth of each count.\n";
  return md;
}

// A render's rate per ray over its scene's primary-ray tracing rate: from the render's paired rounds
// (`raybench render --primary-rays`: primary.render_over_primary); in a record of an older report,
// the ratio of medians with the 95 % interval of two samples measured apart (the timed renders
// against the timed traces); with one sample a side (--quick) or from a record without the samples,
// the ratio alone, which decides nothing.
stats::RatioInterval render_over_primary(const json& j) {
  if (j.contains("primary") && j["primary"].contains("render_over_primary")) {
    const stats::RatioInterval r = stats::interval_from_json(j["primary"]["render_over_primary"]);
    if (std::isfinite(r.ratio)) return r;
  }
  auto rates = [](const json& secs, double rays) {
    std::vector<double> v;
    for (const auto& x : secs)
      if (x.is_number() && x.get<double>() > 0) v.push_back(rays / x.get<double>());
    return v;
  };
  if (j.contains("trace_seconds") && j.contains("trace_primary_seconds") && j.contains("trace_primary_rays")) {
    const stats::RatioInterval r = stats::unpaired_ratio(rates(j["trace_seconds"], j["total_rays"].get<double>()),
                                                         rates(j["trace_primary_seconds"], j["trace_primary_rays"].get<double>()));
    if (std::isfinite(r.ratio)) return r;
  }
  stats::RatioInterval r;
  const json& p = j["trace_primary_mrays_per_s"];
  if (!p.is_null() && p.get<double>() > 0) r.ratio = j["mrays_per_s"].get<double>() / p.get<double>();
  return r;
}

// Every render's time, rate and rate against primary-ray tracing, and the goal on that ratio
// (its verdict in `summary`): met where the interval clears 0.5, not met where it lies below.
std::string render_time_table(int threads, std::initializer_list<const std::vector<json>*> groups, json& summary) {
  std::string md;
  md += fmt::format("\n### Time and throughput ({} threads)\n\nPreprocessing is the scene's generation and the BVH build; tracing "
                    "is every ray of the image (eye, reflection, refraction, shadow) through the plain traversal, the median of 9 "
                    "timed renders, each repeated until it lasted 0.1 s; the test counts above come from one more render, untimed, "
                    "through the counting traversal. The last column divides the render's rate (all rays) by the rate of the scene's "
                    "primary rays (as many as the image has pixels, `raybench trace`'s primary set, in 8-ray packets on {} threads), "
                    "each timed render followed by those rays traced for as long (`raybench render SCENE --primary-rays N`): the "
                    "median of the rounds' ratios with its 95 % interval (the sign test's), paired rounds that a change of the "
                    "machine's load falls on alike. Packets: the eye rays', their shadow rays' and the other rays' packet size, each the fastest in the trial renders.\n\n"
                    "| scene | rays | packets (eye / eye shadow / others) | load ms | BVH ms | trace ms | Mrays/s | primary trace Mrays/s | "
                    "render / primary | >= 0.5 |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n", threads, threads);
  int met = 0, below = 0, undecided = 0, all = 0;
  for (const auto* group : groups)
    for (const auto& j : *group) {
      const double a = j["mrays_per_s"].get<double>();
      const json& p = j["trace_primary_mrays_per_s"];
      const stats::RatioInterval r = render_over_primary(j);
      int verdict = doc::kGoalNotMeasured;
      if (r.valid()) verdict = r.lo >= 0.5 ? doc::kGoalMet : r.hi < 0.5 ? doc::kGoalNotMet : doc::kGoalUndecided;
      else if (std::isfinite(r.ratio)) verdict = doc::kGoalUndecided;  // one sample a side (--quick), or a record without them
      if (verdict != doc::kGoalNotMeasured) ++all;
      met += verdict == doc::kGoalMet, below += verdict == doc::kGoalNotMet, undecided += verdict == doc::kGoalUndecided;
      md += fmt::format("| {} | {} | {} / {} / {} | {:.1f} | {:.1f} | {:.1f} | {:.2f} | {} | {} | {} |\n", j["scene"].get<std::string>(),
                        u(j["total_rays"]), j["eye_packet"].get<int>(), j.value("eye_shadow_packet", j["secondary_packet"].get<int>()),
                        j["secondary_packet"].get<int>(), j["load_ms"].get<double>(),
                        j["build_ms"].get<double>(), j["trace_ms"].get<double>(), a, p.is_null() ? "-" : fmt::format("{:.2f}", p.get<double>()),
                        r.valid() ? stats::interval_text(r) : std::isfinite(r.ratio) ? fmt::format("{:.2f}", r.ratio) : "-",
                        doc::goal_cell(verdict));
    }
  md += fmt::format("\nGoal: rendering (all rays of every kind) at least half as fast per ray as primary-ray tracing: met on {} of {} "
                    "scenes in this run, not met on {}, undecided on {} (an interval straddling 0.5). Primary rays are the cheapest "
                    "rays there are (coherent 8-ray packets, nothing but the closest hit); a rendered ray also pays for its "
                    "generation (normalised in double), its shading (the hit's normal and material, Lambert, Phong) and the "
                    "traversal of reflection, refraction and shadow rays, which are less coherent than eye rays: the next table "
                    "shows how the time divides.\n", met, all, below, undecided);
  summary["render_goal_half_of_primary"] = {{"met", met}, {"not_met", below}, {"undecided", undecided}, {"scenes", all}};
  return md;
}

// Each render against the same rays traced alone (`raybench render --json`: alone): the render's
// overhead over its tracing, and the goal that it stays under 20 % (render / alone >= 0.8, its
// verdict in `summary`).
std::string render_alone_table(std::initializer_list<const std::vector<json>*> groups, json& summary) {
  std::string md =
      "\n### The render against its own rays traced alone\n\n"
      "One more render, untimed, keeps every ray it traces (each generation's rays and shadow rays, in the order and the "
      "packets it traced them, shadow rays past transmitting occluders included); then each timed repetition of the render "
      "is followed by one as long of those rays traced alone, section by section with the render's packet size and query and "
      "nothing else (no ray making, packing or shading): paired rounds, so a change of the machine's load falls on both sides "
      "(`raybench render SCENE --rays-out FILE`, then `raybench trace SCENE --rays FILE`, traces a file's rays alone). "
      "render / alone is the time tracing alone takes over the render's time (the render's rate over the rate of its own rays "
      "traced alone, both counted as the render counts them): the median of the rounds' ratios with its 95 % interval (the "
      "sign test's); 1 would be a render that does nothing but trace.\n\n"
      "| scene | render ms | rays traced alone | alone ms | alone Mrays/s | render / alone | >= 0.8 |\n|---|---:|---:|---:|---:|---:|---|\n";
  int met = 0, below = 0, undecided = 0, all = 0;
  for (const auto* group : groups)
    for (const auto& j : *group) {
      if (!j.contains("alone") || !j["alone"].contains("ms")) continue;
      const json& a = j["alone"];
      const stats::RatioInterval r = stats::interval_from_json(a["render_over_alone"]);
      int verdict = doc::kGoalNotMeasured;
      if (r.valid()) verdict = r.lo >= 0.8 ? doc::kGoalMet : r.hi < 0.8 ? doc::kGoalNotMet : doc::kGoalUndecided;
      else if (std::isfinite(r.ratio)) verdict = doc::kGoalUndecided;
      if (verdict != doc::kGoalNotMeasured) ++all;
      met += verdict == doc::kGoalMet, below += verdict == doc::kGoalNotMet, undecided += verdict == doc::kGoalUndecided;
      md += fmt::format("| {} | {:.1f} | {} | {:.1f} | {:.2f} | {} | {} |\n", j["scene"].get<std::string>(), j["trace_ms"].get<double>(),
                        u(a["rays"]), a["ms"].get<double>(), a["mrays_per_s"].get<double>(),
                        r.valid() ? stats::interval_text(r) : std::isfinite(r.ratio) ? fmt::format("{:.2f}", r.ratio) : "-",
                        doc::goal_cell(verdict));
    }
  md += fmt::format("\nGoal: each render at least 0.8x the rate of its own rays traced alone (its overhead over tracing under "
                    "20 %): met on {} of {} scenes, not met on {}, undecided on {}.\n\n"
                    "![render / primary and render / alone per scene](render_speed.png)\n", met, all, below, undecided);
  summary["render_goal_alone"] = {{"met", met}, {"not_met", below}, {"undecided", undecided}, {"scenes", all}};
  return md;
}

// Where each render's time went (`raybench render --json`: time_split), as shares of its thread time.
std::string render_split_table(std::initializer_list<const std::vector<json>*> groups) {
  std::string md =
      "\n### Where the render's time goes\n\n"
      "Thread time of the last timed render (summed over the threads), split into the eye rays made, the rays packed "
      "(sorted by octant and copied into SoA batches), the BVH by kind of ray, shading (local light, the next generation's "
      "and the shadow rays made) and the shadow rays' light; `accounted` is that sum over threads x wall time (the rest: "
      "tiles waiting on the scheduler, clock reads). Coherent: the share of the reflection and refraction rays' 8-ray groups "
      "(in the order they are traced) whose rays share a direction octant, which the traversal takes as one packet. Per "
      "generation: `raybench render --json` (time_split.generations).\n\n"
      "| scene | thread ms | accounted | rays made | packed | BVH eye | BVH reflection, refraction | BVH shadow | shading | "
      "shadow light | eye hit rate | generations | generation 2 coherent |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto* group : groups)
    for (const auto& j : *group) {
      if (!j.contains("time_split")) continue;
      const json& ts = j["time_split"];
      const double total = ts["thread_ms"].get<double>();
      if (!(total > 0)) continue;
      auto pc = [&](const char* key) { return fmt::format("{:.1f} %", 100.0 * ts[key].get<double>() / total); };
      const json& g = ts["generations"];
      md += fmt::format("| {} | {:.1f} | {:.0f} % | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", j["scene"].get<std::string>(), total,
                        100.0 * total / (std::max(1, j["threads"].get<int>()) * ts["render_ms"].get<double>()), pc("generate_ms"), pc("pack_ms"),
                        pc("traverse_eye_ms"), pc("traverse_secondary_ms"), pc("traverse_shadow_ms"), pc("shade_ms"), pc("shadow_light_ms"),
                        g.empty() ? "-" : fmt::format("{:.1f} %", 100.0 * g[0]["hit_rate"].get<double>()), g.size(),
                        g.size() < 2 || !g[1].contains("coherent_groups") ? "-" : fmt::format("{:.1f} %", 100.0 * g[1]["coherent_groups"].get<double>()));
    }
  return md;
}

}  // namespace

std::string report_section_render(const ReportOptions& o, Record& rec, const fs::path& out, json& summary) {
  const int threads = 2;
  const int size = o.quick ? 128 : 512;
  std::string md = "## Rendering: the recursive ray tracer\n\n";
  md += "The lecture's RT_trace / RT_shade over the 8-wide BVH (`raybench render`): the closest hit, an ambient term, per light "
        "a shadow ray (none when the normal faces away from the light; opaque occluders block, transmitting ones scale the "
        "light by their T per surface crossed), Lambert diffuse and Phong specular, a reflection ray for Ks > 0 and a "
        "refraction ray by Snell's law for T > 0 (on total internal reflection the reflection ray takes the transmitted share), "
        "up to a depth limit. Each 16 x 16 tile of samples is traced generation by generation: all rays of one generation "
        "go through the BVH as one SoA batch, their shadow rays as another batch. Each scene's eye rays go in packets of 64, 16 "
        "or 8 and its other rays one by one or sorted by direction octant into packets of 8 (a packet whose rays do not "
        "share an octant falls back to single rays), whichever traced fastest in trial renders before the timed one (the "
        "time table names the choice). Shading takes a generation's hits eight at a time in SIMD lanes (per light the "
        "direction to it and Snell's law in double, Lambert and Phong in float, the rays' spawn points), each lane giving "
        "the bits of one hit shaded alone. Tiles run on TBB threads (and under `mpirun` on MPI ranks).\n\n";
  md += "SPD scenes follow Haines' protocol (`--spd`): 513 x 513 rays through the pixel corners of a 512 x 512 image, each "
        "pixel the mean of its four corners, depth 5 with the eye ray at depth 1, every ray hitting a reflector or a "
        "transmitter spawns a reflection ray, positional lights, smooth shading of `pp` patches, opaque surfaces one-sided "
        "(the light test uses the normal as given) except the teapot's. Scenes at the generators' default size factors. "
        "Haines' published counts are for a classical ray tracer; he expects others within about 10 %.\n\n";

  json rows = json::array();
  std::string img_md;
  const auto names = scene::spd_names();
  std::size_t step = 0;
  const std::size_t total = names.size() + 1 + scene::lecture_scene_names().size() + scene::csg_scene_names().size();
  // A render and the primary-ray trace of the same scene, measured (writing its image) or replayed.
  auto measure_one = [&](const std::string& src, bool spd, const std::string& png, bool alone) {
    RenderRunOptions ro;
    ro.scene = src;
    ro.out = (out / png).string();
    ro.threads = threads;
    ro.spd = spd;
    ro.width = ro.height = size;
    ro.warmup = 1;  // so that the first trial render of the packet sizes does not pay the cold start
    ro.count_tests = true;  // the tables' test counts, from one more render (untimed)
    // Paired rounds: each timed render followed by its own rays traced alone and by the scene's
    // primary rays, each as long. 9 rounds: the ratios' sign-test interval leaves out the lowest and
    // the highest round (96.1 % coverage); at 6 it is the range of the rounds (96.9 %).
    ro.repetitions = 9;
    ro.min_time = 0.1;
    ro.trace_alone = alone;
    ro.primary_rays = std::size_t(size) * std::size_t(size);
    if (o.quick) {  // the layout only: one render, the usual packet sizes, no trials
      ro.repetitions = 1;
      ro.min_time = 0;
      ro.warmup = 0;
      ro.eye_packet = 16;
      ro.secondary_packet = 8;
    }
    json j = run_render(ro, nullptr);
    j["trace_primary_mrays_per_s"] = j["primary"]["mrays_per_s"];
    j["trace_primary_rays"] = j["primary"]["rays"];
    j["png"] = png;
    return j;
  };
  // --quick (the layout only) traces the rays alone for the first scene of each group.
  auto render_one = [&](const std::string& src, bool spd, const std::string& png, bool first) {
    std::cerr << fmt::format("[report render {}/{}] {}\n", ++step, total, src);
    json j = rec.take("render/" + src, [&] { return measure_one(src, spd, png, first || !o.quick); });
    j["render_over_primary"] = stats::interval_json(render_over_primary(j));  // for the chart
    rows.push_back(j);
    return j;
  };

  std::vector<json> spd, lect;
  for (const auto& n : names) {
    spd.push_back(render_one("spd:" + n, true, "render_spd_" + n + ".png", spd.empty()));
    if (n == "teapot") spd.push_back(render_one("spd:teapot:12", true, "render_spd_teapot_12.png", false));
  }
  for (const auto& n : scene::lecture_scene_names())
    lect.push_back(render_one("lecture:" + n, false, "render_lecture_" + n + ".png", lect.empty()));
  std::vector<json> csgs;  // the embedded CSG scenes (the JSON scene format's camera, lights, materials)
  for (const auto& n : scene::csg_scene_names()) csgs.push_back(render_one("csg:" + n, false, "render_csg_" + n + ".png", csgs.empty()));

  md += render_spd_tables(spd);
  md += render_time_table(threads, {&spd, &lect, &csgs}, summary);
  md += render_alone_table({&spd, &lect, &csgs}, summary);
  md += render_split_table({&spd, &lect, &csgs});
  std::vector<const json*> rows_lc;
  md += "\n### The lecture's scenes and the CSG scenes\n\n512 x 512, one ray per pixel centre, depth 5, two-sided surfaces.\n\n| scene | eye hits | "
        "reflection | refraction | shadow | box tests | primitive tests |\n|---|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& j : lect) rows_lc.push_back(&j);
  for (const auto& j : csgs) rows_lc.push_back(&j);
  for (const json* jp : rows_lc) {
    const json& j = *jp;
    std::uint64_t pt = 0;
    for (const auto& [k, v] : j["prim_tests"].items()) pt += v.get<std::uint64_t>();
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", j["scene"].get<std::string>(), u(j["eye_hit_rays"]),
                      u(j["reflect_rays"]), u(j["refract_rays"]), u(j["shadow_rays"]), u(j["box_tests"]), sep(pt));
  }
  md += "\n### Images\n\n";
  for (const auto* group : {&spd, &lect, &csgs})
    for (const auto& j : *group) md += fmt::format("`{}`\n\n![{}]({})\n\n", j["scene"].get<std::string>(), j["scene"].get<std::string>(),
                                                   j["png"].get<std::string>());
  summary["render"] = rows;
  return md;
}

}  // namespace rb::app
