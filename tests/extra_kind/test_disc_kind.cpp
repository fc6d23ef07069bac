// A kind added in a test (tests/extra_kind/disc_kind.hpp): with its header and its line in the kind
// table, the tracer builds, plans, traces and shades it like an engine kind, beside triangles and
// spheres, in single rays and packets.
#include "tracer/accel.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace rb {
namespace {

using kinds::DiscIn;
using kinds::DiscKind;
using kinds::Kind;

// A floor of two triangles and a sphere, and (in the disc table, while it lives) `n` discs of every
// orientation above the floor.
struct DiscScene {
  scene::Scene s;
  DiscScene(int n, std::uint64_t seed) {
    s.materials.resize(3);
    s.verts = {{-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}};
    s.triangles = {{{0, 1, 2}, 0}, {{0, 2, 3}, 0}};
    s.spheres = {{{0, 0, 3}, 1.5, 1}};
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<DiscIn>& d = kinds::disc_table()[&s];
    for (int i = 0; i < n; ++i) {
      const Vec3d c{8 * u(rng), 8 * u(rng), 4 + 3 * u(rng)}, normal{u(rng), u(rng), u(rng) + 1e-3};
      d.push_back({c, normal, 0.3 + 0.5 * (u(rng) + 1), 2});
    }
  }
  ~DiscScene() { kinds::disc_table().erase(&s); }
  DiscScene(const DiscScene&) = delete;
  DiscScene& operator=(const DiscScene&) = delete;
};

// Rays from above towards the floor, every direction a little different.
RaySoA rays_down(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  RaySoA r;
  for (int i = 0; i < n; ++i) r.push(Vec3f{float(9 * u(rng)), float(9 * u(rng)), 12.f}, Vec3f{float(0.3 * u(rng)), float(0.3 * u(rng)), -1.f});
  return r;
}

// The disc hit in double, nearest first: the reference for a ray the tracer says hits a disc.
double disc_t(const DiscIn& d, const Ray<float>& r) {
  const Vec3d n = DiscKind::unit_normal(d), o = to_double(r.o), dir = to_double(r.d);
  const double t = dot(n, d.c - o) / dot(n, dir);
  const Vec3d p = o + dir * t - d.c;
  return dot(p, p) <= d.r * d.r ? t : std::numeric_limits<double>::infinity();
}

TEST(ExtraKind, TheKindTableHasTheTestKind) {
  EXPECT_EQ(kinds::kKinds, 8);
  EXPECT_EQ(int(DiscKind::id), 7);
  EXPECT_STREQ(kinds::kind_name(Kind::disc), "disc");
  Kind k = Kind::triangle;
  EXPECT_TRUE(kinds::parse_kind("disc", k));
  EXPECT_EQ(k, Kind::disc);
  const DiscScene ds(40, 1);
  const scene::Scene& s = ds.s;
  const auto counts = kinds::kind_counts(s);
  EXPECT_EQ(counts[std::size_t(Kind::disc)], 40u);
  EXPECT_EQ(counts[std::size_t(Kind::triangle)], 2u);
  EXPECT_EQ(counts[std::size_t(Kind::sphere)], 1u);
}

TEST(ExtraKind, ThePlanChoosesItsMethodAndSaysWhy) {
  const DiscScene ds(40, 2);
  const scene::Scene& s = ds.s;
  const tracer::Plan p = tracer::make_plan(s, tracer::Model::automatic);
  const tracer::KindPlan& kp = p.kinds[std::size_t(Kind::disc)];
  EXPECT_EQ(kp.count, 40u);
  EXPECT_EQ(kp.method, 0);
  EXPECT_FALSE(kp.f64);
  EXPECT_NE(p.text().find("disc"), std::string::npos) << p.text();
  EXPECT_NE(p.text().find("plane_radius"), std::string::npos) << p.text();
}

// Single rays, 8-ray packets and the any-hit query against the lecture's loop over every primitive
// (brute_force: the same leaf functions without the tree), and each disc hit against the disc in
// double; its surface lies on the disc's plane with the disc's normal and material.
TEST(ExtraKind, TracedLikeAnEngineKind) {
  const DiscScene ds(300, 3);
  const scene::Scene& s = ds.s;
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a.scene_prims(), 303u);
  EXPECT_GT(a.kind_bytes(Kind::disc), 300 * sizeof(float) * 7);
  const RaySoA rays = rays_down(4096, 4);
  std::size_t disc_hits = 0, sphere_hits = 0, floor_hits = 0;
  for (int packet : {1, 8}) {
    for (bool any : {false, true}) {
      std::vector<bvh::HitRec> hits(rays.size());
      tracer::TraceOptions o;
      o.packet = packet;
      o.any = any;
      a.trace(rays, 0, rays.size(), hits.data(), o);
      for (std::size_t i = 0; i < rays.count; ++i) {
        const Ray<float> r = rays.get(i);
        const bvh::HitRec want = a.brute_force(r, any);
        ASSERT_EQ(hits[i].prim == bvh::kNoPrim, want.prim == bvh::kNoPrim) << "ray " << i << " packet " << packet << " any " << any;
        if (any || want.prim == bvh::kNoPrim) continue;
        ASSERT_EQ(hits[i].prim, want.prim) << "ray " << i;
        ASSERT_EQ(hits[i].t, want.t) << "ray " << i;
        if (packet != 1) continue;
        const Kind k = kinds::kind_of(hits[i].prim);
        if (k == Kind::triangle) ++floor_hits;
        if (k == Kind::sphere) ++sphere_hits;
        if (k != Kind::disc) continue;
        ++disc_hits;
        const DiscIn& d = kinds::discs_of(s)[kinds::index_of(hits[i].prim)];
        const double t = disc_t(d, r);
        ASSERT_TRUE(std::isfinite(t)) << "ray " << i;
        EXPECT_NEAR(hits[i].t, t, 1e-5 * t) << "ray " << i;
        const kinds::Surface sf = a.surface(hits[i], r);
        const Vec3d n = DiscKind::unit_normal(d);
        EXPECT_NEAR(dot(sf.p - d.c, n), 0.0, 1e-12);
        EXPECT_NEAR(std::fabs(dot(to_double(sf.ng), n)), 1.0, 1e-6);
        EXPECT_EQ(sf.mat, 2u);
      }
    }
  }
  // The scene is such that every kind is hit (so that the comparison above covers each).
  EXPECT_GT(disc_hits, 500u);
  EXPECT_GT(sphere_hits, 20u);
  EXPECT_GT(floor_hits, 500u);
}

// A degenerate disc (zero radius, zero normal) is a defined miss and leaves the others' hits alone.
TEST(ExtraKind, DegenerateDiscsAreMissed) {
  DiscScene ds(50, 5);
  const scene::Scene& s = ds.s;
  kinds::disc_table()[&s].push_back({{0, 0, 8}, {0, 0, 1}, 0.0, 2});
  kinds::disc_table()[&s].push_back({{0, 0, 9}, {0, 0, 0}, 1.0, 2});
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  const RaySoA rays = rays_down(1024, 6);
  std::vector<bvh::HitRec> hits(rays.size());
  a.trace(rays, 0, rays.size(), hits.data(), tracer::TraceOptions{});
  for (std::size_t i = 0; i < rays.count; ++i) {
    if (hits[i].prim == bvh::kNoPrim || kinds::kind_of(hits[i].prim) != Kind::disc) continue;
    EXPECT_LT(kinds::index_of(hits[i].prim), 50u);
  }
}

}  // namespace
}  // namespace rb
