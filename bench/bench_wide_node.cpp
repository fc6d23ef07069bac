// Kernel benchmark of the 8-wide BVH node's slab test (bvh/slab.hpp): 256 rays x 64 nodes of 8
// random child boxes (all L1-resident), every ray against every node, fast (FMA form) and robust
// (Ize 2013). Counter `box_tests_per_s`: ray-box tests per second (8 per node test), one thread.
// Named with three parts (wide_node_slab/VARIANT/l1) so the scalar-vs-SIMD table leaves it out.
// With the 16-lane rows (--isa), also the same test in one 16-lane AVX-512 register (bvh/slab16.hpp:
// fast16, robust16), on the same nodes and rays; that pass sets up each ray's 16-lane form inside
// the timed loop (once per 64 node tests), the 8-lane rows outside it.
#include "bench/harness.hpp"
#include "bench/register.hpp"
#include "bench/simd16.hpp"
#include "bvh/slab.hpp"

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

namespace rb::bench {

namespace {
// 64 nodes of 8 random child boxes and 256 rays towards them, from the benchmark seed.
struct NodeData {
  std::vector<bvh::WNode, xsimd::aligned_allocator<bvh::WNode, 32>> nodes;
  std::vector<Ray<float>> rays;
};
NodeData node_data() {
  NodeData d;
  std::mt19937 g(kBenchSeed);
  std::uniform_real_distribution<float> U(-1, 1), S(0.05f, 0.6f);
  d.nodes.resize(kBenchPrims);
  for (auto& n : d.nodes)
    for (int c = 0; c < 8; ++c) {
      for (int a = 0; a < 3; ++a) {
        const float m = U(g), h = S(g);
        n.b[2 * a][c] = m - h;
        n.b[2 * a + 1][c] = m + h;
      }
      n.child[c] = std::uint32_t(c);
    }
  for (std::size_t i = 0; i < kBenchRays; ++i) d.rays.push_back(make_ray(Vec3f{U(g), U(g), -3.f}, Vec3f{U(g) * 0.3f, U(g) * 0.3f, 1.f}));
  return d;
}

void count_tests(benchmark::State& st, std::uint64_t hits) {
  const double tests = double(kBenchRays * kBenchPrims * 8);
  st.counters["box_tests_per_s"] = benchmark::Counter(tests, benchmark::Counter::kIsIterationInvariantRate);
  st.counters["hit_fraction"] = double(hits) / (tests * double(st.iterations()));
}

template <bool Robust>
void wide_node_slab(benchmark::State& st) {
  const NodeData d = node_data();
  const auto& nodes = d.nodes;
  std::vector<bvh::SlabRay> rays;
  for (const auto& r : d.rays) rays.push_back(bvh::SlabRay::make(r));
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
  count_tests(st, hits);
}

#ifdef RB_HAVE_SIMD16
template <bool Robust>
void wide_node_slab16(benchmark::State& st) {
  const NodeData d = node_data();
  std::uint64_t hits = 0;
  for (auto _ : st) {
    const unsigned acc = simd16_node_pass<Robust>(d.nodes.data(), d.nodes.size(), d.rays.data(), d.rays.size(), 1e30f);
    benchmark::DoNotOptimize(acc);
    hits += acc;
  }
  count_tests(st, hits);
}
#endif
}  // namespace

void register_wide_node([[maybe_unused]] bool simd16) {
  auto add = [](const char* name, void (*fn)(benchmark::State&)) { register_benchmark(name, fn); };
  add("wide_node_slab/fast/l1", wide_node_slab<false>);
  add("wide_node_slab/robust/l1", wide_node_slab<true>);
#ifdef RB_HAVE_SIMD16
  if (simd16) {
    add("wide_node_slab/fast16/l1", wide_node_slab16<false>);
    add("wide_node_slab/robust16/l1", wide_node_slab16<true>);
  }
#endif
}

}  // namespace rb::bench
