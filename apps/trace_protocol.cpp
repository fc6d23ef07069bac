#include "apps/trace_protocol.hpp"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rb::app {

namespace {

// Pins the calling thread to one CPU (pin), then gives it back the CPUs it had (release, or when
// this goes). If the system refuses, the thread runs where it was: the figures stay valid, unpinned.
class CpuPin {
 public:
  CpuPin() { CPU_ZERO(&saved_); }
  ~CpuPin() { release(); }
  CpuPin(const CpuPin&) = delete;
  CpuPin& operator=(const CpuPin&) = delete;
  void pin(int cpu) {
    release();
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    pinned_ = pthread_getaffinity_np(pthread_self(), sizeof saved_, &saved_) == 0 &&
              pthread_setaffinity_np(pthread_self(), sizeof one, &one) == 0;
  }
  void release() {
    if (pinned_) pthread_setaffinity_np(pthread_self(), sizeof saved_, &saved_);
    pinned_ = false;
  }

 private:
  cpu_set_t saved_;
  bool pinned_ = false;
};

}  // namespace

std::vector<int> allowed_cpus(int most) {
  std::vector<int> out;
  cpu_set_t mask;
  if (pthread_getaffinity_np(pthread_self(), sizeof mask, &mask) != 0) return out;
  for (int c = 0; c < CPU_SETSIZE && int(out.size()) < most; ++c)
    if (CPU_ISSET(c, &mask)) out.push_back(c);
  return out;
}

Timings time_engines(trace::ThreadScope& ts, std::size_t n, const Engine& ours, const std::vector<const Engine*>& beside,
                     const std::vector<Engine>& modes, const TraceRunOptions& o, ProgressBar& bar, const std::vector<int>& cpus,
                     trace::ThreadScope* embree_beside) {
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
  // Embree's control: its fastest mode on the given order (group 0) by the last warm-up run, on the
  // threads beside.
  auto fastest_given = [&] {
    std::size_t f = modes.size();
    for (std::size_t m = 0; m < modes.size(); ++m)
      if (modes[m].group == 0 && !t.warm_modes[m].empty() && (f == modes.size() || t.warm_modes[m].back() < t.warm_modes[f].back())) f = m;
    return f;
  };
  auto control = [&](std::size_t m) {
    Engine e = modes[m];
    e.scope = embree_beside;
    return e;
  };
  for (int w = 0; w < std::max(kMaxWarmup, o.warmup); ++w) {
    t.warm_ours.push_back(per_pass(ours, 1));
    for (const Engine* e : beside) per_pass(*e, 1);
    std::size_t fastest = 0;
    for (std::size_t m = 0; m < modes.size(); ++m) {
      t.warm_modes[m].push_back(per_pass(modes[m], 1));
      if (t.warm_modes[m].back() < t.warm_modes[fastest].back()) fastest = m;
    }
    if (embree_beside && fastest_given() < modes.size()) per_pass(control(fastest_given()), 1);
    bar.update(0.1 * double(w + 1) / std::max(kMaxWarmup, o.warmup));
    if (w + 1 >= std::max(1, o.warmup) && !moved(t.warm_ours) && (modes.empty() || !moved(t.warm_modes[fastest]))) break;
  }
  // 2. Passes per repetition: enough for ours to last --min-time at the pace of its fastest warm-up
  // run (more passes, never fewer rays; by the last run alone, a slow last run left the repetitions
  // short of --min-time); every engine makes the same passes. At most 10^4 (a pass of under 10 us
  // is a handful of rays; no rays at all: one pass).
  const double fastest_warm = *std::min_element(t.warm_ours.begin(), t.warm_ours.end());
  t.passes = n == 0 ? 1 : int(std::clamp(std::ceil(o.min_time / std::max(fastest_warm, 1e-9)), 1.0, 1e4));
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
  // alike. With `cpus`, the one-thread engines of round r run on cpus[r % k], raybench then on each
  // other CPU of the list, and the engines of more threads last, unpinned.
  const std::size_t given = embree_beside ? fastest_given() : modes.size();
  const Engine embree_control = given < modes.size() ? control(given) : Engine{};
  if (given < modes.size()) t.mode_beside = given;
  const bool pin = cpus.size() >= 2 && o.threads == 1;
  const std::size_t k = pin ? cpus.size() : 0;
  auto several = [&](const Engine* e) { return pin && e->scope && e->scope->threads() > 1; };
  if (pin) t.cpus = cpus, t.ours_on.resize(k);
  if (pin && given < modes.size()) t.mode_on.resize(k);
  CpuPin on;
  for (int r = 0; r < o.repetitions; ++r) {
    if (pin) on.pin(cpus[std::size_t(r) % k]);
    t.ours.push_back(per_pass(ours, t.passes));
    for (std::size_t b = 0; b < beside.size(); ++b)
      if (!several(beside[b])) t.beside[b].push_back(per_pass(*beside[b], t.passes));
    for (const std::size_t m : timed) t.modes[m].push_back(per_pass(modes[m], t.passes));
    for (std::size_t c = 0; c < k; ++c) {
      if (c == std::size_t(r) % k) {
        t.ours_on[c].push_back(t.ours.back());
        if (!t.mode_on.empty()) t.mode_on[c].push_back(t.modes[given].back());
        continue;
      }
      on.pin(cpus[c]);
      t.ours_on[c].push_back(per_pass(ours, t.passes));
      if (!t.mode_on.empty()) t.mode_on[c].push_back(per_pass(modes[given], t.passes));
    }
    on.release();
    for (std::size_t b = 0; b < beside.size(); ++b)
      if (several(beside[b])) t.beside[b].push_back(per_pass(*beside[b], t.passes));
    if (given < modes.size()) t.mode_beside_seconds.push_back(per_pass(embree_control, t.passes));
    bar.update(0.1 + 0.85 * double(r + 1) / o.repetitions);
  }
  return t;
}

}  // namespace rb::app
