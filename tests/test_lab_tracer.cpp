// The accuracy lab's cases through the whole tracer (rb_accuracy_tracer): the closed meshes traced
// through an 8-wide BVH, and the tracer's plan, whose every option cites lab cases. These run in
// the `debug` preset (the tracer's own flags there); the kernels' lab figures, which depend on the
// optimiser and on contraction, are tests/test_accuracy.cpp, built optimised as well.
#include "accuracy/lab.hpp"
#include "plan_evidence_util.hpp"
#include "tracer/plan.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

std::vector<rb::acc::Row> traced_lab(const std::string& filter, std::size_t rays) {
  rb::acc::Options o;
  o.filter = filter;
  o.rays = rays;
  o.timing = false;
  o.tracer = &rb::acc::tracer_cases();
  return rb::acc::run_lab(o);
}

}  // namespace

// The closed-mesh triangle cases through the whole tracer: an 8-wide BVH in its default
// configuration (conservative node boxes) and with the robust slab test, single rays and 8-ray
// packets: no leak and no farther face returned (a near face's box culled).
TEST(AccuracyBvh, WatertightThroughTheTracer) {
  int traced = 0;
  for (const rb::acc::Row& r : traced_lab("^triangle/", 256)) {
    if (r.family != "bvh" || (r.method != "default" && r.method != "robust_slabs")) continue;
    ++traced;
    EXPECT_EQ(r.leaks, 0u) << r.case_name << " " << r.method << " " << r.precision;
    EXPECT_EQ(r.wrong_roots, 0u) << r.case_name << " " << r.method << " " << r.precision;
  }
  EXPECT_GE(traced, 8 * 2 * 2);
}

// Without the tracer's cases, the lab runs the kernels' families only.
TEST(AccuracyBvh, KernelLabAloneHasNoTracerRows) {
  rb::acc::Options o;
  o.filter = "^triangle/octahedron_edges$";
  o.rays = 64;
  o.timing = false;
  bool bvh = false;
  for (const rb::acc::Row& r : rb::acc::run_lab(o)) bvh = bvh || r.family == "bvh";
  EXPECT_FALSE(bvh);
  o.tracer = &rb::acc::tracer_cases();
  for (const rb::acc::Row& r : rb::acc::run_lab(o)) bvh = bvh || r.family == "bvh";
  EXPECT_TRUE(bvh);
  std::size_t scenes = 0;
  for (const auto& c : rb::acc::case_list(&rb::acc::tracer_cases())) scenes += c.family == "scene";
  EXPECT_GT(scenes, 0u);
  for (const auto& c : rb::acc::case_list(nullptr)) EXPECT_TRUE(c.family != "scene" && c.family != "storage") << c.family;
}

// The plan's evidence, every cited case, those through the whole tracer included
// (tests/plan_evidence_util.hpp; test_accuracy.cpp checks the kernels' cases optimised).
TEST(AccuracyPlan, EveryOptionHasNoFailureOnTheCasesItCites) { EXPECT_GT(check_plan_evidence(&rb::acc::tracer_cases()), 40); }

// Every kind's storage costs cite the lab case that measures them (kinds::StorageCost), and the
// case runs: the kind in the frame, in local frames and in double, in that order, each with the
// reference's answer on every ray.
TEST(AccuracyPlan, StorageCostsCiteTheirLabCaseAndItsThreeStoragesAgree) {
  int kinds_cited = 0;
  for (const auto& c : rb::tracer::storage_costs()) {
    const std::string ev = c.evidence;
    if (ev.empty()) continue;
    ++kinds_cited;
    EXPECT_GT(c.local, 0.0);
    EXPECT_GT(c.f64, 0.0);
    EXPECT_NE(std::string(c.measured_on), "");
    rb::acc::Options o;
    o.filter = "^" + ev + "$";
    o.rays = 256;  // the bunny's reference loops over its 69,451 triangles per ray
    o.timing = false;
    o.data_dir = std::string(RB_SOURCE_DIR) + "/data";
    o.tracer = &rb::acc::tracer_cases();
    const auto rows = rb::acc::run_lab(o);
    ASSERT_EQ(rows.size(), 3u) << ev;
    const char* order[] = {rb::acc::kStorageFloat, rb::acc::kStorageLocal, rb::acc::kStorageDouble};
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_EQ(rows[i].family + "/" + rows[i].case_name, ev);
      EXPECT_EQ(rows[i].method, order[i]);
      EXPECT_EQ(rows[i].rays, rows[0].rays);
      EXPECT_EQ(rows[i].failure_ppm(), 0.0) << ev << " " << rows[i].method << ": " << rows[i].false_hits << " false hits, "
                                            << rows[i].false_misses << " false misses, " << rows[i].wrong_roots << " wrong hits";
    }
  }
  EXPECT_EQ(kinds_cited, 2);  // spheres and triangles, the kinds that store double
}
