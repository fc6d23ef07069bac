// Whole-scene tracing runs timed: the multi-threaded trace of a ray set (tracer/ray_sets.hpp) and
// the progress of a long run.
#pragma once

#include "tracer/accel.hpp"
#include "tracer/parallel.hpp"
#include "tracer/ray_sets.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rb::trace {

using tracer::ThreadScope;
using bvh::HitRec;

// A tracer: traces rays [begin, end) into out (begin a multiple of 16).
using Tracer = std::function<void(std::size_t begin, std::size_t end, HitRec* out)>;

// Times `reps` runs of the tracer over all rays with TBB parallel_for over tiles of `tile` rays;
// returns the seconds of each run. `progress(done, total)` after each run. `before` and `after`,
// when given, run inside each timed run before and after the tiles (a stream's sort and the hits
// put back in its order).
std::vector<double> time_runs(ThreadScope& ts, const Tracer& t, std::size_t rays, std::vector<HitRec>& out, int reps,
                              std::size_t tile, const std::function<void(int, int)>& progress = {},
                              const std::function<void()>& before = {}, const std::function<void()>& after = {});

// The lecture's loop over all objects (SceneAccel::brute_force) on rays [0, n), 16 rays a task on
// the scope's threads, into out (resized to n); returns its seconds. The oracle and the baseline.
double time_brute_force(ThreadScope& ts, const tracer::SceneAccel& a, const RaySoA& rays, std::size_t n, bool any, std::vector<HitRec>& out);

// A progress bar on stderr (only when stderr is a terminal).
struct Progress {
  std::string label;
  bool tty;
  explicit Progress(std::string l);
  void update(double fraction);
  void done();
};

}  // namespace rb::trace
