// The terminal table of a `raybench trace` result (apps/trace_run.hpp): scene, rays, build, tree,
// memory, model, the machine's load, both engines' timing and the disagreement, from its JSON.
#include "apps/trace_run.hpp"

#include "apps/cli.hpp"
#include "apps/results/stats.hpp"

#include <fmt/format.h>

#include <string>

namespace rb::app {

using nlohmann::json;

namespace {
std::string num_or_dash(const json& v, const char* f) { return v.is_null() ? "-" : fmt::format(fmt::runtime(f), v.get<double>()); }
}  // namespace

std::string trace_text(const json& j) {
  std::string o;
  o += fmt::format("scene      {} ({} primitives)\n", j["scene"].get<std::string>(), j["primitives"].get<std::size_t>());
  const std::string light = j["light"].get<std::string>();
  o += fmt::format("rays       {} {} (seed {}, camera {}{}), {:.1f}% hit\n", j["rays"].get<std::size_t>(), j["ray_set"].get<std::string>(),
                   j["seed"].get<std::uint64_t>(), j["camera"].get<std::string>(), light.empty() ? "" : ", light " + light,
                   100 * j["hit_fraction"].get<double>());
  std::string hist;
  for (const auto& h : j["leaf_size_histogram"]) hist += fmt::format("{}{}", hist.empty() ? "" : " ", h.get<std::size_t>());
  if (j.value("builds", 1) > 1)
    o += fmt::format("build      raybench {:.1f} ms, Embree {} ms: medians of {} builds after an untimed one (the traced build: SAH {:.1f}, "
                     "reorder {:.1f}, collapse {:.1f})\n",
                     j["build_ms"].get<double>(), num_or_dash(j["embree_build_ms"], "{:.1f}"), j["builds"].get<int>(),
                     j["sah_build_ms"].get<double>(), j["reorder_ms"].get<double>(), j["collapse_ms"].get<double>());
  else
    o += fmt::format("build      raybench {:.1f} ms (SAH {:.1f}, reorder {:.1f}, collapse {:.1f}); Embree {} ms\n", j["build_ms"].get<double>(),
                     j["sah_build_ms"].get<double>(), j["reorder_ms"].get<double>(), j["collapse_ms"].get<double>(),
                     num_or_dash(j["embree_build_ms"], "{:.1f}"));
  o += fmt::format("bvh        {} tree: {} binary nodes, {} wide nodes, {} leaves (sizes 1..8: {}), depth {}, SAH cost {:.2f}\n",
                   j["builder"].get<std::string>(), j["nodes_binary"].get<std::size_t>(), j["nodes_wide"].get<std::size_t>(),
                   j["leaves"].get<std::size_t>(), hist,
                   j["depth"].get<int>(), j["sah_cost"].get<double>());
  o += fmt::format("memory     raybench {:.1f} B/prim (8-wide nodes + leaf-ordered batches); Embree {} B/prim (BVH)\n",
                   j["bytes_per_prim"].get<double>(), num_or_dash(j["embree_bytes_per_prim"], "{:.1f}"));
  o += fmt::format("model      {} (frame {}; `raybench plan` explains the choices)\n", j["model"].get<std::string>(), j["frame"].get<std::string>());
  if (j.contains("plan_kinds"))
    for (const auto& k : j["plan_kinds"]) {
      const std::string classes = k["classes"]["summary"].get<std::string>();
      o += fmt::format("           {} {}: {} in {}, stored in {}{}\n", k["count"].get<std::size_t>(), k["kind"].get<std::string>(),
                       k["method"].get<std::string>(), k["precision"].get<std::string>(), k["storage"].get<std::string>(),
                       classes.empty() ? "" : "; " + classes);
      if (const json& a = k["split"]; !a.is_null())
        o += fmt::format("           apart: {} {} primitives in {}{}, {:.1f} KiB\n", a["count"].get<std::size_t>(), k["kind"].get<std::string>(),
                         a["storage"].get<std::string>(),
                         a["storage"] == "local frames" ? fmt::format(" ({} of them in double)", a["in_double"].get<std::size_t>()) : "",
                         a["bytes"].get<double>() / 1024);
    }
  // The median with its range and coefficient of variation over the timed runs (after the warm-up).
  auto timing = [&](const std::string& p) {
    return fmt::format("{:.2f} Mrays/s (median of {}, range {:.2f}-{:.2f}{})", j[p + "mrays_per_s"].get<double>(), j["repetitions"].get<int>(),
                       j[p + "mrays_per_s_min"].get<double>(), j[p + "mrays_per_s_max"].get<double>(),
                       j[p + "cv"].is_null() ? "" : fmt::format(", CV {:.1f} %", 100 * j[p + "cv"].get<double>()));
  };
  if (j.contains("machine_load")) o += wrap_words("machine    " + load_text(j["machine_load"]), 80, "           ");
  const int lanes = j.value("group_lanes", 0);
  const std::string groups = lanes > 1 ? fmt::format(" in groups of {} lanes ({})", lanes, lanes == 16 ? "AVX-512" : "AVX2") : "";
  o += fmt::format("trace      raybench packet {}{}, {} thread(s), {} slab test, {} warm-up run(s) until the times settled;\n"
                   "           {} pass(es) over the rays per repetition ({:.2f} s, at least {} s):\n",
                   j["packet"].get<int>(), groups, j["threads"].get<int>(), j["slab"].get<std::string>(), j["warmup_seconds"].size(),
                   j["passes"].get<int>(), j["repetition_seconds"].get<double>(), j["min_time"].get<double>());
  o += "           " + timing("") + "\n";
  if (!j["outliers"].empty())
    o += fmt::format("           {} repetition(s) far above the others (Tukey's fence), kept in every figure\n", j["outliers"].size());
  o += fmt::format("           {:.2f} nodes, {:.2f} box tests, {:.2f} primitive tests per ray\n", j["nodes_per_ray"].get<double>(),
                   j["box_tests_per_ray"].get<double>(), j["prim_tests_per_ray"].get<double>());
  if (j.contains("lanes8")) {
    const json& w = j["lanes8"];
    o += fmt::format("           in groups of 8 lanes (AVX2), same rounds: {:.2f} Mrays/s;\n"
                     "           16 lanes over 8: {}; {} ray(s) with other hits\n",
                     w["mrays_per_s"].get<double>(), stats::interval_text(stats::interval_from_json(w["speedup_16_over_8"])),
                     w["mismatches"].get<std::size_t>());
  }
  if (j.contains("threads_beside")) {
    const json& w = j["threads_beside"];
    o += fmt::format("           on {} thread(s), same rounds: {:.2f} Mrays/s;\n"
                     "           {} thread(s) over {}: {}; {} ray(s) with other hits\n",
                     w["threads"].get<int>(), w["mrays_per_s"].get<double>(), w["threads"].get<int>(), j["threads"].get<int>(),
                     stats::interval_text(stats::interval_from_json(w["speedup"])), w["mismatches"].get<std::size_t>());
    if (w.contains("one_thread_cpus")) {
      std::string per;
      for (std::size_t c = 0; c < w["one_thread_cpus"].size(); ++c)
        per += fmt::format("{}CPU {}: {:.2f}", c ? ", " : "", w["one_thread_cpus"][c].get<int>(),
                           w["one_thread_mrays_per_s_by_cpu"][c].get<double>());
      o += fmt::format("           (over one thread's rate averaged over the CPUs it took turns on: {:.2f} Mrays/s; {})\n",
                       w["one_thread_mrays_per_s"].get<double>(), per);
    }
    if (w.contains("embree")) {
      const json& e = w["embree"];
      o += fmt::format("           Embree ({}) in the same rounds: {:.2f} -> {:.2f} Mrays/s, {} thread(s) over {}: {}\n",
                       e["mode"].get<std::string>(), e["one_thread_mrays_per_s"].get<double>(), e["mrays_per_s"].get<double>(),
                       w["threads"].get<int>(), j["threads"].get<int>(), stats::interval_text(stats::interval_from_json(e["speedup"])));
    }
  }
  if (j.contains("sah_tree") && j["sah_tree"].contains("mrays_per_s")) {
    const json& t = j["sah_tree"];
    o += fmt::format("tree       the tree above is Embree's builder's ({}); raybench's SAH tree through the same traversal:\n",
                     j["builder"].get<std::string>());
    o += fmt::format("           {:.2f} Mrays/s; {:.2f} nodes, {:.2f} box tests, {:.2f} primitive tests per ray; SAH cost {:.2f}\n",
                     t["mrays_per_s"].get<double>(), t["nodes_per_ray"].get<double>(), t["box_tests_per_ray"].get<double>(),
                     t["prim_tests_per_ray"].get<double>(), t["sah_cost"].get<double>());
    o += fmt::format("           Embree's tree / SAH tree = {:.2f}\n", j["mrays_per_s"].get<double>() / t["mrays_per_s"].get<double>());
  }
  if (!j["embree_mrays_per_s"].is_null()) {
    o += fmt::format("           Embree's best mode, {} (ISA {}), runs alternating with raybench's:\n           {}\n",
                     j["embree_mode"].get<std::string>(), j["embree_isa"].get<std::string>(), timing("embree_"));
    std::string each;
    for (const json& m : j["embree_modes"])
      each += fmt::format("{}{} {:.2f}{}", each.empty() ? "" : ", ", m["mode"].get<std::string>(),
                          m.contains("mrays_per_s") ? m["mrays_per_s"].get<double>() : m["warmup_mrays_per_s"].get<double>(),
                          m.contains("mrays_per_s") ? "" : " (warm-up)");
    o += wrap_words("           every mode (Mrays/s; modes over 10 % slower in the warm-up are left out of the rounds): " + each, 80,
                    "           ");
    const stats::RatioInterval vr = stats::interval_from_json(j["vs_embree"]);
    o += fmt::format("           raybench / Embree ({}):\n           {}: the median of {} rounds' ratios{}\n",
                     j["embree_mode"].get<std::string>(), stats::interval_text(vr), vr.n,
                     vr.valid() && vr.coverage >= 0.95 ? " [95 % interval]" : "");
    o += fmt::format("mismatch   {:.4f}% ({} of {} rays; {} hits at the same t on another primitive)\n", 100 * j["mismatch_rate"].get<double>(),
                     j["mismatches"].get<std::size_t>(), j["rays"].get<std::size_t>(), j["other_prim_same_t"].get<std::size_t>());
  } else {
    o += fmt::format("           Embree: {}\n", j["embree_why"].get<std::string>());
  }
  if (j.value("order", std::string("given")) == "sorted") {
    o += wrap_words(fmt::format("order      sorted: every pass of every engine sorts the rays ({}; {:.2f} ms a sort) and puts the hits "
                                "back in the given order, inside the timed pass; Embree's figures above are on the given order",
                                j["sort_key"].get<std::string>(), j["sort_ms"].get<double>()),
                    80, "           ");
    if (j.contains("embree_sorted") && !j["embree_sorted"].is_null()) {
      const json& e = j["embree_sorted"];
      const stats::RatioInterval vr = stats::interval_from_json(e["vs_embree_sorted"]);
      o += fmt::format("           Embree on the sorted order, best mode {}: {:.2f} Mrays/s; raybench / Embree sorted {}\n",
                       e["mode"].get<std::string>(), e["mrays_per_s"].get<double>(), stats::interval_text(vr));
    }
  }
  if (!j["brute_mrays_per_s"].is_null())
    o += fmt::format("brute      loop over all objects on {} rays: {:.4f} Mrays/s, {} mismatches against the BVH\n",
                     j["brute_rays"].get<std::size_t>(), j["brute_mrays_per_s"].get<double>(), j["brute_mismatches"].get<std::size_t>());
  return o;
}

}  // namespace rb::app
