// The packet walk in 16 AVX-512 lanes (tracer/traverse_mesh16.cpp) against the 8-lane single-ray
// walk on the same trees: coherent packets of 16, 64 and 256 rays over triangle meshes (a scanned
// mesh, a closed sphere, and meshes far from the origin whose triangles are stored apart in local
// frames or in double, which the 16-lane walk tests as two 8-lane halves), closest and any hit, the
// fast slab test where trace_range would take it and the robust one always. Closest hits are
// canonical (bvh/hit.hpp), so every ray's t and primitive must be equal bit for bit; any hit must
// agree on hit or miss, at a distance no nearer than the closest hit's and within the ray's
// interval (any-hit leaves test two rays at a time in 16 lanes, one in each half). Rays include zero
// and tiny direction components, finite and infinite tmax, origins inside the meshes, and invalid
// rays. Built in the `exact` preset without the tracer's other walks (rb_tracer_core); skipped where
// the build or the CPU has no AVX-512.
#include "scene/sources.hpp"
#include "tracer/accel.hpp"
#include "tracer/traversal.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace rb::test {
namespace {

using bvh::HitRec;
using bvh::kNoPrim;

// `packets` packets of `size` rays, each in one direction octant: a quarter from outside the
// scene's box aimed into it, a quarter from inside it, half from a distance at one of the `targets`
// triangles (all of them when empty), spread over a few of its sizes.
RaySoA coherent_rays(const tracer::SceneAccel& a, const scene::Scene& s, int size, int packets, std::uint64_t seed,
                     const std::vector<std::uint32_t>& targets) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const scene::Bounds b = s.bounds();
  const double lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
  const float inf = std::numeric_limits<float>::infinity();
  RaySoA rays;
  for (int p = 0; p < packets; ++p) {
    const int oct = int(rng() % 8);
    const double sign[3] = {oct & 1 ? -1.0 : 1.0, oct & 2 ? -1.0 : 1.0, oct & 4 ? -1.0 : 1.0};
    // The packet's first origin, the point it aims at, and the spread of both.
    double base[3], aim[3], spread[3];
    if (p % 4 < 2) {
      const std::uint32_t t = targets.empty() ? std::uint32_t(rng() % s.triangles.size()) : targets[rng() % targets.size()];
      const Vec3d A = s.verts[s.triangles[t].v[0]], B = s.verts[s.triangles[t].v[1]], C = s.verts[s.triangles[t].v[2]];
      const Vec3d c = (A + B + C) * (1.0 / 3);
      const double size_t3 = std::max({length(B - A), length(C - B), length(A - C)}), r = 4 * size_t3 + 1e-9 * length(c);
      const double cc[3] = {c.x, c.y, c.z};
      for (int k = 0; k < 3; ++k) {
        aim[k] = cc[k];
        base[k] = cc[k] - sign[k] * 40 * r * (0.2 + u(rng));
        spread[k] = r;
      }
    } else {
      const bool inside = p % 4 == 3;
      for (int k = 0; k < 3; ++k) {
        const double e = hi[k] - lo[k];
        base[k] = inside ? lo[k] + e * (0.3 + 0.4 * u(rng)) : (sign[k] > 0 ? lo[k] - 0.3 * e : hi[k] + 0.3 * e);
        aim[k] = lo[k] + e * u(rng);
        spread[k] = 0.05 * e;
      }
    }
    for (int r = 0; r < size; ++r) {
      double o[3], d[3];
      for (int k = 0; k < 3; ++k) {
        o[k] = base[k] + spread[k] * (u(rng) - 0.5);
        d[k] = sign[k] * std::fabs(aim[k] + spread[k] * (u(rng) - 0.5) - o[k]);  // one octant
      }
      const int kind = int(rng() % 16);
      const int k = int(rng() % 3);
      if (kind == 0) d[k] = sign[k] > 0 ? 0.0 : -0.0;  // a zero component, with its octant's sign
      if (kind == 1) d[k] *= 1e-30;                     // a tiny one
      double tmax = std::numeric_limits<double>::infinity();
      if (kind == 2) tmax = 60 * spread[0] * u(rng);  // may stop short of the target
      Ray<float> fr = a.frame_ray({o[0], o[1], o[2]}, {d[0], d[1], d[2]}, 0.0, tmax);
      if (kind == 3) fr.tmin = inf, fr.tmax = 0;  // invalid: an empty interval
      rays.push(fr);
    }
  }
  return rays;
}

// The 8-lane single-ray walk over the same tree and leaves: the reference.
template <bool Any>
std::vector<HitRec> single_rays(const tracer::SceneAccel& a, const tracer::MeshLeaves& leaves, const RaySoA& rays) {
  std::vector<HitRec> out(rays.size());
  bvh::TraceCounters c;
  bvh::trace_singles<bvh::Slab::robust, Any, false>(a.wide, leaves, rays, 0, rays.size(), out.data(), c);
  return out;
}

// Counts of the rays checked, those that hit, and those that hit a triangle stored apart.
struct Tally {
  int rays = 0, hits = 0, apart = 0;
};

void same_hits_in_16_lanes(const std::string& what, const scene::Scene& s, const tracer::Plan& plan, Tally& n,
                           const std::vector<std::uint32_t>& targets = {}) {
  const tracer::SceneAccel a = tracer::SceneAccel::build(s, plan);
  const tracer::MeshLeaves* leaves = a.mesh_leaves();
  ASSERT_NE(leaves, nullptr) << what << ": a triangle mesh traced with Woop in float";
  for (const int size : {16, 64, 256}) {
    const RaySoA rays = coherent_rays(a, s, size, size == 256 ? 24 : 96, std::uint64_t(size) * 7 + s.triangles.size(), targets);
    for (const bool any : {false, true}) {
      const std::vector<HitRec> closest = single_rays<false>(a, *leaves, rays);
      const std::vector<HitRec> ref = any ? single_rays<true>(a, *leaves, rays) : closest;
      for (const bool robust : {false, true}) {
        std::vector<HitRec> out(rays.size(), HitRec{-1.0f, 12345u});
        int walked = 0;
        for (std::size_t i = 0; i + std::size_t(size) <= rays.count; i += std::size_t(size)) {
          // The fast form only where trace_range would take it (origins within the boxes' bound, tmin >= 0).
          const bool r = robust || bvh::needs_robust<bvh::Slab::conservative>(a.wide, rays, i, std::size_t(size));
          ASSERT_TRUE(bvh::shared_octant(rays, i, std::size_t(size)));
          tracer::trace_packet_simd16(a.wide, *leaves, rays, i, size, r, any, out.data());
          ++walked;
        }
        ASSERT_GT(walked, 0);
        const std::string label = what + ", packets of " + std::to_string(size) + (any ? ", any hit" : ", closest hit") +
                                  (robust ? ", robust test" : ", fast test where it applies");
        int bad = 0;
        for (std::size_t i = 0; i < rays.count && bad < 5; ++i) {
          // Any hit: hit or miss as the single ray, and a hit no nearer than the closest one and
          // within the ray's interval (another ray's hit, taken from the wrong lanes, is not).
          const bool same = any ? (out[i].prim == kNoPrim) == (ref[i].prim == kNoPrim) &&
                                      (out[i].prim == kNoPrim || (out[i].t >= closest[i].t && out[i].t <= rays.tmax[i]))
                                : out[i].prim == ref[i].prim && (out[i].t == ref[i].t || (std::isinf(out[i].t) && std::isinf(ref[i].t)));
          if (same) continue;
          ++bad;
          ADD_FAILURE() << label << ": ray " << i << " 16 lanes (t " << out[i].t << ", prim " << out[i].prim << ") against single rays (t "
                        << ref[i].t << ", prim " << ref[i].prim << ")";
        }
        n.rays += int(rays.count);
        for (std::size_t i = 0; i < rays.count; ++i) {
          if (out[i].prim == kNoPrim) continue;
          ++n.hits;
          n.apart += a.stored_apart(tracer::Kind::triangle, kinds::index_of(out[i].prim));
        }
      }
    }
  }
}

bool can_run() { return tracer::simd16_traversal_runs(); }

TEST(Trace16, PacketsGiveTheSingleRayHitsOnAScannedMeshAndASphere) {
  if (!can_run()) GTEST_SKIP() << "this build or CPU has no 16-lane traversal";
  Tally n;
  const scene::Scene bunny = scene::load_scene(std::string(RB_SOURCE_DIR) + "/data/meshes/stanford-bunny.obj");
  same_hits_in_16_lanes("bunny", bunny, tracer::make_plan(bunny, tracer::Model::automatic), n);
  scene::Scene ball;
  scene::add_icosphere(ball, {0.25, -0.5, 1.0}, 2.0, 4);
  same_hits_in_16_lanes("icosphere", ball, tracer::make_plan(ball, tracer::Model::automatic), n);
  EXPECT_GT(n.hits, n.rays / 3) << "most packets aim at the mesh";
  EXPECT_LT(n.hits, n.rays) << "some rays miss (short, invalid, or aimed past it)";
}

TEST(Trace16, PacketsGiveTheSingleRayHitsWhereTrianglesAreStoredApart) {
  if (!can_run()) GTEST_SKIP() << "this build or CPU has no 16-lane traversal";
  const scene::Scene s = scene::precision_scene("scattered");
  for (const bool local : {false, true}) {
    tracer::Plan p = tracer::make_plan(s, tracer::Model::automatic);
    ASSERT_FALSE(p.kinds[0].split.empty()) << "the far meshes are stored apart";
    p.kinds[0].split_local = local;
    Tally n;
    same_hits_in_16_lanes(local ? "far meshes in local frames" : "far meshes in double", s, p, n, p.kinds[0].split);
    EXPECT_GT(n.apart, n.rays / 10) << "the packets aimed at triangles stored apart hit them";
  }
}

// The choice of width: 16 lanes only for packets of 16 or more rays of a mesh traced in float,
// where the build and the CPU have them; 8 otherwise, and 1 for single rays.
TEST(Trace16, GroupLanesFollowTheOptionsTheSceneAndTheMachine) {
  scene::Scene ball;
  scene::add_icosphere(ball, {0, 0, 0}, 1.0, 2);
  const tracer::SceneAccel a = tracer::SceneAccel::build(ball, tracer::make_plan(ball, tracer::Model::automatic));
  tracer::TraceOptions o;
  o.lanes = 16;
  o.packet = 1;
  EXPECT_EQ(a.group_lanes(o), 1);
  o.packet = 8;
  EXPECT_EQ(a.group_lanes(o), 8);
  for (int p : {16, 64, 256}) {
    o.packet = p;
    EXPECT_EQ(a.group_lanes(o), can_run() ? 16 : 8) << p;
  }
  o.lanes = 8;
  EXPECT_EQ(a.group_lanes(o), 8);
  const scene::Scene spheres = scene::load_scene("spd:balls:1");
  const tracer::SceneAccel b = tracer::SceneAccel::build(spheres, tracer::make_plan(spheres, tracer::Model::automatic));
  EXPECT_EQ(b.mesh_leaves(), nullptr);
  o.lanes = 16;
  o.packet = 64;
  EXPECT_EQ(b.group_lanes(o), 8) << "only triangle meshes walk in 16 lanes";
}

}  // namespace
}  // namespace rb::test
