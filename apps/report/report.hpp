// `raybench report`: the main job. Runs every measurement on the embedded defaults and writes
// report/index.md with JSON and PNG charts beside it.
#pragma once

#include "apps/results/stats.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rb::app {

struct ReportOptions {
  std::string out = "report";
  // Benchmark rounds (apps/bench_run.cpp): medians, and ratios with a 95 % interval. 9 is the
  // fewest rounds whose sign-test interval leaves out the most extreme round on each side (from 6
  // to 8 it is the whole range, which one disturbed round widens); a repetition's time is shorter
  // than `bench`'s so that the section takes about what 7 rounds of 0.05 s took (docs/DESIGN.md).
  int repetitions = 9;
  double min_time = 0.04;       // seconds per benchmark repetition
  // Then up to 6 more rounds of the forms whose ratio's interval is wider than +-5 %
  // (BenchOptions::extra_rounds): a stretch in which the host ran slow is then left out.
  int extra_rounds = 6;
  double within = 0.05;
  std::string filter = ".";     // benchmark name filter (regex)
  bool charts = true;
  // A small report in about a minute (few repetitions, few rays, small images, fewer scenes): to
  // check the report's layout and links, not to quote its figures.
  bool quick = false;
  // --from DIR: write DIR's document again from its record (DIR/measured.json) without measuring;
  // the options above are then the record's.
  std::string from;
  bool json = false;            // --json: the summary JSON also to json_file ("" or "-": stdout)
  std::string json_file;
};

// The record of everything a report measured, in its folder (apps/report_record.hpp).
inline constexpr const char* kRecordFile = "measured.json";

int run_report(const ReportOptions& o);

// A run of the registered benchmarks (apps/bench_run.cpp).
struct BenchOptions {
  // Rounds (each runs every selected benchmark once: a benchmark's repetitions are its rounds): 6 or
  // more give SIMD / scalar a 95 % interval (stats::paired_ratio), from 9 one that leaves out the
  // most extreme round on each side (ReportOptions); 4 or more let `compare`'s U test reach p < 0.05.
  // 9 rounds of 0.08 s take about what 7 of 0.1 s took.
  int repetitions = 9;
  double min_time = 0.08;               // seconds per benchmark per round
  // After the rounds, up to `extra_rounds` more, each of the forms of every kernel, method and case
  // one of whose ratios (SIMD / scalar, 16 / 8 lanes) still has an interval wider than `within`
  // (relative half-width), and of the lone benchmarks whose rate's interval is (the node test).
  int extra_rounds = 0;
  double within = 0.05;
  std::string filter = ".";             // regex on kernel/method/variant/case
  bool every_repetition = true;         // false: medians and the other aggregates only
  std::uint32_t seed = 0;               // seed of the rays and primitives; 0: the report's data
  std::string what = "raybench bench";  // the progress bar's label
  std::string command = "bench";        // the subcommand named in error lines
  std::string isa = "auto";             // auto, avx2, avx512: the 16-lane rows run under avx512 (bench/simd16.hpp)
};

// The registered benchmarks whose name the filter selects (Google Benchmark's rule: a POSIX
// extended regex searched in the name, a leading '-' negates it). Throws std::invalid_argument on
// a bad regex, or for an ISA this machine lacks. The first call fixes the ISA (`isa`: auto, avx2,
// avx512; the 16-lane rows are registered under avx512).
std::vector<std::string> benchmark_names(const std::string& filter, const std::string& isa = "auto");

// Runs the benchmarks in this process with a progress bar on stderr; every figure lands in `doc` as
// Google Benchmark JSON (its bare NaN and infinities as null). 0 on success, 2 when the filter
// selects nothing, 1 when a benchmark reported an error.
int run_benchmarks(const BenchOptions& o, nlohmann::json& doc);
// One sentence on the extra rounds a run took (raybench_extra_rounds): how many, of how many runs,
// and how many ratios were still wider than the target after them; "" when none were asked for.
std::string extra_rounds_text(const nlohmann::json& doc);

// Per SIMD benchmark of a run (kernel/method/variant/case), its speedup over the scalar form of the
// same kernel, method and case: its tests per second over the scalar's, round by round (the rounds
// are the repetitions), as the median of the rounds' ratios with its interval (stats::paired_ratio).
// run_benchmarks stores them in the document as "raybench_simd_vs_scalar" (interval JSON by name).
std::map<std::string, stats::RatioInterval> simd_speedups(const nlohmann::json& doc);
// Per 16-lane benchmark (variant rays_in_lanes16, prims_in_lanes16), its speed over the 8-lane form
// of the same kernel, method, mapping and case, the same way ("raybench_simd16_vs_simd8").
std::map<std::string, stats::RatioInterval> simd16_speedups(const nlohmann::json& doc);

}  // namespace rb::app
