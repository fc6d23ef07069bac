// The options of one `raybench trace` run (also the report's Tracing section, apps/trace_run.hpp):
// a header of its own so that the command line (apps/cli/) does not parse the tracer.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

namespace rb::app {

struct TraceRunOptions {
  std::string scene;
  std::string ray_set = "primary";
  int threads = 1;
  int packet = 1;
  std::size_t count = std::size_t(1) << 20;
  std::uint64_t seed = 1;
  std::string model = "auto";  // auto | fast | exact (tracer/plan.hpp)
  std::string slab = "plan";   // plan (the model's) | conservative | fast | robust
  // 15 rounds of at least 0.05 s: the sign test's interval then leaves out the 3 most extreme rounds'
  // ratios on each side (7 rounds of 0.1 s, as long, gave the whole range: docs/DESIGN.md).
  int repetitions = 15;  // from 6 paired rounds a ratio has its 95 % interval (apps/stats.hpp)
  int warmup = 1;        // untimed runs of each engine before the timed ones, at least (more until stable)
  double min_time = 0.05;  // seconds a repetition lasts at least: the ray set traced that many times over
  long long brute_rays = -1;  // -1: a budget by scene size; 0: none
  bool embree = true;
  int builds = 1;  // > 1: the build times quoted are medians of this many builds after an untimed one
  // The tree raybench traces: "sah" (its binned SAH) or Embree's builder ("embree": medium
  // quality, "embree-high": high quality with spatial splits of triangles), a diagnostic that
  // separates the tree's share of the gap to Embree from the kernel's (the SAH tree is then
  // timed beside it in the same run).
  std::string builder = "sah";
  // The rays' order: "given" (the ray set's), or "sorted": each pass first sorts them into coherent
  // groups (tracer/ray_order.hpp) and puts the hits back in the given order, both inside the timed
  // pass; Embree then traces both orders, each mode sorting in its own pass.
  std::string order = "given";
  // The width of a packet's groups of rays (packets of 16 or more rays of triangle meshes): "auto"
  // (16 AVX-512 lanes where the binary and the CPU have them), "avx2" (8 lanes), "avx512" (16; an
  // error where they cannot run) or "both" (auto, with the 8-lane walk timed beside it).
  std::string isa = "auto";
  // Thread scaling: raybench also on this many threads (0: not), timed in the same rounds, so that
  // the speed-up of these threads over `threads` is a paired ratio with its interval. The builds
  // then run on the larger count (Embree's device limits the process's threads to its own).
  int threads_beside = 0;
  int build_threads() const { return std::max(threads, threads_beside); }
};

}  // namespace rb::app
