// Runs the registered kernel benchmarks in this process (`raybench bench`, `raybench report`):
// Google Benchmark's JSON reporter writes every figure into memory, while the terminal shows one
// progress bar on stderr instead of Google Benchmark's console table (`raybench bench` prints its
// own table from the JSON afterwards, apps/cmd_bench.cpp). The caller writes the JSON where the
// user asked, by the one output rule (core/output_file.hpp).
//
// The protocol: rounds, not repetitions back to back. Each round runs every selected benchmark
// once (at least --min-time seconds each: Google Benchmark chooses the iterations in the first
// round, the later rounds run as many), in
// registration order, which puts a method's scalar, 8-lane and 16-lane forms of one case back to
// back (bench/register.hpp), so that a change of the machine's load falls on all of them; a
// benchmark's repetitions are its rounds, and a ratio between two benchmarks is taken round by
// round (stats::paired_ratio). With --extra-rounds, the forms of a case whose ratio's interval is
// still wider than --within run again, a round at a time (rows_to_extend).
#include "apps/cli.hpp"
#include "apps/results/machine.hpp"
#include "apps/progress.hpp"
#include "apps/report/report.hpp"
#include "apps/results/results.hpp"
#include "apps/results/stats.hpp"
#include "bench/register.hpp"

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <fstream>
#include <iostream>
#include <regex>
#include <set>
#include <sstream>
#include <string_view>
#include <utility>

namespace rb::app {
namespace {

// Registers every benchmark once, for the ISA the first caller names (one per process).
void ensure_registered(const std::string& isa) {
  static bool registered = false;
  if (!registered) {
    rb::bench::register_all_benchmarks(rb::bench::isa_choice(isa).simd16);
    registered = true;
  }
}

// A benchmark's name without the "/iterations:N" Google Benchmark appends once its iterations are
// fixed (run_benchmarks: the rounds after the first).
std::string plain_name(const std::string& name) {
  static const std::regex suffix("/iterations:[0-9]+$");
  return std::regex_replace(name, suffix, "");
}

// Google Benchmark's filter selecting exactly these benchmarks, with or without "/iterations:N".
std::string exact_filter(const std::vector<std::pair<std::string, benchmark::IterationCount>>& runs) {
  std::string spec = "^(";
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (i) spec += '|';
    for (const char c : runs[i].first) {
      if (std::string_view(".^$|()[]{}*+?\\").find(c) != std::string_view::npos) spec += '\\';
      spec += c;
    }
  }
  return spec + ")(/iterations:[0-9]+)?$";
}

// Hands every figure of a round to Google Benchmark's JSON reporter, writing into a string (one
// per round), and draws the one progress bar (apps/progress.hpp) over all rounds with the benchmark
// under way.
class ProgressReporter : public benchmark::BenchmarkReporter {
 public:
  ProgressReporter(std::size_t total, int rounds, const std::string& what)
      : total_(total * std::size_t(rounds)), benchmarks_(total), rounds_(rounds), what_(what), bar_(what) {}
  // Starts a round: a fresh JSON reporter (each round is a whole Google Benchmark run).
  void start_round(int round) {
    round_ = round;
    label_ = fmt::format("round {}/{}", round + 1, rounds_);
    start_run();
  }
  // Starts the k-th of at most `of` extra rounds, over n of the benchmarks (the bar grows by them).
  void start_extra(int k, int of, std::size_t n) {
    round_ = rounds_ + k;
    total_ += n;
    label_ = fmt::format("extra round {}/{} ({} benchmarks)", k + 1, of, n);
    ++extra_;
    start_run();
  }
  void start_run() {
    text_ = std::make_unique<std::ostringstream>();
    json_ = std::make_unique<benchmark::JSONReporter>();
    json_->SetOutputStream(text_.get());
    json_->SetErrorStream(text_.get());
  }
  bool ReportContext(const Context& c) override {
    bar_.update(double(done_) / double(std::max<std::size_t>(total_, 1)));
    return json_->ReportContext(c);
  }
  void ReportRuns(const std::vector<Run>& runs) override {
    if (runs.empty()) return;
    json_->ReportRuns(runs);
    ++done_;
    for (const auto& r : runs) {
      if (r.error_occurred) errors_.push_back(plain_name(r.benchmark_name()) + ": " + r.error_message);
      if (round_ == 0) first_round_.emplace_back(r.benchmark_name(), r.error_occurred ? 0 : r.iterations);
    }
    bar_.update(double(done_) / double(std::max(total_, done_)), fmt::format("{}: {}", label_, plain_name(runs.front().run_name.str())));
  }
  void Finalize() override {
    json_->Finalize();
    texts_.push_back(text_->str());
  }
  void done() {
    bar_.done();
    const std::size_t extra = total_ - benchmarks_ * std::size_t(rounds_);
    std::cerr << fmt::format("{}: {} benchmarks x {} rounds{} in {}\n", what_, benchmarks_, rounds_,
                             extra_ ? fmt::format(", then {} runs in {} extra rounds", extra, extra_) : "", format_duration(bar_.seconds()));
    for (const auto& e : errors_) std::cerr << "  error: " << e << "\n";
  }
  std::size_t errors() const { return errors_.size(); }
  const std::vector<std::string>& texts() const { return texts_; }
  // Each benchmark the first round ran, with its iterations there (0: it failed).
  const std::vector<std::pair<std::string, benchmark::IterationCount>>& first_round() const { return first_round_; }

 private:
  std::size_t total_, benchmarks_, done_ = 0;
  int rounds_, round_ = 0, extra_ = 0;
  std::string what_, label_;
  ProgressBar bar_;
  std::vector<std::string> errors_, texts_;
  std::vector<std::pair<std::string, benchmark::IterationCount>> first_round_;
  std::unique_ptr<std::ostringstream> text_;
  std::unique_ptr<benchmark::JSONReporter> json_;
};

// The rounds' runs as one Google Benchmark document: the first round's context, every round's run
// of each benchmark as a repetition (repetition_index = its round), and after them, per benchmark, the
// aggregates Google Benchmark would give its repetitions (mean, median, stddev, cv of every
// numeric field that varies by run).
nlohmann::json merge_rounds(const std::vector<nlohmann::json>& rounds) {
  nlohmann::json doc = rounds.front();
  doc["context"]["raybench_rounds"] = rounds.size();
  nlohmann::json all = nlohmann::json::array();
  std::vector<std::string> order;
  std::map<std::string, std::vector<nlohmann::json>> runs;
  for (std::size_t r = 0; r < rounds.size(); ++r)
    for (nlohmann::json b : rounds[r].at("benchmarks")) {
      if (b.value("run_type", "") != "iteration") continue;
      const std::string name = b.value("run_name", b.value("name", ""));
      b["repetition_index"] = r;
      if (!runs.count(name)) order.push_back(name);
      runs[name].push_back(b);
    }
  for (auto& [name, v] : runs)  // a benchmark's rounds: the common ones and its extra ones
    for (auto& b : v) b["repetitions"] = v.size();
  static const std::set<std::string> kFixed = {"family_index", "per_family_instance_index", "repetitions", "repetition_index", "threads",
                                              "iterations"};
  for (const auto& name : order) {
    const auto& v = runs[name];
    for (const auto& b : v) all.push_back(b);
    for (const char* agg : {"mean", "median", "stddev", "cv"}) {
      nlohmann::json a = v.front();
      a["name"] = name + "_" + agg;
      a["run_type"] = "aggregate";
      a["aggregate_name"] = agg;
      a["aggregate_unit"] = std::string(agg) == "cv" ? "percentage" : "time";
      a.erase("repetition_index");
      for (auto it = a.begin(); it != a.end(); ++it) {
        if (!it.value().is_number() || kFixed.count(it.key())) continue;
        std::vector<double> x;
        for (const auto& b : v)
          if (b.contains(it.key()) && b[it.key()].is_number()) x.push_back(b[it.key()].get<double>());
        const std::string g = agg;
        const double y = g == "mean" ? stats::mean(x) : g == "median" ? stats::median(x) : g == "stddev" ? stats::stddev(x) : stats::cv(x);
        it.value() = std::isfinite(y) ? nlohmann::json(y) : nlohmann::json(nullptr);
      }
      all.push_back(a);
    }
  }
  doc["benchmarks"] = all;
  return doc;
}

}  // namespace

namespace {

// Each benchmark whose variant `partner` maps to another (kernel/method/variant/case: same kernel,
// method and case), against that one, round by round: the median of the rounds' ratios with its
// interval.
template <class Partner>
std::map<std::string, stats::RatioInterval> variant_ratios(const nlohmann::json& doc, Partner partner) {
  // name -> round -> tests per second
  std::map<std::string, std::map<std::size_t, double>> rate;
  for (const auto& b : doc.at("benchmarks")) {
    if (b.value("run_type", "") != "iteration" || !b.contains("tests_per_s") || !b["tests_per_s"].is_number()) continue;
    const std::size_t round = b.contains("repetition_index") && b["repetition_index"].is_number() ? b["repetition_index"].get<std::size_t>() : 0;
    rate[b.value("run_name", b.value("name", ""))][round] = b["tests_per_s"].get<double>();
  }
  std::map<std::string, stats::RatioInterval> out;
  for (const auto& [name, by_round] : rate) {
    auto parts = rb::bench::BenchName::parse(name);
    if (!parts) continue;
    const std::string other = partner(parts->variant);
    if (other.empty()) continue;
    parts->variant = other;
    const auto base = rate.find(parts->str());
    if (base == rate.end()) continue;
    std::vector<double> x, y;
    for (const auto& [round, r] : by_round)
      if (const auto it = base->second.find(round); it != base->second.end()) x.push_back(r), y.push_back(it->second);
    out[name] = stats::paired_ratio(x, y);
  }
  return out;
}

}  // namespace

std::map<std::string, stats::RatioInterval> simd_speedups(const nlohmann::json& doc) {
  return variant_ratios(doc, [](const std::string& v) { return v == "scalar" ? std::string() : std::string("scalar"); });
}

std::map<std::string, stats::RatioInterval> simd16_speedups(const nlohmann::json& doc) {
  return variant_ratios(doc, [](const std::string& v) {
    return v.size() > 2 && v.compare(v.size() - 2, 2, "16") == 0 ? v.substr(0, v.size() - 2) : std::string();
  });
}

namespace {

// The benchmarks an extra round runs: every form of a kernel, method and case (scalar, 8 and 16
// lanes) one of whose ratios (SIMD / scalar, 16 / 8 lanes) has an interval wider than `precision`,
// and each benchmark in no such ratio (the node test, the instruction rows) whose rate's interval
// is; all forms of a case run again, so that its ratios stay paired round by round. With the wide
// ratios' names (the JSON's record of why).
std::pair<std::set<std::string>, std::vector<std::string>> rows_to_extend(const nlohmann::json& doc, double precision) {
  std::set<std::string> groups, paired, names;
  std::vector<std::string> why;
  auto group_of = [](const std::string& name) {
    const auto b = rb::bench::BenchName::parse(name);
    return b ? b->kernel_method() + "/" + b->kase : name;
  };
  for (const auto& ratios : {simd_speedups(doc), simd16_speedups(doc)})
    for (const auto& [name, r] : ratios) {
      paired.insert(group_of(name));
      if (stats::too_wide(r, precision)) groups.insert(group_of(name)), why.push_back(name);
    }
  std::map<std::string, std::vector<double>> rates;
  for (const auto& b : doc.at("benchmarks"))
    if (b.value("run_type", "") == "iteration" && b.contains("tests_per_s") && b["tests_per_s"].is_number())
      rates[b.value("run_name", "")].push_back(b["tests_per_s"].get<double>());
  for (const auto& [name, v] : rates) {
    const std::string g = group_of(name);
    if (groups.count(g)) names.insert(name);
    else if (!paired.count(g) && stats::too_wide(stats::paired_ratio(v, std::vector<double>(v.size(), 1.0)), precision))
      names.insert(name), why.push_back(name);
  }
  return {names, why};
}

}  // namespace

std::string extra_rounds_text(const nlohmann::json& doc) {
  const nlohmann::json* e = doc.contains("raybench_extra_rounds") ? &doc["raybench_extra_rounds"] : nullptr;
  if (!e || !e->is_object() || e->value("most", 0) <= 0) return "";
  const double within = e->value("within", 0.05);
  std::size_t still = 0, ratios = 0;
  for (const auto& ratios_of : {simd_speedups(doc), simd16_speedups(doc)})
    for (const auto& [name, r] : ratios_of) ++ratios, still += stats::too_wide(r, within);
  const auto& rounds = (*e)["rounds"];
  if (doc.contains("context") && doc["context"].value("raybench_rounds", 2) < 2)
    return "Extra rounds: none (one round gives no interval to narrow).";
  if (rounds.empty())
    return fmt::format("Extra rounds: none needed (every ratio's 95 % interval within +-{:g} % after the rounds).", 100 * within);
  std::string runs;
  for (const auto& r : rounds) runs += (runs.empty() ? "" : ", ") + std::to_string(r.value("benchmarks", 0));
  return fmt::format("Extra rounds: {} of at most {} ({} benchmarks in turn: the forms of each case with a ratio whose 95 % interval was "
                     "wider than +-{:g} %, and lone benchmarks whose rate's was); {} of {} ratios still wider after them.",
                     rounds.size(), e->value("most", 0), runs, 100 * within, still, ratios);
}

std::vector<std::string> benchmark_names(const std::string& filter, const std::string& isa) {
  ensure_registered(isa);
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
  const rb::bench::IsaChoice isa = rb::bench::isa_choice(o.isa);  // throws for an ISA this machine lacks
  ensure_registered(o.isa);
  rb::bench::bench_data_seed() = o.seed ? o.seed : rb::bench::kBenchSeed;
  const std::size_t total = benchmark_names(o.filter, o.isa).size();  // throws on a bad regex
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
  benchmark::AddCustomContext("raybench_simd", isa.simd16 ? "xsimd 8.1 fma3<avx2> 8 x float and avx512dq 16 x float" : "xsimd 8.1 fma3<avx2> 8 x float");
  benchmark::AddCustomContext("raybench_isa", isa.name);
  benchmark::AddCustomContext("raybench_isa_why", isa.why);
  benchmark::AddCustomContext("raybench_seed", std::to_string(rb::bench::bench_data_seed()));
  benchmark::AddCustomContext("raybench_repetitions", std::to_string(o.repetitions));
  benchmark::AddCustomContext("raybench_protocol",
                              fmt::format("{} rounds, each running every selected benchmark once in registration order: a benchmark's "
                                          "repetitions are its rounds; the first round finds the iterations that last at least {} s, the "
                                          "later ones run as many{}",
                                          o.repetitions, o.min_time,
                                          o.extra_rounds > 0 ? fmt::format("; then up to {} extra rounds of the cases whose ratio's 95 % "
                                                                           "interval is wider than +-{:g} % (raybench_extra_rounds)",
                                                                           o.extra_rounds, 100 * o.within)
                                                             : ""));
  std::vector<std::string> args = {"raybench", "--benchmark_repetitions=1", fmt::format("--benchmark_min_time={}", o.min_time),
                                   "--benchmark_filter=" + o.filter};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  int argc = int(argv.size());
  benchmark::Initialize(&argc, argv.data());
  const int rounds = std::max(1, o.repetitions);
  // Google Benchmark looks for each benchmark's iterations anew in every run: shorter runs first,
  // each calling the benchmark again with its setup (in the report, about as long as the timed
  // runs themselves). The first round looks; the later rounds run the iterations it settled on
  // (Google Benchmark aims at 1.4x --min-time), once per benchmark. Set on the registered
  // benchmarks, so once per process.
  static double fixed_for = 0;
  if (fixed_for != 0 && fixed_for != o.min_time)
    throw std::logic_error(fmt::format("benchmarks already ran with --min-time {} in this process", fixed_for));
  ProgressReporter progress(total, rounds, o.what);
  std::size_t n = 0;
  std::string spec = o.filter;
  const LoadWatch watch;
  for (int r = 0; r < rounds; ++r) {
    progress.start_round(r);
    n += benchmark::RunSpecifiedBenchmarks(&progress, spec);
    if (r == 0 && rounds > 1 && !progress.first_round().empty()) {
      for (const auto& [name, it] : progress.first_round())
        if (const auto b = rb::bench::registered_benchmarks().find(name); it > 0 && b != rb::bench::registered_benchmarks().end())
          b->second->Iterations(it);
      fixed_for = o.min_time;
      spec = exact_filter(progress.first_round());
    }
  }
  // The rounds so far as one document (names without Google Benchmark's "/iterations:N").
  auto merged = [&] {
    std::vector<nlohmann::json> docs;
    for (const auto& t : progress.texts()) {
      docs.push_back(parse_json_text(t, "Google Benchmark's JSON"));
      for (auto& b : docs.back().at("benchmarks"))
        for (const char* key : {"name", "run_name"})
          if (b.contains(key) && b[key].is_string()) b[key] = plain_name(b[key].get<std::string>());
    }
    return merge_rounds(docs);
  };
  // Extra rounds: while some ratio's interval is wider than --within, one more round of the forms
  // it compares (rows_to_extend), at most --extra-rounds of them. A stretch in which the host runs
  // slow (it can slow the SIMD forms more than the scalar ones) then falls among more rounds, and
  // the interval, which leaves out the most extreme rounds on each side, can leave it out.
  nlohmann::json extension = {{"within", o.within}, {"most", o.extra_rounds}, {"rounds", nlohmann::json::array()}};
  try {
    for (int e = 0; e < o.extra_rounds && rounds >= 2 && n > 0; ++e) {
      const auto [names, why] = rows_to_extend(merged(), o.within);
      if (names.empty()) break;
      std::vector<std::pair<std::string, benchmark::IterationCount>> runs;
      for (const auto& [name, it] : progress.first_round())
        if (it > 0 && names.count(plain_name(name))) runs.emplace_back(name, it);
      if (runs.empty()) break;
      progress.start_extra(e, o.extra_rounds, runs.size());
      n += benchmark::RunSpecifiedBenchmarks(&progress, exact_filter(runs));
      extension["rounds"].push_back({{"round", rounds + e}, {"benchmarks", runs.size()}, {"wide", why}});
    }
  } catch (const std::exception& e) {
    std::cerr << error_line(o.command, "", e.what()) << "\n";
    return kExitError;
  }
  const nlohmann::json machine_load = watch.json();
  benchmark::Shutdown();
  progress.done();
  if (n == 0) {
    std::cerr << error_line(o.command, "", "no benchmark ran (--filter '" + o.filter + "')") << "\n";
    return kExitNothing;
  }
  try {
    doc = merged();
    doc["context"]["raybench_rounds"] = rounds;
    doc["raybench_extra_rounds"] = extension;
    // Every SIMD benchmark's speedup over its scalar form, round by round, with its interval.
    nlohmann::json sp = nlohmann::json::object();
    for (const auto& [name, r] : simd_speedups(doc)) sp[name] = stats::interval_json(r);
    doc["raybench_simd_vs_scalar"] = sp;
    // Every 16-lane benchmark over its 8-lane form, the same way.
    nlohmann::json s16 = nlohmann::json::object();
    for (const auto& [name, r] : simd16_speedups(doc)) s16[name] = stats::interval_json(r);
    if (!s16.empty()) doc["raybench_simd16_vs_simd8"] = s16;
    if (!o.every_repetition) {  // the aggregates only
      auto& all = doc["benchmarks"];
      all.erase(std::remove_if(all.begin(), all.end(), [](const nlohmann::json& b) { return b.value("run_type", "") == "iteration"; }),
                all.end());
    }
    doc["machine_load"] = machine_load;
  } catch (const std::exception& e) {
    std::cerr << error_line(o.command, "", e.what()) << "\n";
    return kExitError;
  }
  return progress.errors() ? kExitError : kExitOk;
}

}  // namespace rb::app
