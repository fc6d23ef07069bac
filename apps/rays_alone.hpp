// A render's own rays traced alone: every section of a ray file (tracer/ray_file.hpp: the rays of
// each generation as the render traced them) through the BVH with the render's packet size and
// query, with nothing else: no shading, no packing, no ray making. `raybench render` times it
// beside the render (how much of the render is tracing) and `raybench trace --rays FILE` runs it
// on a file a render wrote.
#pragma once

#include "tracer/accel.hpp"
#include "tracer/ray_file.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace rb::app {

// A ray file's sections, traced pass after pass: every section in turn (TBB over chunks of 256
// rays on `threads` threads) with its packet size and query. Made with one untimed pass; each
// repetition() then times passes until they have lasted `min_time`, so that a caller can put its
// own repetitions between them (`raybench render` alternates them with its renders: both see the
// same machine). The accel and the file must outlive it.
class RaysAlone {
 public:
  RaysAlone(const tracer::SceneAccel& accel, const tracer::RayFile& f, int threads, int lanes);
  ~RaysAlone();
  RaysAlone(const RaysAlone&) = delete;
  RaysAlone& operator=(const RaysAlone&) = delete;
  // One timed repetition: passes until they have lasted min_time (at most 1000); seconds per pass.
  double repetition(double min_time);
  // Keys: rays, threads, seconds (per pass, per repetition), passes, min_time, ms and mrays_per_s
  // (median), cv, and sections: kind, generation, query, packet, lanes (per group of a packet:
  // tracer::TraceOptions::lanes, asked for as `lanes`), rays, hits, ms (per pass, over every timed
  // pass), mrays_per_s.
  nlohmann::json figures() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

// `repetitions` repetitions of RaysAlone (at least one); `progress(fraction)` after each.
nlohmann::json trace_rays_alone(const tracer::SceneAccel& accel, const tracer::RayFile& f, int threads, int repetitions,
                                double min_time, int lanes, const std::function<void(double)>& progress = {});

// `raybench trace SCENE --rays FILE`: the file's rays moved into the plan's frame and traced alone;
// the scene's JSON figures beside (scene, model, primitives, build_ms).
nlohmann::json run_trace_file(const std::string& scene, const std::string& file, const std::string& model, int threads,
                              int repetitions, double min_time, int lanes, bool progress);
std::string trace_file_text(const nlohmann::json& j);

}  // namespace rb::app
