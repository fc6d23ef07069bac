// `raybench compare A B`: two results of one kind (bench, trace, render, accuracy, csg JSON, or
// two report folders), row by row: both figures, their ratio, for repeated measurements the
// ratio's confidence interval, and a verdict by it; a summary (geometric mean of the speed ratios,
// how many rows are faster or slower beyond noise); --threshold turns regressions into exit 1.
#pragma once

#include "apps/results/results.hpp"
#include "apps/results/stats.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rb::app {

struct CompareOptions {
  double alpha = 0.05;       // timings with repetitions on both sides: B/A's interval at level 1 - alpha
  double noise = 0.05;       // a single timing figure differs beyond noise when it moved by more than this fraction
  double threshold = -1;     // >= 0: a row worse beyond noise by more than this fraction is a regression (exit 1)
  std::string filter;        // regex on the row's name ("" : every row)
  std::string metric;        // only this metric ("" : every metric)
  bool all = false;          // also list the deterministic figures that did not change
  // Compare two trace or render runs made with other settings (scene, ray set, packet size, threads,
  // rays, model): refused without it, since their figures measure different things.
  bool force = false;
  // A results history: A and B are the ids of two of its runs (`raybench history` lists them).
  std::string history;
};

struct ComparedRow {
  Figure a, b;
  double ratio = 0;          // B / A of the figure
  double gain = 0;           // how much better B is: ratio for higher-is-better, 1 / ratio for lower-is-better; NaN: neither
  stats::RatioInterval interval;  // B/A's interval (stats::unpaired_ratio); not valid below 2 repetitions a side
  std::string verdict;       // faster, slower (timings); better, worse, changed (deterministic figures); "" within noise
  bool regression = false;   // worse beyond noise by more than the threshold (the whole interval)
  bool possible_regression = false;  // the median worse by more than the threshold, the interval reaching it
  bool judged = true;        // counted in the summary and by --threshold (Figure::judged, or named by --metric)
};

// A goal of two reports: its verdict in each (met, not met, undecided, not measured).
struct ComparedGoal {
  std::string section, goal, a, b;
  bool flipped = false;  // met in one, not met in the other
};

struct Comparison {
  std::string kind;
  ResultSet a, b;            // the figures are moved into rows; a.figures, b.figures hold the unmatched ones
  std::vector<ComparedRow> rows;
  std::vector<std::string> notes;  // differences of machine, build or configuration, and limits of the test
  CompareOptions options;
  // Summary.
  double geomean_gain = 0;   // over the timing rows
  std::size_t timings = 0, faster = 0, slower = 0, figures = 0, better = 0, worse = 0, changed = 0, regressions = 0;
  // Two reports: every goal in both, matched by section and goal; how many flipped between met and
  // not met, and how many moved to or from undecided (a verdict by interval may: a flip may not).
  std::vector<ComparedGoal> goals;
  std::size_t goal_flips = 0, goal_moves = 0;
};

// Throws std::runtime_error when the kinds differ or nothing is left to compare.
Comparison compare_results(ResultSet a, ResultSet b, const CompareOptions& o);

std::string compare_text(const Comparison& c);      // fits 80 columns
std::string compare_markdown(const Comparison& c);
nlohmann::json compare_json(const Comparison& c);
std::string compare_summary_line(const Comparison& c);

}  // namespace rb::app
