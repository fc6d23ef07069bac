// One `raybench trace` run (also used by the report's Tracing section): load, build both BVHs,
// make the ray set, time both engines, compare them ray by ray and against brute force.
#pragma once

#include "apps/trace_options.hpp"
#include "bench/embree_trace.hpp"
#include "bench/timed_trace.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>

namespace rb::app {

// A scene with both engines built once (with `build_threads`), then any number of runs.
class TraceSession {
 public:
  // The scene traced under `model` (auto | fast | exact): the plan, the BVH and Embree's scene in
  // the plan's frame.
  // `builder`: the tree raybench traces (TraceRunOptions::builder); with one of Embree's, the SAH
  // tree is built too and timed beside it.
  TraceSession(rb::scene::Scene s, std::string source, int build_threads, bool embree, const std::string& model = "auto",
               const std::string& builder = "sah");
  nlohmann::json run(const TraceRunOptions& o, bool progress);
  nlohmann::json build_json() const;
  const tracer::SceneAccel& accel() const { return accel_; }
  const tracer::Plan& plan() const { return accel_.plan(); }
  const rb::scene::Scene& scene() const { return scene_; }

 private:
  rb::scene::Scene scene_;
  std::string source_;
  tracer::SceneAccel accel_;
  std::string builder_ = "sah";
  std::optional<tracer::SceneAccel> sah_;  // the SAH tree beside Embree's builder's
  trace::EmbreeBuild embree_;
  std::map<std::string, std::pair<RaySoA, tracer::RaySetInfo>> rays_;
  const RaySoA& rays(tracer::RaySet set, std::size_t count, std::uint64_t seed, tracer::RaySetInfo& info);
};

// Build times of both engines on scene `s` at `threads`: the medians of `builds` builds, each a
// fresh TraceSession, after one untimed build when `warm` (the first build at a thread count also
// starts its threads and maps fresh memory). Keys: build_ms, embree_build_ms (null without
// Embree), builds, build_ms_runs, embree_build_ms_runs, and `first`: the first timed build's
// build_json(). `done(fraction)` is told after each build.
nlohmann::json time_builds(const rb::scene::Scene& s, const std::string& source, int threads, int builds, bool warm, bool embree,
                           const std::string& model = "auto", const std::string& builder = "sah",
                           const std::function<void(double)>& done = {});

nlohmann::json run_trace(const TraceRunOptions& o, bool progress);
// The lanes per group of a packet's rays that `--isa` asks for (tracer::TraceOptions::lanes): 8 for
// avx2, 16 for auto and both where the binary and the CPU have the 16-lane walk; avx512 where they
// do not throws std::invalid_argument.
int trace_lanes(const std::string& isa);
std::string trace_text(const nlohmann::json& j);

}  // namespace rb::app
