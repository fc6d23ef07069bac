// Runs the registered kernel benchmarks in this process (`raybench bench`, `raybench report`):
// Google Benchmark's JSON reporter writes every figure into memory, while the terminal shows one
// progress bar on stderr instead of Google Benchmark's console table (`raybench bench` prints its
// own table from the JSON afterwards, apps/cmd_bench.cpp). The caller writes the JSON where the
// user asked, by the one output rule (core/output_file.hpp).
#include "apps/cli.hpp"
#include "apps/machine.hpp"
#include "apps/progress.hpp"
#include "apps/report.hpp"
#include "apps/results.hpp"
#include "bench/register.hpp"

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <chrono>
#include <fstream>
#include <iostream>
#include <regex>
#include <set>
#include <sstream>

namespace rb::app {
namespace {

void ensure_registered() {
  static bool registered = false;
  if (!registered) {
    rb::bench::register_all_benchmarks();
    registered = true;
  }
}

// Hands every figure to Google Benchmark's JSON reporter, writing into a string, and draws the one
// progress bar (apps/progress.hpp) with the benchmark under way.
class ProgressReporter : public benchmark::BenchmarkReporter {
 public:
  ProgressReporter(std::size_t total, const std::string& what) : total_(total), what_(what), bar_(what) {
    json_.SetOutputStream(&text_);
    json_.SetErrorStream(&text_);
  }
  bool ReportContext(const Context& c) override {
    bar_.update(0);
    return json_.ReportContext(c);
  }
  void ReportRuns(const std::vector<Run>& runs) override {
    // Called once for a benchmark's repetitions and once for their aggregates: count names.
    if (runs.empty()) return;
    json_.ReportRuns(runs);
    if (!seen_.insert(runs.front().run_name.str()).second) return;
    ++done_;
    for (const auto& r : runs)
      if (r.error_occurred) errors_.push_back(r.benchmark_name() + ": " + r.error_message);
    bar_.update(double(done_) / double(std::max(total_, done_)), fmt::format("{}/{} {}", done_, std::max(total_, done_), runs.front().run_name.str()));
  }
  void Finalize() override {
    json_.Finalize();
    bar_.done();
    std::cerr << fmt::format("{}: {} benchmarks in {}\n", what_, done_, format_duration(bar_.seconds()));
    for (const auto& e : errors_) std::cerr << "  error: " << e << "\n";
  }
  std::size_t done() const { return done_; }
  std::size_t errors() const { return errors_.size(); }
  std::string json_text() const { return text_.str(); }

 private:
  std::size_t total_, done_ = 0;
  std::string what_;
  ProgressBar bar_;
  std::vector<std::string> errors_;
  std::set<std::string> seen_;
  std::ostringstream text_;
  benchmark::JSONReporter json_;
};

}  // namespace

std::vector<std::string> benchmark_names(const std::string& filter) {
  ensure_registered();
  const auto& names = rb::bench::registered_names();
  if (filter.empty() || filter == "all") return names;
  // Google Benchmark's rule: a POSIX extended regex searched in the name, a leading '-' negates it.
  const bool neg = filter[0] == '-';
  const std::regex re = filter_regex(neg ? filter.substr(1) : filter);
  std::vector<std::string> out;
  for (const auto& s : names)
    if (filter_matches(re, s) != neg) out.push_back(s);
  return out;
}

int run_benchmarks(const BenchOptions& o, nlohmann::json& doc) {
  ensure_registered();
  rb::bench::bench_data_seed() = o.seed ? o.seed : rb::bench::kBenchSeed;
  const std::size_t total = benchmark_names(o.filter).size();  // throws on a bad regex
  if (total == 0) {
    std::cerr << error_line(o.command, "", fmt::format("--filter '{}' selects no benchmark (names are kernel/method/variant/case; "
                                                       "--list shows them)", o.filter))
              << "\n";
    return kExitNothing;
  }
  const Machine m = machine();
  benchmark::AddCustomContext("raybench_cpu", m.cpu);
  benchmark::AddCustomContext("raybench_build_flags", m.build_flags);
  benchmark::AddCustomContext("raybench_fp_contract", m.fp_contract);
  benchmark::AddCustomContext("raybench_pgo", m.pgo);
  benchmark::AddCustomContext("raybench_git", m.git);
  benchmark::AddCustomContext("raybench_simd", "xsimd 8.1 fma3<avx2> 8 x float");
  benchmark::AddCustomContext("raybench_seed", std::to_string(rb::bench::bench_data_seed()));
  benchmark::AddCustomContext("raybench_repetitions", std::to_string(o.repetitions));
  std::vector<std::string> args = {"raybench",
                                   fmt::format("--benchmark_repetitions={}", o.repetitions),
                                   fmt::format("--benchmark_report_aggregates_only={}", o.every_repetition ? "false" : "true"),
                                   fmt::format("--benchmark_min_time={}", o.min_time),
                                   "--benchmark_filter=" + o.filter};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  int argc = int(argv.size());
  benchmark::Initialize(&argc, argv.data());
  ProgressReporter progress(total, o.what);
  const std::size_t n = benchmark::RunSpecifiedBenchmarks(&progress);
  benchmark::Shutdown();
  if (n == 0) {
    std::cerr << error_line(o.command, "", "no benchmark ran (--filter '" + o.filter + "')") << "\n";
    return kExitNothing;
  }
  try {
    doc = parse_json_text(progress.json_text(), "Google Benchmark's JSON");
  } catch (const std::exception& e) {
    std::cerr << error_line(o.command, "", e.what()) << "\n";
    return kExitError;
  }
  return progress.errors() ? kExitError : kExitOk;
}

}  // namespace rb::app
