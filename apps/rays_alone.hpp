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
#include <string>
#include <vector>

namespace rb::app {

// One untimed pass, then `repetitions` timed ones, each tracing every section in turn (TBB over
// chunks of 256 rays on `threads` threads) as often as makes it last `min_time`. Keys: rays,
// seconds (per pass, per repetition), passes, mrays_per_s (median), cv, and sections: kind,
// generation, query, packet, lanes (per group of a packet: tracer::TraceOptions::lanes, asked
// for as `lanes`), rays, hits, ms (per pass, over every timed pass), mrays_per_s.
// `progress(fraction)` after each repetition.
nlohmann::json trace_rays_alone(const tracer::SceneAccel& accel, const tracer::RayFile& f, int threads, int repetitions,
                                double min_time, int lanes, const std::function<void(double)>& progress = {});

// `raybench trace SCENE --rays FILE`: the file's rays moved into the plan's frame and traced alone;
// the scene's JSON figures beside (scene, model, primitives, build_ms).
nlohmann::json run_trace_file(const std::string& scene, const std::string& file, const std::string& model, int threads,
                              int repetitions, double min_time, int lanes, bool progress);
std::string trace_file_text(const nlohmann::json& j);

}  // namespace rb::app
