// Helpers of the BVH tests (tests/test_bvh.cpp, tests/test_bvh_trees.cpp): scenes, the brute-force
// oracle, trace options and the comparison of two hit lists.
#pragma once

#include "scene/sources.hpp"
#include "tracer/accel.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace rbtest_bvh {

using namespace rb;
using bvh::HitRec;
using bvh::kNoPrim;

// A closed icosphere (shared vertices, consistent winding) of radius r at c.
inline scene::Scene icosphere(int levels, Vec3d c = {0, 0, 0}, double r = 1.0) {
  scene::Scene s;
  s.name = "icosphere";
  scene::add_icosphere(s, c, r, levels);
  return s;
}

// Spheres, cylinders, cones and polygons scattered in a box, a few of each kind overlapping.
inline scene::Scene mixed(std::uint64_t seed) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> U(-5, 5), R(0.1, 0.8);
  scene::Scene s;
  s.name = "mixed";
  for (int i = 0; i < 60; ++i) s.spheres.push_back({{U(g), U(g), U(g)}, R(g), 0});
  for (int i = 0; i < 40; ++i) {
    const Vec3d b{U(g), U(g), U(g)};
    const Vec3d a = b + Vec3d{R(g) * 2 - 0.8, R(g) * 2, R(g) - 0.4};
    const double rb = R(g);
    s.cones.push_back({b, rb, a, i % 2 ? rb : rb * 0.3, 0});  // even: frustum, odd: cylinder
  }
  for (int i = 0; i < 40; ++i) {
    const Vec3d c{U(g), U(g), U(g)};
    const int n = 3 + i % 5;
    const double r = R(g);
    s.polygons.push_back({std::uint32_t(s.poly_verts.size()), std::uint32_t(n), 0});
    for (int k = 0; k < n; ++k) {
      const double a = 6.283185307179586 * double(k) / double(n);
      const Vec3d p = i % 3 == 0 ? Vec3d{0, r * std::cos(a), r * std::sin(a)} : Vec3d{r * std::cos(a), 0.3 * r * std::sin(a), r * std::sin(a)};
      s.poly_verts.push_back(c + p);
    }
  }
  // Tori of several sizes and axes.
  for (int i = 0; i < 12; ++i) s.tori.push_back({{U(g), U(g), U(g)}, {U(g), U(g), U(g)}, 0.6 + 0.05 * i, 0.1 + 0.02 * i, 0});
  // A few triangles too.
  s.verts = {{-4, -4, -4}, {4, -4, -4}, {0, 4, -4}, {-4, -4, 4}, {4, -4, 4}};
  s.triangles = {{{0, 1, 2}, 0}, {{0, 3, 4}, 0}, {{0, 4, 1}, 0}};
  return s;
}

inline std::vector<HitRec> brute(const tracer::SceneAccel& a, const RaySoA& rays, bool any) {
  std::vector<HitRec> h(rays.size());
  for (std::size_t i = 0; i < rays.count; ++i) h[i] = a.brute_force(rays.get(i), any);
  return h;
}

inline tracer::TraceOptions opts(int packet, bvh::Slab slab = bvh::Slab::conservative, bool any = false) {
  tracer::TraceOptions o;
  o.packet = packet;
  o.any = any;
  o.slab_given = true;
  o.slab = slab;
  return o;
}

inline void expect_same(const std::vector<HitRec>& a, const std::vector<HitRec>& b, std::size_t n, bool any, const std::string& what) {
  std::size_t bad = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool ha = a[i].prim != kNoPrim, hb = b[i].prim != kNoPrim;
    bool ok = ha == hb;
    if (ok && ha && !any) ok = std::fabs(a[i].t - b[i].t) <= 1e-6f * std::max(1.0f, std::fabs(b[i].t));
    if (!ok && ++bad <= 3)
      ADD_FAILURE() << what << " ray " << i << ": " << a[i].t << " prim " << a[i].prim << " vs oracle " << b[i].t << " prim " << b[i].prim;
  }
  EXPECT_EQ(bad, 0u) << what;
}

}  // namespace rbtest_bvh
