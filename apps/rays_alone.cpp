#include "apps/rays_alone.hpp"

#include "apps/progress.hpp"
#include "apps/results/stats.hpp"
#include "bench/timed_trace.hpp"
#include "core/text.hpp"
#include "scene/sources.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

namespace rb::app {

using nlohmann::json;

struct RaysAlone::State {
  static constexpr std::size_t kChunk = 256;  // a multiple of every packet size
  const tracer::SceneAccel& accel;
  const tracer::RayFile& f;
  int threads, lanes;
  std::vector<RaySoA> soa;
  std::vector<std::vector<bvh::HitRec>> out;
  std::vector<double> section_s;  // over the timed passes
  trace::ThreadScope ts;
  std::vector<double> seconds;
  std::vector<int> passes;
  int timed_passes = 0;
  double min_time = 0;

  State(const tracer::SceneAccel& a, const tracer::RayFile& file, int t, int l)
      : accel(a), f(file), threads(t), lanes(l), soa(file.sections.size()), out(file.sections.size()),
        section_s(file.sections.size(), 0.0), ts(t) {
    for (std::size_t k = 0; k < f.sections.size(); ++k) {
      soa[k].reserve(f.sections[k].rays.size());
      for (const auto& r : f.sections[k].rays) soa[k].push(r);
    }
  }
  // One pass: every section traced in turn, each with its packet size and query; its seconds.
  double pass(bool count) {
    double total = 0;
    for (std::size_t k = 0; k < f.sections.size(); ++k) {
      tracer::TraceOptions to;
      to.packet = f.sections[k].packet;
      to.any = f.sections[k].any;
      to.lanes = lanes;
      const trace::Tracer t = [&](std::size_t b, std::size_t e, bvh::HitRec* o) { accel.trace(soa[k], b, e, o, to); };
      const double s = trace::time_runs(ts, t, soa[k].count, out[k], 1, kChunk)[0];
      if (count) section_s[k] += s;
      total += s;
    }
    return total;
  }
};

RaysAlone::RaysAlone(const tracer::SceneAccel& accel, const tracer::RayFile& f, int threads, int lanes)
    : s_(std::make_unique<State>(accel, f, threads, lanes)) {
  s_->pass(false);  // untimed: caches, pages, the threads' start
}

RaysAlone::~RaysAlone() = default;

double RaysAlone::repetition(double min_time) {
  State& st = *s_;
  double sum = 0;
  int p = 0;
  do {
    sum += st.pass(true);
    ++p;
  } while (sum < min_time && p < 1000);
  st.seconds.push_back(sum / p);
  st.passes.push_back(p);
  st.timed_passes += p;
  st.min_time = min_time;
  return sum / p;
}

json RaysAlone::figures() const {
  const State& st = *s_;
  const std::size_t n = st.f.rays();
  const stats::Summary sm = stats::summarize(st.seconds);
  json secs = json::array();
  for (std::size_t k = 0; k < st.f.sections.size(); ++k) {
    const tracer::RaySection& s = st.f.sections[k];
    std::size_t hits = 0;
    for (std::size_t i = 0; i < s.rays.size(); ++i) hits += st.out[k][i].prim != bvh::kNoPrim;
    const double ms = 1e3 * st.section_s[k] / std::max(1, st.timed_passes);
    tracer::TraceOptions to;
    to.packet = s.packet;
    to.lanes = st.lanes;
    secs.push_back({{"kind", s.kind}, {"generation", s.generation}, {"query", s.any ? "any" : "closest"}, {"packet", s.packet},
                    {"lanes", st.accel.group_lanes(to)}, {"rays", s.rays.size()}, {"hits", hits}, {"ms", ms},
                    {"mrays_per_s", ms > 0 ? double(s.rays.size()) / (ms * 1e3) : 0.0}});
  }
  return {{"rays", n},
          {"threads", st.threads},
          {"seconds", st.seconds},
          {"passes", st.passes},
          {"min_time", st.min_time},
          {"ms", 1e3 * sm.median},
          {"mrays_per_s", sm.median > 0 ? double(n) / sm.median / 1e6 : 0.0},
          {"cv", std::isfinite(sm.cv) ? json(sm.cv) : json(nullptr)},
          {"sections", secs}};
}

json trace_rays_alone(const tracer::SceneAccel& accel, const tracer::RayFile& f, int threads, int repetitions, double min_time,
                      int lanes, const std::function<void(double)>& progress) {
  RaysAlone alone(accel, f, threads, lanes);
  for (int r = 0; r < std::max(1, repetitions); ++r) {
    alone.repetition(min_time);
    if (progress) progress(double(r + 1) / std::max(1, repetitions));
  }
  return alone.figures();
}

json run_trace_file(const std::string& scene, const std::string& file, const std::string& model, int threads, int repetitions,
                    double min_time, int lanes, bool progress) {
  tracer::RayFile f = tracer::read_ray_file(file);
  const std::string m = model.empty() ? f.model : model;
  const scene::Scene s = scene::load_scene(scene);
  const tracer::Plan plan = tracer::make_plan(s, tracer::parse_model(m));
  tracer::SceneAccel accel;
  {
    trace::ThreadScope ts(threads);
    ts.run([&] { accel = tracer::SceneAccel::build(s, plan); });
  }
  const bool moved = !(f.origin.x == plan.origin.x && f.origin.y == plan.origin.y && f.origin.z == plan.origin.z);
  tracer::move_frame(f, plan.origin);
  ProgressBar bar(fmt::format("trace {} {}", scene, file), progress ? ProgressBar::Mode::automatic : ProgressBar::Mode::off);
  json j = trace_rays_alone(accel, f, threads, repetitions, min_time, lanes, [&](double x) { bar.update(x); });
  bar.done();
  j["scene"] = scene;
  j["rays_file"] = file;
  j["written_for"] = {{"scene", f.scene}, {"model", f.model}};
  j["model"] = m;
  j["primitives"] = accel.scene_prims();
  j["build_ms"] = accel.build_ms;
  j["moved_frame"] = moved;
  return j;
}

std::string trace_file_text(const json& j) {
  std::string t = fmt::format("{} traced alone on {} ({}, {} primitives), {} thread(s)\n", j["rays_file"].get<std::string>(),
                              j["scene"].get<std::string>(), j["model"].get<std::string>(), j["primitives"].get<std::size_t>(),
                              j["threads"].get<int>());
  const json& w = j["written_for"];
  if (w["scene"] != j["scene"] || w["model"] != j["model"])
    t += wrap_words(fmt::format("note: the rays were written for {} under the {} model; the hits are not the render's.",
                                w["scene"].get<std::string>(), w["model"].get<std::string>()));
  if (j["moved_frame"].get<bool>()) t += wrap_words("note: the rays were moved into this plan's frame (in double): they are not bit for bit the file's.");
  t += fmt::format("  {:<24} {:>8} {:>6} {:>10} {:>7} {:>9} {:>9}\n", "section", "query", "packet", "rays", "hit %", "ms", "Mrays/s");
  for (const auto& s : j["sections"]) {
    const double rays = s["rays"].get<double>();
    t += fmt::format("  {:<24} {:>8} {:>6} {:>10} {:>7.1f} {:>9.2f} {:>9.1f}\n",
                     fmt::format("generation {} {}", s["generation"].get<int>(), s["kind"].get<std::string>()),
                     s["query"].get<std::string>(), s["packet"].get<int>(), s["rays"].get<std::size_t>(),
                     rays > 0 ? 100.0 * s["hits"].get<double>() / rays : 0.0, s["ms"].get<double>(), s["mrays_per_s"].get<double>());
  }
  const stats::Summary sm = stats::summarize(j["seconds"].get<std::vector<double>>());
  t += fmt::format("  all: {} rays, {:.2f} ms per pass, {:.2f} Mrays/s (median of {} repetition(s), range {:.2f}-{:.2f} ms)\n",
                   j["rays"].get<std::size_t>(), j["ms"].get<double>(), j["mrays_per_s"].get<double>(), j["seconds"].size(),
                   1e3 * sm.min, 1e3 * sm.max);
  return t;
}

}  // namespace rb::app
