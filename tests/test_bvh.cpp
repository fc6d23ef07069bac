// The BVH against the loop over all objects (the oracle), its boxes, packets against single
// rays and watertightness of the robust traversal (its layout, hostile inputs and adversarial trees:
// tests/test_bvh_trees.cpp).
#include "bvh/slab.hpp"
#include "scene/csg_scene.hpp"
#include "scene/sources.hpp"
#include "soa/groups.hpp"
#include "tracer/accel.hpp"
#include "tracer/mesh_leaves.hpp"
#include "tracer/ray_sets.hpp"
#include "bvh_test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <stdexcept>

namespace {

using namespace rb;
using namespace rbtest_bvh;

// `sparse`: a scene whose bounds are mostly empty (diffuse and random rays may all miss); its
// primary rays must still hit.
void check_all_modes(const scene::Scene& s, std::size_t count, tracer::Model model = tracer::Model::automatic, bool sparse = false) {
  const tracer::SceneAccel a = tracer::SceneAccel::build(s, tracer::make_plan(s, model));
  for (auto set : {tracer::RaySet::primary, tracer::RaySet::shadow, tracer::RaySet::diffuse, tracer::RaySet::random}) {
    const RaySoA rays = tracer::make_rays(s, a, set, count, 7);
    const bool any = set == tracer::RaySet::shadow;
    const auto ref = brute(a, rays, any);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.count; ++i) hits += ref[i].prim != kNoPrim;
    if (set == tracer::RaySet::primary || (set != tracer::RaySet::shadow && !sparse)) {
      EXPECT_GT(hits, 0u) << tracer::ray_set_name(set);
    }
    for (int packet : {1, 8, 16, 64, 256})
      for (bvh::Slab slab : {bvh::Slab::conservative, bvh::Slab::fast, bvh::Slab::robust}) {
      const tracer::TraceOptions o = opts(packet, slab, any);
      std::vector<HitRec> h(rays.size());
      a.trace(rays, 0, rays.size(), h.data(), o);
      const std::string what = std::string(tracer::ray_set_name(set)) + " packet " + std::to_string(packet) + " " + bvh::slab_name(slab) +
                               " " + tracer::model_name(model);
      expect_same(h, ref, rays.count, any, what);
      // The counted traversal gives the same answers.
      bvh::TraceCounters c;
      std::vector<HitRec> hc(rays.size());
      a.trace_counted(rays, 0, rays.size(), hc.data(), o, c);
      expect_same(hc, ref, rays.count, any, what + " counted");
      EXPECT_GT(c.nodes, 0u);
    }
  }
}

// A closed mesh on a two-triangle floor (diffuse rays bounce between them: a convex mesh alone
// is never hit by its own bounce rays).
scene::Scene mesh_on_floor() {
  scene::Scene s = icosphere(3);
  const auto base = std::uint32_t(s.verts.size());
  for (Vec3d p : {Vec3d{-4, -1.5, -4}, Vec3d{4, -1.5, -4}, Vec3d{4, -1.5, 4}, Vec3d{-4, -1.5, 4}}) s.verts.push_back(p);
  s.triangles.push_back({{base, base + 1, base + 2}, 0});
  s.triangles.push_back({{base, base + 2, base + 3}, 0});
  return s;
}

TEST(Bvh, MeshEqualsBruteForceForEveryRaySetAndMode) { check_all_modes(mesh_on_floor(), 512); }

TEST(Bvh, MixedAnalyticSceneEqualsBruteForce) {
  for (auto m : {tracer::Model::automatic, tracer::Model::fast, tracer::Model::exact}) check_all_modes(mixed(3), 512, m);
}

// Primitives the plan stores apart, in double, in leaves of their own: traced by the mesh path (a
// triangle-only scene) and by the table of leaf functions (with spheres beside them), every ray
// set, packet size and slab test as the oracle.
TEST(Bvh, PrimitivesStoredApartEqualBruteForce) {
  scene::Scene s = scene::precision_scene("scattered");
  const tracer::Plan mesh = tracer::make_plan(s, tracer::Model::automatic);
  ASSERT_FALSE(mesh.kinds[0].split.empty());
  check_all_modes(s, 128, tracer::Model::automatic, true);
  for (int i = 0; i < 8; ++i) s.spheres.push_back({s.camera.at + Vec3d{3.0 * i - 12, 0.5, 2.0 - i}, 0.4 + 0.1 * i, 0});
  const tracer::Plan p = tracer::make_plan(s, tracer::Model::automatic);
  ASSERT_FALSE(p.kinds[0].split.empty());
  check_all_modes(s, 128, tracer::Model::automatic, true);
}

// The same primitives stored apart in double as a whole (the plan's other storage), and with a
// leaf that no origin of its own holds in float: a floor 2e4 across, which float rounds by more than
// the tolerance of the small meshes on it in any frame, goes apart with the far meshes and its leaf
// stays in double beside the local frames.
TEST(Bvh, PrimitivesApartInDoubleAndInLocalFramesEqualBruteForce) {
  scene::Scene s = scene::precision_scene("scattered");
  auto traced = [](const scene::Scene& sc, bool local) {
    tracer::Plan p = tracer::make_plan(sc, tracer::Model::automatic);
    p.kinds[0].split_local = local;
    const tracer::SceneAccel a = tracer::SceneAccel::build(sc, p);
    const RaySoA rays = tracer::make_rays(sc, a, tracer::RaySet::primary, 256, 7);
    const auto ref = brute(a, rays, false);
    for (int packet : {1, 8, 64}) {
      std::vector<HitRec> h(rays.size());
      a.trace(rays, 0, rays.size(), h.data(), opts(packet, bvh::Slab::conservative, false));
      expect_same(h, ref, rays.count, false, "packet " + std::to_string(packet) + (local ? " local" : " double"));
    }
    return std::pair{a.apart_deep(tracer::Kind::triangle), ref};
  };
  const auto [deep64, hits64] = traced(s, false);
  const auto [deep_local, hits_local] = traced(s, true);
  EXPECT_EQ(deep64, 2400u);
  EXPECT_EQ(deep_local, 0u);
  // Both storages hit the same triangles, at distances within float's rounding of the far meshes.
  std::size_t hits = 0;
  for (std::size_t i = 0; i < hits64.size(); ++i) {
    EXPECT_EQ(hits64[i].prim, hits_local[i].prim) << i;
    if (hits64[i].prim == kNoPrim) continue;
    ++hits;
    EXPECT_NEAR(hits64[i].t, hits_local[i].t, 1e-5 * double(hits64[i].t)) << i;
  }
  EXPECT_GT(hits, 0u);
  const auto base = std::uint32_t(s.verts.size());
  const Vec3d c = s.camera.at;
  for (Vec3d p : {Vec3d{-1e4, -50, -1e4}, Vec3d{1e4, -50, -1e4}, Vec3d{0, -50, 1e4}}) s.verts.push_back(c + p);
  s.triangles.push_back({{base, base + 1, base + 2}, 0});
  const tracer::Plan p = tracer::make_plan(s, tracer::Model::automatic);
  ASSERT_TRUE(std::binary_search(p.kinds[0].split.begin(), p.kinds[0].split.end(), std::uint32_t(s.triangles.size() - 1)))
      << p.kinds[0].split_reason;
  const tracer::SceneAccel a = tracer::SceneAccel::build(s, p);
  EXPECT_GE(a.apart_deep(tracer::Kind::triangle), 1u);
  EXPECT_LT(a.apart_deep(tracer::Kind::triangle), 2400u);
  check_all_modes(s, 128, tracer::Model::automatic, true);
}

TEST(Bvh, GeneratedSceneEqualsBruteForce) { check_all_modes(scene::generate_spd("balls", 1), 256); }

TEST(Bvh, EveryBoxContainsItsChildrenAndPrimitives) {
  for (const auto& s : {icosphere(2), mixed(5)}) {
    const tracer::SceneAccel a = tracer::SceneAccel::build(s);
    const auto& N = a.bin.nodes;
    ASSERT_FALSE(N.empty());
    auto inside = [](const float* lo, const float* hi, const float* clo, const float* chi) {
      for (int k = 0; k < 3; ++k)
        if (!(lo[k] <= clo[k] && chi[k] <= hi[k])) return false;
      return true;
    };
    std::size_t prims = 0;
    for (const auto& n : N) {
      if (!n.leaf()) {
        EXPECT_TRUE(inside(n.lo, n.hi, N[n.first].lo, N[n.first].hi));
        EXPECT_TRUE(inside(n.lo, n.hi, N[n.first + 1].lo, N[n.first + 1].hi));
        continue;
      }
      for (std::size_t j = 0; j < 8; ++j) {
        const std::uint32_t id = a.slot_id(n.kind, std::size_t(n.first) * 8 + j);
        if (id == UINT32_MAX) continue;
        ++prims;
        const scene::Bounds b = kinds::AllKinds::at<scene::Bounds>(tracer::tag_kind(n.kind), [&]<class K>() { return K::bounds(s, id); });
        float lo[3], hi[3];
        kinds::frame_box(b, a.origin(), lo, hi);
        EXPECT_TRUE(inside(n.lo, n.hi, lo, hi));
      }
    }
    EXPECT_EQ(prims, s.primitive_count());
    // Wide nodes: every child box contains the boxes of its own children.
    for (const auto& w : a.wide.nodes)
      for (int c = 0; c < 8; ++c) {
        if (w.child[c] == bvh::kEmpty || bvh::is_leaf(w.child[c])) continue;
        const auto& ch = a.wide.nodes[w.child[c]];
        for (int d = 0; d < 8; ++d) {
          if (ch.child[d] == bvh::kEmpty) continue;
          const float lo[3] = {w.b[0][c], w.b[2][c], w.b[4][c]}, hi[3] = {w.b[1][c], w.b[3][c], w.b[5][c]};
          const float clo[3] = {ch.b[0][d], ch.b[2][d], ch.b[4][d]}, chi[3] = {ch.b[1][d], ch.b[3][d], ch.b[5][d]};
          EXPECT_TRUE(inside(lo, hi, clo, chi));
        }
      }
  }
}

TEST(Bvh, PacketsGiveTheSameHitsAsSingleRays) {
  const scene::Scene s = icosphere(3);
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  for (auto set : {tracer::RaySet::primary, tracer::RaySet::diffuse, tracer::RaySet::random}) {
    const RaySoA rays = tracer::make_rays(s, a, set, 1024, 11);
    std::vector<HitRec> one(rays.size()), p8(rays.size()), p16(rays.size());
    a.trace(rays, 0, rays.size(), one.data(), opts(1));
    a.trace(rays, 0, rays.size(), p8.data(), opts(8));
    a.trace(rays, 0, rays.size(), p16.data(), opts(16));
    for (std::size_t i = 0; i < rays.count; ++i) {
      EXPECT_EQ(one[i].t, p8[i].t) << i;
      EXPECT_EQ(one[i].t, p16[i].t) << i;
    }
  }
}

// The closest hit is one answer whatever the traversal: every packet size, slab test and the
// brute-force loop give the same primitive and the same bits of t for every ray. Covered: faces
// meeting a ray at one distance (rays aimed at the shared vertices and edge midpoints of a closed
// mesh, where the least code must win the tie), polygons and CSG solids (whose scalar single-ray
// query must give the bits of the 8-lane one that packets run), and a mixed analytic scene in its
// fast and its exact model (double kernels).
TEST(Bvh, ClosestHitIsTheSameForEveryPacketSizeAndTheOracle) {
  struct Case {
    std::string name;
    scene::Scene s;
    tracer::Model model = tracer::Model::automatic;
  };
  std::vector<Case> cases;
  cases.push_back({"icosphere vertices", icosphere(2, {0.25, -0.5, 0.125}, 1.5)});
  cases.push_back({"gears", scene::generate_spd("gears", 1)});
  cases.push_back({"mixed exact", mixed(5), tracer::Model::exact});
  cases.push_back({"mixed fast", mixed(5), tracer::Model::fast});
  cases.push_back({"csg die", scene::load_scene("csg:die")});
  cases.push_back({"csg torus box", scene::load_scene("csg:torus_box")});
  for (const Case& c : cases) {
    const tracer::SceneAccel a = tracer::SceneAccel::build(c.s, tracer::make_plan(c.s, c.model));
    RaySoA rays;
    if (c.name == "icosphere vertices") {
      // From three points around the sphere through every vertex and edge midpoint, the rays of
      // one eye side by side (so that a packet's rays share their origin).
      const std::vector<Vec3d>& v = c.s.verts;
      std::vector<Vec3d> targets(v.begin(), v.end());
      for (const auto& t : c.s.triangles)
        for (int e = 0; e < 3; ++e) targets.push_back((v[t.v[std::size_t(e)]] + v[t.v[std::size_t((e + 1) % 3)]]) * 0.5);
      const Vec3d eyes[] = {{0.3, 0.2, 6.0}, {-5.0, 1.0, -2.0}, {2.0, -6.0, 1.0}};
      for (const Vec3d& eye : eyes)
        for (const Vec3d& t : targets) rays.push(a.frame_ray(eye, t - eye));
    } else {
      rays = tracer::make_rays(c.s, a, tracer::RaySet::primary, 4096, 3);
      const RaySoA diffuse = tracer::make_rays(c.s, a, tracer::RaySet::diffuse, 4096, 3);
      for (std::size_t i = 0; i < diffuse.count; ++i) rays.push(diffuse.get(i));
    }
    const auto ref = brute(a, rays, false);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.count; ++i) hits += ref[i].prim != kNoPrim;
    EXPECT_GT(hits, rays.count / 4) << c.name;
    for (int packet : {1, 8, 16, 64, 256})
      for (bvh::Slab slab : {bvh::Slab::conservative, bvh::Slab::robust}) {
        std::vector<HitRec> h(rays.size());
        a.trace(rays, 0, rays.size(), h.data(), opts(packet, slab));
        std::size_t bad = 0;
        for (std::size_t i = 0; i < rays.count; ++i)
          if ((h[i].prim != ref[i].prim || std::bit_cast<std::uint32_t>(h[i].t) != std::bit_cast<std::uint32_t>(ref[i].t)) && ++bad <= 3)
            ADD_FAILURE() << c.name << ", packet " << packet << ", " << bvh::slab_name(slab) << ", ray " << i << ": t " << h[i].t
                          << " prim " << h[i].prim << ", brute force t " << ref[i].t << " prim " << ref[i].prim;
        EXPECT_EQ(bad, 0u) << c.name << ", packet " << packet << ", " << bvh::slab_name(slab);
      }
  }
}

// Any-hit packets whose rays share an octant but spread over the scene (shadow rays towards one
// light from a grid of points): at nodes where at most a few of a packet's rays remain, they go on
// one by one. The same hit or miss as brute force, plain and counted, with rays that end before
// the mesh and invalid rays among them.
TEST(Bvh, AnyHitPacketsThatGoOnRayByRayGiveTheSameAnswers) {
  const scene::Scene s = mesh_on_floor();
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> J(-0.02f, 0.02f);
  RaySoA rays;
  for (int z = 0; z < 48; ++z)
    for (int x = 0; x < 48; ++x) {
      const Vec3f o{-6.0f + 0.25f * float(x), 4.0f, -6.0f + 0.25f * float(z)}, d{0.1f + J(rng), -1.0f, 0.05f + J(rng)};
      const int k = (48 * z + x) % 37;
      if (k == 5) rays.push(o, d, 2.0f, 1.0f);  // an empty interval
      else if (k == 11) rays.push(o, d, 0.0f, 2.5f);  // ends before the mesh
      else rays.push(o, d);
    }
  const auto ref = brute(a, rays, true);
  std::size_t hits = 0;
  for (std::size_t i = 0; i < rays.count; ++i) hits += ref[i].prim != kNoPrim;
  EXPECT_GT(hits, rays.count / 4);
  EXPECT_LT(hits, rays.count * 3 / 4);
  for (int packet : {8, 16, 64, 256})
    for (bvh::Slab slab : {bvh::Slab::conservative, bvh::Slab::robust}) {
      const tracer::TraceOptions o = opts(packet, slab, true);
      std::vector<HitRec> h(rays.size()), hc(rays.size());
      a.trace(rays, 0, rays.size(), h.data(), o);
      const std::string what = "packet " + std::to_string(packet) + " " + bvh::slab_name(slab);
      expect_same(h, ref, rays.count, true, what);
      bvh::TraceCounters c;
      a.trace_counted(rays, 0, rays.size(), hc.data(), o, c);
      expect_same(hc, ref, rays.count, true, what + " counted");
    }
}

// Packets whose rays start far apart walk two rays at once: the same hits as single rays, bit for
// bit, closest and any hit, with invalid rays among a packet's rays (which the walkers skip), and
// groups of 8 with no valid ray or with one, the last.
TEST(Bvh, RaysThatStartApartGiveTheSameHitsAsSingleRays) {
  const scene::Scene s = mesh_on_floor();
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> U(-4.0f, 4.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  RaySoA rays;
  for (int i = 0; i < 2048; ++i) {
    const Vec3f o{U(rng), U(rng) * 0.5f, U(rng)}, d{U(rng), U(rng), U(rng)};
    const int k = i % 64;
    if (k >= 8 && k < 16) rays.push(o, d, 2.0f, 1.0f);     // a group of none
    else if (k >= 16 && k < 23) rays.push(o, d, nan, 1.0f);  // ... of one, the last
    else if (k != 23 && i % 5 == 0) rays.push(o, d, 1.0f, 0.5f);
    else rays.push(o, d);
  }
  for (bool any : {false, true})
    for (int packet : {8, 64}) {
      std::vector<HitRec> one(rays.size()), p(rays.size());
      a.trace(rays, 0, rays.size(), one.data(), opts(1, bvh::Slab::conservative, any));
      a.trace(rays, 0, rays.size(), p.data(), opts(packet, bvh::Slab::conservative, any));
      std::size_t hits = 0;
      for (std::size_t i = 0; i < rays.count; ++i) {
        hits += one[i].prim != kNoPrim;
        EXPECT_EQ(one[i].prim != kNoPrim, p[i].prim != kNoPrim) << i << " any " << any << " packet " << packet;
        if (!any) {
          EXPECT_EQ(one[i].t, p[i].t) << i << " packet " << packet;
          EXPECT_EQ(one[i].prim, p[i].prim) << i << " packet " << packet;
        }
      }
      EXPECT_GT(hits, rays.count / 8);
      for (std::size_t i = 8; i < 16; ++i) EXPECT_EQ(p[i].prim, kNoPrim);
    }
}

TEST(Bvh, RaySetsAreReproducibleFromTheSeed) {
  const scene::Scene s = icosphere(2);
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  const RaySoA x = tracer::make_rays(s, a, tracer::RaySet::diffuse, 300, 5), y = tracer::make_rays(s, a, tracer::RaySet::diffuse, 300, 5);
  const RaySoA z = tracer::make_rays(s, a, tracer::RaySet::diffuse, 300, 6);
  ASSERT_EQ(x.count, y.count);
  for (std::size_t i = 0; i < x.count; ++i) EXPECT_EQ(x.dx[i], y.dx[i]);
  bool differ = x.count != z.count;
  for (std::size_t i = 0; i < std::min(x.count, z.count) && !differ; ++i) differ = x.dx[i] != z.dx[i];
  EXPECT_TRUE(differ);
}

// Rays from inside a closed mesh must all hit it: the default (conservative) slab test and the
// robust one with the watertight triangle test, including rays aimed exactly at vertices and at
// edges' midpoints, from inside and from a camera outside.
TEST(Bvh, DefaultAndRobustTraversalLetNoRayThroughAClosedMesh) {
  const Vec3d c{0.25, -0.5, 0.125};
  const scene::Scene s = icosphere(3, c, 3.0);
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  RaySoA rays;
  std::mt19937_64 g(42);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int i = 0; i < 2000; ++i) rays.push(to_float(c + Vec3d{U(g), U(g), U(g)}), to_float(Vec3d{U(g), U(g), U(g)}));
  for (const auto& v : s.verts) rays.push(to_float(c), to_float(v - c));  // exactly at every vertex
  for (const auto& t : s.triangles) rays.push(to_float(c), to_float((s.verts[t.v[0]] + s.verts[t.v[1]]) * 0.5 - c));  // edge midpoints
  for (int packet : {1, 8, 16, 64, 256})
    for (bvh::Slab slab : {bvh::Slab::conservative, bvh::Slab::robust}) {
      std::vector<HitRec> h(rays.size());
      a.trace(rays, 0, rays.size(), h.data(), opts(packet, slab));
      std::size_t leaks = 0;
      for (std::size_t i = 0; i < rays.count; ++i) leaks += h[i].prim == kNoPrim;
      EXPECT_EQ(leaks, 0u) << "packet " << packet << " " << bvh::slab_name(slab);
    }
}

}  // namespace

namespace {

// The surface at a hit, field by field, bit for bit.
void expect_same_surface(const kinds::Surface& a, const kinds::Surface& b, const std::string& what) {
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a.p.x), std::bit_cast<std::uint64_t>(b.p.x)) << what;
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a.p.y), std::bit_cast<std::uint64_t>(b.p.y)) << what;
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a.p.z), std::bit_cast<std::uint64_t>(b.p.z)) << what;
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(std::bit_cast<std::uint32_t>(a.ng[c]), std::bit_cast<std::uint32_t>(b.ng[c])) << what;
    EXPECT_EQ(std::bit_cast<std::uint32_t>(a.ns[c]), std::bit_cast<std::uint32_t>(b.ns[c])) << what;
  }
  EXPECT_EQ(a.mat, b.mat) << what;
}

}  // namespace

// What shading asks of every hit, kept or shortened where it costs most: a polygon's unit normal,
// geometric normal and extent from its batch (computed once from all its vertices), a triangle's
// extent with one square root, a sphere's, a triangle's and a torus' normal normalised once. Each
// gives the bits of the long way, so images do not change.
TEST(Surface, ShortcutsGiveTheLongWaysBits) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // Polygons: the gears' (many vertices each) and the checkerboard's floor.
  for (const scene::Scene& s : {scene::generate_spd("gears", 1), scene::lecture_scene("checkerboard")}) {
    ASSERT_FALSE(s.polygons.empty()) << s.name;
    kinds::PolygonKind::Batch b;
    kinds::SlotIds ids;
    for (std::uint32_t i = 0; i < s.polygons.size(); ++i) ids.push_back(i);
    kinds::PolygonKind::build(b, s, std::move(ids), {0, 0, 0}, 0, false, false);
    for (std::uint32_t i = 0; i < s.polygons.size(); i += 7) {
      kinds::HitQuery q;
      q.scene = &s;
      const auto& pg = s.polygons[i];
      const Vec3d a = s.poly_verts[pg.first], c = s.poly_verts[pg.first + pg.count / 2];
      q.p = a + (c - a) * u(rng) + Vec3d{1e-3, -2e-3, 5e-4};
      q.ray = make_ray(Vec3f{0, 0, 0}, Vec3f{0.3f, -0.9f, 0.1f});
      const kinds::Surface slow = kinds::PolygonKind::surface(q, i);
      const double slow_extent = kinds::PolygonKind::extent(q, i);
      EXPECT_EQ(slow_extent, kinds::PolygonKind::feature(s, i).extent);
      q.batch = &b;
      expect_same_surface(kinds::PolygonKind::surface(q, i), slow, s.name + " polygon " + std::to_string(i));
      EXPECT_EQ(kinds::PolygonKind::extent(q, i), slow_extent) << s.name << " polygon " << i;
    }
  }
  // Triangles: the bunny's and a tessellated teapot's; each hit at a point off its centre, with
  // the normal normalised once against unit_d, then unit_or of the result.
  for (const scene::Scene& s : {scene::load_scene(std::string(RB_SOURCE_DIR) + "/data/meshes/stanford-bunny.obj"), scene::generate_spd("teapot", 1)}) {
    kinds::HitQuery q;
    q.scene = &s;
    q.ray = make_ray(Vec3f{0, 0, 0}, Vec3f{0.3f, -0.9f, 0.1f});
    for (std::uint32_t i = 0; i < s.triangles.size(); ++i) {
      ASSERT_EQ(kinds::TriangleKind::extent(q, i), kinds::TriangleKind::feature(s, i).extent) << s.name << " triangle " << i;
      const auto& t = s.triangles[i];
      const Vec3d a = s.verts[t.v[0]], b = s.verts[t.v[1]], c = s.verts[t.v[2]];
      q.p = (a + b + c) * (1.0 / 3.0) + (b - a) * (0.2 * u(rng)) + Vec3d{1e-4, -3e-4, 2e-4};
      const kinds::Surface got = kinds::TriangleKind::surface(q, i);
      const Vec3d n = kinds::detail::unit_d(cross(b - a, c - a));
      const Vec3d p = kinds::detail::onto_plane(q.p, n, a);
      const Vec3f ng = kinds::detail::unit_or(n, -q.ray.d);
      for (int k = 0; k < 3; ++k) {
        ASSERT_EQ(std::bit_cast<std::uint64_t>(got.p[k]), std::bit_cast<std::uint64_t>(p[k])) << s.name << " triangle " << i;
        ASSERT_EQ(std::bit_cast<std::uint32_t>(got.ng[k]), std::bit_cast<std::uint32_t>(ng[k])) << s.name << " triangle " << i;
      }
    }
  }
  // A degenerate triangle (its vertices on a line) has no normal: the one against the ray.
  {
    scene::Scene s;
    s.verts = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
    s.triangles.push_back({{0, 1, 2}, 0});
    kinds::HitQuery q;
    q.scene = &s;
    q.ray = make_ray(Vec3f{0, 0, 0}, Vec3f{0.3f, -0.9f, 0.1f});
    q.p = {1, 1, 1};
    const kinds::Surface got = kinds::TriangleKind::surface(q, 0);
    EXPECT_TRUE(got.ng.x == -q.ray.d.x && got.ng.y == -q.ray.d.y && got.ng.z == -q.ray.d.z);
  }
  // Tori: points around the tube (and on its centre circle), against unit_d and unit_or of the
  // vector from the tube's centre.
  {
    scene::Scene s;
    s.tori.push_back({{3.0, -1.5, 6400000.25}, {0.2, 1.0, -0.3}, 2.0, 0.5, 0});
    for (int k = 0; k < 400; ++k) {
      kinds::HitQuery q;
      q.scene = &s;
      q.ray = make_ray(Vec3f{0, 0, 0}, Vec3f{0.6f, 0.0f, -0.8f});
      const auto& t = s.tori[0];
      const Vec3d w = kinds::TorusKind::unit_axis(t);
      const Vec3d e = kinds::detail::unit_d(cross(w, Vec3d{1, 0, 0}));
      const double phi = 6.283185307179586 * u(rng);
      const Vec3d radial = e * std::cos(phi) + cross(w, e) * std::sin(phi);
      const Vec3d off{u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5};
      q.p = t.c + radial * t.R + (k == 0 ? Vec3d{0, 0, 0} : off * (2.0 * t.r));
      const kinds::Surface got = kinds::TorusKind::surface(q, 0);
      const Vec3d rel = q.p - t.c;
      const Vec3d rad = rel - w * dot(rel, w);
      const double rl = std::sqrt(dot(rad, rad));
      const Vec3d ring = rl > 0 ? t.c + rad * (t.R / rl) : t.c;
      const Vec3d n = kinds::detail::unit_d(q.p - ring);
      kinds::Surface want;
      want.p = rl > 0 && dot(n, n) > 0 ? ring + n * t.r : q.p;
      want.ng = want.ns = kinds::detail::unit_or(q.p - ring, -q.ray.d);
      want.mat = t.mat;
      expect_same_surface(got, want, "torus point " + std::to_string(k));
    }
  }
  // Spheres: points around the centre (and at it), against unit_d and unit_or of the radial vector.
  scene::Scene s;
  s.spheres.push_back({{6400000.3, -2.7, 1e-3}, 1.7, 0});
  s.spheres.push_back({{0.1, 0.2, 0.3}, 1e-30, 0});
  for (std::uint32_t i = 0; i < 2; ++i)
    for (int k = 0; k < 200; ++k) {
      const auto& sp = s.spheres[i];
      kinds::HitQuery q;
      q.scene = &s;
      q.ray = make_ray(Vec3f{0, 0, 0}, Vec3f{0.6f, 0.0f, -0.8f});
      const Vec3d off{u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5};
      q.p = k == 0 ? sp.c : sp.c + off * (sp.r * 2.0);
      const kinds::Surface got = kinds::SphereKind::surface(q, i);
      kinds::Surface want;
      const Vec3d n = kinds::detail::unit_d(q.p - sp.c);
      want.p = dot(n, n) > 0 ? sp.c + n * sp.r : q.p;
      want.ng = want.ns = kinds::detail::unit_or(q.p - sp.c, -q.ray.d);
      want.mat = sp.mat;
      expect_same_surface(got, want, "sphere " + std::to_string(i) + " point " + std::to_string(k));
    }
}

// A miss has no surface: the empty one (zero point and normals, material 0), not a call through
// the kinds' table with a kind that is not there.
TEST(Surface, AMissHasTheEmptySurface) {
  const scene::Scene s = scene::lecture_scene("checkerboard");
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  const Ray<float> r = make_ray(Vec3f{0, 0, 0}, Vec3f{0.3f, -0.9f, 0.1f});
  const kinds::Surface sf = a.surface({std::numeric_limits<float>::infinity(), bvh::kNoPrim}, r);
  EXPECT_TRUE(sf.p.x == 0 && sf.p.y == 0 && sf.p.z == 0);
  EXPECT_TRUE(sf.ng.x == 0 && sf.ng.y == 0 && sf.ng.z == 0 && sf.ns.x == 0 && sf.ns.y == 0 && sf.ns.z == 0);
  EXPECT_EQ(sf.mat, 0u);
  EXPECT_EQ(sf.err, 0.0);
}

// A shadow ray asks an occluder for its material alone (SceneAccel::material): for every kind's
// hits, with or without the CSG leaf carried, the material the whole surface gives.
TEST(Surface, MaterialAloneIsTheSurfacesMaterial) {
  std::vector<scene::Scene> scenes;
  for (const std::string& n : scene::lecture_scene_names()) scenes.push_back(scene::lecture_scene(n));
  for (const std::string& n : scene::csg_scene_names()) scenes.push_back(scene::csg_scene(n));
  for (const std::string& n : scene::spd_names()) scenes.push_back(scene::generate_spd(n, 1));
  std::map<kinds::Kind, std::size_t> hits_of;
  std::size_t scenes_with_materials = 0;
  for (const scene::Scene& s : scenes) {
    const tracer::SceneAccel a = tracer::SceneAccel::build(s);
    std::set<std::uint32_t> seen;
    for (const tracer::RaySet set : {tracer::RaySet::primary, tracer::RaySet::random}) {
      const RaySoA rays = tracer::make_rays(s, a, set, 2048, 3);
      std::vector<HitRec> h(rays.count);
      a.trace(rays, 0, rays.count, h.data(), tracer::TraceOptions{});
      for (std::size_t i = 0; i < rays.count; ++i) {
        const std::string what = s.name + " ray " + std::to_string(i);
        const Ray<float> r = rays.get(i);
        ASSERT_EQ(a.material(h[i], r), a.surface(h[i], r).mat) << what;
        const HitRec bare{h[i].t, h[i].prim};  // no leaf carried: the CSG query runs again
        ASSERT_EQ(a.material(bare, r), a.surface(bare, r).mat) << what;
        if (h[i].prim == kNoPrim) continue;
        ++hits_of[kinds::kind_of(h[i].prim)];
        seen.insert(a.material(h[i], r));
      }
    }
    scenes_with_materials += seen.size() > 1;
  }
  // Kinds of every shape the embedded scenes hold were hit, and most scenes hit several materials
  // (an index taken from the wrong array would show).
  for (const kinds::Kind k : {kinds::Kind::sphere, kinds::Kind::polygon, kinds::Kind::triangle, kinds::Kind::csg})
    EXPECT_GT(hits_of[k], 100u) << int(k);
  EXPECT_GT(hits_of[kinds::Kind::cone] + hits_of[kinds::Kind::cylinder], 100u);
  EXPECT_GT(scenes_with_materials, scenes.size() / 2);
}

// A CSG hit carries the leaf its surface is on (HitRec::aux, the tag of the closest-hit query), so
// shading does not run the tree's query again. The surface from the carried leaf has the material and
// the normal (to float rounding: the query run again may round t differently where contraction
// differs) of the surface the query run again finds: for every single ray (the same scalar query),
// and for packets (the 8-lane query) except where the two queries meet a leaf's edge differently.
TEST(Surface, CsgHitsCarryTheLeafTheirSurfaceIsOn) {
  for (const std::string& name : scene::csg_scene_names()) {
    const scene::Scene s = scene::csg_scene(name);
    const tracer::SceneAccel a = tracer::SceneAccel::build(s);
    const RaySoA rays = tracer::make_rays(s, a, tracer::RaySet::primary, 4096, 5);
    for (int packet : {1, 8}) {
      std::vector<HitRec> h(rays.count);
      tracer::TraceOptions o;
      o.packet = packet;
      a.trace(rays, 0, rays.count, h.data(), o);
      std::size_t csg = 0, same_leaf = 0, same_dir = 0;
      for (std::size_t i = 0; i < rays.count; ++i) {
        if (h[i].prim == kNoPrim || kinds::kind_of(h[i].prim) != kinds::Kind::csg) continue;
        ++csg;
        const std::string what = name + " packet " + std::to_string(packet) + " ray " + std::to_string(i);
        ASSERT_NE(h[i].aux, 0.0f) << what;
        const kinds::Surface carried = a.surface(h[i], rays.get(i));
        const kinds::Surface again = a.surface({h[i].t, h[i].prim}, rays.get(i));
        same_leaf += carried.mat == again.mat;
        same_dir += dot(carried.ng, again.ng) > 0.9999f;
        if (packet == 1) {
          EXPECT_GT(dot(carried.ng, again.ng), 0.9999f) << what;
        }
      }
      EXPECT_GT(csg, rays.count / 10) << name;
      const double share = packet == 1 ? 1.0 : 0.999;
      EXPECT_GE(double(same_leaf), share * double(csg)) << name << " packet " << packet;
      EXPECT_GE(double(same_dir), share * double(csg)) << name << " packet " << packet;
    }
  }
}
