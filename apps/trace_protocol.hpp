// The timing protocol of `raybench trace` (and the report's traces): the engines a run times, warm-up
// until stable, passes for --min-time, Embree's clearly slower modes left out, then the engines
// alternating repetition by repetition (docs/DESIGN.md, command-line conventions).
#pragma once

#include "apps/progress.hpp"
#include "apps/trace_options.hpp"
#include "bench/timed_trace.hpp"

#include <functional>
#include <vector>

namespace rb::app {

// An engine a trace run times: a tracer over the run's rays and where its hits go.
struct Engine {
  trace::Tracer trace;
  std::vector<bvh::HitRec>* out;
  std::function<void()> before = {}, after = {};  // inside each timed pass (a sorted stream: the sort, the hits put back)
  int group = 0;  // Embree's modes: 0 on the given order, 1 on the sorted order (each group's slow modes left out apart)
  trace::ThreadScope* scope = nullptr;  // the threads it runs on (none: the run's)
};

// What the timing protocol measured, in seconds per pass over the ray set.
struct Timings {
  std::vector<double> warm_ours;                // the warm-up runs of raybench
  std::vector<std::vector<double>> warm_modes;  // and of each Embree mode
  int passes = 1;                               // passes per timed repetition
  std::vector<double> ours;                     // raybench
  std::vector<std::vector<double>> beside;      // raybench's other engines timed beside it, in their order
  std::vector<std::vector<double>> modes;       // each Embree mode (empty: left out of the rounds)
  std::vector<int> cpus;                        // the CPUs the one-thread engines took turns on (empty: not pinned)
  std::vector<std::vector<double>> ours_on;     // raybench on each of those CPUs, round by round
  // Embree's control (`embree_beside`): its fastest mode on the given order, also on the other
  // thread count in the same rounds (empty: not timed).
  std::size_t mode_beside = 0;                  // which mode
  std::vector<double> mode_beside_seconds;      // its seconds on the other thread count, round by round
  std::vector<std::vector<double>> mode_on;     // and on one thread, on each CPU of `cpus`, round by round
};

// The timing protocol of `raybench trace` (docs/DESIGN.md, command-line conventions): warm-up until
// stable, passes for --min-time, Embree's clearly slower modes left out, then the engines alternating
// repetition by repetition. `beside`: raybench in other configurations, timed in the same rounds
// (the SAH tree beside another builder's; packets in the other lane width; another thread count).
//
// `cpus` (two or more; only for a one-thread run): round r pins the calling thread, on which the
// one-thread engines run, to cpus[r % k], and raybench runs once more on each other CPU of the list;
// the engines of more threads run unpinned. A guest's CPUs may differ in speed for minutes (a host
// thread sharing one's core), so one thread's rate depends on where it ran: pinned, each round's
// engines share a CPU, and the rate on every CPU is known, against which the rate of several
// threads means something whichever CPU was slower.
//
// `embree_beside` (with another thread count beside raybench): Embree's fastest mode on the given
// order also runs on those threads, after raybench's, in every warm-up and timed round, and with
// `cpus` on one thread on each CPU as raybench does: the same machine's answer to the same question,
// the control of a thread-scaling figure (a host that gave the guest less than two cores slows both
// engines' second thread alike).
Timings time_engines(trace::ThreadScope& ts, std::size_t n, const Engine& ours, const std::vector<const Engine*>& beside,
                     const std::vector<Engine>& modes, const TraceRunOptions& o, ProgressBar& bar, const std::vector<int>& cpus = {},
                     trace::ThreadScope* embree_beside = nullptr);

// The CPUs of this thread's affinity mask, at most `most` of them, lowest first.
std::vector<int> allowed_cpus(int most);

}  // namespace rb::app
