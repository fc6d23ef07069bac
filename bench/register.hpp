// Registers the Google Benchmark cases of one bench spec and variant. Included by exactly two
// translation units per kernel family: bench_<family>_scalar.cpp (compiled with auto-vectorisation
// off, the true scalar baseline) and bench_<family>_simd.cpp (the two SIMD mappings).
#pragma once

#include "bench/harness.hpp"
#include "bench/simd16.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rb::bench {

// The names of every registered benchmark, in registration order (the progress bar's total).
inline std::vector<std::string>& registered_names() {
  static std::vector<std::string> names;
  return names;
}

// Every registered benchmark by name: the runner fixes their iterations after the first round.
inline std::map<std::string, benchmark::internal::Benchmark*>& registered_benchmarks() {
  static std::map<std::string, benchmark::internal::Benchmark*> by_name;
  return by_name;
}

// Registers one benchmark with Google Benchmark and in the two lists above.
template <class Fn>
void register_benchmark(const std::string& name, Fn&& fn) {
  registered_names().push_back(name);
  registered_benchmarks()[name] = benchmark::RegisterBenchmark(name.c_str(), std::forward<Fn>(fn));
}

// A kernel benchmark waiting for its place in the run. register_all_benchmarks registers them
// grouped by kernel, method and case, so that the rows a ratio pairs (the true scalar form, 8 lanes
// and 16 lanes of one method and case) run back to back in every round, within a second instead
// of minutes apart: the host's speed drifts over minutes, and a ratio of rows measured apart carries that
// drift.
struct PendingBenchmark {
  std::string name, group;  // group: kernel/method/case
  std::function<void(benchmark::State&)> run;
};
inline std::vector<PendingBenchmark>& pending_benchmarks() {
  static std::vector<PendingBenchmark> p;
  return p;
}

template <class Spec, Variant V>
void register_one() {
  for (Case c : {Case::hit, Case::miss, Case::half}) {
    const BenchName bn{Spec::kernel, Spec::method, variant_name(V), case_name(c)};
    pending_benchmarks().push_back({bn.str(), bn.kernel_method() + "/" + bn.kase, [c](benchmark::State& st) {
      const auto d = std::make_unique<BenchData<Spec>>(make_bench_data<Spec>(c));  // set-up, not timed
      OpMix mix;  // the 16-lane rows' (bench/bench_simd16.cpp)
      if constexpr (is_simd16(V)) mix = simd16_op_mix<Spec>(c, V);
      const double opt = is_simd16(V) ? mix.ops : ops_per_test(Spec::kernel, Spec::method, c, V);
      Acc a;
      for (auto _ : st) {
        if constexpr (V == Variant::scalar) a = run_rays_in_lanes<Spec, float>(*d);
        else if constexpr (V == Variant::rays_in_lanes) a = run_rays_in_lanes<Spec, f8>(*d);
        else if constexpr (V == Variant::prims_in_lanes) a = run_prims_in_lanes<Spec, f8>(*d);
        else a = run_simd16<Spec>(*d, V);  // the AVX-512 translation unit's loop (one call per pass)
        benchmark::DoNotOptimize(a);
      }
      const double tests = double(d->tests());
      st.counters["tests_per_s"] = benchmark::Counter(tests, benchmark::Counter::kIsIterationInvariantRate);
      st.counters["ops_per_test"] = opt;
      st.counters["hit_fraction"] = double(a.hits) / tests;
      if constexpr (is_simd16(V)) {
        st.counters["instructions_per_test"] = mix.instructions;
        st.counters["div_per_test"] = mix.div;
        st.counters["sqrt_per_test"] = mix.sqrt;
      }
    }});
  }
}

// One pair per kernel family: bench_<family>_scalar.cpp and bench_<family>_simd.cpp.
void register_basic_scalar();
void register_basic_simd();
void register_planar_scalar();
void register_planar_simd();
void register_quadric_scalar();
void register_quadric_simd();
void register_solver_scalar();
void register_solver_simd();
void register_wide_node(bool simd16);  // bench_wide_node.cpp: the 8-wide BVH node's slab test (8 lanes; also 16)
void register_simd16();                // bench_simd16.cpp: the 16-lane rows (nothing without them)
void register_instructions(bool simd16);  // bench_instructions.cpp: division, square root and FMA at 8 and 16 lanes (with the 16-lane rows)
// Every benchmark; the 16-lane rows when `simd16` (bench/simd16.hpp: isa_choice).
inline void register_all_benchmarks(bool simd16) {
  register_basic_scalar();
  register_basic_simd();
  register_planar_scalar();
  register_planar_simd();
  register_quadric_scalar();
  register_quadric_simd();
  register_solver_scalar();
  register_solver_simd();
  if (simd16) register_simd16();
  // Grouped by kernel, method and case, each group where its first row was registered, its rows in
  // registration order (scalar, 8 lanes, 16 lanes).
  auto& p = pending_benchmarks();
  std::map<std::string, std::size_t> first;
  for (std::size_t i = 0; i < p.size(); ++i) first.emplace(p[i].group, i);
  std::stable_sort(p.begin(), p.end(), [&](const PendingBenchmark& a, const PendingBenchmark& b) { return first[a.group] < first[b.group]; });
  for (auto& b : p) register_benchmark(b.name, std::move(b.run));
  p.clear();
  register_wide_node(simd16);
  register_instructions(simd16);
}

}  // namespace rb::bench
