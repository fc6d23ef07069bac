// Section "Scalar against SIMD" of the report: the kernel benchmarks (run in rounds by
// apps/bench_run.cpp) as a table of tests per second and SIMD speedups, each speedup the median of
// the rounds' ratios with its 95 % interval; the speed goals (met when every interval clears the
// target, undecided when one straddles it) and the target of 4x per method with the structural
// reason where a method falls short.
#include "apps/report/report.hpp"
#include "apps/report/report_doc.hpp"
#include "apps/report/report_sections.hpp"
#include "apps/report/report_simd.hpp"
#include "apps/results/stats.hpp"
#include "bench/bench_name.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace rb::app {
using nlohmann::json;

namespace simd_report {

// Medians of a Google Benchmark JSON run: name -> counters.
std::map<std::string, json> medians(const json& j) {
  std::map<std::string, json> m;
  for (const auto& b : j.at("benchmarks")) {
    if (b.value("aggregate_name", "") == "median") m[b.at("run_name").get<std::string>()] = b;
    else if (!b.contains("aggregate_name") && !m.count(b.value("run_name", b.value("name", "")))) m[b.value("run_name", b.value("name", ""))] = b;
  }
  return m;
}

// A goal over several ratios (every case of a method): not met when one interval lies below the
// target, met when every one clears it, undecided otherwise; a ratio without an interval (a single
// round) counts by its median.
int all_clear(const std::vector<stats::RatioInterval>& v, double target) {
  std::size_t met = 0, below = 0;
  for (const auto& r : v) {
    const stats::Verdict x = r.valid() ? stats::verdict(r, target) : r.ratio >= target ? stats::Verdict::met : stats::Verdict::not_met;
    met += x == stats::Verdict::met;
    below += x == stats::Verdict::not_met;
  }
  return doc::goal_over(v.size(), met, below);
}

// Structural reasons a method gains less from more lanes, true of the method whatever the
// measurement (its loops run until the packet's slowest lane is done: the more lanes, the longer).
const std::map<std::string, std::string>& structural_reasons() {
  static const std::map<std::string, std::string> why = {
      {"torus/robust", "iterative: derivative isolation and safeguarded Newton run until the packet's slowest lane converges"},
      {"algebraic/isolation_d4", "iterative root isolation: the packet runs to the lane with the most roots and steps"},
      {"algebraic/isolation_d6", "iterative root isolation: the packet runs to the lane with the most roots and steps"},
      {"implicit/sphere_tracing", "data-dependent step count: the packet marches until its slowest lane stops"},
      {"implicit/illinois", "fixed-step sign search then Illinois steps: the packet runs its longest lane's search"},
      {"revolution/polynomial", "iterative roots of K*(s): the packet runs to its slowest lane"},
      {"revolution/bezier", "iterative roots of K*(s): the packet runs to its slowest lane"},
  };
  return why;
}

}  // namespace simd_report

namespace {
using namespace simd_report;

// A rate counter's median over a benchmark's rounds with its 95 % interval (the sign test's: the
// range of the rounds where they are few), from every repetition of `run_name`: a throughput goal is
// judged by it like a ratio, so that one busy or one fast round cannot decide it.
stats::RatioInterval rate_interval(const json& bench, const std::string& run_name, const char* counter) {
  std::vector<double> v;
  for (const auto& b : bench.at("benchmarks"))
    if (b.value("run_type", "") == "iteration" && b.value("run_name", "") == run_name && b.contains(counter) && b[counter].is_number())
      v.push_back(b[counter].get<double>());
  return stats::paired_ratio(v, std::vector<double>(v.size(), 1.0));
}

// The throughput goals' intervals (G tests/s): the fastest benchmark of the method (by median) for
// the box slab and Moller-Trumbore, the default form of the 8-wide node test.
json rate_goals(const json& bench, const std::map<std::string, json>& med) {
  auto best = [&](const std::string& prefix) {
    std::string name;
    double top = -1;
    for (const auto& [n, b] : med)
      if (n.rfind(prefix, 0) == 0 && n.find("/scalar/") == std::string::npos && b.contains("tests_per_s") && b["tests_per_s"].is_number() &&
          b["tests_per_s"].get<double>() > top)
        top = b["tests_per_s"].get<double>(), name = n;
    return name;
  };
  json g = json::object();
  auto put = [&](const char* key, const std::string& name, const char* counter) {
    if (name.empty()) return;
    stats::RatioInterval r = rate_interval(bench, name, counter);
    r.ratio /= 1e9, r.lo /= 1e9, r.hi /= 1e9;
    g[key] = stats::interval_json(r);
    g[key]["benchmark"] = name;
  };
  put("box_slab", best("box/slab/"), "tests_per_s");
  put("moller_trumbore", best("triangle/moller_trumbore/"), "tests_per_s");
  if (med.count("wide_node_slab/fast/l1")) put("wide_node_fast", "wide_node_slab/fast/l1", "box_tests_per_s");
  if (med.count("wide_node_slab/fast16/l1")) put("wide_node_fast16", "wide_node_slab/fast16/l1", "box_tests_per_s");
  return g;
}

std::string speed_section(const json& bench, json& summary) {
  const auto med = medians(bench);
  const auto speedup = simd_speedups(bench);
  struct Key { std::string kernel, method, kase; };
  std::vector<std::string> order;
  std::map<std::string, std::map<std::string, json>> rows;  // "kernel/method/case" -> variant -> median
  for (const auto& [name, b] : med) {
    const auto p = bench::BenchName::parse(name);
    if (!p) continue;
    const std::string k = p->kernel_method() + "/" + p->kase;
    if (!rows.count(k)) order.push_back(k);
    rows[k][p->variant] = b;
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
  for (const char* form : {"fast", "robust", "fast16", "robust16"}) {
    const auto it = med.find(fmt::format("wide_node_slab/{}/l1", form));
    if (it != med.end() && it->second.contains("box_tests_per_s")) summary["wide_node_slab"][form] = it->second["box_tests_per_s"];
  }
  summary["rate_goals"] = rate_goals(bench, med);
  return md;
}

}  // namespace

double better_mapping(const json& r) {
  return std::max(r["speedup_rays_in_lanes"].get<double>(), r["speedup_prims_in_lanes"].get<double>());
}

namespace {

// Its interval (the mapping with the higher median).
stats::RatioInterval better_interval(const json& r) {
  const bool rays = r["speedup_rays_in_lanes"].get<double>() >= r["speedup_prims_in_lanes"].get<double>();
  return stats::interval_from_json(r.value(rays ? "speedup_rays_in_lanes_interval" : "speedup_prims_in_lanes_interval", json()));
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
    "- **The same node test in 16 AVX-512 lanes at least 5 G box tests/s on one core, default form.** Beyond what "
    "the 8-lane AVX2 test can reach on a core with three vector ports (docs/DESIGN.md section 12): the near and far "
    "planes of the 8 children share one 16-lane register, so each axis costs one FMA instead of two. The tracer keeps "
    "the 8-lane test: this one runs within a tenth of it, faster or slower with the host's load (docs/DESIGN.md section 12); "
    "both rates are below.\n"
    "- **Moller-Trumbore at least 0.75 G tests/s on one core.** The triangle test is the leaf work of tracing a mesh: its "
    "rate caps how many rays per second a triangle scene can be traced at.\n\n";

std::vector<Goal> speed_goals(const json& summary) {
  std::vector<Goal> goals;
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
  // Throughput goals by the interval of the rounds' rates: met when it clears the target, not met
  // when it lies below, undecided when it straddles it.
  const json rg = summary.value("rate_goals", json::object());
  auto rate_goal = [&](const char* key, const std::string& goal, double target, const std::string& extra = "",
                       const std::string& missing = "") {
    if (!rg.contains(key)) {
      goals.push_back({goal, missing.empty() ? not_measured : missing, -1});
      return;
    }
    const stats::RatioInterval r = stats::interval_from_json(rg[key]);
    goals.push_back({goal, stats::interval_text(r, " G/s") + extra, all_clear({r}, target)});
  };
  rate_goal("box_slab", "box slab >= 3 G tests/s, one core", 3.0);
  // The node test's robust form, beside the default form's goal.
  auto robust = [&](const char* form) {
    const json w = summary.value("wide_node_slab", json::object());
    return w.contains(form) ? fmt::format(" (robust form {:.2f} G/s)", w[form].get<double>() / 1e9) : std::string();
  };
  rate_goal("wide_node_fast", "8-wide node test >= 7 G box tests/s, one core, default form", 7.0, robust("robust"));
  rate_goal("wide_node_fast16", "8-wide node test in 16 AVX-512 lanes >= 5 G box tests/s, one core, default form", 5.0, robust("robust16"),
            "not measured: this run has no 16-lane rows (a CPU or build without AVX-512, --isa avx2, or --filter)");
  rate_goal("moller_trumbore", "Moller-Trumbore >= 0.75 G tests/s, one core", 0.75);
  return goals;
}

std::string goals_markdown(const std::vector<Goal>& goals) {
  std::string md = "| goal | measured (median of this run; a ratio or a rate over the rounds with its 95 % interval) | met |\n|---|---|---|\n";
  for (const auto& g : goals) md += fmt::format("| {} | {} | {} |\n", g.goal, g.measured, doc::goal_cell(g.met));
  return md;
}

// Every kernel's SIMD form >= 4x its true-scalar form on 8 lanes, or the reason it cannot be. Per
// method: the better of the two mappings, in its worst case (hit, miss, half).
// The reasons are the structural ones of each method; a method below target without one is
// flagged as unexplained.
std::string simd_target_section(json& summary) {
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
    const auto it = structural_reasons().find(km);
    const auto& cs = sp[km];
    const double hit = cs.count("hit") ? cs.at("hit") : 0, miss = cs.count("miss") ? cs.at("miss") : 0;
    std::string reason;
    if (!ok && it != structural_reasons().end()) reason = it->second;
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

}  // namespace

std::string report_section_simd(const json& bench, json& summary, std::vector<doc::Goal>& goals) {
  std::string md;
  md += "## 2. Scalar against SIMD, L1-resident\n\n"
        "256 rays x 64 primitives per iteration, every pair tested (~16k tests, all data in L1). `scalar` is compiled with "
        "`-fno-tree-vectorize -fno-tree-slp-vectorize` in its own translation unit; the SIMD mappings run the same kernel text "
        "on 8 float lanes: 8 rays x 1 primitive (rays in lanes) or 1 ray x 8 primitives (prims in lanes). Cases: every pair hits, "
        "every pair misses, half the pairs hit (lanes diverge). One thread. Raw Google Benchmark JSON: [bench.json](bench.json).\n\n";
  if (const std::string e = extra_rounds_text(bench); !e.empty()) md += e + "\n\n";
  md += speed_section(bench, summary) + "\n";
  md += "![SIMD speedup over scalar](simd_speedup.png)\n\n";
  const std::vector<Goal> speed = speed_goals(summary);
  md += "### Goals: SIMD speedup and throughput of the basic kernels\n\n";
  md += kSpeedGoalReasons + goals_markdown(speed) + "\n";
  md += "### Goal: every kernel's SIMD form at least 4x its true-scalar form\n\n"
        "SIMD is worth its place in the engine only if every kernel gains from it. Where a method cannot reach 4x on 8 lanes, "
        "the reason is a property of the method (lanes that need different amounts of work), named here, so that a caller "
        "can choose the scalar form for it knowingly.\n\n";
  md += simd_target_section(summary) + "\n";
  for (const auto& s : speed) goals.push_back({"Scalar against SIMD", s.goal, s.measured, s.met, "simd_speedup.png"});
  if (summary.contains("simd_target_4x_counts")) {
    const auto& c = summary["simd_target_4x_counts"];
    const int met = c["met"].get<int>(), n = c["methods"].get<int>(), und = c.value("undecided", 0);
    goals.push_back({"Scalar against SIMD", "every kernel's SIMD form >= 4x its true-scalar form",
                     fmt::format("{} of {} methods; {} undecided; {} short for a stated structural reason, {} unexplained", met, n, und,
                                 c["explained"].get<int>(), c["unexplained"].get<int>()),
                     doc::goal_over(std::size_t(n), std::size_t(met), std::size_t(n - met - und)),
                     "simd_speedup.png"});
  }
  md += simd16_section(bench, summary, goals);
  return md;
}

}  // namespace rb::app
