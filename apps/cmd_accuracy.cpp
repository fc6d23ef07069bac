// `raybench accuracy`: the accuracy lab. Adversarial, seeded cases per primitive family, exact
// references from the same float inputs, and per method x precision x case: false hits, false
// misses, leaks through closed meshes, t error in ulps and scale-normalised, self-hits of
// spawned rays, solver iterations and ns per test.
#include "apps/accuracy_run.hpp"
#include "apps/commands.hpp"
#include "apps/machine.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>

namespace rb::app {

namespace {

// A progress bar on stderr: redrawn in place on a terminal, one line per tenth of the run otherwise.
struct Bar {
  std::string label;
  bool tty = isatty(2) != 0;
  int last_tenth = -1;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  void operator()(double f, const std::string& what) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (tty) {
      const int w = 30, k = int(f * w + 0.5);
      std::cerr << fmt::format("\r{} [{}{}] {:3.0f}% {:.0f} s {:<40}", label, std::string(std::size_t(k), '#'),
                               std::string(std::size_t(w - k), '.'), 100 * f, s, what.substr(0, 40))
                << std::flush;
    } else if (int tenth = int(f * 10); tenth > last_tenth) {
      last_tenth = tenth;
      std::cerr << fmt::format("{}: {:3d}% ({:.0f} s) {}\n", label, tenth * 10, s, what);
    }
  }
  void done() {
    if (tty) std::cerr << "\r" << std::string(100, ' ') << "\r";
  }
};

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
  j["rows"] = nlohmann::json::array();
  for (const auto& r : rows) j["rows"].push_back(r.json());
  j["cases"] = nlohmann::json::array();
  for (const auto& c : acc::case_list()) j["cases"].push_back({{"family", c.family}, {"case", c.name}, {"what", c.what}});
  return j;
}

std::string accuracy_text(const std::vector<acc::Row>& all) {
  // Grouped by family, in the order the families first appear (the BVH rows follow each mesh case).
  std::vector<std::string> fams;
  for (const auto& r : all)
    if (std::find(fams.begin(), fams.end(), r.family) == fams.end()) fams.push_back(r.family);
  std::vector<acc::Row> rows;
  for (const auto& f : fams)
    for (const auto& r : all)
      if (r.family == f) rows.push_back(r);
  std::string s;
  std::string fam;
  for (const auto& r : rows) {
    if (r.family != fam) {
      fam = r.family;
      s += fmt::format("\n{}\n{:<26} {:<16} {:<7} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9} {:>8}\n", fam, "case", "method", "prec",
                       "false_hit", "false_miss", "leak", "self_hit", "ulp_p99", "ulp_max", "scaled99", "ns/test");
    }
    s += fmt::format("{:<26} {:<16} {:<7} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9} {:>8}\n", r.case_name, r.method, r.precision,
                     fmt_num(r.false_hit_ppm), fmt_num(r.false_miss_ppm), fmt_num(r.leak_ppm), fmt_num(r.self_hit_ppm),
                     fmt_num(r.t_err_ulp_p99), fmt_num(r.t_err_ulp_max), fmt_num(r.scaled_err_p99), fmt_num(r.ns_per_test));
  }
  return s + "\nRates per million tests (leak: per million rays through a closed mesh; self_hit: per million spawned rays).\n";
}

std::vector<acc::Row> run_accuracy(acc::Options o, const std::string& label) {
  auto bar = std::make_shared<Bar>();
  bar->label = label;
  o.progress = [bar](double f, const std::string& what) { (*bar)(f, what); };
  auto rows = acc::run_lab(o);
  bar->done();
  return rows;
}

int run_accuracy_command(const acc::Options& o, bool list, const JsonOut& out) {
  if (list) {
    for (const auto& c : acc::case_list()) std::cout << fmt::format("{:<10} {:<26} {}\n", c.family, c.name, c.what);
    return 0;
  }
  std::size_t selected = 0;
  for (const auto& c : acc::case_list()) selected += o.filter.empty() || (c.family + "/" + c.name).find(o.filter) != std::string::npos;
  if (selected == 0) {
    std::cerr << "raybench accuracy: --filter '" << o.filter << "' selects no case (see --list)\n";
    return 2;
  }
  const auto rows = run_accuracy(o, "raybench accuracy");
  return write_result("accuracy", out.json, out.file, [&] { return accuracy_text(rows); }, [&] { return accuracy_json(o, rows); },
                      std::to_string(rows.size()) + " rows");
}

}  // namespace rb::app
