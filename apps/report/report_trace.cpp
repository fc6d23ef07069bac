// Report section "Tracing": whole scenes through the BVH beside Embree and the brute-force loop.
#include "core/median.hpp"
#include "core/output_file.hpp"
#include "apps/paths.hpp"
#include "apps/report/report.hpp"
#include "apps/report/report_record.hpp"
#include "apps/report/report_doc.hpp"
#include "apps/report/report_sections.hpp"
#include "apps/report/report_trace.hpp"
#include "apps/results/stats.hpp"
#include "apps/trace_run.hpp"
#include "scene/sources.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>

namespace rb::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {


// The generated third mesh: its scene source (so that `raybench trace` reproduces its rows) and
// its label in the tables.
std::string height_field_source() { return fmt::format("heightfield:{}x{}", rb::scene::kHeightFieldNx, rb::scene::kHeightFieldNy); }
std::string height_field_label() { return fmt::format("height field {}x{} (generated)", rb::scene::kHeightFieldNx, rb::scene::kHeightFieldNy); }
constexpr int kBuildReps = 15;  // builds per engine and thread count, paired: at 15 the interval leaves out 3 on each side

json ratio_value(const json& a, const json& b) {
  return a.is_null() || b.is_null() || b.get<double>() <= 0 ? json(nullptr) : json(a.get<double>() / b.get<double>());
}

std::string f2(const json& v) { return v.is_null() ? "-" : fmt::format("{:.2f}", v.get<double>()); }
std::string ratio(const json& a, const json& b) { return f2(ratio_value(a, b)); }
// A trace row's raybench / Embree: the median of its rounds' ratios with the 95 % interval, or the
// ratio of the medians where the row has no interval (a quick report's single round).
std::string vs_embree(const json& row) {
  const stats::RatioInterval r = row.contains("vs_embree") ? stats::interval_from_json(row["vs_embree"]) : stats::RatioInterval{};
  return r.valid() ? stats::interval_text(r) : ratio(row["mrays_per_s"], row["embree_mrays_per_s"]);
}

// What the parts of the section share: options, the record, the rays per set and rounds per row,
// and the matrix's rows as they are measured.
struct TracingRun {
  const ReportOptions& o;
  Record& rec;
  std::string data;  // the embedded meshes' folder, with a trailing '/'
  std::size_t count;
  int reps;
  double min_time;  // seconds a repetition lasts at least (the rays traced that many times over)
  json rows = json::array(), scaling = json::array(), matrix_builds = json::array();
  json sorted = json::array();  // the sorted-stream rows (diffuse and random rays, packets of 8)
  // A row's trace: the report's ray count, repetitions and minimum time, no brute-force check.
  // Coherent packets of 16 or more rays walk in 16 AVX-512 lanes where the CPU has them, the 8-lane
  // walk timed beside in the same rounds (`--isa both`; incoherent rays walk one by one).
  TraceRunOptions row(const char* ray_set = "primary", int packet = 1, int threads = 1) const {
    TraceRunOptions t;
    const std::string set = ray_set;
    if (packet >= 16 && (set == "primary" || set == "shadow")) t.isa = "both";
    t.ray_set = ray_set;
    t.packet = packet;
    t.threads = threads;
    t.count = count;
    t.repetitions = reps;
    t.min_time = min_time;
    t.brute_rays = 0;
    return t;
  }
};
struct TracedMesh {
  std::string label;
  std::function<rb::scene::Scene()> make;
};

// The incoherent rows again as sorted streams (`raybench trace --order sorted`): diffuse and random
// single rays, the sort and the hits put back inside every timed pass, Embree on both orders. Single
// rays, sorted by origin first: one ray after another finds the nodes the previous ray brought into
// the cache (packets would need the octant first, and cost these diverging rays more nodes than
// they save).
std::string trace_sorted_rows(TracingRun& x, const std::string& label, const json& mrows, const std::function<TraceSession&()>& sess) {
  constexpr int kPacket = 1;
  std::string rows, key;
  for (const char* set : {"diffuse", "random"})
    for (int th : {1, 2}) {
      if (x.o.quick && (th == 2 || std::string(set) == "random")) continue;  // the layout only
      TraceRunOptions t = x.row(set, kPacket, th);
      t.order = "sorted";
      json j = x.rec.take(fmt::format("tracing/{}/{}/{}/{}t/sorted", label, set, kPacket, th), [&] { return sess().run(t, true); });
      j["mesh"] = label;
      json given;
      for (const auto& r : mrows)
        if (r["ray_set"] == set && r["packet"] == kPacket && r["threads"] == th) given = r;
      const json& es = j["embree_sorted"];
      const stats::RatioInterval vs = es.is_null() ? stats::RatioInterval{} : stats::interval_from_json(es["vs_embree_sorted"]);
      if (key.empty() && j.contains("sort_key")) key = j["sort_key"].get<std::string>();
      rows += fmt::format("| {} | {} | {} | {} | {:.2f} | {} | {} | {} | {} |\n", set, th, given.is_null() ? "-" : f2(given["mrays_per_s"]),
                        f2(j["mrays_per_s"]), j["sort_ms"].get<double>(), f2(j["embree_mrays_per_s"]),
                        es.is_null() ? "-" : f2(es["mrays_per_s"]), vs_embree(j),
                        vs.valid() ? stats::interval_text(vs) : es.is_null() ? "-" : ratio(j["mrays_per_s"], es["mrays_per_s"]));
      x.sorted.push_back(j);
    }
  return fmt::format("Sorted streams (`--order sorted --packet {}`): every pass sorts the rays by {} and puts the hits back in the "
                     "given order, inside the timed pass; Embree traces the given order and the sorted one (sorting in its own "
                     "passes), with its single-ray call. The goal's ratio is raybench sorted over Embree's best mode on the given "
                     "order, round by round. Single rays, one after another: a ray finds the nodes near its origin that the previous "
                     "rays brought into the cache. The direction's octant first would split every region of origins into eight "
                     "passes over the tree; it is the key for packets of 8 or 16 (`--packet 8`), whose rays must share an octant, "
                     "and on these diverging rays packets cost more nodes than they save (on the height field, 65 box tests per ray "
                     "against 47). The diffuse rays' given order is already coherent (they leave the primary hits of 4x4 pixel "
                     "tiles in Z order), so sorting them buys the traversal little and costs the sort.\n\n"
                     "| rays | threads | raybench given | raybench sorted | sort ms | Embree given | Embree sorted | "
                     "sorted / Embree given [95 %] | sorted / Embree sorted [95 %] |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
                     kPacket, key.empty() ? "a key of origin and direction" : key) +
         rows + "\n";
}

// One mesh of the matrix: its builds at one and two threads, a row per ray set, packet size and
// thread count (raybench beside Embree), and two threads over one.
std::string trace_matrix_mesh(TracingRun& x, const TracedMesh& m, const std::vector<int>& packets) {
  const ReportOptions& o = x.o;
  Record& rec = x.rec;
  json& rows = x.rows;
  json& scaling = x.scaling;
  std::string md;
  std::cerr << "[report] tracing: " << m.label << "\n";
  // The mesh and its session are made only when something is measured (not in a replay).
  std::optional<rb::scene::Scene> scene;
  std::optional<TraceSession> session;
  auto mesh = [&]() -> rb::scene::Scene& {
    if (!scene) scene.emplace(m.make());
    return *scene;
  };
  auto sess = [&]() -> TraceSession& {
    if (!session) session.emplace(std::move(mesh()), m.label, 2, true);
    return *session;
  };
  // Builds: medians of kBuildReps at one and two threads, both engines, after one untimed build
  // of each (the first build of a thread count also pays for starting its threads).
  json bj = rec.take("tracing/" + m.label + "/builds", [&] {
    json first = json::object(), times = json::object();
    for (int th : {1, 2}) {
      const json t = time_builds(mesh(), m.label, th, o.quick ? 1 : kBuildReps, !o.quick, true);
      if (th == 1) first = t["first"];
      times[fmt::format("build_ms_{}t", th)] = t["build_ms"];
      times[fmt::format("embree_build_ms_{}t", th)] = t["embree_build_ms"];
      // Each build session builds both engines back to back: Embree's time over ours, paired.
      const auto runs = [&](const char* k) { return t[k].get<std::vector<double>>(); };
      times[fmt::format("embree_over_ours_{}t", th)] =
          stats::interval_json(stats::paired_ratio(runs("embree_build_ms_runs"), runs("build_ms_runs")));
    }
    first.update(times);
    first["triangles"] = mesh().triangles.size();
    return first;
  });
  const std::size_t prims = bj["triangles"].get<std::size_t>();
  md += fmt::format("#### {} ({} triangles)\n\n", m.label, prims);
  md += fmt::format("Build, median of {} after one untimed build: raybench {:.1f} ms at one thread, {:.1f} ms at two; Embree {} ms and {} ms "
                    "(raybench / Embree {} and {}; `raybench trace SCENE --threads 1 --builds 5` reproduces the one-thread figure). Memory: raybench "
                    "{:.1f} bytes per triangle, Embree {}.\n\n",
                    o.quick ? 1 : kBuildReps, bj["build_ms_1t"].get<double>(), bj["build_ms_2t"].get<double>(), f2(bj["embree_build_ms_1t"]),
                    f2(bj["embree_build_ms_2t"]), ratio(bj["build_ms_1t"], bj["embree_build_ms_1t"]),
                    ratio(bj["build_ms_2t"], bj["embree_build_ms_2t"]), bj["bytes_per_prim"].get<double>(),
                    f2(bj["embree_bytes_per_prim"]));
  // One table row per ray set and packet size, one and two threads side by side (16 rows).
  md += "| rays | packet | raybench Mrays/s, 1 thread | Embree | ratio [95 %] | raybench, 2 threads | Embree | ratio [95 %] | Embree's mode, "
        "1 / 2 threads (ISA) | raybench's lanes: 16 over 8 [95 %], 1 / 2 threads | boxes/ray | prims/ray | mismatch vs Embree |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---|---|---:|---:|---:|\n";
  json mrows = json::array();
  auto mode = [](const json& j) {
    return j.contains("embree_mode") ? j["embree_mode"].get<std::string>() + " (" + j.value("embree_isa", std::string("?")) + ")"
                                     : std::string("-");
  };
  auto mismatch = [](const json& j) { return j["mismatch_rate"].is_null() ? -1.0 : j["mismatch_rate"].get<double>(); };
  // The lanes a row's packets walked in; with the 8-lane walk beside, 16 over 8 with its interval.
  // Diffuse and random rays share no octant: they walk one or two at a time whatever the width.
  auto lanes = [](const json& j) -> std::string {
    const int l = j.value("group_lanes", 0);
    if (l <= 1 || !(j["ray_set"] == "primary" || j["ray_set"] == "shadow")) return "-";
    if (!j.contains("lanes8")) return fmt::format("{} ({})", l, l == 16 ? "AVX-512" : "AVX2");
    return stats::interval_text(stats::interval_from_json(j["lanes8"]["speedup_16_over_8"]));
  };
  for (const char* set : {"primary", "shadow", "diffuse", "random"})
    for (int packet : packets) {
      json pair[2];
      for (int th : {1, 2}) {
        TraceRunOptions t = x.row(set, packet, th);
        if (th == 1) t.threads_beside = 2;  // the thread scaling, paired: two threads in the one-thread row's rounds
        json j = rec.take(fmt::format("tracing/{}/{}/{}/{}t", m.label, set, packet, th), [&] { return sess().run(t, true); });
        j["mesh"] = m.label;
        mrows.push_back(j);
        rows.push_back(j);  // with the seconds of every run: `raybench compare` tests two reports' repetitions
        pair[th - 1] = std::move(j);
      }
      const json& a = pair[0];
      const json& b = pair[1];
      const std::string modes = mode(a) == mode(b) ? mode(a) : mode(a) + " / " + mode(b);
      const double mm = std::max(mismatch(a), mismatch(b));
      const std::string la = lanes(a), lb = lanes(b);
      md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.1f} | {:.1f} | {} |\n", set, packet, f2(a["mrays_per_s"]),
                        f2(a["embree_mrays_per_s"]), vs_embree(a), f2(b["mrays_per_s"]), f2(b["embree_mrays_per_s"]), vs_embree(b), modes,
                        la == lb ? la : la + " / " + lb,
                        a["box_tests_per_ray"].get<double>(), a["prim_tests_per_ray"].get<double>(),
                        mm < 0 ? "-" : fmt::format("{:.4f} %", 100 * mm));
    }
  md += "\n";
  bj["mesh"] = m.label;
  bj["triangles"] = prims;
  // Thread scaling of tracing: two threads over one, per ray set and packet size, from the
  // one-thread row, whose rounds also traced the rays on two threads (paired), and so did Embree's
  // fastest mode (its control: where both engines' second thread gave less than the goal in the
  // same rounds, the host gave less than two cores then, not the tracer). A record without the
  // control (`--from` an older report): Embree's two rows' medians, unpaired.
  md += "Two threads over one (same rays, same rounds; raybench's one-thread rate averaged over the two CPUs, on which it took turns), "
        "raybench (Embree's fastest mode in the same rounds, in brackets): ";
  std::vector<std::string> sc;
  for (std::size_t i = 0; i + 1 < mrows.size(); i += 2) {
    const json& a = mrows[i];
    const json& b = mrows[i + 1];
    const json e = ratio_value(b["embree_mrays_per_s"], a["embree_mrays_per_s"]);
    // A record from before the pairing (`--from` an older report): the two rows' runs, unpaired.
    const stats::RatioInterval ri = a.contains("threads_beside")
                                        ? stats::interval_from_json(a["threads_beside"]["speedup"])
                                        : stats::unpaired_ratio(a["seconds"].get<std::vector<double>>(), b["seconds"].get<std::vector<double>>());
    const double r = std::isfinite(ri.ratio) ? ri.ratio : b["mrays_per_s"].get<double>() / a["mrays_per_s"].get<double>();
    const bool control = a.contains("threads_beside") && a["threads_beside"].contains("embree");
    const stats::RatioInterval ei = control ? stats::interval_from_json(a["threads_beside"]["embree"]["speedup"]) : stats::RatioInterval{};
    sc.push_back(fmt::format("{} {}: {} ({})", a["ray_set"].get<std::string>(), a["packet"].get<int>(), stats::interval_text(ri),
                             control ? stats::interval_text(ei) : f2(e) + ", unpaired"));
    scaling.push_back({{"mesh", m.label}, {"ray_set", a["ray_set"]}, {"packet", a["packet"]}, {"ours", r},
                       {"embree", control && std::isfinite(ei.ratio) ? json(ei.ratio) : e}, {"ours_interval", stats::interval_json(ri)},
                       {"embree_interval", control ? stats::interval_json(ei) : json(nullptr)}});
  }
  for (std::size_t i = 0; i < sc.size(); ++i) md += (i ? ", " : "") + sc[i];
  md += ".\n\n";
  x.matrix_builds.push_back(bj);
  md += trace_sorted_rows(x, m.label, mrows, sess);
  return md;
}

// Embree's builder's tree through raybench's traversal (`trees`: its rows), as a table.
std::string trace_tree_vs_kernel(TracingRun& x, json& trees) {
  Record& rec = x.rec;
  const std::string& data = x.data;
  std::string md;
  std::cerr << "[report] tracing: Embree's tree through raybench's traversal\n";
  std::optional<TraceSession> session;  // made only when something is measured
  auto sess = [&]() -> TraceSession& {
    if (!session) session.emplace(rb::scene::load_scene(data + "stanford-bunny.obj"), "stanford-bunny.obj", 1, true, "auto", "embree");
    return *session;
  };
  md += "### Tree against kernel: Embree's tree through raybench's traversal (bunny, one thread, packets of 8)\n\n"
        "Embree's own builder (`rtcBuildBVH`, medium quality, leaves of at most 8, SAH block 8, the same SAH costs) makes the "
        "binary tree; raybench collapses it to its 8-wide nodes as it does its own and traces it with the same traversal and "
        "leaves. The speed difference between the two trees under one traversal is the tree's share of the gap to Embree; what "
        "remains between raybench on Embree's tree and Embree itself is the kernel's (traversal, node layout, leaf tests).\n\n"
        "| rays | SAH tree Mrays/s | Embree's tree Mrays/s | Embree Mrays/s (best mode) | nodes/ray SAH, Embree's | "
        "boxes/ray SAH, Embree's | prims/ray SAH, Embree's |\n|---|---:|---:|---:|---:|---:|---:|\n";
  for (const char* set : {"primary", "shadow", "diffuse", "random"}) {
    TraceRunOptions t = x.row(set, 8);
    t.builder = "embree";
    json j = rec.take(fmt::format("tracing/embree_tree/{}", set), [&] { return sess().run(t, true); });
    const json& st = j["sah_tree"];
    md += fmt::format("| {} | {} | {} | {} | {:.2f}, {:.2f} | {:.1f}, {:.1f} | {:.1f}, {:.1f} |\n", set, f2(st["mrays_per_s"]),
                      f2(j["mrays_per_s"]), f2(j["embree_mrays_per_s"]), st["nodes_per_ray"].get<double>(), j["nodes_per_ray"].get<double>(),
                      st["box_tests_per_ray"].get<double>(), j["box_tests_per_ray"].get<double>(), st["prim_tests_per_ray"].get<double>(),
                      j["prim_tests_per_ray"].get<double>());
    trees.push_back(j);
  }
  md += "\n";
  return md;
}

// Time per ray against primitive count, with build time and memory per primitive (`builds`: its
// rows), as a table.
std::string trace_by_size(TracingRun& x, json& builds) {
  const ReportOptions& o = x.o;
  Record& rec = x.rec;
  const std::string& data = x.data;
  std::string md;
  std::cerr << "[report] tracing: scenes by size\n";
  struct Src { std::string label; std::function<rb::scene::Scene()> make; };
  std::vector<Src> srcs;
  for (int k = 1; k <= (o.quick ? 1 : 5); ++k) srcs.push_back({fmt::format("spd:balls:{}", k), [k] { return rb::scene::generate_spd("balls", k); }});
  for (const char* d : {"dragon_vrip_res4_bin.ply", "dragon_vrip_res3_bin.ply", "dragon_vrip_res2_bin.ply"})
    if (!o.quick && fs::exists(data + d)) srcs.push_back({d, [data, d] { return rb::scene::load_scene(data + d); }});
  srcs.push_back({"stanford-bunny.obj", [data] { return rb::scene::load_scene(data + "stanford-bunny.obj"); }});
  if (!o.quick) srcs.push_back({height_field_label(), [] { return rb::scene::load_scene(height_field_source()); }});
  md += "### Scenes by size: primary rays, 8-wide, single rays, one thread\n\n"
        "| scene | primitives | raybench ns/ray | Embree ns/ray | raybench build ms | Embree build ms | raybench B/prim | Embree B/prim | "
        "mismatch vs Embree |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& src : srcs) {
    const json j = rec.take("tracing/by_size/" + src.label, [&] {
      TraceSession sess(src.make(), src.label, 1, true);
      return sess.run(x.row(), true);
    });
    const double ns = 1e3 / j["mrays_per_s"].get<double>();
    const json ens = j["embree_mrays_per_s"].is_null() ? json(nullptr) : json(1e3 / j["embree_mrays_per_s"].get<double>());
    md += fmt::format("| {} | {} | {:.1f} | {} | {:.1f} | {} | {:.1f} | {} | {} |\n", src.label, j["primitives"].get<std::size_t>(), ns,
                      ens.is_null() ? "-" : fmt::format("{:.1f}", ens.get<double>()), j["build_ms"].get<double>(), f2(j["embree_build_ms"]),
                      j["bytes_per_prim"].get<double>(), f2(j["embree_bytes_per_prim"]),
                      j["mismatch_rate"].is_null() ? "-" : fmt::format("{:.4f} %", 100 * j["mismatch_rate"].get<double>()));
    builds.push_back({{"scene", src.label}, {"primitives", j["primitives"]}, {"ns_per_ray", ns}, {"embree_ns_per_ray", ens},
                      {"build_ms", j["build_ms"]}, {"embree_build_ms", j["embree_build_ms"]}, {"bytes_per_prim", j["bytes_per_prim"]},
                      {"embree_bytes_per_prim", j["embree_bytes_per_prim"]}});
  }
  md += "\nBuild times are one-thread builds here (the bunny matrix above used two); raybench's memory is the wide nodes plus the "
        "leaf-ordered kernel batches with their ids, Embree's the bytes its memory monitor saw allocated by the scene commit.\n\n";
  md += "![time per ray against primitive count](trace_scaling.png)\n\n";
  return md;
}

}  // namespace

std::string report_section_tracing(const ReportOptions& o, Record& rec, const fs::path& out, json& summary) {
  const std::string data = data_dir() + "/meshes/";
  const std::size_t count = o.quick ? 1u << 12 : 1u << 18;
  // `raybench trace`'s protocol: 15 rounds of at least 0.05 s each. 7 rounds of 0.1 s took about as
  // long, but at 7 the sign test's interval is the whole range of the rounds' ratios, and one
  // disturbed round widened a row's interval to 10-30 % (docs/DESIGN.md).
  const TraceRunOptions defaults;
  const int reps = o.quick ? 1 : defaults.repetitions;
  const double min_time = o.quick ? 0.0 : defaults.min_time;
  TracingRun x{o, rec, data, count, reps, min_time};
  std::string md = "## Tracing whole scenes\n\n";
  md += "Goal: answer \"how many rays per second on my mesh, against Embree?\". One binned-SAH build (TBB) gives an "
        "8-wide BVH whose nodes hold their 8 child boxes as structure of arrays (one 8-lane slab test per node, in the FMA form "
        "t = box * (1/d) - o * (1/d) with o * (1/d) precomputed per ray); every leaf is one 8-slot lane group of its kind's "
        "kernel batch, reordered at build time, so a leaf is one call of the SIMD kernel (watertight triangle test for meshes) "
        "with 8 primitives in the lanes. Packets of 8 or 16 rays traverse the wide tree together with an active mask. "
        "A packet whose rays do not share a direction octant (diffuse and random rays) goes ray by ray: one at a time when "
        "its rays start near each other, two at a time (a node or a leaf of each in turn, so that one ray's memory loads "
        "overlap the other's work) when they start apart. "
        "Embree 3 runs in the same process on the same float triangles and rays (default build quality), with flush-to-zero and "
        "denormals-are-zero set in every thread of both. Its best mode is the yardstick: every row times Embree on a device with "
        "its native ISA (config \"\") and on one limited to AVX2 (`isa=avx2`, the ISA of raybench's kernels), with the call for "
        "the packet size (`rtcIntersect1`, `rtcIntersect8`, `rtcIntersect16`; `rtcOccluded*` for shadow rays), the coherent flag "
        "for primary and shadow rays, and quotes the faster; the Embree mode column names it. Rays Embree would reject never "
        "reach it (they are misses, as in raybench). The brute-force row is the lecture's loop over all objects on a prefix of the rays (it is "
        "also the correctness oracle). " + std::to_string(count) + " rays per set; after warm-up runs until the times settle (within "
        "5 % of the previous run), medians of " + std::to_string(reps) + " repetitions, each tracing the rays as often as makes it "
        "last " + fmt::format("{:g}", min_time) + " s or more, the engines alternating repetition by repetition (Embree's modes more than "
        "10 % slower than its fastest in the warm-up are left out of the rounds); a ratio to Embree is the median of the rounds' "
        "ratios with its 95 % interval (distribution-free, from the order statistics of the rounds' ratios). Repetitions above "
        "Tukey's fence are counted in tracing.json (`outliers`), never dropped.\n\n";
  md += "Goals, with the reason for each: (1) single rays and 8-ray packets at least as fast as Embree's matching call on every "
        "mesh and ray set, with one and two threads, because Embree is the yardstick users know; (2) 8-ray packets 1.2x Embree on "
        "primary and shadow rays, and large coherent packets 1.5x, because coherent rays are where a packet tracer earns its "
        "keep; (3) a build no slower than Embree's and no more memory per triangle, so that the speed is not bought with build "
        "cost; (4) two threads at least 1.8x one, so tracing scales on the machine; (5) under 0.01 % of rays disagreeing with "
        "Embree, so both engines answer the same question.\n\n";

  // 1. The matrix: three meshes x every ray set x packet size x thread count, each row raybench
  // and Embree on the same rays in the same run; builds timed at one and two threads.
  std::vector<TracedMesh> meshes;
  meshes.push_back({"stanford-bunny.obj", [data] { return rb::scene::load_scene(data + "stanford-bunny.obj"); }});
  if (!o.quick && fs::exists(data + "dragon_vrip_res2_bin.ply"))
    meshes.push_back({"dragon_vrip_res2_bin.ply", [data] { return rb::scene::load_scene(data + "dragon_vrip_res2_bin.ply"); }});
  if (!o.quick) meshes.push_back({height_field_label(), [] { return rb::scene::load_scene(height_field_source()); }});
  const std::vector<int> packets{1, 8, 16, kLargePacket};
  md += fmt::format("### The matrix: every ray set, packet size and thread count\n\nPacket sizes: 1 (single rays), 8 and 16 "
                    "(one packet traverses the tree under an active mask), {} (a large coherent packet: an 8x8 block of the "
                    "image, with a frustum test of the node's children before any per-ray test). Embree answers each row in its best "
                    "mode for that packet size (its 1-, 8- and 16-ray calls, `rtcIntersect1M` streams for the large packets; "
                    "native ISA or AVX2, whichever is faster), named in the row. The third mesh is generated: the scene source "
                    "`{}` (a wavy height field, the size of a large scan), so `raybench trace {} ...` reproduces its rows. "
                    "Coherent packets of 16 and {} rays (primary and shadow rays) walk in groups of 16 rays in one AVX-512 "
                    "register where the CPU has it (the node test stays the 8-lane one; the groups' box tests, the triangle test "
                    "with 16 rays in lanes and the packet's bookkeeping take 16 lanes), with the same packets in groups of 8 AVX2 "
                    "lanes timed beside them in the same rounds (`raybench trace --isa both`): the column \"raybench's lanes\" "
                    "gives the 16-lane walk over the 8-lane one, and the row's raybench figures are the 16-lane walk's. Other "
                    "rows name the lanes their packets walked in (diffuse and random rays share no octant and walk one or two "
                    "at a time).\n\n",
                    kLargePacket, height_field_source(), height_field_source(), kLargePacket);
  for (const auto& m : meshes) md += trace_matrix_mesh(x, m, packets);
  md += "![Mrays/s per ray set, both engines](trace_matrix.png)\n\n";

  json goal_rows = json::array(), trees = json::array(), builds = json::array();
  md += trace_goals({x.rows, x.sorted, x.matrix_builds, x.scaling, x.reps}, goal_rows);
  md += trace_tree_vs_kernel(x, trees);
  md += trace_by_size(x, builds);
  summary["tracing"] = {{"matrix", x.rows},   {"sorted", x.sorted}, {"builds", x.matrix_builds}, {"thread_scaling", x.scaling},
                        {"by_size", builds}, {"goals", goal_rows}, {"tree_vs_kernel", trees}};
  write_output((out / "tracing.json").string(), summary["tracing"].dump(2) + "\n");
  md += "Raw rows: [tracing.json](tracing.json).\n\n";
  return md;
}

}  // namespace rb::app
