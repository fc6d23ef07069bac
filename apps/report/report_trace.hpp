// The parts of report section "Tracing" (apps/report/report_trace.cpp) that live in files of their
// own: the goals judged from the section's rows (report_trace_goals.cpp).
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace rb::app {

inline constexpr int kLargePacket = 64;  // the large coherent packet of the tracing matrix

// What the goals are judged on: the matrix's rows (`raybench trace` JSON with mesh), the sorted
// streams' rows, the builds per mesh, the thread-scaling rows, and the rounds per row.
struct TraceRows {
  const nlohmann::json& rows;
  const nlohmann::json& sorted;
  const nlohmann::json& builds;
  const nlohmann::json& scaling;
  int reps;
};

// The section's goals, each against its worst row (appended to `goal_rows`), as a markdown table.
std::string trace_goals(const TraceRows& x, nlohmann::json& goal_rows);

}  // namespace rb::app
