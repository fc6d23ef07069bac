#include "apps/trace_protocol.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rb::app {

Timings time_engines(trace::ThreadScope& ts, std::size_t n, const Engine& ours, const std::vector<const Engine*>& beside,
                     const std::vector<Engine>& modes, const TraceRunOptions& o, ProgressBar& bar) {
  const std::size_t tile = 256;  // a multiple of every packet and stream size
  // Seconds per pass over the ray set, of `passes` passes in a row.
  auto per_pass = [&](const Engine& e, int passes) {
    double sum = 0;
    for (const double x : trace::time_runs(e.scope ? *e.scope : ts, e.trace, n, *e.out, passes, tile, {}, e.before, e.after)) sum += x;
    return sum / passes;
  };
  Timings t;
  t.warm_modes.resize(modes.size());
  t.modes.resize(modes.size());
  t.beside.resize(beside.size());
  // 1. Warm-up until stable (caches, page faults, the thread pool's start, the clock's boost): the
  // engines alternate run by run, for at least --warmup rounds and on while ours or Embree's fastest
  // mode still moved by more than kSettled from its previous run (at most kMaxWarmup rounds).
  constexpr double kSettled = 0.05;
  constexpr int kMaxWarmup = 6;
  auto moved = [&](const std::vector<double>& v) { return v.size() < 2 || std::fabs(v.back() / v[v.size() - 2] - 1) > kSettled; };
  for (int w = 0; w < std::max(kMaxWarmup, o.warmup); ++w) {
    t.warm_ours.push_back(per_pass(ours, 1));
    for (const Engine* e : beside) per_pass(*e, 1);
    std::size_t fastest = 0;
    for (std::size_t m = 0; m < modes.size(); ++m) {
      t.warm_modes[m].push_back(per_pass(modes[m], 1));
      if (t.warm_modes[m].back() < t.warm_modes[fastest].back()) fastest = m;
    }
    bar.update(0.1 * double(w + 1) / std::max(kMaxWarmup, o.warmup));
    if (w + 1 >= std::max(1, o.warmup) && !moved(t.warm_ours) && (modes.empty() || !moved(t.warm_modes[fastest]))) break;
  }
  // 2. Passes per repetition: enough for ours to last --min-time by its last warm-up run (more passes,
  // never fewer rays); every engine makes the same passes. At most 10^4 (a pass of under 10 us is a
  // handful of rays; no rays at all: one pass).
  t.passes = n == 0 ? 1 : int(std::clamp(std::ceil(o.min_time / std::max(t.warm_ours.back(), 1e-9)), 1.0, 1e4));
  // 3. Embree's modes in the timed rounds: the fastest in the warm-up and every mode within
  // kModeSpread of it (the others are clearly slower: their warm-up figures are kept in the JSON).
  constexpr double kModeSpread = 1.10;
  std::vector<std::size_t> timed;
  double best[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  for (std::size_t m = 0; m < modes.size(); ++m) best[modes[m].group] = std::min(best[modes[m].group], t.warm_modes[m].back());
  for (std::size_t m = 0; m < modes.size(); ++m)
    if (t.warm_modes[m].back() <= kModeSpread * best[modes[m].group]) timed.push_back(m);
  // 4. The timed rounds: the engines alternate repetition by repetition (raybench, its engines
  // beside it, then each timed Embree mode), so that a change in the machine's load falls on all
  // alike.
  for (int r = 0; r < o.repetitions; ++r) {
    t.ours.push_back(per_pass(ours, t.passes));
    for (std::size_t k = 0; k < beside.size(); ++k) t.beside[k].push_back(per_pass(*beside[k], t.passes));
    for (const std::size_t m : timed) t.modes[m].push_back(per_pass(modes[m], t.passes));
    bar.update(0.1 + 0.85 * double(r + 1) / o.repetitions);
  }
  return t;
}

}  // namespace rb::app
