// Model no more than a scene needs: the numerical profile and the plan (tracer/profile.hpp,
// tracer/plan.hpp) on scenes with known needs, the whole-scene accuracy of each model against the
// exact reference (the lab's family "scene"), and invariance: a scene moved far from the origin or
// scaled renders like the original under the auto model. Spawn offsets: test_plan_spawn.cpp.
#include "accuracy/lab.hpp"
#include "render/render.hpp"
#include "scene/camera.hpp"
#include "scene/sources.hpp"
#include "scene/scene_transform.hpp"
#include "tracer/accel.hpp"
#include "tracer/plan.hpp"
#include "tracer/profile.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

namespace {

using namespace rb;
using tracer::Model;
using kinds::Kind;

const tracer::KindPlan& kp(const tracer::Plan& p, Kind k) { return p.kinds[std::size_t(k)]; }
std::string method(const tracer::Plan& p, Kind k) {
  std::string n;
  kinds::AllKinds::each([&]<class K>() {
    if (K::id == k) n = K::methods[std::size_t(kp(p, k).method)].name;
  });
  return n;
}

TEST(Plan, APlainSceneKeepsWorldCoordinatesAndTheCheapMethods) {
  const scene::Scene s = scene::precision_scene("ball_ground");
  const tracer::Plan p = tracer::make_plan(s, Model::automatic);
  EXPECT_EQ(p.frame, tracer::FrameKind::world);
  EXPECT_EQ(method(p, Kind::sphere), "geometric");
  EXPECT_FALSE(kp(p, Kind::sphere).f64);
  EXPECT_FALSE(kp(p, Kind::sphere).f64_storage);
  EXPECT_EQ(p.slab, bvh::Slab::conservative);
  EXPECT_EQ(p.spawn, tracer::SpawnScheme::error_bound);
  // Every choice says why and cites its lab cases.
  for (Kind k : {Kind::sphere, Kind::polygon}) EXPECT_FALSE(kp(p, k).reason.empty());
  EXPECT_NE(kp(p, Kind::sphere).evidence.find("sphere/far_small_1e1"), std::string::npos);
  EXPECT_NE(p.text().find("geometric"), std::string::npos);
  EXPECT_EQ(p.json()["frame"]["kind"], "world");
}

TEST(Plan, AFarSceneIsRecentredAndNeedsNothingElse) {
  const tracer::Plan near = tracer::make_plan(scene::precision_scene("ball_ground"), Model::automatic);
  const tracer::Plan far = tracer::make_plan(scene::precision_scene("ball_ground_far"), Model::automatic);
  EXPECT_NE(far.frame, tracer::FrameKind::world);
  EXPECT_GT(std::fabs(far.origin.x), 6e6);
  // Relative to its frame the far copy is the near scene: the same methods.
  for (int k = 0; k < kinds::kKinds; ++k) {
    EXPECT_EQ(far.kinds[std::size_t(k)].method, near.kinds[std::size_t(k)].method) << k;
    EXPECT_EQ(far.kinds[std::size_t(k)].f64, near.kinds[std::size_t(k)].f64) << k;
  }
}

TEST(Plan, APlanetIsStoredInDouble) {
  const scene::Scene s = scene::precision_scene("planet");
  const tracer::Profile pr = tracer::make_profile(s);
  EXPECT_GT(pr.kinds[std::size_t(Kind::sphere)].scale_ratio, 1e6);
  const tracer::Plan p = tracer::make_plan(s, pr, Model::automatic);
  EXPECT_TRUE(kp(p, Kind::sphere).f64_storage);
  EXPECT_TRUE(kp(p, Kind::sphere).f64);
}

TEST(Plan, FarSmallSpheresThinToriAndFarCylindersGetTheirMethods) {
  const tracer::Plan sp = tracer::make_plan(scene::precision_scene("far_spheres"), Model::automatic);
  EXPECT_TRUE(kp(sp, Kind::sphere).f64);  // 5e5 radii away: beyond float's 1e5
  const tracer::Plan to = tracer::make_plan(scene::precision_scene("thin_torus"), Model::automatic);
  EXPECT_EQ(method(to, Kind::torus), "robust");
  EXPECT_TRUE(kp(to, Kind::torus).f64);
  const tracer::Plan cy = tracer::make_plan(scene::precision_scene("far_cylinders"), Model::automatic);
  EXPECT_EQ(method(cy, Kind::cylinder), "recentred");
  EXPECT_EQ(method(cy, Kind::cone), "recentred");
}

TEST(Plan, FastAndExactModels) {
  const scene::Scene s = scene::precision_scene("mixed_scales");
  const tracer::Plan f = tracer::make_plan(s, Model::fast);
  EXPECT_EQ(f.frame, tracer::FrameKind::world);
  EXPECT_EQ(f.spawn, tracer::SpawnScheme::extent_eps);
  EXPECT_EQ(f.slab, bvh::Slab::fast);
  for (const auto& k : f.kinds) EXPECT_TRUE(k.method == 0 && !k.f64 && !k.f64_storage);
  const tracer::Plan e = tracer::make_plan(s, Model::exact);
  EXPECT_EQ(e.spawn, tracer::SpawnScheme::error_bound);
  EXPECT_TRUE(kp(e, Kind::sphere).f64_storage);
  EXPECT_TRUE(kp(e, Kind::triangle).f64_storage);
  EXPECT_TRUE(kp(e, Kind::cylinder).f64);
  EXPECT_EQ(method(e, Kind::sphere), "compensated");
}

// ---- the data's own precision, and degenerate primitives ---------------------------------------
// A scanned mesh whose coordinates are floats keeps float storage whatever its slivers: float
// reproduces every vertex the input held. The same mesh in double puts only its slivers above the
// float tolerance; collapsed triangles never change the plan.
TEST(PlanPrimitives, AFloatScanKeepsFloatAndItsSliversAreCountedApart) {
  const scene::Scene s = scene::precision_scene("scanned");
  const tracer::Profile pr = tracer::make_profile(s);
  EXPECT_EQ(pr.input.floats, pr.input.coords);
  EXPECT_EQ(pr.input.finer, 0u);
  const tracer::Plan p = tracer::make_plan(s, pr, Model::automatic);
  const auto& t = kp(p, Kind::triangle);
  EXPECT_EQ(p.frame, tracer::FrameKind::world);
  EXPECT_FALSE(t.f64_storage) << t.reason;
  EXPECT_FALSE(t.f64);
  EXPECT_EQ(t.classes.coarse, 0u);
  // The 50 with a repeated vertex; the slivers (floats, even under one float step) and the 50 whose
  // middle vertex lay on the line between the others (thin needles once rounded to float) are counted
  // as the input.
  EXPECT_GE(t.classes.degenerate, 50u);
  EXPECT_EQ(t.classes.as_input + t.classes.degenerate + t.classes.fine, s.triangles.size());
  EXPECT_NE(p.text().find("as the input holds them"), std::string::npos) << p.text();
  // The smallest object is the mesh's, not a sliver's.
  EXPECT_GT(pr.object_min, 1e-4);
}

TEST(PlanPrimitives, TheSameScanInDoublePutsOnlyItsSliversAboveTheToleranceAndJudgesThemByEffect) {
  const scene::Scene s = scene::precision_scene("scanned_double");
  const tracer::Profile pr = tracer::make_profile(s);
  EXPECT_GT(pr.input.finer, 0u);
  const tracer::Plan p = tracer::make_plan(s, pr, Model::automatic);
  const auto& t = kp(p, Kind::triangle);
  const std::size_t mesh = 20480;  // the icosphere's triangles come first; the slivers after them
  EXPECT_GT(t.classes.coarse, 0u);
  EXPECT_LE(t.classes.coarse, (s.triangles.size() - mesh));
  EXPECT_GE(t.classes.worst_coarse, mesh) << "the worst primitive is a sliver";
  EXPECT_GE(t.classes.fine, mesh - 10);
  // The slivers' rounding can change a negligible share of the hits: the kind stays in float.
  EXPECT_TRUE(t.classes.negligible);
  EXPECT_LT(t.classes.moved_share, tracer::kNegligibleShare);
  EXPECT_FALSE(t.f64_storage) << t.classes_text();
  EXPECT_NE(t.classes_text().find("negligible"), std::string::npos) << t.classes_text();
}

// Coarse primitives that matter still decide: two copies of the scan a million units apart (no
// frame serves both). Neither copy is huge, so the far one goes to local frames (half the kind,
// every leaf of it in float relative to its own origin) and the kind stays in float; with a huge
// coarse primitive among them (a floor 1e6 across, judged against the smallest triangle) beyond a
// quarter of the kind, the kind goes to double as a whole.
TEST(PlanPrimitives, CoarsePrimitivesThatChangeHitsGoToLocalFramesOrPutTheKindInDouble) {
  scene::Scene s = scene::precision_scene("scanned_double");
  const auto nv = std::uint32_t(s.verts.size());
  const std::size_t nt = s.triangles.size();
  for (std::uint32_t v = 0; v < nv; ++v) s.verts.push_back(s.verts[v] + Vec3d{1.0e6 + 0.37, -2.1e5, 3.3e5});
  for (std::size_t i = 0; i < nt; ++i) {
    auto t = s.triangles[i];
    for (auto& v : t.v) v += nv;
    s.triangles.push_back(t);
  }
  const tracer::Plan p = tracer::make_plan(s, Model::automatic);
  const auto& t = kp(p, Kind::triangle);
  EXPECT_FALSE(t.classes.negligible);
  EXPECT_GT(t.classes.moved_share, tracer::kNegligibleShare);
  EXPECT_EQ(t.classes.coarse_huge, 0u);
  EXPECT_FALSE(t.f64_storage) << t.classes_text();
  EXPECT_TRUE(t.split_local);
  // Apart: the far copy (but its degenerate triangles) and the near copy's slivers, coarse in any
  // frame of the mesh's size.
  const auto far = std::size_t(std::count_if(t.split.begin(), t.split.end(), [&](std::uint32_t i) { return i >= nt; }));
  EXPECT_GE(far, nt - t.classes.degenerate) << t.split_reason;
  EXPECT_LT(t.split.size() - far, nt / 20);
  // The slivers that a leaf's origin does not hold in float (leaves of slivers spread over the
  // mesh) stay in double: a few of the primitives apart.
  const tracer::SceneAccel a = tracer::SceneAccel::build(s, p);
  EXPECT_LT(a.apart_deep(Kind::triangle), t.split.size() / 4);
  // A floor a million across under the far copy: huge, and coarse in every frame.
  const auto nv2 = std::uint32_t(s.verts.size());
  for (Vec3d c : {Vec3d{-5e5 + 0.1, -1.3, -5e5 + 0.7}, Vec3d{5e5 + 0.3, -1.3, -5e5 + 0.9}, Vec3d{0.1, -1.3, 5e5 + 0.3}})
    s.verts.push_back(c + Vec3d{1.0e6, -2.1e5, 3.3e5});
  s.triangles.push_back({{nv2, nv2 + 1, nv2 + 2}, 0});
  const tracer::Plan q = tracer::make_plan(s, Model::automatic);
  EXPECT_EQ(kp(q, Kind::triangle).classes.coarse_huge, 1u);
  EXPECT_TRUE(kp(q, Kind::triangle).f64_storage) << kp(q, Kind::triangle).classes_text();
}

// A few coarse primitives whose rounding would change hits go to a batch of their own in local
// frames; the rest of the kind stays in float. Small meshes scattered over a world 3.7e4 wide: the
// 30 far from the origin (2,400 triangles, 13 %) are coarse in every frame that keeps the other 200
// in float, and fine relative to an origin near them.
TEST(PlanPrimitives, AFewCoarsePrimitivesGoApartInLocalFramesAndTheRestStaysInFloat) {
  const scene::Scene s = scene::precision_scene("scattered");
  const std::uint32_t near = 200 * 80;  // the near meshes' triangles come first
  const tracer::Plan p = tracer::make_plan(s, Model::automatic);
  const auto& t = kp(p, Kind::triangle);
  EXPECT_EQ(p.frame, tracer::FrameKind::world);
  EXPECT_FALSE(t.f64_storage) << t.reason;
  EXPECT_FALSE(t.f64);
  EXPECT_FALSE(t.classes.negligible);
  ASSERT_EQ(t.split.size(), t.classes.coarse);
  EXPECT_EQ(t.split.size(), s.triangles.size() - near);
  EXPECT_TRUE(std::is_sorted(t.split.begin(), t.split.end()));
  EXPECT_GE(t.split.front(), near) << "only the far meshes' triangles are apart";
  EXPECT_NE(p.text().find("apart:   2400 coarse of 18400"), std::string::npos) << p.text();
  EXPECT_EQ(p.json()["kinds"][0]["split"]["count"], 2400);
  EXPECT_EQ(p.json()["kinds"][0]["split"]["storage"], "local frames");
  EXPECT_TRUE(t.split_local);
  // The tree: the apart triangles in leaves of their own tag, every one of them there, the rest in
  // the kind's float batch; memory in proportion.
  const tracer::SceneAccel a = tracer::SceneAccel::build(s, p);
  std::size_t apart = 0, kept = 0;
  for (const bvh::BNode& n : a.bin.nodes) {
    if (!n.leaf()) continue;
    for (std::uint32_t j = 0; j < n.count; ++j) {
      const std::uint32_t id = a.slot_id(n.kind, std::size_t(n.first) * 8 + j);
      ASSERT_NE(id, UINT32_MAX);
      if (n.kind == tracer::apart_tag(Kind::triangle)) {
        ++apart;
        EXPECT_TRUE(a.stored_apart(Kind::triangle, id)) << id;
      } else {
        ASSERT_EQ(n.kind, int(Kind::triangle));
        ++kept;
        EXPECT_FALSE(a.stored_apart(Kind::triangle, id)) << id;
      }
    }
  }
  EXPECT_EQ(apart, t.split.size());
  EXPECT_EQ(kept, s.triangles.size() - t.split.size());
  EXPECT_GT(a.apart_bytes(Kind::triangle), 0u);
  EXPECT_LT(a.apart_bytes(Kind::triangle), a.kind_bytes(Kind::triangle) / 3);
  // Every far mesh is held by an origin near it: no leaf stays in double, and none holds a
  // coordinate beyond a few of its triangles' sizes (they are under 1 across).
  EXPECT_EQ(a.apart_deep(Kind::triangle), 0u);
  EXPECT_GT(a.apart_reach(Kind::triangle), 0.0);
  EXPECT_LT(a.apart_reach(Kind::triangle), 8.0);
  // A hit on an apart triangle carries the rounding error of float in its local frame: a few float
  // roundings of its reach, not of its world coordinates (3e4: 8 float roundings there are 0.014).
  RaySoA rays;
  const scene::View v = scene::view_of(s);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) rays.push(a.frame_ray(v.from, v.dir(x / 8.0 - 1, y / 8.0 - 1)));
  std::vector<bvh::HitRec> h(rays.size());
  a.trace(rays, 0, rays.size(), h.data(), {});
  std::size_t hits = 0;
  for (std::size_t i = 0; i < rays.count; ++i) {
    if (h[i].prim == bvh::kNoPrim) continue;
    ++hits;
    EXPECT_TRUE(a.stored_apart(Kind::triangle, kinds::index_of(h[i].prim)));
    EXPECT_LT(a.surface(h[i], rays.get(i)).err, 8 * 0x1p-24 * 9.0);
  }
  EXPECT_GT(hits, 0u);
  // The fast model keeps them in float, and the exact model stores the whole kind in double.
  const tracer::Plan fast = tracer::make_plan(s, Model::fast), exact = tracer::make_plan(s, Model::exact);
  EXPECT_TRUE(kp(fast, Kind::triangle).split.empty());
  EXPECT_TRUE(kp(exact, Kind::triangle).split.empty());
  EXPECT_TRUE(kp(exact, Kind::triangle).f64_storage);
}

// The coarse primitives go to whichever storage apart the kind's measured costs make cheaper: local
// frames at the kinds' own figures, double where double were the cheaper one.
TEST(PlanPrimitives, CoarsePrimitivesGoToTheCheaperStorageAtTheKindsCosts) {
  const scene::Scene s = scene::precision_scene("scattered");
  const tracer::Profile prof = tracer::make_profile(s);
  const kinds::StorageCost& own = tracer::storage_costs()[std::size_t(Kind::triangle)];
  ASSERT_LT(own.local, own.f64) << "the measured figures: local frames cheaper for triangles";
  EXPECT_EQ(std::string(own.evidence), "storage/triangle");
  tracer::StorageCosts costs = tracer::storage_costs();
  costs[std::size_t(Kind::triangle)] = {3.0, 1.5, "storage/triangle", "a test"};
  const tracer::Plan mine = tracer::make_plan(s, prof, Model::automatic), other = tracer::make_plan(s, prof, Model::automatic, costs);
  EXPECT_TRUE(kp(mine, Kind::triangle).split_local);
  const auto& t = kp(other, Kind::triangle);
  EXPECT_FALSE(t.split_local);
  EXPECT_EQ(t.split, kp(mine, Kind::triangle).split) << "the same primitives apart, in another storage";
  EXPECT_NE(t.split_reason.find("in a batch of their own in double"), std::string::npos) << t.split_reason;
  EXPECT_NE(t.split_reason.find("3.00x the kind in the frame in local frames and 1.50x in double"), std::string::npos) << t.split_reason;
  const auto j = other.json()["kinds"][0]["split"];
  EXPECT_EQ(j["storage"], "double");
  EXPECT_EQ(j["cost"]["double"], 1.5);
  EXPECT_EQ(j["cost"]["evidence"], "storage/triangle");
}

TEST(PlanPrimitives, DegenerateTrianglesNeverChangeThePlan) {
  for (const char* name : {"scanned", "scanned_double", "mesh_spheres_1e5"}) {
    scene::Scene with = scene::precision_scene(name), without = with;
    if (std::string(name) == "mesh_spheres_1e5") {
      // Collapsed triangles added to a mesh that has none.
      const auto n = std::uint32_t(with.verts.size());
      for (std::uint32_t k = 0; k < 50; ++k) with.triangles.push_back({{k % n, k % n, (k * 7 + 3) % n}, 0});
    } else {
      without.triangles.resize(without.triangles.size() - 100);  // the scene's collapsed triangles come last
    }
    const tracer::Plan a = tracer::make_plan(with, Model::automatic), b = tracer::make_plan(without, Model::automatic);
    EXPECT_EQ(a.frame, b.frame) << name;
    EXPECT_EQ(a.origin.x, b.origin.x) << name;
    for (int k = 0; k < kinds::kKinds; ++k) {
      EXPECT_EQ(a.kinds[std::size_t(k)].method, b.kinds[std::size_t(k)].method) << name << " " << k;
      EXPECT_EQ(a.kinds[std::size_t(k)].f64, b.kinds[std::size_t(k)].f64) << name << " " << k;
      EXPECT_EQ(a.kinds[std::size_t(k)].f64_storage, b.kinds[std::size_t(k)].f64_storage) << name << " " << k;
    }
    EXPECT_GE(kp(a, Kind::triangle).classes.degenerate, kp(b, Kind::triangle).classes.degenerate + 50) << name;
  }
}

// The input's precision read from files: the same mesh as a binary float PLY, as a 17-digit OBJ of
// its double coordinates, and as a 6-digit OBJ (decimal text that float keeps).
TEST(PlanPrimitives, TheInputsPrecisionComesFromTheFileAndDecidesTheStorage) {
  const scene::Scene s = scene::precision_scene("scanned_double");
  const std::string dir = ::testing::TempDir();
  const std::string ply = dir + "/rb_plan_scan.ply", obj17 = dir + "/rb_plan_scan17.obj", obj6 = dir + "/rb_plan_scan6.obj";
  {
    std::ofstream f(ply, std::ios::binary);
    f << "ply\nformat binary_little_endian 1.0\nelement vertex " << s.verts.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << s.triangles.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Vec3d& v : s.verts)
      for (const float c : {float(v.x), float(v.y), float(v.z)}) f.write(reinterpret_cast<const char*>(&c), 4);
    for (const auto& t : s.triangles) {
      const unsigned char three = 3;
      f.write(reinterpret_cast<const char*>(&three), 1);
      for (const auto i : t.v) {
        const std::int32_t k = std::int32_t(i);
        f.write(reinterpret_cast<const char*>(&k), 4);
      }
    }
  }
  for (const auto& [path, format] : {std::pair{obj17, "v {:.17g} {:.17g} {:.17g}\n"}, std::pair{obj6, "v {:.6g} {:.6g} {:.6g}\n"}}) {
    std::ofstream f(path);
    for (const Vec3d& v : s.verts) f << fmt::format(fmt::runtime(format), v.x, v.y, v.z);
    for (const auto& t : s.triangles) f << fmt::format("f {} {} {}\n", t.v[0] + 1, t.v[1] + 1, t.v[2] + 1);
  }
  // All three keep float storage, each for its own reason: the PLY and the 6-digit text as the input
  // holds them; the 17-digit text's mesh by the float tolerance, its slivers by their effect.
  struct Expect {
    std::string path;
    std::string summary, classes;
  };
  for (const Expect& e : {Expect{ply, "float: every mesh coordinate is a float", "as the input holds them"},
                          Expect{obj17, "finer than float", "negligible, kept in float"},
                          Expect{obj6, "decimal text of up to 6 significant digits", "as the input holds them"}}) {
    const scene::Scene loaded = scene::load_scene(e.path);
    const tracer::Profile pr = tracer::make_profile(loaded);
    EXPECT_EQ(pr.input.summary().rfind(e.summary, 0), 0u) << e.path << ": " << pr.input.summary();
    const tracer::Plan p = tracer::make_plan(loaded, pr, Model::automatic);
    EXPECT_FALSE(kp(p, Kind::triangle).f64_storage) << e.path << ": " << kp(p, Kind::triangle).classes_text();
    EXPECT_NE(kp(p, Kind::triangle).classes_text().find(e.classes), std::string::npos) << e.path << ": " << kp(p, Kind::triangle).classes_text();
    EXPECT_EQ(p.json()["kinds"][0]["classes"]["summary"], kp(p, Kind::triangle).classes_text());
    EXPECT_EQ(pr.json()["input_precision"]["summary"], pr.input.summary());
  }
  std::remove(ply.c_str());
  std::remove(obj17.c_str());
  std::remove(obj6.c_str());
}

// ---- whole scenes against the exact reference ------------------------------------------------------
TEST(PlanAccuracy, AutoAndExactHaveNoFailureOnAnyWholeSceneCase) {
  acc::Options o;
  o.filter = "^scene/([^b]|b[^u])";  // the generated scenes, 1024 rays each
  o.rays = 1024;
  o.timing = false;
  o.data_dir = std::string(RB_SOURCE_DIR) + "/data";
  o.tracer = &acc::tracer_cases();
  auto rows = acc::run_lab(o);
  o.filter = "^scene/bunny";  // the real mesh's reference loops over 69,451 triangles per ray: 256 rays
  o.rays = 256;
  for (auto& r : acc::run_lab(o)) rows.push_back(std::move(r));
  int cases = 0;
  std::size_t fast_failures = 0;
  for (const auto& r : rows) {
    if (r.family != "scene") continue;
    if (r.method == "fast") {
      fast_failures += r.false_hits + r.false_misses + r.wrong_roots + r.self_hits;
      continue;
    }
    ++cases;
    EXPECT_EQ(r.failure_ppm(), 0.0) << r.case_name << " " << r.method << ": " << r.false_hits << " false hits, " << r.false_misses
                                    << " false misses, " << r.wrong_roots << " wrong hits, " << r.self_hits << " self-hits";
  }
  EXPECT_GE(cases, 2 * 22);  // every case but the two dragon ones (--full)
  // The cases detect failures: the fast model (world coordinates, the cheapest method in float,
  // the extent epsilon) fails on them.
  EXPECT_GT(fast_failures, 100u);
}

// ---- invariance ----------------------------------------------------------------------------------
std::vector<std::uint8_t> render(const scene::Scene& s, Model m, int size = 64) { return render::render_rgb8(s, m, size); }
double differing(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) { return render::differing_pixels(a, b); }

// Both scenes: the balls on a floor, and the same with a cylinder, a cone, a triangle mesh and a
// torus beside them (every kind's plan moved and scaled at once).
TEST(PlanInvariance, AutoRendersAFarOrScaledCopyLikeTheOriginal) {
  for (const char* name : {"ball_ground", "kinds_ground"}) {
    const scene::Scene s = scene::precision_scene(name);
    const auto ref = render(s, Model::automatic);
    // The ball's shadow is on the floor: some floor pixels are much darker than the lit floor.
    std::size_t dark = 0;
    for (std::size_t p = 0; p < ref.size() / 3; ++p) dark += ref[3 * p] < 40 && ref[3 * p + 1] < 40 && ref[3 * p + 2] < 50;
    EXPECT_GT(dark, 20u) << name;
    // Offsets of an even number of checker cells per axis keep the floor's parity.
    for (double off : {1e3, 1e5, 1e7}) {
      const auto img = render(scene::translated(s, {off, -off * 2, off * 4}), Model::automatic);
      EXPECT_LT(differing(img, ref), 0.01) << name << " moved by " << off;
    }
    for (double k : {1e-3, 1e4}) {
      const auto img = render(scene::scaled(s, k), Model::automatic);
      EXPECT_LT(differing(img, ref), 0.01) << name << " scaled by " << k;
    }
  }
}

TEST(PlanInvariance, TheFastModelFailsFarAway) {
  // The comparison detects the failure the plan avoids: in world coordinates 6.4e6 away the float
  // step is half a unit and the spawn epsilon 64 units.
  const scene::Scene s = scene::precision_scene("ball_ground");
  const auto ref = render(s, Model::fast);
  const auto far = render(scene::translated(s, {6.4e6, 0, 0}), Model::fast);
  EXPECT_GT(differing(far, ref), 0.01);
}

}  // namespace
