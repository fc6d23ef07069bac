#include "apps/trace_run.hpp"

#include "apps/cli.hpp"
#include "apps/progress.hpp"
#include "apps/stats.hpp"
#include "scene/sources.hpp"

#include <fmt/format.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace rb::app {

using nlohmann::json;

TraceSession::TraceSession(rb::scene::Scene s, std::string source, int build_threads, bool embree, const std::string& model)
    : scene_(std::move(s)), source_(std::move(source)) {
  const tracer::Plan plan = tracer::make_plan(scene_, tracer::parse_model(model));
  trace::ThreadScope ts(build_threads);
  ts.run([&] { accel_ = tracer::SceneAccel::build(scene_, plan); });
  if (embree) embree_ = trace::embree_build(accel_, build_threads);
  else embree_.why = "skipped (--no-embree)";
}

const RaySoA& TraceSession::rays(trace::RaySet set, std::size_t count, std::uint64_t seed, trace::RaySetInfo& info) {
  const std::string key = fmt::format("{}/{}/{}", int(set), count, seed);
  auto it = rays_.find(key);
  if (it == rays_.end()) {
    trace::RaySetInfo inf;
    RaySoA r = trace::make_rays(scene_, accel_, set, count, seed, &inf);
    it = rays_.emplace(key, std::make_pair(std::move(r), inf)).first;
  }
  info = it->second.second;
  return it->second.first;
}

json TraceSession::build_json() const {
  const auto& st = accel_.bin.stats;
  json hist = json::array();
  for (std::size_t n = 1; n < st.leaf_hist.size(); ++n) hist.push_back(st.leaf_hist[n]);
  const double prims = double(std::max<std::size_t>(1, accel_.scene_prims()));
  json j{{"model", tracer::model_name(accel_.plan().model)},
         {"frame", tracer::frame_name(accel_.plan().frame)},
         {"build_ms", accel_.build_ms},
         {"sah_build_ms", st.build_ms},
         {"reorder_ms", accel_.reorder_ms},
         {"collapse_ms", accel_.wide.collapse_ms},
         {"nodes_binary", accel_.bin.nodes.size()},
         {"nodes_wide", accel_.wide.nodes.size()},
         {"depth_wide", accel_.wide.depth},
         {"leaves", st.leaves},
         {"depth", st.depth},
         {"sah_cost", st.sah_cost},
         {"leaf_size_histogram", hist},
         {"bytes", accel_.bytes()},
         {"bytes_per_prim", double(accel_.bytes()) / prims},
         {"embree", embree_.ok},
         {"embree_why", embree_.why},
         {"embree_build_ms", embree_.ok ? json(embree_.build_ms) : json(nullptr)},
         {"embree_bvh_bytes", embree_.ok ? json(embree_.bvh_bytes) : json(nullptr)},
         {"embree_bytes_per_prim", embree_.ok ? json(double(embree_.bvh_bytes) / prims) : json(nullptr)}};
  return j;
}

json TraceSession::run(const TraceRunOptions& o, bool progress) {
  const trace::RaySet set = trace::parse_ray_set(o.ray_set);
  trace::RaySetInfo info;
  const RaySoA& rays = this->rays(set, o.count, o.seed, info);
  const std::size_t n = rays.count;
  const bool any = set == trace::RaySet::shadow;
  tracer::TraceOptions to;
  to.packet = o.packet;
  to.any = any;
  if (o.slab != "plan") {
    to.slab_given = true;
    to.slab = o.slab == "conservative" ? bvh::Slab::conservative : o.slab == "fast" ? bvh::Slab::fast : bvh::Slab::robust;
  }
  const bvh::Slab slab = to.slab_given ? to.slab : accel_.plan().slab;

  trace::ThreadScope ts(o.threads);
  const int runs = std::max(0, o.warmup) + o.repetitions;
  const int steps = runs * (embree_.ok ? 2 : 1) + 2;
  int step = 0;
  ProgressBar bar(fmt::format("trace {} {}", source_, o.ray_set), progress ? ProgressBar::Mode::automatic : ProgressBar::Mode::off);
  auto tick = [&](int, int) { bar.update(double(++step) / steps); };

  std::vector<bvh::HitRec> ours, theirs;
  const std::size_t tile = 256;
  trace::Tracer mine = [&](std::size_t b, std::size_t e, bvh::HitRec* out) { accel_.trace(rays, b, e, out, to); };
  const bool coherent = o.packet > 1 && (set == trace::RaySet::primary || set == trace::RaySet::shadow);
  trace::Tracer theirs_t = [&](std::size_t b0, std::size_t e0, bvh::HitRec* out) {
    trace::embree_trace(*embree_.scene, rays, b0, e0, out, any, o.packet, coherent);
  };
  // Warm-up runs first (caches, page faults, the thread pool's start; not in the median), then the
  // two engines alternate run by run, so that a change in the machine's load falls on both alike.
  std::vector<double> secs, es;
  for (int r = 0; r < runs; ++r) {
    const double s = trace::time_runs(ts, mine, n, ours, 1, tile, tick).front();
    if (r >= o.warmup) secs.push_back(s);
    if (!embree_.ok) continue;
    const double e = trace::time_runs(ts, theirs_t, n, theirs, 1, tile, tick).front();
    if (r >= o.warmup) es.push_back(e);
  }
  const double mrays = double(n) / trace::median(secs) / 1e6;
  // Spread of the timed runs: the range in Mrays/s and the coefficient of variation of the times.
  auto spread = [&](json& j, const std::string& prefix, const std::vector<double>& t) {
    const stats::Summary sm = stats::summarize(t);
    j[prefix + "mrays_per_s_min"] = double(n) / sm.max / 1e6;
    j[prefix + "mrays_per_s_max"] = double(n) / sm.min / 1e6;
    j[prefix + "cv"] = std::isfinite(sm.cv) ? json(sm.cv) : json(nullptr);
  };

  // Traversal cost per ray (one extra single-threaded counted pass, not timed).
  bvh::TraceCounters cnt;
  {
    std::vector<bvh::HitRec> tmp(rays.size());
    ts.run([&] { accel_.trace_counted(rays, 0, rays.size(), tmp.data(), to, cnt); });
    tick(0, 0);
  }

  json j;
  j["scene"] = source_;
  j["primitives"] = accel_.scene_prims();
  j["rays"] = n;
  j["ray_set"] = o.ray_set;
  j["camera"] = info.camera;
  j["light"] = info.light;
  j["seed"] = o.seed;
  j["threads"] = o.threads;
  j["packet"] = o.packet;
  j["slab"] = bvh::slab_name(slab);
  j["repetitions"] = o.repetitions;
  j["warmup"] = o.warmup;
  j["mrays_per_s"] = mrays;
  j["seconds"] = secs;
  spread(j, "", secs);
  j["nodes_per_ray"] = double(cnt.nodes) / double(std::max<std::size_t>(1, n));
  j["box_tests_per_ray"] = double(cnt.boxes) / double(std::max<std::size_t>(1, n));
  j["prim_tests_per_ray"] = double(cnt.prims) / double(std::max<std::size_t>(1, n));
  std::size_t hits = 0;
  for (std::size_t i = 0; i < n; ++i) hits += ours[i].prim != bvh::kNoPrim;
  j["hit_fraction"] = double(hits) / double(std::max<std::size_t>(1, n));
  // Every ray's answer (primitive and the bits of t) in one FNV-1a digest: the same for any thread
  // count, packet size and schedule (docs/DESIGN.md section 19).
  {
    std::uint64_t d = 1469598103934665603ull;
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t tb;
      std::memcpy(&tb, &ours[i].t, sizeof tb);
      for (const std::uint32_t v : {ours[i].prim, tb})
        for (int k = 0; k < 4; ++k) d = (d ^ ((v >> (8 * k)) & 0xFFu)) * 1099511628211ull;
    }
    j["hits_fnv1a"] = fmt::format("{:016x}", d);
  }
  const json b = build_json();
  for (auto it = b.begin(); it != b.end(); ++it) j[it.key()] = it.value();

  if (embree_.ok) {
    j["embree_mrays_per_s"] = double(n) / trace::median(es) / 1e6;
    j["embree_seconds"] = es;
    spread(j, "embree_", es);
    j["embree_call"] = std::string(any ? (o.packet == 1 ? "rtcOccluded1" : "rtcOccluded8") : (o.packet == 1 ? "rtcIntersect1" : "rtcIntersect8")) +
                       (o.packet == 16 ? " x2" : "") + (coherent ? " coherent" : "");
    const trace::Compare c = trace::compare(ours, theirs, n, any);
    j["mismatch_rate"] = c.rate();
    j["mismatches"] = c.mismatches;
    j["other_prim_same_t"] = c.other_prim;
    j["mismatch_tolerance"] = "hit vs miss, or |t1 - t2| > 1e-4 max(1, |t|)";
  } else {
    j["embree_mrays_per_s"] = nullptr;
    j["mismatch_rate"] = nullptr;
  }

  // The brute-force loop over all objects on a prefix of the rays: the oracle and the baseline.
  std::size_t nb = 0;
  if (o.brute_rays < 0) nb = std::min<std::size_t>(n, std::max<std::size_t>(64, std::size_t(4e8 / double(std::max<std::size_t>(1, accel_.scene_prims())))));
  else nb = std::min<std::size_t>(n, std::size_t(o.brute_rays));
  nb = nb / 16 * 16;
  if (nb > 0) {
    std::vector<bvh::HitRec> brute(nb);
    const auto t0 = std::chrono::steady_clock::now();
    ts.parallel_for(nb, 16, [&](std::size_t i) { brute[i] = accel_.brute_force(rays.get(i), any); });
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const trace::Compare c = trace::compare(ours, brute, nb, any);
    j["brute_rays"] = nb;
    j["brute_mrays_per_s"] = double(nb) / s / 1e6;
    j["brute_mismatch_rate"] = c.rate();
    j["brute_mismatches"] = c.mismatches;
  } else {
    j["brute_rays"] = 0;
    j["brute_mrays_per_s"] = nullptr;
    j["brute_mismatch_rate"] = nullptr;
  }
  tick(0, 0);
  bar.done();
  return j;
}

json run_trace(const TraceRunOptions& o, bool progress) {
  const auto t0 = std::chrono::steady_clock::now();
  rb::scene::Scene s = rb::scene::load_scene(o.scene);
  if (s.primitive_count() == 0) throw NothingToDo("the scene has no primitives: nothing to trace");
  const double load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  TraceSession session(std::move(s), o.scene, o.threads, o.embree, o.model);
  json j = session.run(o, progress);
  j["load_ms"] = load_ms;
  return j;
}

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
  o += fmt::format("build      raybench {:.1f} ms (SAH {:.1f}, reorder {:.1f}, collapse {:.1f}); Embree {} ms\n", j["build_ms"].get<double>(),
                   j["sah_build_ms"].get<double>(), j["reorder_ms"].get<double>(), j["collapse_ms"].get<double>(),
                   num_or_dash(j["embree_build_ms"], "{:.1f}"));
  o += fmt::format("bvh        {} binary nodes, {} wide nodes, {} leaves (sizes 1..8: {}), depth {}, SAH cost {:.2f}\n",
                   j["nodes_binary"].get<std::size_t>(), j["nodes_wide"].get<std::size_t>(), j["leaves"].get<std::size_t>(), hist,
                   j["depth"].get<int>(), j["sah_cost"].get<double>());
  o += fmt::format("memory     raybench {:.1f} B/prim (8-wide nodes + leaf-ordered batches); Embree {} B/prim (BVH)\n",
                   j["bytes_per_prim"].get<double>(), num_or_dash(j["embree_bytes_per_prim"], "{:.1f}"));
  o += fmt::format("model      {} (frame {}; `raybench plan` explains the choices)\n", j["model"].get<std::string>(), j["frame"].get<std::string>());
  // The median with its range and coefficient of variation over the timed runs (after the warm-up).
  auto timing = [&](const std::string& p) {
    return fmt::format("{:.2f} Mrays/s (median of {}, range {:.2f}-{:.2f}{})", j[p + "mrays_per_s"].get<double>(), j["repetitions"].get<int>(),
                       j[p + "mrays_per_s_min"].get<double>(), j[p + "mrays_per_s_max"].get<double>(),
                       j[p + "cv"].is_null() ? "" : fmt::format(", CV {:.1f} %", 100 * j[p + "cv"].get<double>()));
  };
  o += fmt::format("trace      raybench packet {}, {} thread(s), {} slab test, {} warm-up run(s):\n", j["packet"].get<int>(),
                   j["threads"].get<int>(), j["slab"].get<std::string>(), j["warmup"].get<int>());
  o += "           " + timing("") + "\n";
  o += fmt::format("           {:.2f} nodes, {:.2f} box tests, {:.2f} primitive tests per ray\n", j["nodes_per_ray"].get<double>(),
                   j["box_tests_per_ray"].get<double>(), j["prim_tests_per_ray"].get<double>());
  if (!j["embree_mrays_per_s"].is_null()) {
    o += fmt::format("           Embree {}, runs alternating with raybench's:\n           {}\n", j["embree_call"].get<std::string>(),
                     timing("embree_"));
    o += fmt::format("           raybench / Embree = {:.2f}\n", j["mrays_per_s"].get<double>() / j["embree_mrays_per_s"].get<double>());
    o += fmt::format("mismatch   {:.4f}% ({} of {} rays; {} hits at the same t on another primitive)\n", 100 * j["mismatch_rate"].get<double>(),
                     j["mismatches"].get<std::size_t>(), j["rays"].get<std::size_t>(), j["other_prim_same_t"].get<std::size_t>());
  } else {
    o += fmt::format("           Embree: {}\n", j["embree_why"].get<std::string>());
  }
  if (!j["brute_mrays_per_s"].is_null())
    o += fmt::format("brute      loop over all objects on {} rays: {:.4f} Mrays/s, {} mismatches against the BVH\n",
                     j["brute_rays"].get<std::size_t>(), j["brute_mrays_per_s"].get<double>(), j["brute_mismatches"].get<std::size_t>());
  return o;
}

}  // namespace rb::app
