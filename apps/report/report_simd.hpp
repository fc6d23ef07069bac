// The two files of the report's "Scalar against SIMD" section: report_simd.cpp (scalar against 8
// lanes, the speed goals, the 4x target) and report_simd16.cpp (16 AVX-512 lanes against 8), and the
// helpers they share.
#pragma once

#include "apps/report/report_doc.hpp"
#include "apps/results/stats.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
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

// What a method's divisions and square roots allow at 16 lanes (report_simd16.cpp: the divider
// model). NaN without divisions, square roots or the instruction rows.
struct DividerModel {
  double estimate = stats::kNaN, cap = stats::kNaN;  // no overlap with the rest; the divider alone
  double div = 0, sqrt = 0, instructions = 0;        // per test per lane, counted at 16 lanes
  bool valid() const { return std::isfinite(estimate) && std::isfinite(cap); }
};

// One method at 16 lanes against 8: per case the better mapping's ratio with its interval, the
// verdict against 1.6x in every case, and the reason where it falls short.
struct Simd16Method {
  enum class Why { met, undecided, explained, unexplained };
  std::string km;                                      // kernel/method
  std::map<std::string, stats::RatioInterval> cases;  // hit, miss, half
  std::string low_case, mapping;                       // its lowest case, and that case's mapping
  double ops8 = stats::kNaN, ops16 = stats::kNaN;      // operations per test per lane there
  DividerModel model;
  bool model_fits = false;  // the model's range holds the lowest case (within 0.05)
  int verdict = doc::kGoalUndecided;
  Why why = Why::undecided;
  std::string reason;  // empty when met
};
std::vector<Simd16Method> simd16_methods(const nlohmann::json& bench);

// The 16-against-8-lane part of the section (empty when the run has no 16-lane rows), its goals
// added to `goals`.
std::string simd16_section(const nlohmann::json& bench, nlohmann::json& summary, std::vector<doc::Goal>& goals);

}  // namespace rb::app::simd_report
