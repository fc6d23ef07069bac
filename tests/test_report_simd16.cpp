// The report's verdicts on 16 lanes against 8 (apps/report/report_simd16.cpp, also printed by
// `raybench bench`), on a made-up benchmark run whose figures are known: each method's verdict and
// reason follow from its ratios, its counted divisions and square roots and the run's
// per-instruction rates (the divider model), and a method the model does not fit stays unexplained.
#include "apps/report/report_simd.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <map>
#include <string>

namespace {

using nlohmann::json;
using rb::app::simd_report::Simd16Method;

struct Row16 {
  double ratio;          // 16-lane rate over the 8-lane one, every case and round
  double div, sqrt;      // per test per lane, counted at 16 lanes
  double ops8, ops16;    // operations per test per lane
};

// Nine rounds of every row: the 8-lane rows at 0.4 ns per test, the 16-lane rows at `ratio` times
// their rate; instruction rows at FMA 0.2 ns (both widths), division 1.6 / 3.2 ns, square root 2 / 4.
json made_up_run(const std::map<std::string, Row16>& methods) {
  json doc = {{"benchmarks", json::array()}};
  auto add = [&](const std::string& name, json counters) {
    for (int round = 0; round < 9; ++round) {
      json b = counters;
      b["run_name"] = name;
      b["run_type"] = "iteration";
      b["repetition_index"] = round;
      doc["benchmarks"].push_back(b);
    }
  };
  const std::map<std::string, double> ns = {{"fma8", 0.2}, {"fma16", 0.2}, {"div8", 1.6}, {"div16", 3.2}, {"sqrt8", 2.0}, {"sqrt16", 4.0}};
  for (const auto& [k, t] : ns) add("instruction/" + k + "/reg", {{"instructions_per_s", 1e9 / t}});
  for (const auto& [km, m] : methods)
    for (const char* c : {"hit", "miss", "half"}) {
      add(km + "/rays_in_lanes/" + c, {{"tests_per_s", 2.5e9}, {"ops_per_test", m.ops8}});
      add(km + "/rays_in_lanes16/" + c, {{"tests_per_s", 2.5e9 * m.ratio}, {"ops_per_test", m.ops16}, {"instructions_per_test", m.ops16},
                                          {"div_per_test", m.div}, {"sqrt_per_test", m.sqrt}});
    }
  return doc;
}

TEST(ReportSimd16, VerdictsAndReasonsFollowTheFigures) {
  // One division per test: the divider's time per test is 0.2 ns at both widths, so the model gives
  // 0.4 / ((0.4 - 0.2) / 2 + 0.2) = 1.33x to 0.4 / 0.2 = 2x.
  const auto methods = rb::app::simd_report::simd16_methods(made_up_run({
      {"box/slab", {1.9, 0, 0, 30, 30}},            // met
      {"plane/lecture", {1.4, 1, 0, 18, 18}},       // inside the model's range: the divider
      {"triangle/cramer", {1.2, 1, 0, 50, 50}},     // below the model's 1.33x: something else too
      {"sphere/uv", {1.3, 3, 0, 60, 60}},           // above the cap 0.4 / 0.6 = 0.67x: fewer divisions ran
      {"torus/robust", {1.3, 0, 0, 100, 100}},      // a stated reason
      {"cone/capped", {1.3, 0, 0, 26, 30}},         // more operations per lane at 16 lanes
      {"quadric/matrix", {1.4, 0, 0, 78, 78}},      // nothing explains it
  }));
  std::map<std::string, Simd16Method> by;
  for (const auto& m : methods) by[m.km] = m;
  ASSERT_EQ(by.size(), 7u);
  EXPECT_EQ(by["box/slab"].why, Simd16Method::Why::met);
  EXPECT_TRUE(by["box/slab"].reason.empty());
  EXPECT_FALSE(by["box/slab"].model.valid());  // no division, no model

  const Simd16Method& plane = by["plane/lecture"];
  EXPECT_EQ(plane.why, Simd16Method::Why::explained);
  EXPECT_NEAR(plane.model.estimate, 0.4 / 0.3, 1e-9);
  EXPECT_NEAR(plane.model.cap, 2.0, 1e-9);
  EXPECT_TRUE(plane.model_fits);
  EXPECT_NE(plane.reason.find("divisions and square roots"), std::string::npos) << plane.reason;

  EXPECT_EQ(by["triangle/cramer"].why, Simd16Method::Why::unexplained);
  EXPECT_FALSE(by["triangle/cramer"].model_fits);
  EXPECT_NE(by["triangle/cramer"].reason.find("outside the divider model"), std::string::npos);

  EXPECT_EQ(by["sphere/uv"].why, Simd16Method::Why::unexplained);
  EXPECT_NEAR(by["sphere/uv"].model.cap, 0.4 / 0.6, 1e-9);
  EXPECT_NE(by["sphere/uv"].reason.find("fewer divisions ran than were counted"), std::string::npos);

  EXPECT_EQ(by["torus/robust"].why, Simd16Method::Why::explained);
  EXPECT_NE(by["torus/robust"].reason.find("slowest lane"), std::string::npos) << by["torus/robust"].reason;
  EXPECT_EQ(by["cone/capped"].why, Simd16Method::Why::explained);
  EXPECT_NE(by["cone/capped"].reason.find("30 operations per test per lane at 16 lanes against 26"), std::string::npos);
  EXPECT_EQ(by["quadric/matrix"].why, Simd16Method::Why::unexplained);
  EXPECT_EQ(by["quadric/matrix"].reason, "**unexplained**");
}

// A run without 16-lane rows (--isa avx2, an AVX2-only CPU) has no verdicts to give.
TEST(ReportSimd16, NoSixteenLaneRowsNoVerdicts) {
  json doc = {{"benchmarks", json::array()}};
  for (int round = 0; round < 9; ++round)
    doc["benchmarks"].push_back({{"run_name", "plane/lecture/rays_in_lanes/hit"}, {"run_type", "iteration"}, {"repetition_index", round},
                                 {"tests_per_s", 2.5e9}});
  EXPECT_TRUE(rb::app::simd_report::simd16_methods(doc).empty());
}

}  // namespace
