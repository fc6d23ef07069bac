// The report's section on how precise its ratios are (apps/report/report_precision.cpp), on a
// made-up summary whose intervals are known: each family's half-widths, the widest row named, and
// the goal that trace and kernel rows stay within 5 % (render rows shown, not held to it).
#include "apps/report/report_doc.hpp"
#include "apps/report/report_sections.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace {

using nlohmann::json;

// An interval of `rounds` rounds around `ratio`, `half` wide on each side (relative).
json interval(double ratio, double half, std::size_t rounds = 15) {  // (rounds unsigned, as the stats write them)
  return {{"ratio", ratio}, {"lo", ratio * (1 - half)}, {"hi", ratio * (1 + half)}, {"coverage", 0.965}, {"rounds", rounds}};
}

json trace_row(const char* mesh, double half) {
  return {{"mesh", mesh}, {"ray_set", "primary"}, {"packet", 8}, {"threads", 1}, {"vs_embree", interval(1.1, half)}};
}

json made_up(double widest_trace, double render_half) {
  json s;
  s["tracing"]["matrix"] = json::array({trace_row("bunny", 0.01), trace_row("dragon", 0.03), trace_row("field", widest_trace)});
  s["simd_vs_scalar"] = json::array({{{"kernel", "sphere"}, {"method", "geometric"}, {"case", "hit"},
                                      {"speedup_rays_in_lanes_interval", interval(7.0, 0.02)}}});
  s["render"] = json::array({{{"scene", "spd:balls"}, {"alone", {{"render_over_alone", interval(0.5, render_half, 9)}}}}});
  return s;
}

TEST(ReportPrecision, HoldsTraceAndKernelRowsToFivePerCentAndNamesTheWidest) {
  json s = made_up(0.08, 0.2);
  std::vector<rb::app::doc::Goal> goals;
  const std::string md = rb::app::report_section_precision(s, goals);
  ASSERT_EQ(goals.size(), 1u);
  EXPECT_EQ(goals[0].met, rb::app::doc::kGoalNotMet);
  EXPECT_NE(goals[0].measured.find("1 of 4 rows over"), std::string::npos) << goals[0].measured;
  EXPECT_NE(goals[0].measured.find("largest 8.0 %"), std::string::npos) << goals[0].measured;
  EXPECT_NE(goals[0].measured.find("field, primary, packet 8, 1 thread(s)"), std::string::npos) << goals[0].measured;
  EXPECT_NE(md.find("## How precise the ratios are"), std::string::npos);
  // The render row is shown with its 20 % but held to nothing.
  EXPECT_NE(md.find("| render / its own rays traced alone | other | 1 | 20.0 % |"), std::string::npos) << md;
  const json& fam = s["precision"]["families"];
  ASSERT_EQ(fam.size(), 3u);
  EXPECT_EQ(fam[0]["kind"], "kernel");
  EXPECT_EQ(fam[1]["rows"], 3);
  EXPECT_EQ(fam[1]["over_target"], 1);
  EXPECT_NEAR(fam[1]["median_half_width"].get<double>(), 0.03, 1e-12);

  json within = made_up(0.049, 0.2);
  goals.clear();
  rb::app::report_section_precision(within, goals);
  EXPECT_EQ(goals.at(0).met, rb::app::doc::kGoalMet) << goals[0].measured;
}

// The PGO comparison's ratios (./run.sh pgo, summary "pgo" from pgo.json) are kernel and trace rows
// like the others.
TEST(ReportPrecision, HoldsThePgoRowsToo) {
  json s = made_up(0.01, 0.2);
  s["pgo"]["families"] = json::array({{{"kernel", "sphere"}, {"benchmarks", 12}, {"pgo", interval(1.02, 0.01, 12)}}});
  s["pgo"]["traces"] = json::array({{{"scene", "spd:balls:3"}, {"ray_set", "random"}, {"packet", 1}, {"pgo", interval(0.83, 0.06, 12)}}});
  std::vector<rb::app::doc::Goal> goals;
  const std::string md = rb::app::report_section_precision(s, goals);
  EXPECT_NE(md.find("| PGO build / normal build, per kernel family (./run.sh pgo) | kernel | 1 | 1.0 % |"), std::string::npos) << md;
  EXPECT_NE(md.find("| PGO build / normal build, per trace row (./run.sh pgo) | trace | 1 | 6.0 % | 6.0 % (spd:balls:3, random, packet 1, 1 thread) | 1 |"),
            std::string::npos)
      << md;
  ASSERT_EQ(goals.size(), 1u);
  EXPECT_EQ(goals[0].met, rb::app::doc::kGoalNotMet);
  EXPECT_NE(goals[0].measured.find("1 of 6 rows over"), std::string::npos) << goals[0].measured;
}

TEST(ReportPrecision, ARunOfOneRoundHasNoIntervalToJudge) {
  json s;
  s["tracing"]["matrix"] = json::array({{{"mesh", "bunny"}, {"vs_embree", interval(1.1, 0.0, 1)}}});
  std::vector<rb::app::doc::Goal> goals;
  rb::app::report_section_precision(s, goals);
  ASSERT_EQ(goals.size(), 1u);
  EXPECT_EQ(goals[0].met, rb::app::doc::kGoalNotMeasured);
}

}  // namespace
