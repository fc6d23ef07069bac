// The 16-lane rows of the kernel benchmarks (16 rays x 1 primitive, 1 ray x 16 primitives) and their
// operations per test, compiled for AVX2 like the rest: the 16-lane loops themselves, timed and
// counted, are in bench/simd16_loops.cpp.
#include "bench/register.hpp"
#include "bench/specs_all.hpp"

#include <map>
#include <memory>
#include <mutex>
#include <utility>

namespace rb::bench {

#ifdef RB_HAVE_SIMD16
template <class Spec>
OpMix simd16_op_mix(Case c, Variant v) {
  // Google Benchmark runs a benchmark's function once per round: counted once per case and mapping.
  static std::mutex mu;
  static std::map<std::pair<int, int>, OpMix> memo;
  const std::lock_guard<std::mutex> lock(mu);
  const auto key = std::make_pair(int(c), int(v));
  if (const auto it = memo.find(key); it != memo.end()) return it->second;
  const auto d = std::make_unique<BenchData<Spec>>(make_bench_data<Spec>(c));
  const ops::Scope s;
  run_simd16_counted<Spec>(*d, v);
  const OpCounts e = s.elapsed();
  const double tests = double(d->rays.size()) * double(d->prims.size()), per_lane = 16.0 / tests;
  return memo[key] = {ops_per_lane_test(e, 16.0, tests), double(e.total()) * per_lane, double(e.div) * per_lane, double(e.sqrt) * per_lane};
}

void register_simd16() {
  for_every_spec([]<class Spec>() {
    register_one<Spec, Variant::rays_in_lanes16>();
    if constexpr (max_prim_lanes<Spec>() >= 16) register_one<Spec, Variant::prims_in_lanes16>();
  });
}
#else
void register_simd16() {}
#endif

}  // namespace rb::bench
