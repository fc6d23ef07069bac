// The kernel benchmarks' 16-lane AVX-512 loops (bench/simd16.hpp) against the 8-lane AVX2 ones on
// the benchmarks' own data: every spec, both mappings, hit, miss and half: the same hits, and the
// same sum of hit distances up to the order of the summation (bit for bit per lane in the `exact`
// preset; with contraction GCC fuses 16- and 8-lane code differently). Skipped where the build or
// the CPU has no AVX-512 (the `debug` preset builds none); the ISA choice is checked everywhere.
#include "bench/simd16.hpp"
#include "bench/specs_all.hpp"
#include "bvh/slab.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

namespace rb::test {
namespace {

using bench::Case;
using bench::Variant;

TEST(Simd16, IsaChoiceFollowsTheBuildAndTheCpu) {
  const bool can = bench::simd16_built() && bench::simd16_cpu();
  EXPECT_EQ(bench::isa_choice("auto").simd16, can);
  EXPECT_EQ(bench::isa_choice("auto").name, can ? "avx512" : "avx2");
  EXPECT_FALSE(bench::isa_choice("avx2").simd16);
  if (can) EXPECT_TRUE(bench::isa_choice("avx512").simd16);
  else EXPECT_THROW(bench::isa_choice("avx512"), std::invalid_argument);
  EXPECT_THROW(bench::isa_choice("sse"), std::invalid_argument);
}

template <class Spec>
void same_as_eight_lanes(int& checked) {
  for (Case c : {Case::hit, Case::miss, Case::half}) {
    const auto d = bench::make_bench_data<Spec>(c);
    const std::string what = std::string(Spec::kernel) + "/" + Spec::method + "/" + bench::case_name(c);
    auto expect_same = [&](const bench::Acc& a16, const bench::Acc& a8, const char* mapping) {
      EXPECT_EQ(a16.hits, a8.hits) << what << " " << mapping;
      EXPECT_NEAR(a16.tsum, a8.tsum, 1e-4 * std::fabs(a8.tsum) + 1e-6) << what << " " << mapping;
      EXPECT_NEAR(a16.uvsum, a8.uvsum, 1e-4 * std::fabs(a8.uvsum) + 1e-6) << what << " " << mapping;
      ++checked;
    };
    expect_same(bench::run_simd16<Spec>(d, Variant::rays_in_lanes16), bench::run_rays_in_lanes<Spec, f8>(d), "rays in lanes");
    if constexpr (bench::max_prim_lanes<Spec>() >= 16)
      expect_same(bench::run_simd16<Spec>(d, Variant::prims_in_lanes16), bench::run_prims_in_lanes<Spec, f8>(d), "primitives in lanes");
  }
}

TEST(Simd16, EverySpecGivesTheEightLaneResults) {
#ifndef RB_HAVE_SIMD16
  GTEST_SKIP() << "this build has no AVX-512 loops";
#else
  if (!bench::simd16_cpu()) GTEST_SKIP() << "this CPU lacks AVX-512 F, CD, DQ, BW or VL";
  int checked = 0, specs = 0, prims16 = 0;
  bench::for_every_spec([&]<class Spec>() {
    same_as_eight_lanes<Spec>(checked);
    ++specs;
    prims16 += bench::max_prim_lanes<Spec>() >= 16;
  });
  EXPECT_GE(specs, 30);
  EXPECT_EQ(checked, 3 * (specs + prims16));  // every spec x case x mapping
#endif
}

// The 8-wide node test in one 16-lane register (bvh/slab16.hpp) against the 8-lane test, both forms:
// random boxes (some flat, some empty slots as the builder writes them, some touching the ray's
// origin plane), rays in every octant with components down to zero, tmax finite or infinite.
TEST(Simd16, NodeTestGivesTheEightLaneHitsAndEntries) {
#ifndef RB_HAVE_SIMD16
  GTEST_SKIP() << "this build has no AVX-512 code";
#else
  if (!bench::simd16_cpu()) GTEST_SKIP() << "this CPU lacks AVX-512 F, CD, DQ, BW or VL";
  std::mt19937 g(20261205);
  std::uniform_real_distribution<float> U(-1, 1), S(0, 0.5f);
  std::uniform_int_distribution<int> pick(0, 9);
  const float inf = std::numeric_limits<float>::infinity();
  int tests = 0, hits = 0;
  for (int i = 0; i < 4000; ++i) {
    alignas(64) bvh::WNode n{};
    for (int c = 0; c < 8; ++c) {
      const int kind = pick(g), flat = pick(g) % 3;
      for (int a = 0; a < 3; ++a) {
        const float m = U(g), h = kind == 1 && a == flat ? 0.0f : S(g);  // kind 1: flat along one axis
        n.b[2 * a][c] = kind == 0 ? inf : m - h;                           // kind 0: an empty slot
        n.b[2 * a + 1][c] = kind == 0 ? -inf : m + h;
      }
    }
    // Towards a child's centre (jittered) or one of its corners (where the entry on one axis equals
    // the exit on another but for rounding) most of the time, so that both outcomes are common.
    const Vec3f o{U(g) * 2, U(g) * 2, U(g) * 2};
    const int k = pick(g) % 8, aim_kind = pick(g);
    float aim[3];
    for (int a = 0; a < 3; ++a)
      aim[a] = aim_kind < 4 ? (n.b[2 * a][k] + n.b[2 * a + 1][k]) / 2 + U(g) * 0.3f : n.b[2 * a + (pick(g) & 1)][k];
    Vec3f d = aim_kind < 8 && std::isfinite(aim[0]) ? Vec3f{aim[0], aim[1], aim[2]} - o : Vec3f{U(g), U(g), U(g)};
    for (float* x : {&d.x, &d.y, &d.z})
      if (pick(g) == 0) *x = pick(g) < 5 ? 0.0f : *x * 1e-20f;  // axis-parallel or nearly
    if (d.x == 0 && d.y == 0 && d.z == 0) d.z = 1;
    const Ray<float> r = make_ray(o, d, 0.0f, inf);
    const float tmax = pick(g) < 3 ? S(g) * 8 : inf;
    for (bool robust : {false, true}) {
      const bvh::SlabRay sr = bvh::SlabRay::make(r);
      f8 tn8;
      const unsigned b8 = robust ? bvh::slab8<true>(n, sr, tmax, tn8) : bvh::slab8<false>(n, sr, tmax, tn8);
      float tn16[8], e8[8];
      tn8.store_unaligned(e8);
      const unsigned b16 = bench::simd16_node_test(n, r, tmax, robust, tn16);
      ASSERT_EQ(b16, b8) << "node " << i << (robust ? " robust" : " fast");
      for (int c = 0; c < 8; ++c) EXPECT_EQ(tn16[c], e8[c]) << "node " << i << " child " << c << (robust ? " robust" : " fast");
      hits += __builtin_popcount(b8);
      tests += 8;
    }
  }
  // Both outcomes thousands of times.
  EXPECT_GT(hits, 2000);
  EXPECT_GT(tests - hits, 2000);
#endif
}

// The instruction rows' 16-lane chains (bench/simd16_instructions.cpp), which price the report's
// divisions and square roots, compute what they claim: eight chains of one correctly rounded
// operation from the seed, summed in pairs; the same sum in scalar float, bit for bit.
TEST(Simd16, InstructionChainsComputeTheirOperation) {
#ifndef RB_HAVE_SIMD16
  GTEST_SKIP() << "this build has no AVX-512 code";
#else
  if (!bench::simd16_cpu()) GTEST_SKIP() << "this CPU lacks AVX-512 F, CD, DQ, BW or VL";
  for (const bench::Instr k : bench::kInstrs)
    for (const long steps : {0L, 1L, 7L, 1000L}) {
      const float seed = 1.5f, b = 1.0f + 1e-7f * seed;
      float a[8] = {seed};
      for (int j = 1; j < 8; ++j) a[j] = a[j - 1] + b;
      for (long n = 0; n < steps; ++n)
        for (float& x : a) x = k == bench::Instr::fma ? std::fma(x, b, b) : k == bench::Instr::div ? x / b : std::sqrt(x);
      const float want = ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]));
      EXPECT_EQ(bench::simd16_instruction_pass(k, steps, seed), want) << bench::instr_name(k) << " x " << steps;
    }
#endif
}

}  // namespace
}  // namespace rb::test
