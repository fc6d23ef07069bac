// `raybench bench`: the kernel benchmarks (apps/bench_run.cpp) with a results table on the
// terminal (median, CV, operations per test, SIMD speedup) and Google Benchmark's JSON, every
// repetition kept, with the machine and build block added (`--json FILE`, what compare.py and
// `raybench compare` read).
#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "apps/results/machine.hpp"
#include "apps/report/report.hpp"
#include "apps/report/report_simd.hpp"
#include "apps/results/results.hpp"
#include "apps/results/stats.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <unistd.h>

namespace rb::app {

using nlohmann::json;

namespace {

struct BenchRow {
  std::string name;
  std::vector<double> rates;  // tests per second, one per repetition
  double ops = stats::kNaN;
};

std::string g4(double v) {
  if (!std::isfinite(v)) return "-";
  return std::fabs(v) >= 1e4 ? fmt::format("{:.0f}", v) : std::fabs(v) >= 100 ? fmt::format("{:.1f}", v) : fmt::format("{:.2f}", v);
}

// Per method, 16 lanes over 8 (the report's section 3.3, apps/report/report_simd16.cpp): the lowest
// case with its interval, the verdict against 1.6x in every case and the reason where it falls
// short. Empty without 16-lane rows.
std::string simd16_methods_text(const json& doc) {
  const auto methods = simd_report::simd16_methods(doc);
  if (methods.empty()) return "";
  std::string t = wrap_words("16 lanes over 8, per method (the better mapping's lowest case, 95 % interval; >= 1.6x in every case, or why "
                             "not):");
  for (const auto& m : methods) {
    std::string reason = m.reason;
    for (std::size_t k; (k = reason.find("**")) != std::string::npos;) reason.erase(k, 2);  // markdown bold
    const std::string head = fmt::format("  {:<26} {:>22} {:<4}  {}", m.km, stats::interval_text(m.cases.at(m.low_case)), m.low_case,
                                         doc::goal_word(m.verdict));
    t += wrap_words(reason.empty() || m.why == simd_report::Simd16Method::Why::undecided ? head : head + ": " + reason, 100,
                    std::string(8, ' '));
  }
  return t;
}

}  // namespace

std::string bench_table(const json& doc, double* worst_cv, std::size_t* noisy) {
  std::vector<BenchRow> rows;
  std::map<std::string, std::size_t> at;
  for (const auto& b : doc["benchmarks"]) {
    if (b.value("run_type", "") != "iteration") continue;
    const std::string n = b.value("run_name", b.value("name", ""));
    if (!at.count(n)) at[n] = rows.size(), rows.push_back({n, {}, stats::kNaN});
    BenchRow& r = rows[at[n]];
    if (b.contains("tests_per_s") && b["tests_per_s"].is_number()) r.rates.push_back(b["tests_per_s"].get<double>());
    if (b.contains("ops_per_test") && b["ops_per_test"].is_number()) r.ops = b["ops_per_test"].get<double>();
  }
  const auto speedup = simd_speedups(doc);
  constexpr std::size_t kName = 44;
  std::string t = fmt::format("{:<{}} {:>9} {:>6} {:>8} {:>9}\n", "benchmark (kernel/method/variant/case)", kName, "Mtests/s", "CV %",
                              "ops/test", "vs scalar");
  std::vector<std::pair<stats::RatioInterval, std::string>> speedups;
  double worst = 0;
  std::size_t over = 0;
  for (const auto& r : rows) {
    const double med = stats::median(r.rates), cv = stats::cv(r.rates);
    if (std::isfinite(cv)) worst = std::max(worst, cv), over += cv > 0.05;
    double sp = stats::kNaN;
    if (const auto it = speedup.find(r.name); it != speedup.end() && std::isfinite(it->second.ratio))
      sp = it->second.ratio, speedups.push_back({it->second, r.name});
    std::string name = r.name;
    if (name.size() > kName) {
      t += name + "\n";
      name.clear();
    }
    t += fmt::format("{:<{}} {:>9} {:>6} {:>8} {:>9}\n", name, kName, g4(med / 1e6), std::isfinite(cv) ? fmt::format("{:.1f}", 100 * cv) : "-",
                     g4(r.ops), std::isfinite(sp) ? fmt::format("{:.2f}x", sp) : "-");
  }
  const auto& ctx = doc.contains("context") ? doc["context"] : json::object();
  t += wrap_words(fmt::format("Median of {} rounds per benchmark (each round runs every benchmark once; 256 rays x 64 primitives per "
                              "iteration, one thread); CV: coefficient of variation over the rounds; vs scalar: the median of the rounds' "
                              "ratios to the scalar form of the same kernel, method and case (--json: each with its 95 % interval).",
                              ctx.value("raybench_repetitions", std::string("?"))));
  if (const std::string e = extra_rounds_text(doc); !e.empty()) t += wrap_words(e);
  if (!speedups.empty()) {
    std::sort(speedups.begin(), speedups.end(), [](const auto& a, const auto& b) { return a.first.ratio < b.first.ratio; });
    const auto& lo = speedups.front();
    const auto& hi = speedups.back();
    t += wrap_words(fmt::format("SIMD over scalar, {} SIMD rows: lowest {} ({}), highest {} ({})", speedups.size(),
                                stats::interval_text(lo.first), lo.second, stats::interval_text(hi.first), hi.second));
  }
  std::vector<std::pair<stats::RatioInterval, std::string>> wide;
  for (const auto& [name, r] : simd16_speedups(doc))
    if (std::isfinite(r.ratio)) wide.push_back({r, name});
  if (!wide.empty()) {
    std::sort(wide.begin(), wide.end(), [](const auto& a, const auto& b) { return a.first.ratio < b.first.ratio; });
    t += wrap_words(fmt::format("16 AVX-512 lanes over 8 AVX2 lanes, {} rows: median {:.2f}x, lowest {} ({}), highest {} ({})", wide.size(),
                                wide[wide.size() / 2].first.ratio, stats::interval_text(wide.front().first), wide.front().second,
                                stats::interval_text(wide.back().first), wide.back().second));
  }
  t += simd16_methods_text(doc);
  t += wrap_words("ISA: " + ctx.value("raybench_isa", std::string("avx2")) + " (" + ctx.value("raybench_isa_why", std::string("-")) + ").");
  if (doc.contains("machine_load")) t += wrap_words("Machine: " + load_text(doc["machine_load"]) + ".");
  if (worst_cv) *worst_cv = worst;
  if (noisy) *noisy = over;
  return t;
}

int run_bench_command(const BenchOptions& o, bool list, const JsonOut& out) {
  std::vector<std::string> names;
  try {
    names = benchmark_names(o.filter, o.isa);
  } catch (const std::exception& e) {
    std::cerr << error_line("bench", "", e.what()) << "\n";
    return kExitError;
  }
  if (names.empty()) {
    std::cerr << error_line("bench", "", fmt::format("--filter '{}' selects no benchmark (names are kernel/method/variant/case; --list "
                                                     "shows them)", o.filter))
              << "\n";
    return kExitNothing;
  }
  if (list) {
    for (const auto& n : names) std::cout << n << "\n";
    return kExitOk;
  }
  json doc;
  if (const int rc = run_benchmarks(o, doc); rc != 0) return rc;
  const double load = load_average();
  doc["machine"] = machine().json();  // the block every raybench result carries
  double worst = 0;
  std::size_t noisy = 0;
  const std::string table = bench_table(doc, &worst, &noisy);
  const int rc = write_result("bench", out, [&] { return table; }, [&] { return doc; },
                              fmt::format("Google Benchmark JSON ({} benchmarks, every repetition)", names.size()));
  if (noisy)
    std::cerr << wrap_words(fmt::format("warning: {} of {} benchmarks varied by more than 5 % over their repetitions (CV up to {:.1f} %): "
                                        "more --repetitions, a longer --min-time or a quieter machine give firmer medians",
                                        noisy, names.size(), 100 * worst));
  if (const std::string w = busy_warning(load, 1); !w.empty()) std::cerr << wrap_words(w);
  return rc;
}

}  // namespace rb::app
