// `raybench trace SCENE`: trace a whole scene with the BVH, beside Embree on the same rays.
#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "apps/rays_alone.hpp"
#include "apps/results/machine.hpp"
#include "apps/trace_run.hpp"

#include <fmt/format.h>

#include <iostream>

namespace rb::app {

namespace {

// `trace SCENE --rays FILE`: a ray file's sections traced alone, each with its packet size and query.
int run_trace_file_command(const TraceRunOptions& o, const std::string& model, const JsonOut& out, const std::string& warn) {
  std::cerr << fmt::format("raybench trace {}: the rays of {}, {} thread(s) of {} hardware threads, {} timed repetition(s)\n", o.scene,
                           o.ray_set, o.threads, hardware_threads(), o.repetitions);
  if (!warn.empty()) std::cerr << wrap_words(warn);
  nlohmann::json j;
  try {
    j = run_trace_file(o.scene, o.ray_set, model, o.threads, o.repetitions, o.min_time, trace_lanes(o.isa), true);
  } catch (const std::exception& e) {
    std::cerr << error_line("trace", o.scene, e.what()) << "\n";
    return kExitError;
  }
  j["machine"] = machine().json();
  return write_result("trace", out, [&] { return trace_file_text(j); }, [&] { return j; }, "the trace result");
}

}  // namespace

int run_trace_command(const TraceRunOptions& opt, const JsonOut& out, bool model_given) {
  TraceRunOptions o = opt;
  if (!is_generated_scene(o.scene))
    if (const std::string why = check_input_file(o.scene); !why.empty()) {
      std::cerr << error_line("trace", o.scene, why) << "\n";
      return kExitError;
    }
  std::string warn;
  o.threads = resolve_threads(o.threads, &warn);
  if (!tracer::is_ray_set_name(o.ray_set)) {
    if (o.threads_beside > 0) {
      std::cerr << error_line("trace", o.ray_set, "--threads-beside times a ray set (primary, shadow, diffuse or random), not a ray file") << "\n";
      return kExitError;
    }
    return run_trace_file_command(o, model_given ? o.model : "", out, warn);
  }
  std::cerr << fmt::format("raybench trace {}: {} rays, {} thread(s){} of {} hardware threads, {} warm-up + {} timed run(s) per engine\n",
                           o.scene, o.ray_set, o.threads, o.threads_beside > 0 ? fmt::format(" and {} beside", o.threads_beside) : "",
                           hardware_threads(), o.warmup, o.repetitions);
  if (!warn.empty()) std::cerr << wrap_words(warn);
  nlohmann::json j;
  try {
    j = run_trace(o, true);
  } catch (const NothingToDo& e) {
    std::cerr << error_line("trace", o.scene, e.what()) << "\n";
    return kExitNothing;
  } catch (const std::exception& e) {
    std::cerr << error_line("trace", o.scene, e.what()) << "\n";
    return kExitError;
  }
  const double load = load_average();
  j["machine"] = machine().json();
  const int rc = write_result("trace", out, [&] { return fit_columns(trace_text(j), 11); }, [&] { return j; }, "the trace result");
  for (const char* p : {"", "embree_"})
    if (j.contains(std::string(p) + "cv") && j[std::string(p) + "cv"].is_number())
      if (const std::string w = noise_warning(j[std::string(p) + "cv"].get<double>(), *p ? "Embree's runs" : "raybench's runs"); !w.empty())
        std::cerr << wrap_words(w);
  if (const std::string w = busy_warning(load, o.threads); !w.empty()) std::cerr << wrap_words(w);
  return rc;
}

}  // namespace rb::app
