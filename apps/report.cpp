#include "core/output_file.hpp"
#include "apps/interrupt.hpp"
#include "apps/report.hpp"

#include "apps/cli.hpp"
#include "apps/machine.hpp"
#include "apps/paths.hpp"
#include "apps/progress.hpp"
#include "apps/report_doc.hpp"
#include "apps/report_sections.hpp"
#include "bench/ops_table.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <sstream>

namespace rb::app {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {
struct Clock {
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  double s() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
};

// Every report file is written whole or not at all (core/output_file.hpp).
void write_file(const fs::path& p, const std::string& s) { write_output(p.string(), s); }

// Medians of a Google Benchmark JSON run: name -> counters.
std::map<std::string, json> medians(const json& j) {
  std::map<std::string, json> m;
  for (const auto& b : j.at("benchmarks")) {
    if (b.value("aggregate_name", "") == "median") m[b.at("run_name").get<std::string>()] = b;
    else if (!b.contains("aggregate_name") && !m.count(b.value("run_name", b.value("name", "")))) m[b.value("run_name", b.value("name", ""))] = b;
  }
  return m;
}

std::string speed_section(const json& bench, json& summary) {
  const auto med = medians(bench);
  const auto speedup = simd_speedups(bench);
  struct Key { std::string kernel, method, kase; };
  std::vector<std::string> order;
  std::map<std::string, std::map<std::string, json>> rows;  // "kernel/method/case" -> variant -> median
  for (const auto& [name, b] : med) {
    // kernel/method/variant/case
    std::vector<std::string> p;
    std::size_t s = 0, e;
    while ((e = name.find('/', s)) != std::string::npos) { p.push_back(name.substr(s, e - s)); s = e + 1; }
    p.push_back(name.substr(s));
    if (p.size() != 4) continue;
    const std::string k = p[0] + "/" + p[1] + "/" + p[3];
    if (!rows.count(k)) order.push_back(k);
    rows[k][p[2]] = b;
  }
  std::string md =
      "| kernel | method | case | scalar Mtests/s | rays in lanes Mtests/s | prims in lanes Mtests/s | speedup rays | speedup prims "
      "| ops/test scalar | ops/test SIMD (per lane) |\n|---|---|---|---|---|---|---|---|---|---|\n";
  json out = json::array();
  std::vector<std::string> keys;
  for (const auto& [k, _] : rows) keys.push_back(k);
  for (const auto& k : keys) {
    auto& v = rows[k];
    auto field = [&](const char* var, const char* key) {
      if (!v.count(var)) return 0.0;
      const auto it = v[var].find(key);
      return it != v[var].end() && it->is_number() ? it->template get<double>() : 0.0;
    };
    auto rate = [&](const char* var) { return field(var, "tests_per_s"); };
    auto opt = [&](const char* var) { return field(var, "ops_per_test"); };
    const double sc = rate("scalar"), rl = rate("rays_in_lanes"), pl = rate("prims_in_lanes");
    const auto p1 = k.find('/'), p2 = k.rfind('/');
    const std::string kernel = k.substr(0, p1), method = k.substr(p1 + 1, p2 - p1 - 1), kase = k.substr(p2 + 1);
    // Each speedup round by round (the median of the rounds' ratios, with its interval).
    auto interval = [&](const char* var) {
      const auto it = speedup.find(kernel + "/" + method + "/" + var + "/" + kase);
      return it != speedup.end() ? it->second : stats::RatioInterval{};
    };
    const stats::RatioInterval i1 = interval("rays_in_lanes"), i2 = interval("prims_in_lanes");
    const double s1 = std::isfinite(i1.ratio) ? i1.ratio : 0, s2 = std::isfinite(i2.ratio) ? i2.ratio : 0;
    md += fmt::format("| {} | {} | {} | {:.4g} | {:.4g} | {:.4g} | {} | {} | {:.1f} | {:.1f} |\n", kernel, method, kase, sc / 1e6, rl / 1e6,
                      pl / 1e6, stats::interval_text(i1), stats::interval_text(i2), opt("scalar"), opt("rays_in_lanes"));
    out.push_back({{"kernel", kernel}, {"method", method}, {"case", kase}, {"scalar_tests_per_s", sc},
                   {"rays_in_lanes_tests_per_s", rl}, {"prims_in_lanes_tests_per_s", pl}, {"speedup_rays_in_lanes", s1},
                   {"speedup_prims_in_lanes", s2}, {"speedup_rays_in_lanes_interval", stats::interval_json(i1)},
                   {"speedup_prims_in_lanes_interval", stats::interval_json(i2)}});
  }
  summary["simd_vs_scalar"] = out;
  // The BVH's 8-wide node test (bench/bench_wide_node.cpp): box tests per second of its fast form,
  // which the default traversal runs on conservative boxes, and of its robust form.
  for (const char* form : {"fast", "robust"}) {
    const auto it = med.find(fmt::format("wide_node_slab/{}/l1", form));
    if (it != med.end() && it->second.contains("box_tests_per_s")) summary["wide_node_slab"][form] = it->second["box_tests_per_s"];
  }
  return md;
}

// The speedup of the better of the two SIMD mappings in one simd_vs_scalar row.
double better_mapping(const json& r) {
  return std::max(r["speedup_rays_in_lanes"].get<double>(), r["speedup_prims_in_lanes"].get<double>());
}
// Its interval (the mapping with the higher median).
stats::RatioInterval better_interval(const json& r) {
  const bool rays = r["speedup_rays_in_lanes"].get<double>() >= r["speedup_prims_in_lanes"].get<double>();
  return stats::interval_from_json(r.value(rays ? "speedup_rays_in_lanes_interval" : "speedup_prims_in_lanes_interval", json()));
}
// A goal over several ratios (every case of a method): not met when one interval lies below the
// target, met when every one clears it, undecided otherwise; a ratio without an interval (a single
// round) counts by its median.
int all_clear(const std::vector<stats::RatioInterval>& v, double target) {
  bool straddles = false;
  for (const auto& r : v) {
    const stats::Verdict x = r.valid() ? stats::verdict(r, target) : r.ratio >= target ? stats::Verdict::met : stats::Verdict::not_met;
    if (x == stats::Verdict::not_met) return doc::kGoalNotMet;
    straddles = straddles || x == stats::Verdict::undecided;
  }
  return v.empty() ? doc::kGoalNotMeasured : straddles ? doc::kGoalUndecided : doc::kGoalMet;
}

// A performance goal of the project, checked against this run (shown, never asserted in tests):
// met is a doc::kGoal* code (not measured: --filter left it out).
struct Goal {
  std::string goal, measured;
  int met;
};

// The throughput goals, each with the reason it is a goal (printed above the table).
const char* const kSpeedGoalReasons =
    "- **Triangle, sphere and box: SIMD at least 6x the true scalar form, in every case.** These kernels do the same "
    "straight-line work on every lane, so 8 float lanes can approach 8x; 6x leaves a quarter for masking, packing and "
    "broadcasts. Falling short points at overhead in the data layout or the kernel, which would slow every scene.\n"
    "- **Box slab test at least 3 G tests/s on one core.** The box test is the inner step of every bounding volume "
    "hierarchy traversal: its rate caps how fast rays descend the tree.\n"
    "- **The BVH's 8-wide node test at least 7 G box tests/s on one core, in the default form.** One test of a node's "
    "8 child boxes against a ray is the step the scene tracer repeats most; the default form (one FMA per plane on boxes "
    "widened at build time so that it cannot cull a hit) must be as fast as the plain fast form was.\n"
    "- **Moller-Trumbore at least 0.75 G tests/s on one core.** The triangle test is the leaf work of tracing a mesh: its "
    "rate caps how many rays per second a triangle scene can be traced at.\n\n";

std::vector<Goal> speed_goals(const json& summary) {
  std::vector<Goal> goals;
  auto best = [&](const std::string& kernel, const std::string& method, const char* field) {
    double b = 0;
    for (const auto& r : summary["simd_vs_scalar"])
      if (r["kernel"] == kernel && (method.empty() || r["method"] == method)) b = std::max(b, r[field].get<double>());
    return b;
  };
  auto worst_speedup = [&](const std::string& kernel) {
    double w = 1e30;
    std::string where;
    for (const auto& r : summary["simd_vs_scalar"])
      if (r["kernel"] == kernel) {
        const double s = better_mapping(r);
        if (s < w) { w = s; where = r["method"].get<std::string>() + "/" + r["case"].get<std::string>(); }
      }
    return std::make_pair(w, where);
  };
  // Per kernel: its best method (the highest worst-case speedup), and every method.
  auto best_method = [&](const std::string& kernel) {
    std::map<std::string, double> lowest;  // method -> lowest over cases of the better mapping
    for (const auto& r : summary["simd_vs_scalar"])
      if (r["kernel"] == kernel) {
        const double s = better_mapping(r);
        const std::string m = r["method"].get<std::string>();
        lowest[m] = lowest.count(m) ? std::min(lowest[m], s) : s;
      }
    std::pair<double, std::string> b{0, ""};
    for (const auto& [m, v] : lowest)
      if (v > b.first) b = {v, m};
    return b;
  };
  auto measured = [&](const std::string& kernel, const std::string& method) {
    for (const auto& r : summary["simd_vs_scalar"])
      if (r["kernel"] == kernel && (method.empty() || r["method"] == method)) return true;
    return false;
  };
  const std::string not_measured = "not measured in this run (--filter)";
  for (const char* k : {"triangle", "sphere", "box"}) {
    if (!measured(k, "")) {
      goals.push_back({fmt::format("{} SIMD >= 6x scalar", k), not_measured, -1});
      continue;
    }
    // The intervals of a kernel's rows (of one method, or of all), and the lowest of them.
    auto cases = [&](const std::string& method) {
      std::vector<stats::RatioInterval> v;
      for (const auto& r : summary["simd_vs_scalar"])
        if (r["kernel"] == k && (method.empty() || r["method"] == method)) v.push_back(better_interval(r));
      return v;
    };
    auto lowest = [](const std::vector<stats::RatioInterval>& v) {
      stats::RatioInterval lo;
      for (const auto& r : v)
        if (!std::isfinite(lo.ratio) || r.ratio < lo.ratio) lo = r;
      return stats::interval_text(lo);
    };
    const auto [bw, bm] = best_method(k);
    goals.push_back({fmt::format("{} SIMD >= 6x scalar: best method, in every case (hit, miss, half)", k),
                     fmt::format("{} lowest {}", bm, lowest(cases(bm))), all_clear(cases(bm), 6)});
    const auto [w, where] = worst_speedup(k);
    std::string without_half;
    if (w < 6) {
      // Where the shortfall is: the divergent half-hit case alone, or also uniform packets.
      double u = 1e30;
      std::string uw;
      for (const auto& r : summary["simd_vs_scalar"])
        if (r["kernel"] == k && r["case"] != "half") {
          const double x = better_mapping(r);
          if (x < u) { u = x; uw = r["method"].get<std::string>() + "/" + r["case"].get<std::string>(); }
        }
      without_half = fmt::format("; all-hit and all-miss packets only: lowest {:.2f}x ({})", u, uw);
    }
    goals.push_back({fmt::format("{} SIMD >= 6x scalar: every method, every case", k),
                     fmt::format("lowest {} ({}){}", lowest(cases("")), where, without_half), all_clear(cases(""), 6)});
  }
  const double box = std::max(best("box", "slab", "rays_in_lanes_tests_per_s"), best("box", "slab", "prims_in_lanes_tests_per_s"));
  if (measured("box", "slab"))
    goals.push_back({"box slab >= 3 G tests/s, one core", fmt::format("{:.2f} G/s", box / 1e9), box >= 3e9});
  else
    goals.push_back({"box slab >= 3 G tests/s, one core", not_measured, -1});
  if (summary.contains("wide_node_slab") && summary["wide_node_slab"].contains("fast")) {
    const double w = summary["wide_node_slab"]["fast"].get<double>();
    std::string m = fmt::format("{:.2f} G/s", w / 1e9);
    if (summary["wide_node_slab"].contains("robust"))
      m += fmt::format(" (robust form {:.2f} G/s)", summary["wide_node_slab"]["robust"].get<double>() / 1e9);
    goals.push_back({"8-wide node test >= 7 G box tests/s, one core, default form", m, w >= 7e9});
  } else {
    goals.push_back({"8-wide node test >= 7 G box tests/s, one core, default form", not_measured, -1});
  }
  const double mt = std::max(best("triangle", "moller_trumbore", "rays_in_lanes_tests_per_s"),
                             best("triangle", "moller_trumbore", "prims_in_lanes_tests_per_s"));
  if (measured("triangle", "moller_trumbore"))
    goals.push_back({"Moller-Trumbore >= 0.75 G tests/s, one core", fmt::format("{:.2f} G/s", mt / 1e9), mt >= 0.75e9});
  else
    goals.push_back({"Moller-Trumbore >= 0.75 G tests/s, one core", not_measured, -1});
  return goals;
}

std::string goals_markdown(const std::vector<Goal>& goals) {
  std::string md = "| goal | measured (median of this run; a ratio with its 95 % interval) | met |\n|---|---|---|\n";
  for (const auto& g : goals) md += fmt::format("| {} | {} | {} |\n", g.goal, g.measured, doc::goal_cell(g.met));
  return md;
}

// Every kernel's SIMD form >= 4x its true-scalar form on 8 lanes, or the reason it cannot be. Per
// method: the better of the two mappings, in its worst case (hit, miss, half).
// The reasons are the structural ones of each method; a method below target without one is
// flagged as unexplained.
std::string simd_target_section(json& summary) {
  // Structural reasons, true of the method whatever the measurement (checked in the ops table).
  static const std::map<std::string, std::string> why = {
      {"torus/robust", "iterative: derivative isolation and safeguarded Newton run until the packet's slowest lane converges"},
      {"algebraic/isolation_d4", "iterative root isolation: the packet runs to the lane with the most roots and steps"},
      {"algebraic/isolation_d6", "iterative root isolation: the packet runs to the lane with the most roots and steps"},
      {"implicit/sphere_tracing", "data-dependent step count: the packet marches until its slowest lane stops"},
      {"implicit/illinois", "fixed-step sign search then Illinois steps: the packet runs its longest lane's search"},
      {"revolution/polynomial", "iterative roots of K*(s): the packet runs to its slowest lane"},
      {"revolution/bezier", "iterative roots of K*(s): the packet runs to its slowest lane"},
  };
  // kernel/method -> case -> better-mapping speedup
  std::map<std::string, std::map<std::string, double>> sp;
  std::map<std::string, std::vector<stats::RatioInterval>> iv;  // kernel/method -> every case's interval
  for (const auto& r : summary["simd_vs_scalar"]) {
    const std::string km = r["kernel"].get<std::string>() + "/" + r["method"].get<std::string>();
    sp[km][r["case"].get<std::string>()] = better_mapping(r);
    iv[km].push_back(better_interval(r));
  }
  std::map<std::string, std::pair<double, std::string>> worst;  // kernel/method -> (speedup, case)
  for (const auto& [km, cases] : sp)
    for (const auto& [c, x] : cases)
      if (!worst.count(km) || x < worst[km].first) worst[km] = {x, c};
  std::string md = "| kernel/method | lowest SIMD speedup (better mapping, worst case) | >= 4x | why not |\n|---|---:|---|---|\n";
  json out = json::array();
  int met = 0, undecided = 0, explained = 0, unexplained = 0;
  for (const auto& [km, w] : worst) {
    // By the intervals: every case clears 4x (met), one lies below it (not met), or undecided.
    const int verdict = all_clear(iv[km], 4);
    const bool ok = verdict == doc::kGoalMet;
    stats::RatioInterval lowest;
    for (const auto& r : iv[km])
      if (!std::isfinite(lowest.ratio) || r.ratio < lowest.ratio) lowest = r;
    const auto it = why.find(km);
    const auto& cs = sp[km];
    const double hit = cs.count("hit") ? cs.at("hit") : 0, miss = cs.count("miss") ? cs.at("miss") : 0;
    std::string reason;
    if (!ok && it != why.end()) reason = it->second;
    else if (!ok && w.second == "half" && hit >= 4 && miss >= 4)
      // Measured, not assumed: only the divergent packet falls short.
      reason = fmt::format("only when lanes diverge (hit {:.2f}x, miss {:.2f}x): the scalar form stops early on the missing half, "
                           "a packet with any hitting lane runs the whole test on all lanes", hit, miss);
    else if (verdict == doc::kGoalUndecided) reason = "undecided: an interval straddles 4x";
    else if (!ok) reason = "**unexplained**";
    (ok ? met : verdict == doc::kGoalUndecided ? undecided : (reason != "**unexplained**" ? explained : unexplained))++;
    md += fmt::format("| {} | {} ({}) | {} | {} |\n", km, stats::interval_text(lowest), w.second, doc::goal_cell(verdict), reason);
    out.push_back({{"kernel_method", km}, {"lowest_speedup", w.first}, {"lowest_interval", stats::interval_json(lowest)}, {"case", w.second},
                   {"met", ok}, {"verdict", doc::goal_word(verdict)}, {"reason", reason}});
  }
  summary["simd_target_4x"] = out;
  summary["simd_target_4x_counts"] = {{"methods", worst.size()}, {"met", met},         {"undecided", undecided},
                                      {"explained", explained}, {"unexplained", unexplained}};
  md += fmt::format("\n{} of {} methods reach 4x in every case (each case's interval clears it); {} undecided; {} fall short for the "
                    "structural reason given; {} unexplained.\n",
                    met, worst.size(), undecided, explained, unexplained);
  return md;
}
// What the terminal shows at the end of a report: the headline figures; index.md and the JSON
// beside it hold everything.
std::string terminal_summary(const json& summary, const std::vector<Goal>& goals, std::size_t op_rows, double seconds) {
  std::string t = fmt::format("\nraybench report: {:.0f} s; {} ops rows", seconds, op_rows);
  std::vector<std::pair<double, std::string>> sp;
  for (const auto& r : summary["simd_vs_scalar"])
    sp.push_back({better_mapping(r), fmt::format("{}/{}/{}", r["kernel"].get<std::string>(), r["method"].get<std::string>(),
                                                 r["case"].get<std::string>())});
  std::sort(sp.begin(), sp.end());
  if (!sp.empty())
    t += fmt::format("; {} kernel x method x case speedups of SIMD (better mapping) over true scalar:\n"
                     "  lowest {:.2f}x ({}), median {:.2f}x, highest {:.2f}x ({})\n",
                     sp.size(), sp.front().first, sp.front().second, sp[sp.size() / 2].first, sp.back().first, sp.back().second);
  else
    t += "\n";
  t += "Goals:\n";
  for (const auto& g : goals) t += fmt::format("  [{}] {}: {}\n", doc::goal_word(g.met), g.goal, g.measured);
  if (summary.contains("tracing") && summary["tracing"].contains("goals"))
    for (const auto& g : summary["tracing"]["goals"])
      t += fmt::format("  [{}] tracing: {}: {}\n", doc::goal_word(g["met"].get<int>()), g["goal"].get<std::string>(),
                       g["measured"].get<std::string>());
  if (summary.contains("simd_target_4x_counts")) {
    const auto& c = summary["simd_target_4x_counts"];
    t += fmt::format("  every method SIMD >= 4x scalar: {} of {} methods; {} undecided; {} fall short for a stated structural reason, {} "
                     "unexplained\n",
                     c["met"].get<int>(), c["methods"].get<int>(), c.value("undecided", 0), c["explained"].get<int>(),
                     c["unexplained"].get<int>());
  }
  return t;
}

// The goals every section checks, for the summary at the top of the report: the speed goals and
// the 4x target of section "Scalar against SIMD", the tracing goals (checked by that section), the
// rendering goal and the accuracy lab's targets.
std::vector<doc::Goal> report_goals(const std::vector<Goal>& speed, const json& summary) {
  std::vector<doc::Goal> g;
  for (const auto& s : speed) g.push_back({"Scalar against SIMD", s.goal, s.measured, s.met, "simd_speedup.png"});
  if (summary.contains("simd_target_4x_counts")) {
    const auto& c = summary["simd_target_4x_counts"];
    const int met = c["met"].get<int>(), n = c["methods"].get<int>(), und = c.value("undecided", 0);
    g.push_back({"Scalar against SIMD", "every kernel's SIMD form >= 4x its true-scalar form",
                 fmt::format("{} of {} methods; {} undecided; {} short for a stated structural reason, {} unexplained", met, n, und,
                             c["explained"].get<int>(), c["unexplained"].get<int>()),
                 n == 0 ? doc::kGoalNotMeasured : met == n ? doc::kGoalMet : met + und == n ? doc::kGoalUndecided : doc::kGoalNotMet,
                 "simd_speedup.png"});
  }
  // The tracing goals are checked by the section itself, each against its worst row.
  if (summary.contains("tracing") && summary["tracing"].contains("goals"))
    for (const auto& r : summary["tracing"]["goals"])
      g.push_back({"Tracing whole scenes", r["goal"].get<std::string>(), r["measured"].get<std::string>(), r["met"].get<int>(),
                   "trace_matrix.png"});
  if (summary.contains("render_goal_half_of_primary")) {
    const auto& r = summary["render_goal_half_of_primary"];
    const int met = r["met"].get<int>(), n = r["scenes"].get<int>();
    g.push_back({"Rendering", "rendering at least half as fast per ray as primary-ray tracing",
                 fmt::format("{} of {} scenes", met, n), n > 0 ? int(met == n) : -1, "render_spd_balls.png"});
  }
  if (summary.contains("accuracy"))
    for (const auto& t : summary["accuracy"]["targets"])
      g.push_back({"Accuracy and stability", t["target"].get<std::string>(), t["measured"].get<std::string>(), int(t["met"].get<bool>()), ""});
  return g;
}

// The profile-guided optimisation section is measured by `./run.sh pgo` (four builds and three
// benchmark runs: too long for the default report), which writes OUT/pgo.md; the report carries
// the latest one between markers so that `./run.sh pgo` can also refresh an existing index.md.
std::string pgo_section(const fs::path& out) {
  std::string body;
  std::ifstream f;
  if (readable_back((out / "pgo.md").string())) f.open(out / "pgo.md");  // never block on a FIFO there
  if (f.is_open()) {  // (a stream never opened is not in a failed state)
    std::stringstream ss;
    ss << f.rdbuf();
    body = ss.str();
  } else {
    body = "## Profile-guided optimisation\n\nNot measured for this report: `./run.sh pgo` builds an instrumented binary, "
           "trains it on a workload apart from the measured one, rebuilds with the profile and compares every benchmark and "
           "trace with the normal build back to back (25 min on this project's 2-core machine); it then fills this section.\n\n";
  }
  return "<!-- pgo-section -->\n" + body + "<!-- /pgo-section -->\n\n";
}

}  // namespace

int run_report(const ReportOptions& o) {
  const Clock clock;
  const fs::path out = o.out;
  // Nothing to do is found before the work starts: a --filter that selects no benchmark.
  if (benchmark_names(o.filter).empty()) {
    std::cerr << error_line("report", "", fmt::format("--filter '{}' selects no benchmark (raybench bench --list shows them)", o.filter))
              << "\n";
    return kExitNothing;
  }
  fs::create_directories(out);
  // The numbered stages, each with the report's elapsed time.
  constexpr int kStages = 9;
  int stage = 0;
  auto next_stage = [&](const std::string& what) {
    std::cerr << fmt::format("[report {}/{}, {}] {}\n", ++stage, kStages, format_duration(clock.s()), what);
    return fmt::format("[report {}/{}]", stage, kStages);
  };
  const Machine m = machine();
  json summary;
  summary["machine"] = m.json();
  std::string md = "# raybench report\n\n";
  if (o.quick)
    md += "**Quick mode** (`--quick`): few repetitions, few rays and small images, to check the report's layout; its figures "
          "are not the ones to quote.\n\n";
  md += "Produced by `raybench report` on the embedded default scenes; every figure below was measured in this run. "
        "Speeds are medians over " + std::to_string(o.repetitions) + " repetitions, ratios are taken within this run.\n\n";
  md += "## Machine and build\n\n" + m.markdown() + "\n";

  next_stage("operations per intersection (Counted<float>, Counted<simd8>)");
  const auto rows = rb::opstable::build();
  write_file(out / "ops.json", rb::opstable::to_json(rows).dump(2));
  md += "## 1. Operations per intersection\n\n"
        "Lecture counts (seed 000) beside the counts measured by running each kernel with `Counted<float>` on one ray that hits "
        "and one that misses, and with `Counted<simd8>` (per lane: SIMD code runs the whole kernel when its lanes disagree). "
        "`\u00b1` add/sub, `*` mul, `/` div, cmp comparisons; min/max, selects and FMAs are listed separately "
        "(an FMA is compared with the slide as 1\u00b1 + 1*). Negation and sign operations are free. Raw rows: [ops.json](ops.json).\n\n";
  md += rb::opstable::to_markdown(rows) + "\n";

  const std::string bench_label = next_stage(fmt::format("scalar vs SIMD benchmarks ({} repetitions x {} s each)", o.repetitions, o.min_time));
  const fs::path bj = out / "bench.json";
  BenchOptions bo;
  bo.repetitions = o.repetitions;
  bo.min_time = o.min_time;
  bo.filter = o.filter;
  bo.every_repetition = true;  // every repetition kept: `raybench compare` tests two reports' repetitions
  bo.what = bench_label + " benchmarks";
  bo.command = "report";
  json bench;
  if (const int rc = run_benchmarks(bo, bench); rc != 0) return rc;
  bench["machine"] = summary["machine"];  // bench.json is a result of its own: the block every result carries
  write_file(bj, bench.dump(2));
  md += "## 2. Scalar against SIMD, L1-resident\n\n"
        "256 rays x 64 primitives per iteration, every pair tested (~16k tests, all data in L1). `scalar` is compiled with "
        "`-fno-tree-vectorize -fno-tree-slp-vectorize` in its own translation unit; the SIMD mappings run the same kernel text "
        "on 8 float lanes: 8 rays x 1 primitive (rays in lanes) or 1 ray x 8 primitives (prims in lanes). Cases: every pair hits, "
        "every pair misses, half the pairs hit (lanes diverge). One thread. Raw Google Benchmark JSON: [bench.json](bench.json).\n\n";
  md += speed_section(bench, summary) + "\n";
  md += "![SIMD speedup over scalar](simd_speedup.png)\n\n";
  const std::vector<Goal> goals = speed_goals(summary);
  md += "### Goals: SIMD speedup and throughput of the basic kernels\n\n";
  md += kSpeedGoalReasons + goals_markdown(goals) + "\n";
  md += "### Goal: every kernel's SIMD form at least 4x its true-scalar form\n\n"
        "SIMD is worth its place in the engine only if every kernel gains from it. Where a method cannot reach 4x on 8 lanes, "
        "the reason is a property of the method (lanes that need different amounts of work), named here, so that a caller "
        "can choose the scalar form for it knowingly.\n\n";
  md += simd_target_section(summary) + "\n";

  next_stage("scenes: load and generation times, memory");
  md += report_section_scenes(o, out, summary);

  next_stage("tracing whole scenes (raybench BVH beside Embree)");
  md += report_section_tracing(o, out, summary);
  next_stage("rendering: SPD, lecture and CSG scenes");
  md += report_section_render(o, out, summary);

  next_stage("accuracy lab");
  md += report_section_accuracy(o, out, summary);

  next_stage("what each scene needs: plans, their cost and failures");
  md += report_section_plan(o, out, summary);

  next_stage("CSG queries, scalar against 8-ray packets");
  md += report_section_csg(o, out, summary);

  md += pgo_section(out);

  next_stage("charts and index.md");
  // Every goal with its verdict, for `raybench compare` of two reports.
  const std::vector<doc::Goal> all_goals = report_goals(goals, summary);
  summary["goals"] = json::array();
  for (const auto& g : all_goals)
    summary["goals"].push_back({{"section", g.section}, {"goal", g.goal}, {"measured", g.measured}, {"verdict", doc::goal_word(g.met)}});
  write_file(out / "summary.json", summary.dump(2));
  if (o.charts && !readable_back((out / "summary.json").string())) {
    md += "_Charts were not drawn: summary.json, which they read, is not a regular file._\n\n";
  } else if (o.charts) {
    const std::string cmd = "/usr/bin/python3 " + shell_quote(tool_path("charts.py")) + " " + shell_quote(out.string());
    const int rc = run_command(cmd);
    if (rc != 0) md += "_Charts were not drawn: `" + cmd + "` failed (is python3-matplotlib installed?)._\n\n";
  }
  md += fmt::format("---\n\nReport written in {:.0f} s by `raybench report --out {}{}`.\n", clock.s(), o.out, o.quick ? " --quick" : "");
  // One model, two pages: index.md and the self-contained index.html beside it.
  doc::Document page = doc::parse_markdown(md);
  doc::organise(page, all_goals, out);
  write_file(out / "index.md", doc::to_markdown(page));
  const std::string html = doc::to_html(page);
  write_file(out / "index.html", html);
  for (const auto& b : doc::broken_links(html, out)) std::cerr << "raybench report: warning: index.html: " << b << "\n";
  // The terminal summary goes to stdout, unless --json without a file puts the summary JSON there.
  const bool json_stdout = o.json && (o.json_file.empty() || is_standard_output(o.json_file));
  (json_stdout ? std::cerr : std::cout) << fit_columns(terminal_summary(summary, goals, rows.size() / 2, clock.s()), 4)
                                        << "report written: " << fs::absolute(out / "index.md").string() << " and index.html\n";
  if (o.json) write_file(json_stdout ? "-" : o.json_file, summary.dump(2) + "\n");
  return 0;
}

}  // namespace rb::app
