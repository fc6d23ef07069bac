// The accuracy lab's bounds: the robust methods meet their targets on the adversarial sets, and
// the naive methods fail where they are known to, so the sets provably detect failures. The lab
// (accuracy/) is compiled with FMA contraction on in every preset, as is this file, so the
// figures are those of the release build. Small ray counts keep the suite fast under ASan at -O0.
#include "accuracy/exact.hpp"
#include "accuracy/lab.hpp"
#include "kernels/torus.hpp"
#include "plan_evidence_util.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

using rb::acc::Options;
using rb::acc::Row;

std::vector<Row> lab(const std::string& filter, std::size_t rays = 256, std::uint32_t seed = 1) {
  Options o;
  o.filter = filter;
  o.rays = rays;
  o.seed = seed;
  o.timing = false;
  return rb::acc::run_lab(o);
}
const Row& row(const std::vector<Row>& rows, const std::string& cs, const std::string& method, const std::string& prec) {
  for (const Row& r : rows)
    if (r.case_name == cs && r.method == method && r.precision == prec) return r;
  throw std::runtime_error("no row " + cs + " " + method + " " + prec);
}
double misclassified(const Row& r) { return r.false_hit_ppm + r.false_miss_ppm; }

// ---- references ------------------------------------------------------------------------------
TEST(AccuracyReference, TriangleEdgesExactly) {
  using rb::Vec3f;
  using rb::acc::Cls;
  const Vec3f a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0}, d{0, 0, 1};
  // Through the interior, exactly through the edge x + y = 1, through a vertex, outside.
  auto cls = [&](Vec3f o) { return rb::acc::triangle_ref(o, d, 0.f, 1e30f, a, b, c); };
  const auto in = cls({0.25f, 0.25f, -1}), edge = cls({0.5f, 0.5f, -1}), vert = cls({0, 0, -1}), out = cls({0.75f, 0.5f, -1});
  EXPECT_EQ(in.cls, Cls::hit);
  EXPECT_EQ(double(in.t), 1.0);
  EXPECT_EQ(edge.cls, Cls::either);
  EXPECT_TRUE(edge.has_t);
  EXPECT_EQ(vert.cls, Cls::either);
  EXPECT_EQ(out.cls, Cls::miss);
  // The next float past the edge is outside; the one before inside: the decision is exact.
  EXPECT_EQ(cls({0.5f, std::nextafter(0.5f, 1.f), -1}).cls, Cls::miss);
  EXPECT_EQ(cls({0.5f, std::nextafter(0.5f, 0.f), -1}).cls, Cls::hit);
}

TEST(AccuracyReference, BoxSlabPlanesWithSignedZero) {
  using rb::Vec3f;
  using rb::acc::Cls;
  const Vec3f lo{-1, -1, -1}, hi{1, 1, 1};
  // Origin on the plane x = 1, running in it (dx = +0 or -0): on the face, either answer.
  for (float zero : {0.0f, -0.0f}) {
    const auto r = rb::acc::box_ref({1, 0, -5}, {zero, 0, 1}, 0.f, 1e30f, lo, hi);
    EXPECT_EQ(r.cls, Cls::either);
  }
  const auto inside = rb::acc::box_ref({0, 0, 0}, {0, 0, 1}, 0.f, 1e30f, lo, hi);  // the exit
  EXPECT_EQ(inside.cls, Cls::hit);
  EXPECT_EQ(double(inside.t), 1.0);
  const auto flat = rb::acc::box_ref({0, 0, -5}, {0, 0, 1}, 0.f, 1e30f, {-1, -1, 0}, {1, 1, 0});  // a rectangle
  EXPECT_EQ(flat.cls, Cls::hit);
  EXPECT_EQ(double(flat.t), 5.0);
}

TEST(AccuracyReference, QuarticRootsKnown) {
  // (x - 1)(x - 1.001)(x + 2)(x - 50): clustered and spread roots, long double isolation.
  long double c[5] = {0, 0, 0, 0, 1};
  const long double roots[4] = {1.0L, 1.001L, -2.0L, 50.0L};
  // Multiply out.
  long double p[5] = {1, 0, 0, 0, 0};
  int deg = 0;
  for (long double r : roots) {
    for (int k = deg + 1; k >= 1; --k) p[k] = p[k - 1] - r * p[k];
    p[0] = -r * p[0];
    ++deg;
  }
  for (int k = 0; k < 5; ++k) c[k] = p[k];
  const auto x = rb::acc::poly_roots_ld(c, 4, -100.0L, 100.0L);
  ASSERT_EQ(x.size(), 4u);
  EXPECT_NEAR(double(x[0]), -2.0, 1e-15);
  EXPECT_NEAR(double(x[1]), 1.0, 1e-13);
  EXPECT_NEAR(double(x[2]), 1.001, 1e-13);
  EXPECT_NEAR(double(x[3]), 50.0, 1e-13);
}

// ---- triangles -------------------------------------------------------------------------------
TEST(AccuracyTriangle, WatertightNoLeaksOnEdgeAndVertexSets) {
  const auto rows = lab("triangle/");
  int closed = 0;
  for (const Row& r : rows) {
    if (r.method != "woop" || !std::isfinite(r.leak_ppm)) continue;
    ++closed;
    EXPECT_EQ(r.leaks, 0u) << r.case_name << " " << r.precision;
  }
  EXPECT_GE(closed, 8 * 3);  // every closed-mesh case in float, double and simd8
  // The same rays through the whole tracer: tests/test_lab_tracer.cpp (the lab's tracer cases).
}

TEST(AccuracyTriangle, PbrtBadCaseNeverHits) {
  const auto rows = lab("triangle/pbrt_bad_triangle", 64);
  ASSERT_EQ(rows.size(), 9u);
  for (const Row& r : rows) EXPECT_EQ(r.false_hits, 0u) << r.method << " " << r.precision;
}

TEST(AccuracyTriangle, NaiveMethodsLeakWhereKnown) {
  // Moller-Trumbore and Cramer (edges precomputed and rounded, no shared edge function) let
  // rays through a square refined into a triangle fan, in float and in SIMD: the set detects it.
  const auto rows = lab("triangle/fan_square");
  for (const char* m : {"moller_trumbore", "cramer"})
    for (const char* p : {"float", "simd8"}) EXPECT_GT(row(rows, "fan_square", m, p).leaks, 3u) << m << " " << p;
  EXPECT_EQ(row(rows, "fan_square", "woop", "float").leaks, 0u);
}

// ---- spheres ---------------------------------------------------------------------------------
TEST(AccuracySphere, BestFloatMethodFarAndPlanet) {
  const auto rows = lab("sphere/");
  for (const char* cs : {"far_small_1e1", "far_small_1e3", "far_small_1e5"})
    for (const char* p : {"float", "simd8"}) {
      const Row& r = row(rows, cs, "compensated", p);
      EXPECT_EQ(misclassified(r), 0.0) << cs << " " << p;
      EXPECT_LE(r.t_err_ulp_p99, 2.0) << cs << " " << p;
    }
  for (const char* cs : {"planet_pole", "planet_45"}) {
    const Row& r = row(rows, cs, "compensated", "float");
    EXPECT_EQ(misclassified(r), 0.0) << cs;
    EXPECT_LE(r.scaled_err_p99, 4.0) << cs;
    // The textbook float methods misclassify grazing planet rays (> 1 %): the set detects it.
    EXPECT_GT(misclassified(row(rows, cs, "stable", "float")), 1e4) << cs;
    EXPECT_EQ(misclassified(row(rows, cs, "stable", "double")), 0.0) << cs;
  }
  // A small sphere 1e5 radii away: float algebraic / stable misclassify, hearn_baker does not.
  EXPECT_GT(misclassified(row(rows, "far_small_1e5", "stable", "float")), 1e4);
  EXPECT_EQ(misclassified(row(rows, "far_small_1e5", "hearn_baker", "float")), 0.0);
}

// ---- torus -----------------------------------------------------------------------------------
TEST(AccuracyTorus, RobustAt500xAndFerrariFails) {
  const auto rows = lab("torus/camera_");
  for (const char* cs : {"camera_5x", "camera_50x", "camera_500x"})
    for (const char* p : {"float", "simd8", "double"}) {
      const Row& r = row(rows, cs, "robust", p);
      EXPECT_LE(misclassified(r), 200.0) << cs << " " << p;
      EXPECT_EQ(r.wrong_roots, 0u) << cs << " " << p;
      EXPECT_LE(r.scaled_err_p99, 3.0) << cs << " " << p;
      EXPECT_GT(r.iterations, 0.0);
    }
  // The closed form formed at the ray origin loses the roots far away.
  EXPECT_GT(misclassified(row(rows, "camera_500x", "ferrari", "float")), 1e5);
}

// The lab's first torus finding: the robust solver lost the first root when it lay within
// rounding of the bounding-sphere entry (p(0) rounded past it) and returned the second.
TEST(AccuracyTorus, RootAtTheBoundingSphereEntry) {
  using namespace rb;
  Ray<float> r{{-297.667053f, 495.401398f, -236.626144f}, {0.477625281f, -0.792741477f, 0.378728211f}, {}, 0.f, 3e38f};
  r.rd = {1 / r.d.x, 1 / r.d.y, 1 / r.d.z};
  const Torus<float> T = make_torus(Vec3d{0.5, -0.25, 0.125}, Vec3d{0.352547377, -0.312942177, -0.881917}, 1.0, 0.25);
  const auto ref = acc::torus_ref_roots(r.o, r.d, r.tmin, r.tmax, T.c, T.w, T.R, T.r);
  ASSERT_EQ(ref.size(), 4u);
  const Hit<float> h = intersect_torus_robust(r, T);
  ASSERT_TRUE(h.mask);
  EXPECT_NEAR(double(h.t), double(ref[0]), 1e-3);  // the roots are 0.54 apart
  const Hit<f8> h8 = intersect_torus_robust(Ray<f8>::broadcast(r), prim_cast<f8>(T));
  EXPECT_NEAR(double(lane(h8.t, 3)), double(ref[0]), 1e-3);
}

// The solver-only set: widely spread roots are found in double; a cluster of four roots within
// 1e-5 is beyond float (its roots move by ~eps^(1/4)): the set detects that.
TEST(AccuracyQuartic, SpreadInDoubleClusterBeyondFloat) {
  const auto rows = lab("quartic/");
  EXPECT_EQ(misclassified(row(rows, "spread", "isolation_newton", "double")), 0.0);
  EXPECT_GT(misclassified(row(rows, "clustered", "isolation_newton", "float")), 1e4);
  EXPECT_GT(row(rows, "spread", "isolation_newton", "float").iterations, 0.0);
}

// ---- cylinder, cone ----------------------------------------------------------------------------
TEST(AccuracyQuadric, NoNaNAndApexInDouble) {
  const auto rows = lab("quadric/");
  for (const Row& r : rows) EXPECT_EQ(r.nans, 0u) << r.case_name << " " << r.method << " " << r.precision;
  EXPECT_EQ(misclassified(row(rows, "cone_apex", "cone_capped", "double")), 0.0);
  EXPECT_EQ(misclassified(row(rows, "cone_apex", "cone", "double")), 0.0);
  EXPECT_EQ(misclassified(row(rows, "cyl_parallel_axis", "cylinder_capped", "float")), 0.0);
  // Float at 1e4 away: the quadratic's cancellation misclassifies most rays; double does not.
  EXPECT_GT(misclassified(row(rows, "cyl_far_camera", "cylinder", "float")), 1e5);
  EXPECT_EQ(misclassified(row(rows, "cyl_far_camera", "cylinder", "double")), 0.0);
}

// ---- boxes, secondary rays -----------------------------------------------------------------------
TEST(AccuracyBox, SlabTestExactOnPlanesFlatAndInside) {
  std::vector<Row> rows;
  for (const Row& r : lab("box/"))
    if (r.case_name.rfind("secondary", 0) != 0) rows.push_back(r);
  ASSERT_EQ(rows.size(), 4u * 3u);
  for (const Row& r : rows)
    if (r.precision != "double") {
      EXPECT_EQ(r.failure_ppm(), 0.0) << r.case_name << " " << r.precision;
    }
}

TEST(AccuracySecondary, OffsetRemovesSelfHits) {
  const auto rows = lab("secondary", 512);
  EXPECT_GT(row(rows, "secondary_no_offset", "stable", "float").self_hits, 10u);
  // Both offset schemes: no self-hit on any primitive (sphere, triangle, box, cylinder, torus).
  int schemes = 0;
  for (const Row& r : rows)
    if (r.case_name == "secondary_wb_offset" || r.case_name == "secondary_bound_offset") {
      ++schemes;
      EXPECT_EQ(r.self_hits, 0u) << r.family << " " << r.method << " " << r.case_name;
      EXPECT_EQ(r.rays, 512u);
    }
  EXPECT_EQ(schemes, 2 * 8);  // sphere x3, triangle x2, box, cylinder, torus
  // Spawned without an offset, the box and the cylinder hit themselves: the sets detect it.
  for (const char* fam : {"box", "quadric"}) {
    std::size_t self = 0;
    for (const Row& r : rows)
      if (r.family == fam && r.case_name == "secondary_no_offset") self += r.self_hits;
    EXPECT_GT(self, 10u) << fam;
  }
}

// ---- implicit surfaces -----------------------------------------------------------------------------
TEST(AccuracyImplicit, CoarseMarcherStepsOverThinFeatures) {
  const auto rows = lab("implicit/", 128);
  // The marching step (bounding radius / 8) is far above the wall: the marcher steps over the
  // near wall of the shell and returns its far side (a wrong root) or nothing; over twin planes
  // it misses the pair.
  const Row& shell = row(rows, "thin_shell", "illinois", "float");
  EXPECT_GT(shell.wrong_roots + shell.false_misses, 20u);
  EXPECT_GT(shell.wrong_roots, 0u);
  EXPECT_GT(row(rows, "twin_planes", "illinois", "simd8").false_misses, 20u);
  // A step below the feature finds the first surface, in every precision.
  for (const char* p : {"float", "double", "simd8"}) {
    const Row& twin = row(rows, "twin_planes", "illinois_fine_step", p);
    EXPECT_EQ(twin.failure_ppm(), 0.0) << p;
    EXPECT_EQ(row(rows, "thin_shell", "illinois_fine_step", p).wrong_roots, 0u) << p;
    EXPECT_GT(twin.iterations, row(rows, "twin_planes", "illinois", p).iterations) << p;
  }
}

TEST(AccuracyLab, SeededAndReproducible) {
  const auto a = lab("torus/camera_5x", 64, 7), b = lab("torus/camera_5x", 64, 7), c = lab("torus/camera_5x", 64, 8);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k].json().dump(), b[k].json().dump());
  bool differ = false;
  for (std::size_t k = 0; k < a.size(); ++k) differ = differ || a[k].t_err_ulp_max != c[k].t_err_ulp_max;
  EXPECT_TRUE(differ);
}

}  // namespace

// The plan's evidence on the kernels' cases, built as the release build computes them (optimised,
// contraction on): tests/plan_evidence_util.hpp; the cases through the whole tracer are checked in
// tests/test_lab_tracer.cpp.
TEST(AccuracyPlan, EveryOptionHasNoFailureOnTheKernelCasesItCites) { EXPECT_GT(check_plan_evidence(nullptr), 30); }
