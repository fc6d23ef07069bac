// Kernel benchmark of the 8-wide BVH node's slab test (bvh/slab.hpp): 256 rays x 64 nodes of 8
// random child boxes (all L1-resident), every ray against every node, fast (FMA form) and robust
// (Ize 2013). Counter `box_tests_per_s`: ray-box tests per second (8 per node test), one thread.
// Named with three parts (wide_node_slab/VARIANT/l1) so the scalar-vs-SIMD table leaves it out.
#include "bench/harness.hpp"
#include "bench/register.hpp"
#include "bvh/slab.hpp"

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

namespace rb::bench {

namespace {
template <bool Robust>
void wide_node_slab(benchmark::State& st) {
  std::mt19937 g(kBenchSeed);
  std::uniform_real_distribution<float> U(-1, 1), S(0.05f, 0.6f);
  std::vector<bvh::WNode, xsimd::aligned_allocator<bvh::WNode, 32>> nodes(kBenchPrims);
  for (auto& n : nodes)
    for (int c = 0; c < 8; ++c) {
      for (int a = 0; a < 3; ++a) {
        const float m = U(g), h = S(g);
        n.b[2 * a][c] = m - h;
        n.b[2 * a + 1][c] = m + h;
      }
      n.child[c] = std::uint32_t(c);
    }
  std::vector<bvh::SlabRay> rays;
  for (std::size_t i = 0; i < kBenchRays; ++i) rays.push_back(bvh::SlabRay::make(make_ray(Vec3f{U(g), U(g), -3.f}, Vec3f{U(g) * 0.3f, U(g) * 0.3f, 1.f})));
  std::uint64_t hits = 0;
  for (auto _ : st) {
    unsigned acc = 0;
    for (const auto& r : rays)
      for (const auto& n : nodes) {
        f8 tn;
        acc += unsigned(__builtin_popcount(bvh::slab8<Robust>(n, r, 1e30f, tn)));
      }
    benchmark::DoNotOptimize(acc);
    hits += acc;
  }
  const double tests = double(kBenchRays * kBenchPrims * 8);
  st.counters["box_tests_per_s"] = benchmark::Counter(tests, benchmark::Counter::kIsIterationInvariantRate);
  st.counters["hit_fraction"] = double(hits) / (tests * double(st.iterations()));
}
}  // namespace

void register_wide_node() {
  for (const char* name : {"wide_node_slab/fast/l1", "wide_node_slab/robust/l1"}) registered_names().push_back(name);
  benchmark::RegisterBenchmark("wide_node_slab/fast/l1", wide_node_slab<false>);
  benchmark::RegisterBenchmark("wide_node_slab/robust/l1", wide_node_slab<true>);
}

}  // namespace rb::bench
