// `raybench trace SCENE`: trace a whole scene with the BVH, beside Embree on the same rays.
#include "apps/commands.hpp"
#include "apps/trace_run.hpp"

#include <iostream>

namespace rb::app {

int run_trace_command(const TraceRunOptions& o, const JsonOut& out) {
  try {
    const nlohmann::json j = run_trace(o, true);
    return write_result("trace", out.json, out.file, [&] { return trace_text(j); }, [&] { return j; });
  } catch (const std::exception& e) {
    std::cerr << "raybench trace: " << o.scene << ": " << e.what() << "\n";
    return 1;
  }
}

}  // namespace rb::app
