// `raybench bench`: the kernel benchmarks (apps/bench_run.cpp) with a results table on the
// terminal (median, CV, operations per test, SIMD speedup) and Google Benchmark's JSON, every
// repetition kept, with the machine and build block added (`--json FILE`, what compare.py and
// `raybench compare` read).
#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "apps/machine.hpp"
#include "apps/report.hpp"
#include "apps/results.hpp"
#include "apps/stats.hpp"

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

// "kernel/method/variant/case" -> ("kernel/method/case", variant)
std::pair<std::string, std::string> split_variant(const std::string& name) {
  const auto a = name.find('/'), b = name.find('/', a == std::string::npos ? a : a + 1),
             c = name.find('/', b == std::string::npos ? b : b + 1);
  if (c == std::string::npos) return {name, ""};
  return {name.substr(0, b) + name.substr(c), name.substr(b + 1, c - b - 1)};
}

std::string g4(double v) {
  if (!std::isfinite(v)) return "-";
  return std::fabs(v) >= 1e4 ? fmt::format("{:.0f}", v) : std::fabs(v) >= 100 ? fmt::format("{:.1f}", v) : fmt::format("{:.2f}", v);
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
  std::map<std::string, double> scalar;  // kernel/method/case -> median scalar rate
  for (const auto& r : rows) {
    const auto [k, v] = split_variant(r.name);
    if (v == "scalar") scalar[k] = stats::median(r.rates);
  }
  constexpr std::size_t kName = 44;
  std::string t = fmt::format("{:<{}} {:>9} {:>6} {:>8} {:>9}\n", "benchmark (kernel/method/variant/case)", kName, "Mtests/s", "CV %",
                              "ops/test", "vs scalar");
  std::vector<double> speedups;
  double worst = 0;
  std::size_t over = 0;
  for (const auto& r : rows) {
    const double med = stats::median(r.rates), cv = stats::cv(r.rates);
    if (std::isfinite(cv)) worst = std::max(worst, cv), over += cv > 0.05;
    const auto [k, v] = split_variant(r.name);
    double sp = stats::kNaN;
    if (v != "scalar" && scalar.count(k) && scalar[k] > 0) sp = med / scalar[k], speedups.push_back(sp);
    std::string name = r.name;
    if (name.size() > kName) {
      t += name + "\n";
      name.clear();
    }
    t += fmt::format("{:<{}} {:>9} {:>6} {:>8} {:>9}\n", name, kName, g4(med / 1e6), std::isfinite(cv) ? fmt::format("{:.1f}", 100 * cv) : "-",
                     g4(r.ops), std::isfinite(sp) ? fmt::format("{:.2f}x", sp) : "-");
  }
  const auto& ctx = doc.contains("context") ? doc["context"] : json::object();
  t += wrap_words(fmt::format("Median of {} repetition(s) per benchmark (256 rays x 64 primitives per iteration, one thread); CV: "
                              "coefficient of variation over the repetitions; vs scalar: the median over the scalar median of the same "
                              "kernel, method and case.",
                              ctx.value("raybench_repetitions", std::string("?"))));
  if (!speedups.empty()) {
    std::sort(speedups.begin(), speedups.end());
    t += fmt::format("SIMD over scalar: lowest {:.2f}x, median {:.2f}x, highest {:.2f}x over {} SIMD rows\n", speedups.front(),
                     stats::median(speedups), speedups.back(), speedups.size());
  }
  if (worst_cv) *worst_cv = worst;
  if (noisy) *noisy = over;
  return t;
}

int run_bench_command(const BenchOptions& o, bool list, const JsonOut& out) {
  std::vector<std::string> names;
  try {
    names = benchmark_names(o.filter);
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
