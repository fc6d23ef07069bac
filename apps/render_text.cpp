// `raybench render`'s summary for the terminal, from its JSON (apps/render_run.cpp measures).
#include "apps/render_run.hpp"

#include "apps/cli.hpp"
#include "apps/results/stats.hpp"
#include "core/output_file.hpp"
#include "core/text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>

namespace rb::app {

using json = nlohmann::json;

// What a timed repetition was: one render, or several lasting --min-time.
std::string passes_text(const json& j) {
  int most = 1;
  if (j.contains("passes"))
    for (const auto& p : j["passes"]) most = std::max(most, p.get<int>());
  if (most == 1) return "renders";
  return fmt::format("repetitions of at least {:g} s (up to {} renders each; the figures are per render)", j["min_time"].get<double>(), most);
}

// The time split as a paragraph and a table per generation.
std::string time_split_text(const json& ts, int threads) {
  const double total = ts["thread_ms"].get<double>();
  if (!(total > 0)) return "";
  auto pc = [&](const char* key) { return 100.0 * ts[key].get<double>() / total; };
  const double bvh = pc("traverse_eye_ms") + pc("traverse_secondary_ms") + pc("traverse_shadow_ms");
  std::string line = fmt::format(
      "time split of the last timed render ({:.1f} ms of thread time{}): eye rays made {:.1f} %, rays packed {:.1f} %, BVH {:.1f} % "
      "(eye {:.1f}, reflection and refraction {:.1f}, shadow {:.1f}), shading {:.1f} %, shadow light {:.1f} %",
      total,
      threads > 0 ? fmt::format("; {} thread(s) x {:.1f} ms: {:.0f} % accounted", threads, ts["render_ms"].get<double>(),
                                100.0 * total / (threads * ts["render_ms"].get<double>()))
                  : "",
      pc("generate_ms"), pc("pack_ms"), bvh, pc("traverse_eye_ms"), pc("traverse_secondary_ms"), pc("traverse_shadow_ms"), pc("shade_ms"),
      pc("shadow_light_ms"));
  std::string t = wrap_words(line, 80, "  ");
  t += "  gen      rays  hit %  coherent  shadow rays  BVH ms  shadow BVH  shading\n";
  for (const auto& g : ts["generations"])
    t += fmt::format("  {:>3} {:>9} {:>6.1f} {:>9.1f} {:>12} {:>7.1f} {:>11.1f} {:>8.1f}\n", g["generation"].get<int>(),
                     g["rays"].get<std::uint64_t>(), 100.0 * g["hit_rate"].get<double>(), 100.0 * g.value("coherent_groups", 0.0),
                     g["shadow_rays"].get<std::uint64_t>(), g["traverse_ms"].get<double>(), g["shadow_traverse_ms"].get<double>(),
                     g["shade_ms"].get<double>() + g["shadow_light_ms"].get<double>());
  t += "  (gen: generation, 1 the eye rays; coherent: % of 8-ray groups in one\n  direction octant, traced as packets when the packet size is 8 or more; times\n  in ms)\n";
  return t;
}

std::string render_text(const json& j) {
  std::string t;
  t += fmt::format("{} ({}): {} x {}, depth {}{}, {} thread(s){}\n", j["scene"].get<std::string>(), j["scene_name"].get<std::string>(),
                   j["width"].get<int>(), j["height"].get<int>(), j["depth"].get<int>(), j["spd"].get<bool>() ? ", SPD protocol" : "",
                   j["threads"].get<int>(), j["ranks"].get<int>() > 1 ? fmt::format(", {} MPI ranks", j["ranks"].get<int>()) : "");
  const bool hh = j.contains("haines");
  auto row = [&](const char* label, const char* key) {
    const auto v = j[key].get<std::uint64_t>();
    if (hh && j["haines"].contains(key)) {
      const double ref = j["haines"][key].get<double>();
      const std::string dev = ref > 0 ? fmt::format("{:+.1f} %", 100.0 * (double(v) - ref) / ref) : (v == 0 ? "equal" : "-");
      t += fmt::format("  {:<16} {:>14}   Haines {:>12.0f}   {}\n", label, v, ref, dev);
    } else {
      t += fmt::format("  {:<16} {:>14}\n", label, v);
    }
  };
  t += "rays\n";
  row("eye", "eye_rays");
  row("eye hits", "eye_hit_rays");
  row("reflection", "reflect_rays");
  row("refraction", "refract_rays");
  row("shadow", "shadow_rays");
  row("all", "total_rays");
  if (!j["tests_counted"].get<bool>()) t += "intersection tests: not counted (--no-counts)\n";
  else t += "intersection tests\n";
  if (j["tests_counted"].get<bool>()) t += fmt::format("  {:<16} {:>14}{}\n", "boxes", j["box_tests"].get<std::uint64_t>(),
                   hh && j["haines"].contains("box_tests") ? fmt::format("   Haines {:>12.0f}", j["haines"]["box_tests"].get<double>()) : "");
  for (const auto& [k, v] : j["prim_tests"].items()) {
    if (!j["tests_counted"].get<bool>()) break;
    if (v.get<std::uint64_t>() == 0) continue;
    std::string ref;
    if (hh && (k == "sphere") && j["haines"].contains("sphere_tests"))
      ref = fmt::format("   Haines {:>12.0f}", j["haines"]["sphere_tests"].get<double>());
    if (hh && (k == "polygon" || k == "triangle") && j["haines"].contains("polygon_tests"))
      ref = fmt::format("   Haines {:>12.0f} (polygons)", j["haines"]["polygon_tests"].get<double>());
    t += fmt::format("  {:<16} {:>14}{}\n", k, v.get<std::uint64_t>(), ref);
  }
  t += fmt::format("model: {} (frame {}; `raybench plan` explains the choices)\n", j["model"].get<std::string>(),
                   j["plan"]["frame"]["kind"].get<std::string>());
  if (j.contains("packet_choice")) {
    const json& pc = j["packet_choice"];
    const int esh = j.value("eye_shadow_packet", j["secondary_packet"].get<int>());
    t += fmt::format("packets: eye rays {} ({}), their shadow rays {} ({}), reflection, refraction and later shadow rays {} ({})\n",
                     j["eye_packet"].get<int>(), pc["eye"].get<std::string>(), esh, pc.value("eye_shadow", pc["secondary"].get<std::string>()),
                     j["secondary_packet"].get<int>(), pc["secondary"].get<std::string>());
    if ((j.value("secondary_packet", 1) == 8 || esh >= 8) && j.contains("secondary_order"))
      t += fmt::format("  secondary packets in {} order (--secondary-order)\n",
                       j["secondary_order"] == "sfc" ? "octant, origin and direction Morton" : "direction octant");
    for (const auto& tr : pc["trials"])
      t += fmt::format("  trial render: eye {:>2} -> {:.1f} ms, their shadow rays {} -> {:.1f} ms, others {} -> {:.1f} ms in the BVH\n",
                       tr["eye_packet"].get<int>(), tr["eye_trace_ms"].get<double>(), tr.value("eye_shadow_packet", 0),
                       tr.value("eye_shadow_trace_ms", 0.0), tr["secondary_packet"].get<int>(), tr["secondary_trace_ms"].get<double>());
  }
  if (j.contains("tile")) t += fmt::format("tiles: {0} x {0} samples, each traced generation by generation (--tile)\n", j["tile"].get<int>());
  t += fmt::format("time: preprocess {:.1f} ms (load {:.1f}, plan {:.1f}, BVH {:.1f}), trace {:.1f} ms, {:.2f} Mrays/s\n",
                   j["preprocess_ms"].get<double>(), j["load_ms"].get<double>(), j["plan_ms"].get<double>(), j["build_ms"].get<double>(),
                   j["trace_ms"].get<double>(), j["mrays_per_s"].get<double>());
  if (j.contains("trace_seconds") && j["trace_seconds"].size() > 1)
    t += fmt::format("      trace: median of {} {} after {} warm-up{}, range {:.1f}-{:.1f} ms{}\n", j["trace_seconds"].size(),
                     passes_text(j), j["warmup"].get<int>(),
                     j.value("trial_renders", 0) > 0 ? fmt::format(" and {} trial renders", j["trial_renders"].get<int>()) : "",
                     j["trace_ms_min"].get<double>(), j["trace_ms_max"].get<double>(),
                     j["cv"].is_null() ? "" : fmt::format(", CV {:.1f} %", 100 * j["cv"].get<double>()));
  if (j.contains("time_split")) t += time_split_text(j["time_split"], j["threads"].get<int>());
  if (j.contains("alone") && j["alone"].contains("ms")) {
    const json& a = j["alone"];
    t += wrap_words(fmt::format("the same rays traced alone: {} rays in {} sections (every generation's rays and shadow rays, "
                                "with the render's packets), {:.1f} ms per pass, {:.2f} Mrays/s; render / alone {} (the time "
                                "tracing alone takes over the render's time: 1 would be a render that only traces)",
                                a["rays"].get<std::size_t>(), a["sections"].size(), a["ms"].get<double>(), a["mrays_per_s"].get<double>(),
                                stats::interval_text(stats::interval_from_json(a["render_over_alone"]))),
                    80, "  ");
  }
  if (j.contains("primary") && j["primary"].contains("ms")) {
    const json& p = j["primary"];
    t += wrap_words(fmt::format("the scene's primary rays (--primary-rays, 8-ray packets, the closest hit): {} rays, {:.1f} ms "
                                "per pass, {:.2f} Mrays/s; render / primary {} per ray (each timed render followed by them)",
                                p["rays"].get<std::size_t>(), p["ms"].get<double>(), p["mrays_per_s"].get<double>(),
                                stats::interval_text(stats::interval_from_json(p["render_over_primary"]))),
                    80, "  ");
  }
  if (j.contains("rays_file")) t += fmt::format("wrote the rays traced to {}\n", j["rays_file"].get<std::string>());
  if (j.contains("machine_load")) t += wrap_words("      machine: " + load_text(j["machine_load"]), 80, "      ");
  if (j.contains("image")) {
    const std::string image = j["image"].get<std::string>();
    t += is_standard_output(image) ? "wrote the image to standard output\n" : fmt::format("wrote {}\n", image);
  }
  return t;
}

}  // namespace rb::app
