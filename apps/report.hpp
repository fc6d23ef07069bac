// `raybench report`: the main job. Runs every measurement on the embedded defaults and writes
// report/index.md with JSON and PNG charts beside it.
#pragma once

#include <cstdint>
#include <string>

namespace rb::app {

struct ReportOptions {
  std::string out = "report";
  int repetitions = 5;          // benchmark repetitions; the report quotes medians
  double min_time = 0.05;       // seconds per benchmark repetition
  std::string filter = ".";     // benchmark name filter (regex)
  bool charts = true;
};

int run_report(const ReportOptions& o);

// Runs the kernel benchmarks matching `filter` in this process, writing Google Benchmark JSON to
// `json_out` with every repetition (U-tests need them). `seed` makes the rays and primitives
// (bench::kBenchSeed is the reported data).
int run_benchmarks(const std::string& json_out, int repetitions, double min_time, const std::string& filter, std::uint32_t seed);

}  // namespace rb::app
