// Runs the registered kernel benchmarks in this process (`raybench bench`, `raybench report`):
// Google Benchmark writes every figure to its JSON file, while the terminal shows one progress bar
// on stderr instead of Google Benchmark's console table.
#include "apps/machine.hpp"
#include "apps/report.hpp"
#include "bench/register.hpp"

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <chrono>
#include <fstream>
#include <iostream>
#include <regex>
#include <set>
#include <unistd.h>

namespace rb::app {
namespace {

// How many registered benchmarks the filter selects, by Google Benchmark's rule: a POSIX extended
// regex searched in the name, a leading '-' negates it, "all" selects everything.
std::size_t matching(const std::string& filter) {
  const auto& names = rb::bench::registered_names();
  if (filter.empty() || filter == "all") return names.size();
  const bool neg = filter[0] == '-';
  try {
    const std::regex re(neg ? filter.substr(1) : filter, std::regex::extended);
    std::size_t n = 0;
    for (const auto& s : names) n += std::regex_search(s, re) != neg;
    return n;
  } catch (const std::regex_error&) {
    return names.size();  // Google Benchmark reports the bad filter itself
  }
}

// Collects nothing (the JSON file reporter keeps the figures); draws "[####    ] 12/315 name".
// On a terminal the bar is redrawn in place; otherwise (a log, CI) one line per tenth of the run.
class ProgressReporter : public benchmark::BenchmarkReporter {
 public:
  ProgressReporter(std::size_t total, std::string what) : total_(total), what_(std::move(what)), tty_(isatty(2) != 0) {}
  bool ReportContext(const Context&) override {
    draw("");
    return true;
  }
  void ReportRuns(const std::vector<Run>& runs) override {
    // Called once for a benchmark's repetitions and once for their aggregates: count names.
    if (runs.empty()) return;
    if (!seen_.insert(runs.front().run_name.str()).second) return;
    ++done_;
    for (const auto& r : runs)
      if (r.error_occurred) errors_.push_back(r.benchmark_name() + ": " + r.error_message);
    draw(runs.front().run_name.str());
  }
  void Finalize() override {
    if (tty_) std::cerr << "\r\x1b[K";
    std::cerr << fmt::format("{}: {} benchmarks in {:.0f} s\n", what_, done_, seconds());
    for (const auto& e : errors_) std::cerr << "  error: " << e << "\n";
  }
  std::size_t done() const { return done_; }
  std::size_t errors() const { return errors_.size(); }

 private:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
  void draw(const std::string& name) {
    const std::size_t total = std::max(total_, done_);
    const double f = total ? double(done_) / double(total) : 1.0;
    if (tty_) {
      constexpr int kWidth = 30;
      const int n = int(f * kWidth);
      std::cerr << fmt::format("\r\x1b[K[{}{}] {}/{} {:.0f} s {}", std::string(std::size_t(n), '#'),
                               std::string(std::size_t(kWidth - n), ' '), done_, total, seconds(), name)
                << std::flush;
    } else if (int tenth = int(f * 10); tenth > last_tenth_) {
      last_tenth_ = tenth;
      std::cerr << fmt::format("{}: {:3d}% ({}/{}, {:.0f} s) {}\n", what_, tenth * 10, done_, total, seconds(), name);
    }
  }
  std::size_t total_, done_ = 0;
  std::string what_;
  bool tty_;
  int last_tenth_ = 0;
  std::vector<std::string> errors_;
  std::set<std::string> seen_;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
};

}  // namespace

int run_benchmarks(const BenchOptions& o) {
  static bool registered = false;
  if (!registered) { rb::bench::register_all_benchmarks(); registered = true; }
  rb::bench::bench_data_seed() = o.seed ? o.seed : rb::bench::kBenchSeed;
  const std::size_t total = matching(o.filter);
  if (total == 0) {
    std::cerr << "raybench: no benchmark matches the filter '" << o.filter << "' (names are kernel/method/variant/case)\n";
    return 2;
  }
  if (std::ofstream f(o.json_out); !f) {  // Google Benchmark would exit() on an unwritable file
    std::cerr << "raybench: cannot write " << o.json_out << "\n";
    return 1;
  }
  const Machine m = machine();
  benchmark::AddCustomContext("raybench_cpu", m.cpu);
  benchmark::AddCustomContext("raybench_build_flags", m.build_flags);
  benchmark::AddCustomContext("raybench_fp_contract", m.fp_contract);
  benchmark::AddCustomContext("raybench_pgo", m.pgo);
  benchmark::AddCustomContext("raybench_git", m.git);
  benchmark::AddCustomContext("raybench_simd", "xsimd 8.1 fma3<avx2> 8 x float");
  std::vector<std::string> args = {"raybench",
                                   "--benchmark_out=" + o.json_out,
                                   "--benchmark_out_format=json",
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
    std::cerr << "raybench: no benchmark ran (filter '" << o.filter << "')\n";
    return 2;
  }
  return progress.errors() ? 1 : 0;
}

}  // namespace rb::app
