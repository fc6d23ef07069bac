// The two files of the report's "Scalar against SIMD" section: report_simd.cpp (scalar against 8
// lanes, the speed goals, the 4x target) and report_simd16.cpp (16 AVX-512 lanes against 8), and the
// helpers they share.
#pragma once

#include "apps/report/report_doc.hpp"
#include "apps/results/stats.hpp"

#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <vector>

namespace rb::app::simd_report {

// Medians of a Google Benchmark JSON run: name -> counters.
std::map<std::string, nlohmann::json> medians(const nlohmann::json& j);
// A goal over several ratios: doc::kGoalMet when every interval clears `target`, kGoalNotMet when
// one lies below it, kGoalUndecided otherwise.
int all_clear(const std::vector<stats::RatioInterval>& v, double target);
// Structural reasons a method gains less from more lanes (kernel/method -> reason).
const std::map<std::string, std::string>& structural_reasons();

// The 16-against-8-lane part of the section (empty when the run has no 16-lane rows), its goals
// added to `goals`.
std::string simd16_section(const nlohmann::json& bench, nlohmann::json& summary, std::vector<doc::Goal>& goals);

}  // namespace rb::app::simd_report
