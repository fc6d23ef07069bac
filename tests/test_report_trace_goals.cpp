// The report's thread-scaling goal (apps/report/report_trace_goals.cpp) on made-up rows: a row where
// the machine itself ran two threads of a fixed load at less than the target in the same rounds is
// judged apart, so a busy host makes the goal undecided, never unmet; a row the machine did not
// limit is judged as it stands.
#include "apps/report/report_doc.hpp"
#include "apps/report/report_trace.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace {

using nlohmann::json;

json interval(double ratio, double lo, double hi) {
  return {{"ratio", ratio}, {"lo", lo}, {"hi", hi}, {"coverage", 0.965}, {"rounds", 15u}};
}

// A scaling row: ours with its interval, Embree's figure, and the machine's capacity (if any).
json row(const char* set, json ours, const json& machine = nullptr) {
  json r = {{"mesh", "field"}, {"ray_set", set}, {"packet", 8}, {"ours", ours["ratio"]}, {"embree", 1.6}, {"ours_interval", ours}};
  if (!machine.is_null()) r["machine"] = machine;
  return r;
}

json scaling_goal(const json& scaling) {
  const json none = json::array();
  json goals = json::array();
  rb::app::trace_goals({none, none, none, scaling, 15}, goals);
  for (const auto& g : goals)
    if (g["goal"].get<std::string>().find("two threads >= 1.8x") != std::string::npos) return g;
  ADD_FAILURE() << "no thread-scaling goal";
  return {};
}

TEST(ReportTraceGoals, AMachineThatGaveTwoThreadsLessMakesTheScalingGoalUndecided) {
  const json full = interval(2.0, 1.97, 2.02), busy = interval(1.6, 1.55, 1.65);
  const json good = interval(1.97, 1.94, 2.0), low = interval(1.55, 1.51, 1.58);
  // Every row scales and the machine gave two full CPUs: met.
  EXPECT_EQ(scaling_goal(json::array({row("primary", good, full), row("shadow", good, full)}))["met"], rb::app::doc::kGoalMet);
  // One row low where the machine gave 1.6x: judged apart, the goal undecided, the row named.
  const json g = scaling_goal(json::array({row("primary", good, full), row("shadow", low, busy)}));
  EXPECT_EQ(g["met"], rb::app::doc::kGoalUndecided) << g.dump();
  EXPECT_EQ(g["verdict"], "undecided");
  const std::string m = g["measured"].get<std::string>();
  EXPECT_NE(m.find("1 row(s) judged apart"), std::string::npos) << m;
  EXPECT_NE(m.find("field, shadow, packet 8"), std::string::npos) << m;
  EXPECT_NE(m.find("the machine 1.60x [1.55-1.65]"), std::string::npos) << m;
  // A row scaling as well as the busy machine allowed it: judged apart and clearing, the goal met.
  EXPECT_EQ(scaling_goal(json::array({row("primary", good, full), row("shadow", good, busy)}))["met"], rb::app::doc::kGoalMet);
  // The same low row where the machine gave two full CPUs, or where it was not measured (an older
  // record): the tracer's own shortfall, not met.
  EXPECT_EQ(scaling_goal(json::array({row("primary", good, full), row("shadow", low, full)}))["met"], rb::app::doc::kGoalNotMet);
  EXPECT_EQ(scaling_goal(json::array({row("primary", good, full), row("shadow", low)}))["met"], rb::app::doc::kGoalNotMet);
  // A machine-limited row cannot hide a row the machine did not limit.
  EXPECT_EQ(scaling_goal(json::array({row("primary", low, full), row("shadow", low, busy)}))["met"], rb::app::doc::kGoalNotMet);
}

}  // namespace
