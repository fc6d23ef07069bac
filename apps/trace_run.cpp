// A `raybench trace` run: the session (scene, plan, trees, Embree), its ray sets, the timing protocol,
// the build timings; the result as JSON (its table: apps/trace_text.cpp).
#include "apps/trace_run.hpp"

#include "apps/cli.hpp"
#include "apps/progress.hpp"
#include "apps/results/stats.hpp"
#include "apps/trace_protocol.hpp"
#include "core/median.hpp"
#include "bench/embree_build.hpp"
#include "scene/sources.hpp"
#include "tracer/ray_order.hpp"
#include "tracer/simd16.hpp"

#include <fmt/format.h>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <optional>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace rb::app {

using nlohmann::json;

TraceSession::TraceSession(rb::scene::Scene s, std::string source, int build_threads, bool embree, const std::string& model,
                           const std::string& builder)
    : scene_(std::move(s)), source_(std::move(source)), builder_(builder) {
  const tracer::Plan plan = tracer::make_plan(scene_, tracer::parse_model(model));
  trace::ThreadScope ts(build_threads);
  const tracer::BinaryBuilder bb = trace::embree_builder(builder, scene_, plan, build_threads);
  ts.run([&] { accel_ = tracer::SceneAccel::build(scene_, plan, {}, bb); });
  if (bb) ts.run([&] { sah_.emplace(tracer::SceneAccel::build(scene_, plan)); });
  if (embree) embree_ = trace::embree_build(accel_, build_threads);
  else embree_.why = "skipped (--no-embree)";
}

const RaySoA& TraceSession::rays(tracer::RaySet set, std::size_t count, std::uint64_t seed, tracer::RaySetInfo& info) {
  const std::string key = fmt::format("{}/{}/{}", int(set), count, seed);
  auto it = rays_.find(key);
  if (it == rays_.end()) {
    tracer::RaySetInfo inf;
    RaySoA r = tracer::make_rays(scene_, accel_, set, count, seed, &inf);
    it = rays_.emplace(key, std::make_pair(std::move(r), inf)).first;
  }
  info = it->second.second;
  return it->second.first;
}

namespace {
// The plan's kinds, each with the batch its primitives stored apart took in this tree: its bytes,
// and how many stayed in double (leaves that no origin of their own holds in float).
json apart_kinds(const tracer::SceneAccel& a) {
  json kinds = a.plan().json()["kinds"];
  for (auto& k : kinds)
    for (int i = 0; i < tracer::kKinds; ++i)
      if (!k["split"].is_null() && k["kind"] == kinds::kind_name(tracer::Kind(i))) {
        k["split"]["bytes"] = a.apart_bytes(tracer::Kind(i));
        k["split"]["in_double"] = a.apart_deep(tracer::Kind(i));
      }
  return kinds;
}
}  // namespace

json TraceSession::build_json() const {
  const auto& st = accel_.bin.stats;
  json hist = json::array();
  for (std::size_t n = 1; n < st.leaf_hist.size(); ++n) hist.push_back(st.leaf_hist[n]);
  const double prims = double(std::max<std::size_t>(1, accel_.scene_prims()));
  json j{{"builder", builder_},
         {"model", tracer::model_name(accel_.plan().model)},
         {"frame", tracer::frame_name(accel_.plan().frame)},
         {"plan_kinds", apart_kinds(accel_)},  // each kind's method, storage and classes, and what it stores apart
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
  if (embree_.ok) {
    const auto& nat = embree_.devices[std::size_t(trace::EmbreeIsa::native)];
    const auto& avx2 = embree_.devices[std::size_t(trace::EmbreeIsa::avx2)];
    j["embree_native_isa"] = nat.isa;
    j["embree_avx2_isa"] = avx2.isa;
    j["embree_native_config"] = nat.config;
    j["embree_avx2_config"] = avx2.config;
    j["embree_avx2_build_ms"] = avx2.build_ms;
  }
  if (sah_) {
    const auto& ss = sah_->bin.stats;
    j["sah_tree"] = {{"build_ms", sah_->build_ms}, {"nodes_binary", sah_->bin.nodes.size()}, {"nodes_wide", sah_->wide.nodes.size()},
                     {"depth_wide", sah_->wide.depth}, {"leaves", ss.leaves}, {"depth", ss.depth}, {"sah_cost", ss.sah_cost},
                     {"bytes_per_prim", double(sah_->bytes()) / prims}};
  }
  return j;
}

namespace {

// Spread of timed runs (seconds per pass over n rays): the range in Mrays/s and the coefficient of
// variation of the times, under `prefix`.
void put_spread(json& j, const std::string& prefix, const std::vector<double>& t, std::size_t n) {
  const stats::Summary sm = stats::summarize(t);
  j[prefix + "mrays_per_s_min"] = double(n) / sm.max / 1e6;
  j[prefix + "mrays_per_s_max"] = double(n) / sm.min / 1e6;
  j[prefix + "cv"] = std::isfinite(sm.cv) ? json(sm.cv) : json(nullptr);
}

// Every ray's answer in one FNV-1a digest: the same for any thread count, packet size and
// schedule (docs/DESIGN.md sections 12 and 19). A closest hit's answer is its primitive and the
// bits of its t; an any-hit (shadow) ray's is whether it is blocked, since which blocker it meets
// first depends on the order of the walk.
std::string hits_digest(const std::vector<bvh::HitRec>& ours, std::size_t n, bool any) {
  std::uint64_t d = 1469598103934665603ull;
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t tb;
    std::memcpy(&tb, &ours[i].t, sizeof tb);
    const std::uint32_t prim = any ? std::uint32_t(ours[i].prim != bvh::kNoPrim) : ours[i].prim;
    if (any) tb = 0;
    for (const std::uint32_t v : {prim, tb})
      for (int k = 0; k < 4; ++k) d = (d ^ ((v >> (8 * k)) & 0xFFu)) * 1099511628211ull;
  }
  return fmt::format("{:016x}", d);
}

// Per round, one thread's seconds averaged over the CPUs it ran on (the harmonic mean of the rates,
// as seconds): `on[c][r]`, CPU c, round r.
std::vector<double> averaged_over_cpus(const std::vector<std::vector<double>>& on) {
  std::vector<double> one(on.empty() ? 0 : on[0].size());
  for (std::size_t r = 0; r < one.size(); ++r) {
    double inv = 0;
    for (const auto& c : on) inv += 1 / c[r];
    one[r] = double(on.size()) / inv;
  }
  return one;
}

// An engine timed beside ours in the same rounds: its rate, ours over it or it over ours (the
// median of the rounds' ratios, 95 % interval) and the rays whose hits differ from ours.
void put_beside(json& w, const std::vector<double>& s, const char* ratio_key, const stats::RatioInterval& r,
                const std::vector<bvh::HitRec>& ours, const std::vector<bvh::HitRec>& its_hits, std::size_t n, bool any) {
  w["mrays_per_s"] = double(n) / rb::median(s) / 1e6;
  w["seconds"] = s;
  put_spread(w, "", s, n);
  w[ratio_key] = stats::interval_json(r);
  w["mismatches"] = tracer::compare(ours, its_hits, n, any).mismatches;
}

// --threads-beside: the same packets on the other thread count (the last engine beside ours), its
// speed-up over this run's threads (over one thread's rate averaged over the CPUs it took turns
// on, where it did), and Embree's control: its fastest mode on both thread counts in the same
// rounds, its one thread averaged over the CPUs alike: what this machine gave a second thread.
void put_threads_beside(json& w, int threads, const Timings& tm, const std::vector<trace::EmbreeMode>& modes,
                        const std::vector<bvh::HitRec>& ours, const std::vector<bvh::HitRec>& its_hits, std::size_t n, bool any) {
  const std::vector<double>& st = tm.beside.back();
  w["threads"] = threads;
  if (tm.cpus.empty()) {
    put_beside(w, st, "speedup", stats::paired_ratio(tm.ours, st), ours, its_hits, n, any);
  } else {
    const std::vector<double> one = averaged_over_cpus(tm.ours_on);
    put_beside(w, st, "speedup", stats::paired_ratio(one, st), ours, its_hits, n, any);
    w["one_thread_cpus"] = tm.cpus;
    w["one_thread_mrays_per_s"] = double(n) / rb::median(one) / 1e6;
    json& by = w["one_thread_mrays_per_s_by_cpu"];
    by = json::array();
    for (const auto& on : tm.ours_on) by.push_back(double(n) / rb::median(on) / 1e6);
    w["one_thread_seconds_by_cpu"] = tm.ours_on;
  }
  if (tm.mode_beside_seconds.empty()) return;
  const std::vector<double> one = tm.mode_on.empty() ? tm.modes[tm.mode_beside] : averaged_over_cpus(tm.mode_on);
  const std::vector<double>& more = tm.mode_beside_seconds;
  w["embree"] = {{"mode", modes[tm.mode_beside].name(any)},
                 {"mrays_per_s", double(n) / rb::median(more) / 1e6},
                 {"one_thread_mrays_per_s", double(n) / rb::median(one) / 1e6},
                 {"seconds", more},
                 {"speedup", stats::interval_json(stats::paired_ratio(one, more))}};
  if (!tm.mode_on.empty()) w["embree"]["one_thread_seconds_by_cpu"] = tm.mode_on;
}

// Embree's figures: every mode (its median where it was timed, its warm-up rate where it was not),
// the fastest timed mode as the yardstick, the rays the engines disagree on, and raybench / Embree
// round by round with its interval.
void put_embree(json& j, const trace::EmbreeBuild& embree, const std::vector<trace::EmbreeMode>& modes, const Timings& tm,
                const std::vector<bvh::HitRec>& ours, const std::vector<std::vector<bvh::HitRec>>& theirs, std::size_t n, bool any) {
  const std::vector<double>& secs = tm.ours;
  const std::vector<std::vector<double>>& warm_modes = tm.warm_modes;
  const std::vector<std::vector<double>>& es = tm.modes;
  auto spread = [&](json& row, const std::string& prefix, const std::vector<double>& t) { put_spread(row, prefix, t, n); };
  if (embree.ok) {
    // Every mode's median; the fastest is the yardstick.
    json ms = json::array();
    std::size_t best = 0;
    double best_mr = -1, native_best = -1, avx2_best = -1;
    for (std::size_t m = 0; m < modes.size(); ++m) {
      const tracer::Compare c = tracer::compare(ours, theirs[m], n, any);
      const auto& dev = embree.devices[std::size_t(modes[m].isa)];
      json row{{"mode", modes[m].name(any)}, {"call", modes[m].call_name(any)}, {"device", trace::embree_isa_label(modes[m].isa)},
               {"config", dev.config}, {"isa", dev.isa}, {"coherent", modes[m].coherent}, {"mismatches", c.mismatches},
               {"warmup_mrays_per_s", double(n) / warm_modes[m].back() / 1e6}, {"timed", !es[m].empty()}};
      if (es[m].empty()) {  // clearly slower in the warm-up: not timed in the rounds
        ms.push_back(row);
        continue;
      }
      const double mr = double(n) / rb::median(es[m]) / 1e6;
      row["mrays_per_s"] = mr;
      row["seconds"] = es[m];
      spread(row, "", es[m]);
      ms.push_back(row);
      if (mr > best_mr) { best_mr = mr; best = m; }
      double& slot = modes[m].isa == trace::EmbreeIsa::native ? native_best : avx2_best;
      slot = std::max(slot, mr);
    }
    const auto& bdev = embree.devices[std::size_t(modes[best].isa)];
    j["embree_modes"] = ms;
    j["embree_mrays_per_s"] = best_mr;
    j["embree_native_mrays_per_s"] = native_best > 0 ? json(native_best) : json(nullptr);
    j["embree_avx2_mrays_per_s"] = avx2_best > 0 ? json(avx2_best) : json(nullptr);
    j["embree_mode"] = modes[best].name(any);
    j["embree_call"] = modes[best].call_name(any);
    j["embree_isa"] = bdev.isa;
    j["embree_device_config"] = bdev.config;
    j["embree_seconds"] = es[best];
    spread(j, "embree_", es[best]);
    const tracer::Compare c = tracer::compare(ours, theirs[best], n, any);
    j["mismatch_rate"] = c.rate();
    j["mismatches"] = c.mismatches;
    j["other_prim_same_t"] = c.other_prim;
    j["mismatch_tolerance"] = "hit vs miss, or |t1 - t2| > 1e-4 max(1, |t|)";
    // raybench's speed over Embree's best mode, round by round (Embree's time over ours), with its
    // 95 % interval.
    j["vs_embree"] = stats::interval_json(stats::paired_ratio(es[best], secs));
  } else {
    j["embree_mrays_per_s"] = nullptr;
    j["mismatch_rate"] = nullptr;
    j["vs_embree"] = nullptr;
  }

}

// --order sorted: the sort's own time (median of 5, outside the rounds; inside every timed pass
// too), and Embree's fastest mode on the sorted order with raybench over it round by round.
void put_sorted(json& j, trace::ThreadScope& ts, const std::function<void()>& sort, const std::string& key, const trace::EmbreeBuild& embree,
                const std::vector<trace::EmbreeMode>& modes, const Timings& tm, const std::vector<bvh::HitRec>& ours,
                const std::vector<std::vector<bvh::HitRec>>& theirs_sorted, std::size_t n, bool any) {
  std::vector<double> sort_s;
  for (int r = 0; r < 5; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    sort();
    sort_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  (void)ts;
  j["sort_ms"] = 1e3 * rb::median(sort_s);
  j["sort_key"] = key;
  if (!embree.ok) {
    j["embree_sorted"] = nullptr;
    return;
  }
  std::size_t best = modes.size();
  double best_mr = -1;
  for (std::size_t m = 0; m < modes.size(); ++m) {
    const std::vector<double>& es = tm.modes[modes.size() + m];
    if (es.empty()) continue;
    const double mr = double(n) / rb::median(es) / 1e6;
    if (mr > best_mr) best_mr = mr, best = m;
  }
  if (best == modes.size()) {
    j["embree_sorted"] = nullptr;
    return;
  }
  const std::vector<double>& es = tm.modes[modes.size() + best];
  const tracer::Compare c = tracer::compare(ours, theirs_sorted[best], n, any);
  j["embree_sorted"] = {{"mode", modes[best].name(any)}, {"device", trace::embree_isa_label(modes[best].isa)},
                        {"mrays_per_s", best_mr}, {"seconds", es}, {"mismatches", c.mismatches},
                        {"vs_embree_sorted", stats::interval_json(stats::paired_ratio(es, tm.ours))}};
}

// The brute-force loop over all objects on a prefix of the rays (`brute_rays`; -1: a budget by
// the scene's size): the oracle and the baseline.
void put_brute(json& j, const tracer::SceneAccel& accel, trace::ThreadScope& ts, const RaySoA& rays, const std::vector<bvh::HitRec>& ours,
               long long brute_rays, bool any) {
  const std::size_t n = rays.count;
  std::size_t nb = 0;
  if (brute_rays < 0) nb = std::min<std::size_t>(n, std::max<std::size_t>(64, std::size_t(4e8 / double(std::max<std::size_t>(1, accel.scene_prims())))));
  else nb = std::min<std::size_t>(n, std::size_t(brute_rays));
  nb = nb / 16 * 16;
  if (nb > 0) {
    std::vector<bvh::HitRec> brute;
    const double s = trace::time_brute_force(ts, accel, rays, nb, any, brute);
    const tracer::Compare c = tracer::compare(ours, brute, nb, any);
    j["brute_rays"] = nb;
    j["brute_mrays_per_s"] = double(nb) / s / 1e6;
    j["brute_mismatch_rate"] = c.rate();
    j["brute_mismatches"] = c.mismatches;
  } else {
    j["brute_rays"] = 0;
    j["brute_mrays_per_s"] = nullptr;
    j["brute_mismatch_rate"] = nullptr;
  }
}

// Traversal cost per ray: nodes visited, box and primitive tests.
void put_cost(json& j, const bvh::TraceCounters& c, std::size_t n) {
  const double rays = double(std::max<std::size_t>(1, n));
  j["nodes_per_ray"] = double(c.nodes) / rays;
  j["box_tests_per_ray"] = double(c.boxes) / rays;
  j["prim_tests_per_ray"] = double(c.prims) / rays;
}

// The SAH tree traced beside the tree of Embree's builder (--builder embree): its rate, its cost
// per ray (one counted pass, not timed) and the rays whose hits differ from the builder tree's.
void put_sah_tree(json& t, const tracer::SceneAccel& sah, trace::ThreadScope& ts, const RaySoA& rays, const tracer::TraceOptions& to,
                  const std::vector<double>& secs, const std::vector<bvh::HitRec>& ours, const std::vector<bvh::HitRec>& sah_out,
                  bool any) {
  const std::size_t n = rays.count;
  bvh::TraceCounters sc;
  std::vector<bvh::HitRec> tmp(rays.size());
  ts.run([&] { sah.trace_counted(rays, 0, rays.size(), tmp.data(), to, sc); });
  t["mrays_per_s"] = double(n) / rb::median(secs) / 1e6;
  t["seconds"] = secs;
  put_spread(t, "", secs, n);
  put_cost(t, sc, n);
  t["mismatches_vs_builder_tree"] = tracer::compare(ours, sah_out, n, any).mismatches;
}

}  // namespace

// --isa: the lanes per group of a packet's rays asked for (tracer::TraceOptions::lanes).
int trace_lanes(const std::string& isa) {
  const bool can = tracer::simd16_traversal_runs();
  if (isa == "avx2") return 8;
  if (isa == "avx512" && !can)
    throw std::invalid_argument(tracer::simd16_traversal_built() ? "--isa avx512: this CPU lacks AVX-512 F, CD, DQ, BW or VL"
                                                                 : "--isa avx512: this build has no 16-lane traversal (the debug preset, or a "
                                                                   "compiler that cannot target AVX-512)");
  return can ? 16 : 8;
}

json TraceSession::run(const TraceRunOptions& o, bool progress) {
  const tracer::RaySet set = tracer::parse_ray_set(o.ray_set);
  tracer::RaySetInfo info;
  const RaySoA& rays = this->rays(set, o.count, o.seed, info);
  const std::size_t n = rays.count;
  const bool any = set == tracer::RaySet::shadow;
  tracer::TraceOptions to;
  to.packet = o.packet;
  to.any = any;
  to.lanes = trace_lanes(o.isa);
  if (o.slab != "plan") {
    to.slab_given = true;
    to.slab = o.slab == "conservative" ? bvh::Slab::conservative : o.slab == "fast" ? bvh::Slab::fast : bvh::Slab::robust;
  }
  const bvh::Slab slab = to.slab_given ? to.slab : accel_.plan().slab;

  trace::ThreadScope ts(o.threads);
  // Embree: every call it offers for this packet size, on the native and the AVX2 device; the
  // coherent flag for the coherent sets (primary and shadow rays), incoherent for the others.
  const bool coherent = set == tracer::RaySet::primary || set == tracer::RaySet::shadow;
  const std::vector<trace::EmbreeMode> modes = embree_.ok ? trace::embree_modes(o.packet, coherent) : std::vector<trace::EmbreeMode>{};
  ProgressBar bar(fmt::format("trace {} {}", source_, o.ray_set), progress ? ProgressBar::Mode::automatic : ProgressBar::Mode::off);

  std::vector<bvh::HitRec> ours, sah_out;
  std::vector<std::vector<bvh::HitRec>> theirs(modes.size());
  // --order sorted: every pass of every engine sorts the stream (its origins quantised in the
  // scene's box), traces the sorted rays and puts the hits back in the given order.
  const bool sorted = o.order == "sorted";
  if (sorted && sah_) throw std::invalid_argument("--order sorted traces raybench's own tree: leave --builder at sah");
  tracer::RayOrder order;
  const scene::Bounds box = scene_.bounds();
  const Vec3f lo = accel_.to_frame(box.lo), hi = accel_.to_frame(box.hi);
  // The key by how raybench traces the sorted rays (one by one, or in packets sharing an octant);
  // Embree traces the same order.
  const tracer::RayKey::Layout layout = tracer::RayKey::layout_for(o.packet);
  auto sort = [&] { order.sort(rays, lo, hi, ts, layout); };
  std::vector<std::vector<bvh::HitRec>> sorted_hits(sorted ? 1 + modes.size() : 0), theirs_sorted(sorted ? modes.size() : 0);
  Engine mine{[&](std::size_t b, std::size_t e, bvh::HitRec* out) { accel_.trace(rays, b, e, out, to); }, &ours};
  if (sorted) {
    mine.trace = [&](std::size_t b, std::size_t e, bvh::HitRec*) { accel_.trace(order.sorted(), b, e, sorted_hits[0].data(), to); };
    mine.before = [&] { sort(); sorted_hits[0].resize(rays.size()); };
    mine.after = [&] { order.unsort(sorted_hits[0].data(), ours.data(), ts); };
  }
  std::vector<Engine> embree_engines;
  for (std::size_t m = 0; m < modes.size(); ++m) {
    const trace::EmbreeMode mode = modes[m];
    embree_engines.push_back({[&, mode](std::size_t b0, std::size_t e0, bvh::HitRec* out) { trace::embree_trace(embree_, mode, rays, b0, e0, out, any); },
                              &theirs[m]});
  }
  for (std::size_t m = 0; sorted && m < modes.size(); ++m) {
    const trace::EmbreeMode mode = modes[m];
    std::vector<bvh::HitRec>& sh = sorted_hits[1 + m];
    embree_engines.push_back({[&, mode](std::size_t b0, std::size_t e0, bvh::HitRec*) { trace::embree_trace(embree_, mode, order.sorted(), b0, e0, sh.data(), any); },
                              &theirs_sorted[m], [&] { sort(); sh.resize(rays.size()); },
                              [&, m] { order.unsort(sh.data(), theirs_sorted[m].data(), ts); }, 1});
  }
  const Engine sah_engine{[&](std::size_t b, std::size_t e, bvh::HitRec* out) { sah_->trace(rays, b, e, out, to); }, &sah_out};
  // --isa both: the 8-lane walk timed beside the 16-lane one, when this run's packets walk in 16.
  tracer::TraceOptions to8 = to;
  to8.lanes = 8;
  const bool widths = o.isa == "both" && accel_.group_lanes(to) == 16;
  if (widths && sorted) throw std::invalid_argument("--isa both times the given order: leave --order at given");
  std::vector<bvh::HitRec> out8;
  const Engine width_engine{[&](std::size_t b, std::size_t e, bvh::HitRec* out) { accel_.trace(rays, b, e, out, to8); }, &out8};
  // --threads-beside: the same packets on another thread count, timed in the same rounds.
  std::optional<trace::ThreadScope> other_threads;
  std::vector<bvh::HitRec> out_threads;
  Engine threads_engine{[&](std::size_t b, std::size_t e, bvh::HitRec* out) { accel_.trace(rays, b, e, out, to); }, &out_threads};
  if (o.threads_beside > 0 && o.threads_beside != o.threads) {
    if (sorted) throw std::invalid_argument("--threads-beside times the given order: leave --order at given");
    other_threads.emplace(o.threads_beside);
    threads_engine.scope = &*other_threads;
    // A limit on the process's threads set elsewhere (Embree's device keeps one for the threads it
    // was made with) would quietly run fewer.
    const std::size_t cap = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
    if (cap < std::size_t(std::max(o.threads, o.threads_beside)))
      throw std::invalid_argument(fmt::format("--threads-beside {}: this process may run only {} thread(s) (the builds ran on fewer)",
                                              o.threads_beside, cap));
  }
  std::vector<const Engine*> beside;
  if (sah_) beside.push_back(&sah_engine);
  if (widths) beside.push_back(&width_engine);
  if (other_threads) beside.push_back(&threads_engine);
  // The machine around the runs: its load average before and after, and the CPU time the
  // hypervisor took from this guest while they ran.
  const LoadWatch watch;
  // One thread against more: the one-thread engines take turns on the CPUs the threads beside them
  // may use, and the speed-up is over one thread's rate averaged over those CPUs (time_engines).
  const std::vector<int> cpus = other_threads && o.threads == 1 ? allowed_cpus(o.threads_beside) : std::vector<int>{};
  const Timings tm = time_engines(ts, n, mine, beside, embree_engines, o, bar, cpus, other_threads ? &*other_threads : nullptr);
  const std::vector<double>& secs = tm.ours;
  const std::vector<double>& sah_secs = sah_ ? tm.beside[0] : secs;
  const int passes = tm.passes;
  const json machine_load = watch.json();
  const double mrays = double(n) / rb::median(secs) / 1e6;

  // Traversal cost per ray (one extra single-threaded counted pass, not timed).
  bvh::TraceCounters cnt;
  {
    std::vector<bvh::HitRec> tmp(rays.size());
    ts.run([&] { accel_.trace_counted(sorted ? order.sorted() : rays, 0, rays.size(), tmp.data(), to, cnt); });
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
  // The lanes per group the packets walked in (1: single rays) and the ISA of that walk.
  j["group_lanes"] = accel_.group_lanes(to);
  j["isa"] = j["group_lanes"] == 16 ? "avx512" : "avx2";
  j["slab"] = bvh::slab_name(slab);
  j["repetitions"] = o.repetitions;
  j["warmup"] = o.warmup;
  // The protocol as it ran: warm-up runs until stable (their seconds), passes per repetition for
  // --min-time, and the repetitions far above the others (Tukey's fence), kept in every figure.
  j["warmup_seconds"] = tm.warm_ours;
  j["min_time"] = o.min_time;
  j["passes"] = passes;
  j["repetition_seconds"] = rb::median(secs) * passes;
  j["outliers"] = stats::tukey_outliers(secs);
  j["mrays_per_s"] = mrays;
  j["seconds"] = secs;
  j["machine_load"] = machine_load;
  put_spread(j, "", secs, n);
  put_cost(j, cnt, n);
  std::size_t hits = 0;
  for (std::size_t i = 0; i < n; ++i) hits += ours[i].prim != bvh::kNoPrim;
  j["hit_fraction"] = double(hits) / double(std::max<std::size_t>(1, n));
  j["hits_fnv1a"] = hits_digest(ours, n, any);
  const json b = build_json();
  for (auto it = b.begin(); it != b.end(); ++it) j[it.key()] = it.value();

  if (sah_) put_sah_tree(j["sah_tree"], *sah_, ts, rays, to, sah_secs, ours, sah_out, any);
  if (widths) {  // the same packets in 8 lanes: the 16-lane walk's speed over it
    const std::vector<double>& s8 = tm.beside[(sah_ ? 1 : 0)];
    put_beside(j["lanes8"], s8, "speedup_16_over_8", stats::paired_ratio(s8, secs), ours, out8, n, any);
  }
  if (other_threads) put_threads_beside(j["threads_beside"], o.threads_beside, tm, modes, ours, out_threads, n, any);
  j["build_threads"] = o.build_threads();

  put_embree(j, embree_, modes, tm, ours, theirs, n, any);
  j["order"] = o.order;
  if (sorted) put_sorted(j, ts, sort, tracer::RayKey::describe(layout), embree_, modes, tm, ours, theirs_sorted, n, any);
  put_brute(j, accel_, ts, rays, ours, o.brute_rays, any);
  bar.done();
  return j;
}

json time_builds(const rb::scene::Scene& s, const std::string& source, int threads, int builds, bool warm, bool embree,
                 const std::string& model, const std::string& builder, const std::function<void(double)>& done) {
  const int total = std::max(1, builds) + (warm ? 1 : 0);
  auto tell = [&](int n) {
    if (done) done(double(n) / total);
  };
  if (warm) {
    TraceSession untimed(s, source, threads, embree, model, builder);
    tell(1);
  }
  json ours = json::array(), theirs = json::array(), first;
  std::vector<double> a, b;
  for (int r = 0; r < std::max(1, builds); ++r) {
    TraceSession one(s, source, threads, embree, model, builder);
    const json j = one.build_json();
    if (r == 0) first = j;
    a.push_back(j["build_ms"].get<double>());
    ours.push_back(a.back());
    if (!j["embree_build_ms"].is_null()) {
      b.push_back(j["embree_build_ms"].get<double>());
      theirs.push_back(b.back());
    }
    tell(r + 1 + (warm ? 1 : 0));
  }
  return {{"build_ms", rb::median(a)},
          {"embree_build_ms", b.empty() ? json(nullptr) : json(rb::median(b))},
          {"builds", int(a.size())},
          {"build_ms_runs", ours},
          {"embree_build_ms_runs", theirs},
          {"first", first}};
}

json run_trace(const TraceRunOptions& o, bool progress) {
  const auto t0 = std::chrono::steady_clock::now();
  rb::scene::Scene s = rb::scene::load_scene(o.scene);
  if (s.primitive_count() == 0) throw NothingToDo("the scene has no primitives: nothing to trace");
  const double load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  json builds;
  if (o.builds > 1) {
    ProgressBar bar(fmt::format("trace {} builds", o.scene), progress ? ProgressBar::Mode::automatic : ProgressBar::Mode::off);
    builds = time_builds(s, o.scene, o.build_threads(), o.builds, true, o.embree, o.model, o.builder, [&](double f) { bar.update(f); });
    bar.done();
  }
  TraceSession session(std::move(s), o.scene, o.build_threads(), o.embree, o.model, o.builder);
  json j = session.run(o, progress);
  j["load_ms"] = load_ms;
  j["builds"] = 1;
  if (!builds.is_null()) {
    // The medians replace the traced session's own build times (its parts, SAH, reorder and
    // collapse, stay those of that one build).
    for (const char* k : {"build_ms", "embree_build_ms", "builds", "build_ms_runs", "embree_build_ms_runs"}) j[k] = builds[k];
  }
  return j;
}

}  // namespace rb::app
