// The accuracy lab's cases through the whole tracer (rb_accuracy_tracer): the closed meshes traced
// through an 8-wide BVH, and the tracer's plan, whose every option cites lab cases. These run in
// the `debug` preset (the tracer's own flags there); the kernels' lab figures, which depend on the
// optimiser and on contraction, are tests/test_accuracy.cpp, built optimised as well.
#include "accuracy/lab.hpp"
#include "plan_evidence_util.hpp"

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
  for (const auto& c : rb::acc::case_list(nullptr)) EXPECT_NE(c.family, "scene");
}

// The plan's evidence, every cited case, those through the whole tracer included
// (tests/plan_evidence_util.hpp; test_accuracy.cpp checks the kernels' cases optimised).
TEST(AccuracyPlan, EveryOptionHasNoFailureOnTheCasesItCites) { EXPECT_GT(check_plan_evidence(&rb::acc::tracer_cases()), 40); }
