// Embree beside raybench: rays Embree would reject never reach it on any of its paths (single rays,
// 8/16-ray packets, streams; both devices; closest and any hit), and the tree Embree's builder makes
// (bench/embree_build.hpp), traced by raybench, finds what the loop over all objects finds.
#include "bench/embree_build.hpp"
#include "bench/embree_trace.hpp"
#include "bench/timed_trace.hpp"
#include "tracer/accel.hpp"
#include "scene/sources.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace {

using namespace rb;
using bvh::HitRec;
using bvh::kNoPrim;

// A closed octahedron-like mesh of 8 x 4^levels triangles (a subdivided octahedron pushed to the
// unit sphere) on a floor: small, closed, hit from everywhere.
scene::Scene embree_test_mesh(int levels) {
  scene::Scene s;
  s.name = "sphere mesh";
  std::vector<Vec3d> v;
  std::vector<std::array<Vec3d, 3>> f;
  const Vec3d X{1, 0, 0}, Y{0, 1, 0}, Z{0, 0, 1};
  for (int sx : {-1, 1})
    for (int sy : {-1, 1})
      for (int sz : {-1, 1}) f.push_back({X * double(sx), Y * double(sy), Z * double(sz)});
  for (int l = 0; l < levels; ++l) {
    std::vector<std::array<Vec3d, 3>> g;
    for (auto& t : f) {
      const Vec3d a = (t[0] + t[1]) * 0.5, b = (t[1] + t[2]) * 0.5, c = (t[2] + t[0]) * 0.5;
      g.push_back({t[0], a, c}); g.push_back({t[1], b, a}); g.push_back({t[2], c, b}); g.push_back({a, b, c});
    }
    f = g;
  }
  for (auto& t : f) {
    const auto base = std::uint32_t(s.verts.size());
    for (const Vec3d& p : t) s.verts.push_back(p * (1.0 / std::sqrt(dot(p, p))));
    s.triangles.push_back({{base, base + 1, base + 2}, 0});
  }
  const auto base = std::uint32_t(s.verts.size());
  for (Vec3d p : {Vec3d{-4, -1.5, -4}, Vec3d{4, -1.5, -4}, Vec3d{4, -1.5, 4}, Vec3d{-4, -1.5, 4}}) s.verts.push_back(p);
  s.triangles.push_back({{base, base + 1, base + 2}, 0});
  s.triangles.push_back({{base, base + 2, base + 3}, 0});
  return s;
}

// A ray stored as given (no validation): what a hostile caller could hand the adapter.
Ray<float> raw(Vec3f o, Vec3f d, float t0 = 0.f, float t1 = std::numeric_limits<float>::infinity()) {
  return {o, d, Vec3f{1.f / d.x, 1.f / d.y, 1.f / d.z}, t0, t1};
}

TEST(Embree, InvalidRaysReachNoEmbreePathAndMiss) {
  const scene::Scene s = embree_test_mesh(2);
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  const trace::EmbreeBuild e = trace::embree_build(a, 1);
  ASSERT_TRUE(e.ok) << e.why;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  // Interleaved: every fourth ray is a good one aimed at the sphere (t = 4 at the front).
  const std::vector<Ray<float>> bad = {
      raw({nan, 0, -5}, {0, 0, 1}),        raw({0, 0, -5}, {nan, 0, 1}),       raw({0, 0, -5}, {0, 0, 0}),
      raw({inf, 0, -5}, {0, 0, 1}),        raw({0, 0, -5}, {0, -inf, 1}),      raw({0, 0, -5}, {0, 0, 1}, 0.f, nan),
      raw({0, 0, -5}, {0, 0, 1}, nan, 9.f), raw({0, 0, -5}, {0, 0, 1}, 6.f, 2.f), raw({0, 0, -5}, {0, 0, 1}, -1.f, 9.f),
      raw({3e19f, 0, -5}, {0, 0, 1}),      raw({0, 0, -5}, {0, 0, 1}, inf, inf)};
  RaySoA rays;
  std::vector<bool> good;
  for (std::size_t i = 0; rays.count < 300; ++i) {
    if (i % 4 == 3) {
      rays.push(raw({0.01f * float(i % 7), 0.01f * float(i % 5), -5}, {0, 0, 1}));
      good.push_back(true);
    } else {
      rays.push(bad[i % bad.size()]);
      good.push_back(false);
    }
  }
  for (std::size_t i = 0; i < rays.count; ++i) EXPECT_EQ(trace::embree_valid(rays, i), bool(good[i])) << i;
  // raybench's answers for the good rays (its own filtering is test_bvh.cpp's).
  std::vector<HitRec> ours(round_up(rays.size(), 16));
  a.trace(rays, 0, rays.size(), ours.data(), tracer::TraceOptions{});
  std::size_t paths = 0;
  for (int packet : {1, 8, 16, 64, 256})
    for (bool coherent : {false, true})
      for (bool any : {false, true})
        for (const trace::EmbreeMode& m : trace::embree_modes(packet, coherent)) {
          std::vector<HitRec> h(round_up(rays.size(), 16), HitRec{-1.f, 123u});
          // Two calls, the second from a packet boundary, the first ending inside a group.
          trace::embree_trace(e, m, rays, 0, 256, h.data(), any);
          trace::embree_trace(e, m, rays, 256, rays.count, h.data(), any);
          ++paths;
          for (std::size_t i = 0; i < rays.count; ++i) {
            if (!good[i]) {
              EXPECT_EQ(h[i].prim, kNoPrim) << m.name(any) << " ray " << i;
              EXPECT_EQ(h[i].t, inf) << m.name(any) << " ray " << i;
            } else {
              ASSERT_NE(h[i].prim, kNoPrim) << m.name(any) << " ray " << i;
              if (!any) {
                EXPECT_NEAR(h[i].t, ours[i].t, 1e-4f * ours[i].t) << m.name(any) << " ray " << i;
              }
            }
          }
        }
  EXPECT_EQ(paths, 5u * 2u * 2u * std::size_t(trace::kEmbreeDevices));
  // The devices are what their configs ask for: the AVX2 one never runs 16-wide kernels.
  EXPECT_FALSE(e.devices[std::size_t(trace::EmbreeIsa::avx2)].native_ray16);
  EXPECT_NE(e.devices[std::size_t(trace::EmbreeIsa::avx2)].config.find("isa=avx2"), std::string::npos);
}

// Embree's builder's tree through raybench's traversal against the loop over all objects.
// `bounces`: whether diffuse rays are expected to hit (not on an open surface alone).
void expect_embree_tree_matches_brute(const scene::Scene& s, const std::string& builder, std::size_t count, bool bounces = true) {
  const tracer::Plan plan = tracer::make_plan(s, tracer::Model::automatic);
  const tracer::SceneAccel a = tracer::SceneAccel::build(s, plan, {}, trace::embree_builder(builder, s, plan, 1));
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a.bin.stats.leaf_hist.size(), 9u);  // leaves of 1..8 primitives only
  for (const bvh::BNode& n : a.bin.nodes) EXPECT_LE(n.count, 8u);
  for (auto set : {tracer::RaySet::primary, tracer::RaySet::shadow, tracer::RaySet::diffuse, tracer::RaySet::random}) {
    const RaySoA rays = tracer::make_rays(s, a, set, count, 11);
    const bool any = set == tracer::RaySet::shadow;
    std::size_t hits = 0;
    for (int packet : {1, 8, 16}) {
      tracer::TraceOptions o;
      o.packet = packet;
      o.any = any;
      std::vector<HitRec> h(round_up(rays.size(), 16));
      a.trace(rays, 0, rays.size(), h.data(), o);
      std::size_t bad = 0;
      for (std::size_t i = 0; i < rays.count; ++i) {
        const HitRec b = a.brute_force(rays.get(i), any);
        bool ok = (h[i].prim != kNoPrim) == (b.prim != kNoPrim);
        if (ok && b.prim != kNoPrim && !any) ok = std::fabs(h[i].t - b.t) <= 1e-6f * std::max(1.0f, std::fabs(b.t));
        hits += b.prim != kNoPrim;
        if (!ok && ++bad <= 3) ADD_FAILURE() << builder << " " << tracer::ray_set_name(set) << " packet " << packet << " ray " << i;
      }
      EXPECT_EQ(bad, 0u) << builder << " " << tracer::ray_set_name(set) << " packet " << packet;
    }
    if (set != tracer::RaySet::shadow && (bounces || set != tracer::RaySet::diffuse)) {
      EXPECT_GT(hits, 0u) << tracer::ray_set_name(set);
    }
  }
}

TEST(Embree, BuiltTreeGivesTheHitsOfBruteForce) {
  for (const char* b : {"embree", "embree-high"}) expect_embree_tree_matches_brute(embree_test_mesh(3), b, 256);
  // Several kinds: Embree's leaves of mixed kinds are split by kind.
  expect_embree_tree_matches_brute(scene::generate_spd("balls", 1), "embree", 256);
}

TEST(Embree, HighQualitySplitsTrianglesIntoMoreReferences) {
  // A long thin triangle fan: spatial splits pay, so Embree's high quality makes more references
  // than there are triangles (the split callback is used), and the tree still finds every hit.
  scene::Scene s;
  s.verts.push_back({0, 0, 0});
  for (int i = 0; i <= 200; ++i) {
    const double a = 1.5 * double(i) / 200.0;
    s.verts.push_back({10 * std::cos(a), 10 * std::sin(a), 0.01 * i});
  }
  for (std::uint32_t i = 1; i <= 200; ++i) s.triangles.push_back({{0, i, i + 1}, 0});
  const tracer::Plan plan = tracer::make_plan(s, tracer::Model::automatic);
  const tracer::SceneAccel hi = tracer::SceneAccel::build(s, plan, {}, trace::embree_builder("embree-high", s, plan, 1));
  const tracer::SceneAccel med = tracer::SceneAccel::build(s, plan, {}, trace::embree_builder("embree", s, plan, 1));
  EXPECT_EQ(med.bin.order.size(), s.triangles.size());
  EXPECT_GT(hi.bin.order.size(), s.triangles.size());
  expect_embree_tree_matches_brute(s, "embree-high", 256, false);
}

}  // namespace
