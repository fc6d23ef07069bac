#include "bench/timed_trace.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

namespace rb::trace {

double time_brute_force(ThreadScope& ts, const tracer::SceneAccel& a, const RaySoA& rays, std::size_t n, bool any, std::vector<HitRec>& out) {
  out.resize(n);
  const auto t0 = std::chrono::steady_clock::now();
  ts.parallel_for(n, 16, [&](std::size_t i) { out[i] = a.brute_force(rays.get(i), any); });
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<double> time_runs(ThreadScope& ts, const Tracer& t, std::size_t rays, std::vector<HitRec>& out, int reps, std::size_t tile,
                              const std::function<void(int, int)>& progress, const std::function<void()>& before,
                              const std::function<void()>& after) {
  out.resize(round_up(rays, 16));
  const std::size_t tiles = (rays + tile - 1) / tile;
  std::vector<double> secs;
  for (int r = 0; r < reps; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    if (before) before();
    ts.parallel_for(tiles, 1, [&](std::size_t k) { t(k * tile, std::min(rays, (k + 1) * tile), out.data()); });
    if (after) after();
    secs.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    if (progress) progress(r + 1, reps);
  }
  return secs;
}

Progress::Progress(std::string l) : label(std::move(l)), tty(isatty(2) != 0) {}
void Progress::update(double fraction) {
  if (!tty) return;
  const int w = 30, k = int(fraction * w + 0.5);
  std::fprintf(stderr, "\r%-40.40s [%.*s%*s] %3d%%", label.c_str(), k, "##############################", w - k, "", int(fraction * 100 + 0.5));
  std::fflush(stderr);
}
void Progress::done() {
  if (!tty) return;
  std::fprintf(stderr, "\r%*s\r", 80, "");
  std::fflush(stderr);
}

}  // namespace rb::trace
