// The options of one `raybench render` run (also the report's Rendering section,
// apps/render_run.hpp): a header of its own so that the command line (apps/cli/) does not
// parse the renderer.
#pragma once

#include <string>

namespace rb::app {

struct RenderRunOptions {
  std::string scene;
  std::string out;              // PNG path ("" : no image)
  int width = 0, height = 0;    // 0: 512 (or the scene's NFF resolution without --spd)
  int depth = 5;
  int threads = 1;
  bool spd = false;
  bool progress = true;
  bool count_tests = false;     // one more render, untimed, counts box and primitive tests (--counts; on with --spd)
  int secondary_packet = 0;     // 1 or 8; 0: the faster in trial renders (apps/render_run.cpp)
  int eye_shadow_packet = -1;   // the eye rays' shadow rays: 1, 8 or 16; 0: the fastest in trial renders; -1: as secondary_packet
  int eye_packet = 0;           // 1, 8, 16 or 64; 0: the fastest of 64, 16 and 8 in trial renders
  int tile = 16;                // tile side in samples (render::RenderOptions::tile)
  std::string secondary_order = "octant";  // octant | sfc (render::RenderOptions::secondary_order)
  std::string model = "auto";  // auto | fast | exact (tracer/plan.hpp)
  int warmup = 0;               // untimed renders before the timed ones (the command line: 1)
  int repetitions = 1;          // timed renders; the median is quoted (the command line: 5)
  double min_time = 0;          // seconds a timed repetition lasts at least: renders repeated within it (the command line: 0.1)
  // One more render, untimed, keeps the rays it traces: written to `rays_out` ("": not written) and,
  // with `trace_alone`, traced alone (apps/rays_alone.hpp) after each timed repetition, as long.
  std::string rays_out;
  bool trace_alone = false;     // (the command line: on; --no-trace-alone)
  // > 0: about this many primary rays of the scene (tracer::RaySet::primary, 8-ray packets, the
  // closest hit) traced after each timed repetition, as long: render / primary in paired rounds.
  std::size_t primary_rays = 0;
};

}  // namespace rb::app
