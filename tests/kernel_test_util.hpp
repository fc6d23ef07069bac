// Helpers shared by kernel tests: run a kernel with any number type on one float ray and
// primitive (broadcast to every lane) and read back lane results.
#pragma once

#include "core/counted.hpp"
#include "core/ray.hpp"
#include "soa/prims.hpp"
#include "soa/rays.hpp"

#include <gtest/gtest.h>

#include <cstring>

namespace rb::test {

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

// Every number type a kernel is instantiated with.
using AllNumbers = ::testing::Types<float, double, f8, d4, cfloat, cdouble, cf8, cd4>;

// The generic lambdas the typed tests run.
#define RB_KERNEL(fn) [](const auto& kr_, const auto& kp_) { return fn(kr_, kp_); }

}  // namespace rb::test
