// The figures of a raybench result, whatever command wrote it: what `raybench compare` compares
// and what the results history stores. A result is a JSON file of `bench`, `trace`, `render`,
// `accuracy` or `csg` (--json), or a report folder (bench.json, tracing.json, summary.json's render
// rows, accuracy.json, csg.json, scenes.json).
#pragma once

#include <nlohmann/json.hpp>

#include <limits>
#include <string>
#include <vector>

namespace rb::app {

// One figure of one row: e.g. (bench, "sphere/geometric/scalar/hit", tests_per_s).
struct Figure {
  std::string section;  // bench, trace, render, accuracy, csg, scenes
  std::string name;     // the row: a benchmark, a scene and its configuration, an accuracy case
  std::string metric;   // the JSON field it comes from (tests_per_s, mrays_per_s, false_hit_ppm, ...)
  std::string unit;     // as shown: Mtests/s, Mrays/s, ms, ppm, ...
  double scale = 1;     // shown value = value * scale
  int direction = 1;    // +1 higher is better, -1 lower is better, 0 neither (a count that should not move)
  bool timing = true;   // a measurement, subject to noise; false: a seeded, deterministic figure
  // Judged by `compare` (its summary, verdict counts and --threshold): the subject's own figures.
  // Not judged unless asked for by --metric: a yardstick's (Embree's) and a timing measured once
  // where the result has repetitions of its others (a build time): shown beside them.
  bool judged = true;  // judged_metric(metric) for every figure a result or the history gives
  double value = std::numeric_limits<double>::quiet_NaN();  // the median of the samples, or the one figure
  std::vector<double> samples;                               // the repetitions (unscaled); empty: one figure
  std::string key() const { return section + "\t" + name + "\t" + metric; }
};

struct ResultSet {
  std::string kind;        // bench, trace, render, accuracy, csg or report
  std::string source;      // the file or folder it was read from
  nlohmann::json machine;  // the machine and build block (null when the result has none)
  nlohmann::json config;   // what the run was asked to do, where the result says (seed, mode, repetitions)
  std::vector<Figure> figures;
  // A report's goals, each {section, goal, measured, verdict} (verdict: met, not met, undecided, not
  // measured); empty for other results.
  nlohmann::json goals = nlohmann::json::array();
};

// Whether compare judges a metric by default: not a yardstick's (Embree's: embree_*) nor a build
// time (one build per run unless asked otherwise).
bool judged_metric(const std::string& metric);

// Reads a JSON file; Google Benchmark's bare NaN / Infinity tokens become null. Throws
// std::runtime_error("PATH: reason"), with the system's reason when it cannot be read.
nlohmann::json read_json_file(const std::string& path);
// The same for text in memory (`name` labels it in the error).
nlohmann::json parse_json_text(const std::string& text, const std::string& name);

// The kind of a raybench JSON document: bench, trace, render, accuracy, csg, or "" (not one).
std::string result_kind(const nlohmann::json& doc);

// The figures of one document of a known kind (section = kind).
ResultSet figures_of(const std::string& kind, const nlohmann::json& doc);

// A JSON result file or a report folder. Throws std::runtime_error naming the path and the reason.
ResultSet load_results(const std::string& path);

// The machine and build block of every JSON result (apps/machine.cpp), by kind.
nlohmann::json machine_of(const nlohmann::json& doc);

}  // namespace rb::app
