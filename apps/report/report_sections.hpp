// Report sections contributed by other parts of the engine. Each takes every figure it prints from
// a measurement of the record `rec` (measured now, or replayed by `report --from`), returns markdown
// (with a heading of level 2) and adds its figures to `summary` (written as report/summary.json);
// `out` is the report folder for any JSON or PNG the section writes.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace rb::opstable {
struct Row;
}
namespace rb::app {
namespace doc {
struct Goal;
}
struct ReportOptions;
class Record;
// Section "Scalar against SIMD" from the kernel benchmarks' document (apps/bench_run.cpp): adds
// its goals (the speed goals and the 4x target) to `goals`.  // report_simd.cpp
std::string report_section_simd(const nlohmann::json& bench, nlohmann::json& summary, std::vector<doc::Goal>& goals);
// The speedup of the better of the two SIMD mappings in one row of summary["simd_vs_scalar"].
double better_mapping(const nlohmann::json& row);  // report_simd.cpp
std::string report_section_tracing(const ReportOptions& o, Record& rec, const std::filesystem::path& out, nlohmann::json& summary);  // report_trace.cpp
std::string report_section_scenes(const ReportOptions& o, Record& rec, const std::filesystem::path& out, nlohmann::json& summary);  // report_scenes.cpp
std::string report_section_render(const ReportOptions& o, Record& rec, const std::filesystem::path& out, nlohmann::json& summary);  // report_render.cpp
std::string report_section_accuracy(const ReportOptions& o, Record& rec, const std::filesystem::path& out, nlohmann::json& summary);  // report_accuracy.cpp
std::string report_section_plan(const ReportOptions& o, Record& rec, const std::filesystem::path& out, nlohmann::json& summary);  // report_plan.cpp
// The timed rounds of each whole scene in the lab's section and the plan's table: the lab's default,
// or 3 in quick mode (the layout only: the rounds' fixed time is most of those sections there).
int whole_scene_rounds(const ReportOptions& o);  // report_plan.cpp
// (`ops`: the ops table's rows, for the CSG queries' counts.)
std::string report_section_csg(const ReportOptions& o, Record& rec, const std::filesystem::path& out, nlohmann::json& summary,
                               const std::vector<opstable::Row>& ops);  // report_csg.cpp
// Section "How precise the ratios are", from the summary the sections above wrote: the half-widths
// of every family of ratios with an interval; adds the goal that trace and kernel rows stay within
// 5 % to `goals`.  // report_precision.cpp
std::string report_section_precision(nlohmann::json& summary, std::vector<doc::Goal>& goals);
}  // namespace rb::app
