// Every SIMD lane equals the scalar float result for the same ray and primitive, in both SIMD
// mappings (rays in lanes, primitives in lanes), on seeded random rays that hit and miss.
// Bit for bit when built with -ffp-contract=off (the `exact` and `debug` presets); otherwise
// the hit masks may differ on at most 1 in 1000 pairs, and t (in its own ulps) and u, v (in
// ulps of 1.0) agree within kContractedUlps on the rest, since
// GCC contracts scalar and SIMD code into FMAs differently (docs/DESIGN.md section 6).
#include "bench/specs.hpp"
#include "kernel_test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace rb::test {
namespace {

// With contraction, the sphere quadratics' cancellation (B^2 - 4AC, v.v - t0^2) amplifies the
// single rounding an FMA removes: measured up to 271 ulps on these rays (release preset).
constexpr std::int64_t kContractedUlps = 1024;

template <class Spec>
void check_spec() {
  bench::Rng g(7 + std::strlen(Spec::method));
  std::vector<typename Spec::Input> in;
  for (int k = 0; k < 16; ++k) in.push_back(Spec::make(0, k, g));
  const auto prims = Spec::build(in);
  RaySoA rays;
  for (int i = 0; i < 512; ++i) {
    if (i % 4 == 0) rays.push(Spec::ray(i % 8 == 0 ? 0 : 1, g));
    else {
      const Vec3f o{bench::uni(g, -5, 15), bench::uni(g, -5, 5), bench::uni(g, -60, -40)};
      const Vec3f to{bench::uni(g, -2, 12), bench::uni(g, -2, 2), bench::uni(g, -5, 50)};
      rays.push(o, to - o);
    }
  }
  Tally rl{kContractedUlps}, pl{kContractedUlps};
  tally_lanes<Spec>(prims, rays, rl, pl);
  rl.expect_ok(std::string(Spec::kernel) + "/" + Spec::method + " rays in lanes");
  pl.expect_ok(std::string(Spec::kernel) + "/" + Spec::method + " prims in lanes");
}

TEST(SimdLanes, EqualScalarForEveryBasicKernel) {
  bench::for_each_spec([]<class Spec>() { check_spec<Spec>(); });
}

}  // namespace
}  // namespace rb::test
