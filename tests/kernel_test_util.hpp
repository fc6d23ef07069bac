// The test-support header: helpers shared by the kernel tests. Run a kernel with any number type
// on one float ray and primitive (broadcast to every lane) and read back lane results; measure
// ulp distances; tally SIMD lanes against the scalar result in both SIMD mappings.
// A classic include guard besides #pragma once: GCC may not honour #pragma once for a header
// read from the precompiled test header (tests/test_pch.hpp) when a test includes it again.
#pragma once
#ifndef RB_TESTS_KERNEL_TEST_UTIL_HPP
#define RB_TESTS_KERNEL_TEST_UTIL_HPP

#include "bench/ops_table.hpp"
#include "core/counted.hpp"
#include "core/ray.hpp"
#include "soa/prims.hpp"
#include "soa/rays.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

namespace rb::test {

inline const float kInfF = std::numeric_limits<float>::infinity();
inline const float kNaNF = std::numeric_limits<float>::quiet_NaN();
inline const double kInfD = std::numeric_limits<double>::infinity();

// The rows of the operations table (built once per test executable) and one row by its keys.
inline const std::vector<opstable::Row>& ops_rows() {
  static const auto r = opstable::build();
  return r;
}
inline const opstable::Row& find_row(const std::string& k, const std::string& m, const std::string& c, const std::string& n = "float") {
  for (const auto& r : ops_rows())
    if (r.kernel == k && r.method == m && r.kase == c && r.number == n) return r;
  ADD_FAILURE() << "no row " << k << "/" << m << "/" << c << "/" << n;
  static const opstable::Row none;
  return none;
}
// Golden op counts: add, mul, div, sqrt, cmp, minmax, select, fma.
using Golden = std::tuple<int, int, int, int, int, int, int, int>;
inline Golden gold(const OpCounts& o) {
  return {int(o.add), int(o.mul), int(o.div), int(o.sqrt), int(o.cmp), int(o.minmax), int(o.select), int(o.fma)};
}

struct HitF {
  bool hit;
  double t, u, v;
};

template <class F>
HitF lane_hit(const Hit<F>& h, int k) {
  return {lane_mask<F>(h.mask, k), double(lane(h.t, k)), double(lane(h.u, k)), double(lane(h.v, k))};
}

// Runs fn(Ray<F>, P<F>) with ray and primitive in every lane; checks that all lanes agree.
template <class F, template <class> class P, class Fn>
HitF run_one(Fn fn, const Ray<float>& r, const P<float>& p) {
  const Hit<F> h = fn(Ray<F>::broadcast(r), prim_cast<F>(p));
  const HitF h0 = lane_hit(h, 0);
  for (int k = 1; k < lanes_v<F>; ++k) {
    const HitF hk = lane_hit(h, k);
    EXPECT_EQ(hk.hit, h0.hit);
    EXPECT_TRUE(hk.t == h0.t || (std::isnan(hk.t) && std::isnan(h0.t)));
  }
  return h0;
}

// Built with -ffp-contract=off (the `exact` and `debug` presets): scalar == SIMD bit for bit.
#ifdef RB_FP_CONTRACT_off
inline constexpr bool kExact = true;
#else
inline constexpr bool kExact = false;
#endif

// Distance between two floats in units in the last place (0 when equal or both NaN; INT64_MAX when
// they differ and one is NaN or infinite).
inline std::int64_t ulp_distance(float a, float b) {
  if (a == b || (std::isnan(a) && std::isnan(b))) return 0;
  if (std::isnan(a) || std::isnan(b) || std::isinf(a) || std::isinf(b)) return INT64_MAX;
  std::int32_t ia, ib;
  std::memcpy(&ia, &a, 4);
  std::memcpy(&ib, &b, 4);
  if (ia < 0) ia = INT32_MIN - ia;
  if (ib < 0) ib = INT32_MIN - ib;
  return std::abs(std::int64_t(ia) - std::int64_t(ib));
}

// SIMD lanes against the scalar float result of the same ray and primitive. t is compared in ulps
// of t; u, v in ulps of max(1, |u|), so values near 0 are not over-weighted (u, v of barycentric
// forms lie in [0, 1]; a plane's u, v are unbounded). A lane whose
// distance exceeds `tol` (0 in the exact build) or a miss whose t is not +inf counts as bad.
struct Tally {
  std::int64_t tol = 0;  // allowed distance in contracted builds
  std::size_t pairs = 0, hits = 0, mask_diff = 0, bad = 0;
  std::int64_t max_ulp = 0;
  void add(const Hit<float>& s, bool hv, float tv, float uv, float vv) {
    ++pairs;
    hits += s.mask;
    if (s.mask != hv) { ++mask_diff; return; }
    if (!s.mask) { bad += tv != std::numeric_limits<float>::infinity(); return; }
    const double eps1 = std::ldexp(1.0, -23);
    const auto uvd = [&](float x, float y) {
      const double scale = std::max({1.0, std::fabs(double(x)), std::fabs(double(y))});
      return x == y ? std::int64_t(0) : std::int64_t(std::ceil(std::fabs(double(x) - double(y)) / (eps1 * scale)));
    };
    const std::int64_t d = std::max({ulp_distance(s.t, tv), uvd(s.u, uv), uvd(s.v, vv)});
    max_ulp = std::max(max_ulp, d);
    if (kExact ? d != 0 : d > tol) ++bad;
  }
  // The random rays hit sometimes and miss sometimes; masks agree (exact build) or differ on at
  // most 1 pair in 1000 (contracted); no bad lane.
  void expect_ok(const std::string& what) const {
    SCOPED_TRACE(what);
    EXPECT_GT(hits, pairs / 50) << "the random rays should hit sometimes";
    EXPECT_LT(hits, pairs) << "and miss sometimes";
    if (kExact) EXPECT_EQ(mask_diff, 0u);
    else EXPECT_LE(mask_diff * 1000, pairs);
    EXPECT_EQ(bad, 0u) << "max ulp " << max_ulp;
  }
};

// Every lane of Spec::run (a bench spec: run(ray, prim, batch, slot)) in both SIMD mappings,
// tallied against the scalar run: rays in lanes into `rl`, primitives in lanes into `pl`.
template <class Spec, class Batch, class Rays>
void tally_lanes(const Batch& prims, const Rays& rays, Tally& rl, Tally& pl) {
  for (std::size_t i = 0; i < rays.size(); i += 8)
    for (std::size_t j = 0; j < prims.size(); ++j) {
      const Hit<f8> h = Spec::run(rays.template packet<f8>(i), prims.template broadcast<f8>(j), prims, j);
      for (int k = 0; k < 8; ++k) {
        const Hit<float> s = Spec::run(rays.template packet<float>(i + std::size_t(k)), prims.template broadcast<float>(j), prims, j);
        rl.add(s, lane_mask<f8>(h.mask, k), lane(h.t, k), lane(h.u, k), lane(h.v, k));
      }
    }
  for (std::size_t i = 0; i < rays.size(); ++i)
    for (std::size_t j = 0; j < prims.size(); j += 8) {
      const Hit<f8> h = Spec::run(rays.template broadcast<f8>(i), prims.template load<f8>(j), prims, j);
      for (int k = 0; k < 8; ++k) {
        const std::size_t jk = j + std::size_t(k);
        const Hit<float> s = Spec::run(rays.template packet<float>(i), prims.template broadcast<float>(jk), prims, jk);
        pl.add(s, lane_mask<f8>(h.mask, k), lane(h.t, k), lane(h.u, k), lane(h.v, k));
      }
    }
}

// Every number type a kernel is instantiated with: the first kernels' typed tests (end to end with
// every Counted type) and the root lists.
using AllNumbers = ::testing::Types<float, double, f8, d4, cfloat, cdouble, cf8, cd4>;
// The value types: the typed tests of the planar, quadric and solver families. Counted<T> adds no
// arithmetic of its own: it computes exactly what T computes (checked per operation for every T by
// CountedValue in test_num.cpp), and every family kernel runs as Counted<float> and Counted<f8> in
// the operations table (test_ops.cpp and the families' golden counts), under ASan and UBSan in the
// `debug` preset. Under the sanitizers at -O0 each type added about 5 s of compile time per file.
using ValueNumbers = ::testing::Types<float, double, f8, d4>;

// The generic lambdas the typed tests run.
#define RB_KERNEL(fn) [](const auto& kr_, const auto& kp_) { return fn(kr_, kp_); }

}  // namespace rb::test

#endif  // RB_TESTS_KERNEL_TEST_UTIL_HPP
