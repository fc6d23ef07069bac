// Model no more than a scene needs: the numerical profile and the plan (tracer/profile.hpp,
// tracer/plan.hpp) on scenes with known needs, the whole-scene accuracy of each model against the
// exact reference (the lab's family "scene"), and invariance: a scene moved far from the origin or
// scaled renders like the original under the auto model.
#include "accuracy/lab.hpp"
#include "render/render.hpp"
#include "scene/sources.hpp"
#include "scene/transform.hpp"
#include "tracer/plan.hpp"
#include "tracer/profile.hpp"

#include <gtest/gtest.h>

#include <cmath>

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
  EXPECT_EQ(p.spawn, tracer::SpawnScheme::integer);
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

// ---- whole scenes against the exact reference ------------------------------------------------------
TEST(PlanAccuracy, AutoAndExactHaveNoFailureOnAnyWholeSceneCase) {
  acc::Options o;
  o.filter = "scene/";
  o.rays = 1024;
  o.timing = false;
  const auto rows = acc::run_lab(o);
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
  EXPECT_GE(cases, 2 * 10);
  // The cases detect failures: the fast model (world coordinates, the cheapest method in float,
  // the extent epsilon) fails on them.
  EXPECT_GT(fast_failures, 100u);
}

// ---- invariance ----------------------------------------------------------------------------------
std::vector<std::uint8_t> render(const scene::Scene& s, Model m, int size = 64) {
  const tracer::SceneAccel a = tracer::SceneAccel::build(s, tracer::make_plan(s, m));
  render::RenderOptions o;
  o.width = o.height = size;
  o.count_tests = false;
  const render::Renderer r(s, a, o);
  std::vector<float> samples;
  render::render_tiles(r, samples, 1);
  return render::to_rgb8(r.resolve(samples));
}
// The share of pixels whose largest channel difference is above 4/255.
double differing(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  std::size_t bad = 0;
  for (std::size_t p = 0; p < a.size() / 3; ++p) {
    int worst = 0;
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(a[3 * p + std::size_t(c)]) - int(b[3 * p + std::size_t(c)])));
    bad += worst > 4;
  }
  return double(bad) / double(a.size() / 3);
}

TEST(PlanInvariance, AutoRendersAFarOrScaledCopyLikeTheOriginal) {
  const scene::Scene s = scene::precision_scene("ball_ground");
  const auto ref = render(s, Model::automatic);
  // The ball's shadow is on the floor: some floor pixels are much darker than the lit floor.
  std::size_t dark = 0;
  for (std::size_t p = 0; p < ref.size() / 3; ++p) dark += ref[3 * p] < 40 && ref[3 * p + 1] < 40 && ref[3 * p + 2] < 50;
  EXPECT_GT(dark, 20u);
  // Offsets of an even number of checker cells per axis keep the floor's parity.
  for (double off : {1e3, 1e5, 1e7}) {
    const auto img = render(scene::translated(s, {off, -off * 2, off * 4}), Model::automatic);
    EXPECT_LT(differing(img, ref), 0.01) << "moved by " << off;
  }
  for (double k : {1e-3, 1e4}) {
    const auto img = render(scene::scaled(s, k), Model::automatic);
    EXPECT_LT(differing(img, ref), 0.01) << "scaled by " << k;
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
