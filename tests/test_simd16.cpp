// The kernel benchmarks' 16-lane AVX-512 loops (bench/simd16.hpp) against the 8-lane AVX2 ones on
// the benchmarks' own data: every spec, both mappings, hit, miss and half: the same hits, and the
// same sum of hit distances up to the order of the summation (bit for bit per lane in the `exact`
// preset; with contraction GCC fuses 16- and 8-lane code differently). Skipped where the build or
// the CPU has no AVX-512 (the `debug` preset builds none); the ISA choice is checked everywhere.
#include "bench/simd16.hpp"
#include "bench/specs_all.hpp"

#include <gtest/gtest.h>

#include <cmath>
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

}  // namespace
}  // namespace rb::test
