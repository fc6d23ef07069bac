// Every SIMD lane equals the scalar float result for the same ray and primitive, in both SIMD
// mappings (rays in lanes, primitives in lanes), on seeded random rays that hit and miss.
// Bit for bit when built with -ffp-contract=off (the `exact` and `debug` presets); otherwise
// the hit masks may differ on at most 1 in 1000 pairs, and t (in its own ulps) and u, v (in
// ulps of 1.0) agree within kContractedUlps on the rest, since
// GCC contracts scalar and SIMD code into FMAs differently (DESIGN.md section 6).
#include "bench/specs.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace rb {
namespace {

#ifdef RB_FP_CONTRACT_off
constexpr bool kExact = true;
#else
constexpr bool kExact = false;
#endif

// With contraction, the sphere quadratics' cancellation (B^2 - 4AC, v.v - t0^2) amplifies the
// single rounding an FMA removes: measured up to 271 ulps on these rays (release preset).
constexpr std::int64_t kContractedUlps = 1024;

std::int64_t ulp_distance(float a, float b) {
  if (a == b) return 0;
  if (std::isnan(a) || std::isnan(b) || std::isinf(a) || std::isinf(b)) return INT64_MAX;
  std::int32_t ia, ib;
  std::memcpy(&ia, &a, 4);
  std::memcpy(&ib, &b, 4);
  if (ia < 0) ia = INT32_MIN - ia;
  if (ib < 0) ib = INT32_MIN - ib;
  return std::abs(std::int64_t(ia) - std::int64_t(ib));
}

struct Tally {
  std::size_t pairs = 0, hits = 0, mask_diff = 0, t_bad = 0;
  std::int64_t max_ulp = 0;
  void add(bool hs, float ts, float us, float vs, bool hv, float tv, float uv, float vv) {
    ++pairs;
    hits += hs;
    if (hs != hv) { ++mask_diff; return; }
    if (!hs) return;
    // t in ulps of t; u, v (in [0, 1]) in ulps of 1.0, so values near 0 are not over-weighted
    const double eps1 = std::ldexp(1.0, -23);
    const auto uvd = [&](float x, float y) {
      return x == y ? std::int64_t(0) : std::int64_t(std::ceil(std::fabs(double(x) - double(y)) / eps1));
    };
    const std::int64_t d = std::max({ulp_distance(ts, tv), uvd(us, uv), uvd(vs, vv)});
    max_ulp = std::max(max_ulp, d);
    if (kExact ? d != 0 : d > kContractedUlps) ++t_bad;
  }
};

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
  Tally rl, pl;
  for (std::size_t j = 0; j < prims.size(); j += 8) {
    for (std::size_t i = 0; i < rays.size(); i += 8) {
      for (int a = 0; a < 8; ++a)
        for (int b = 0; b < 8; ++b) {
          // scalar reference for ray i+a, primitive j+b
          const Hit<float> s = Spec::run(rays.packet<float>(i + a), prims.template broadcast<float>(j + b), prims, j + b);
          {
            // primitives in lanes: ray i+a against primitives j..j+7, lane b
            const Hit<f8> h = Spec::run(rays.broadcast<f8>(i + a), prims.template load<f8>(j), prims, j);
            pl.add(s.mask, s.t, s.u, s.v, lane_mask<f8>(h.mask, b), lane(h.t, b), lane(h.u, b), lane(h.v, b));
          }
          {
            // rays in lanes: rays i..i+7 against primitive j+b, lane a
            const Hit<f8> h = Spec::run(rays.packet<f8>(i), prims.template broadcast<f8>(j + b), prims, j + b);
            rl.add(s.mask, s.t, s.u, s.v, lane_mask<f8>(h.mask, a), lane(h.t, a), lane(h.u, a), lane(h.v, a));
          }
        }
    }
  }
  for (const Tally* t : {&rl, &pl}) {
    SCOPED_TRACE(std::string(Spec::kernel) + "/" + Spec::method + (t == &rl ? " rays in lanes" : " prims in lanes"));
    EXPECT_GT(t->hits, t->pairs / 50) << "the random rays should hit sometimes";
    EXPECT_LT(t->hits, t->pairs) << "and miss sometimes";
    if (kExact) {
      EXPECT_EQ(t->mask_diff, 0u);
      EXPECT_EQ(t->t_bad, 0u) << "max ulp " << t->max_ulp;
    } else {
      EXPECT_LE(t->mask_diff * 1000, t->pairs);
      EXPECT_EQ(t->t_bad, 0u) << "max ulp " << t->max_ulp;
    }
  }
}

TEST(SimdLanes, EqualScalarForEveryBasicKernel) {
  bench::for_each_spec([]<class Spec>() { check_spec<Spec>(); });
}

}  // namespace
}  // namespace rb
