// `raybench accuracy`: the accuracy lab. Adversarial, seeded cases per primitive family, exact
// references from the same float inputs, and per method x precision x case: false hits, false
// misses, leaks through closed meshes, t error in ulps and scale-normalised, self-hits of
// spawned rays, solver iterations and ns per test.
#include "apps/accuracy_run.hpp"
#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "apps/results/machine.hpp"
#include "apps/paths.hpp"
#include "apps/progress.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>

namespace rb::app {

namespace {

std::string fmt_num(double x) {
  if (!std::isfinite(x)) return "-";
  if (x == 0) return "0";
  if (std::fabs(x) >= 1e4 || std::fabs(x) < 1e-2) return fmt::format("{:.2g}", x);
  return fmt::format("{:.3g}", x);
}

}  // namespace

nlohmann::json accuracy_json(const acc::Options& o, const std::vector<acc::Row>& rows) {
  nlohmann::json j;
  j["machine"] = machine().json();
  j["mode"] = o.full ? "full" : "quick";
  j["seed"] = o.seed;
  j["rays"] = o.rays ? o.rays : (o.full ? 100000 : 10000);
  j["filter"] = o.filter;
  j["rows"] = nlohmann::json::array();
  for (const auto& r : rows) j["rows"].push_back(r.json());
  j["cases"] = nlohmann::json::array();
  for (const auto& c : acc::case_list(&acc::tracer_cases())) j["cases"].push_back({{"family", c.family}, {"case", c.name}, {"what", c.what}});
  return j;
}

std::string accuracy_text(const std::vector<acc::Row>& all) {
  // Grouped by family, in the order the families first appear (the BVH rows follow each mesh case),
  // then by case; within 80 columns.
  std::vector<std::string> fams;
  for (const auto& r : all)
    if (std::find(fams.begin(), fams.end(), r.family) == fams.end()) fams.push_back(r.family);
  std::string s;
  const char* const kRow = "{:<18} {:<6} {:>9} {:>10} {:>8} {:>8} {:>8} {:>6}\n";
  for (const auto& f : fams) {
    s += fmt::format("\n{}\n", f);
    s += fmt::format(fmt::runtime(kRow), "method", "prec", "false hit", "false miss", "leak", "self hit", "t error", "ns per");
    s += fmt::format(fmt::runtime(kRow), "", "", "ppm", "ppm", "ppm", "ppm", "p99 ulp", "test");
    std::string kase;
    for (const auto& r : all) {
      if (r.family != f) continue;
      if (r.case_name != kase) {
        kase = r.case_name;
        s += fmt::format("case {}\n", kase);
      }
      s += fmt::format(fmt::runtime(kRow), " " + r.method.substr(0, 17), r.precision, fmt_num(r.false_hit_ppm), fmt_num(r.false_miss_ppm),
                       fmt_num(r.leak_ppm), fmt_num(r.self_hit_ppm), fmt_num(r.t_err_ulp_p99), fmt_num(r.ns_per_test));
    }
  }
  return s + wrap_words("\nRates per million tests (leak: per million rays through a closed mesh; self hit: per million spawned rays); "
                        "t error: 99th percentile of |t - exact t| in ulps of t. Every figure, with the maximum error and the "
                        "scale-normalised one: --json.");
}

std::vector<acc::Row> run_accuracy(acc::Options o, const std::string& label) {
  auto bar = std::make_shared<ProgressBar>(label);
  o.progress = [bar](double f, const std::string& what) { bar->update(f, what); };
  if (o.data_dir.empty()) o.data_dir = data_dir();  // the scene family's real meshes
  o.tracer = &acc::tracer_cases();                   // with the cases through the whole tracer
  auto rows = acc::run_lab(o);
  bar->done();
  return rows;
}

int run_accuracy_command(const acc::Options& o, bool list, const JsonOut& out) {
  std::size_t selected = 0;
  std::vector<acc::CaseInfo> cases;
  try {
    if (!o.filter.empty()) filter_regex(o.filter);  // one message for a bad expression
    for (const auto& c : acc::case_list(&acc::tracer_cases()))
      if (acc::selects(o.filter, c.family + "/" + c.name)) ++selected, cases.push_back(c);
  } catch (const std::exception& e) {
    std::cerr << error_line("accuracy", "", e.what()) << "\n";
    return kExitError;
  }
  if (selected == 0) {
    std::cerr << error_line("accuracy", "", "--filter '" + o.filter + "' selects no case (--list shows them)") << "\n";
    return kExitNothing;
  }
  if (list) {
    for (const auto& c : cases) std::cout << wrap_words(fmt::format("{:<10} {:<26} {}", c.family, c.name, c.what), 80, std::string(38, ' '));
    return kExitOk;
  }
  const auto rows = run_accuracy(o, "raybench accuracy");
  return write_result("accuracy", out, [&] { return accuracy_text(rows); }, [&] { return accuracy_json(o, rows); },
                      std::to_string(rows.size()) + " rows");
}

}  // namespace rb::app
