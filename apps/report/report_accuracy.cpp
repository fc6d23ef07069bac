// Report section "Accuracy and stability": the accuracy lab's quick run (apps/cmd_accuracy.cpp),
// per primitive family a chart of speed against accuracy with its Pareto front, the table
// "where each method fails", the targets checked against this run, and the cost of spawning
// secondary rays with an offset.
#include "core/median.hpp"
#include "core/output_file.hpp"
#include "apps/interrupt.hpp"
#include "apps/accuracy_run.hpp"
#include "apps/paths.hpp"
#include "apps/report/report.hpp"
#include "apps/report/report_record.hpp"
#include "apps/report/report_sections.hpp"
#include "apps/results/stats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <set>

namespace rb::app {

namespace fs = std::filesystem;
using nlohmann::json;
using acc::Row;

namespace {

bool is_secondary(const Row& r) { return r.case_name.rfind("secondary", 0) == 0; }
std::string col(const Row& r) { return r.method + " " + r.precision; }
std::string ppm(double x) {
  if (!std::isfinite(x)) return "-";
  if (x == 0) return "0";
  return x >= 100 ? fmt::format("{:.0f}", x) : fmt::format("{:.2g}", x);
}
std::string g3(double x) { return std::isfinite(x) ? fmt::format("{:.3g}", x) : "-"; }

// Cases that at least one method passes (failure 0): the chart's worst case is taken over these
// (a case no method passes is ill-conditioned by construction; the table shows it). A family
// none of whose cases is passed: all its cases.
std::set<std::string> passable_cases(const std::vector<Row>& rows, const std::string& fam) {
  std::set<std::string> s, all;
  for (const Row& r : rows)
    if (r.family == fam && !is_secondary(r)) {
      all.insert(r.case_name);
      if (r.failure_ppm() == 0) s.insert(r.case_name);
    }
  return s.empty() ? all : s;  // no case passed by any method: the worst over all of them
}

struct Point {
  std::string method, precision;
  double ns = std::numeric_limits<double>::quiet_NaN(), worst_fail = 0, worst_ulp99 = 0;
  std::string worst_case;
};

std::vector<Point> family_points(const std::vector<Row>& rows, const std::string& fam) {
  const auto ok = passable_cases(rows, fam);
  std::map<std::string, Point> pts;
  std::map<std::string, std::vector<double>> ns;
  for (const Row& r : rows) {
    if (r.family != fam || is_secondary(r)) continue;
    Point& p = pts[col(r)];
    p.method = r.method, p.precision = r.precision;
    if (std::isfinite(r.ns_per_test)) ns[col(r)].push_back(r.ns_per_test);
    if (!ok.count(r.case_name)) continue;
    if (r.failure_ppm() > p.worst_fail || p.worst_case.empty()) {
      if (r.failure_ppm() > p.worst_fail) p.worst_case = r.case_name;
      p.worst_fail = std::max(p.worst_fail, r.failure_ppm());
    }
    if (std::isfinite(r.t_err_ulp_p99)) p.worst_ulp99 = std::max(p.worst_ulp99, r.t_err_ulp_p99);
  }
  std::vector<Point> v;
  for (auto& [k, p] : pts) {
    auto& n = ns[k];
    if (!n.empty()) {
      std::sort(n.begin(), n.end());
      p.ns = n[n.size() / 2];
    }
    if (p.worst_fail == 0) p.worst_case = "";
    v.push_back(p);
  }
  return v;
}

// The best method of a family: fewest failures, then smallest p99 error class (<= 4 ulp), then fastest.
const Point* best_point(const std::vector<Point>& v) {
  const Point* b = nullptr;
  for (const Point& p : v) {
    auto key = [](const Point& q) { return std::make_tuple(q.worst_fail, q.worst_ulp99 > 4, std::isfinite(q.ns) ? q.ns : 1e300); };
    if (!b || key(p) < key(*b)) b = &p;
  }
  return b;
}

const Row* find(const std::vector<Row>& rows, const std::string& fam, const std::string& cs, const std::string& m, const std::string& p) {
  for (const Row& r : rows)
    if (r.family == fam && r.case_name == cs && r.method == m && r.precision == p) return &r;
  return nullptr;
}

struct Target {
  std::string name, measured;
  bool met;
};

std::vector<Target> targets(const std::vector<Row>& rows) {
  std::vector<Target> t;
  {  // watertight: 0 leaks on every closed-mesh case, every precision
    double worst = 0;
    std::string where = "none";
    bool any = false;
    for (const Row& r : rows)
      if (((r.family == "triangle" && r.method == "woop") || (r.family == "bvh" && r.method == "woop_robust_slabs")) &&
          std::isfinite(r.leak_ppm)) {
        any = true;
        const double f = r.failure_ppm();  // leaks + wrong (farther) hits
        if (f > worst) worst = f, where = r.family + " " + r.case_name + " " + r.precision;
      }
    t.push_back({"Watertight triangle test (woop): 0 leaks per million through the closed meshes' edges and vertices, float, double and "
                 "simd8, also through the BVH with the robust slab test (single rays and packets)",
                 any ? fmt::format("worst {} ppm ({})", ppm(worst), where) : "not run", any && worst == 0});
  }
  {  // sphere: best float method p99 <= 2 ulp, 0 misclassified up to d/R 1e5
    std::string m;
    bool met = false;
    for (const char* method : {"compensated", "hearn_baker", "stable", "geometric", "algebraic"}) {
      double fail = 0, p99 = 0;
      int n = 0;
      for (const char* cs : {"far_small_1e1", "far_small_1e3", "far_small_1e5"})
        if (const Row* r = find(rows, "sphere", cs, method, "float")) {
          ++n;
          fail = std::max(fail, r->false_hit_ppm + r->false_miss_ppm);
          p99 = std::max(p99, r->t_err_ulp_p99);
        }
      if (n == 3 && fail == 0 && p99 <= 2) {
        met = true;
        m = fmt::format("{} float: 0 misclassified, p99 {:.2f} ulp", method, p99);
        break;
      }
      if (m.empty() && n == 3) m = fmt::format("{} float: {} ppm misclassified, p99 {:.2f} ulp", method, ppm(fail), p99);
    }
    t.push_back({"Sphere, best float method: p99 t error <= 2 ulp and 0 misclassified up to distance/radius 1e5", m.empty() ? "not run" : m, met});
  }
  {  // planet
    std::string m = "not run";
    bool met = false;
    for (const char* method : {"compensated", "stable", "algebraic", "hearn_baker", "geometric"})
      for (const char* prec : {"float", "simd8", "double"}) {
        const Row* a = find(rows, "sphere", "planet_pole", method, prec);
        const Row* b = find(rows, "sphere", "planet_45", method, prec);
        if (!a || !b || met) continue;
        const double fail = a->false_hit_ppm + a->false_miss_ppm + b->false_hit_ppm + b->false_miss_ppm;
        const double sc = std::max(a->scaled_err_p99, b->scaled_err_p99);
        if (fail == 0 && sc <= 4) met = true, m = fmt::format("{} {}: 0 misclassified, scaled p99 {:.3g}", method, prec, sc);
      }
    t.push_back({"Planet: a method with 0 misclassified and scale-normalised p99 <= 4", m, met});
  }
  {  // torus at 500x
    const Row* r = find(rows, "torus", "camera_500x", "robust", "float");
    const bool met = r && r->false_hit_ppm + r->false_miss_ppm <= 200 && r->wrong_roots == 0 && r->scaled_err_p99 <= 3;
    t.push_back({"Torus, best float method at 500x the torus size: <= 0.02 % misclassified, 0 wrong roots, scaled p99 <= 3",
                 r ? fmt::format("robust float: {} ppm misclassified, {} wrong roots, scaled p99 {:.3g}", ppm(r->false_hit_ppm + r->false_miss_ppm),
                                 r->wrong_roots, r->scaled_err_p99)
                   : "not run",
                 met});
  }
  {  // cone and cylinder
    double nan = 0;
    bool any = false;
    for (const Row& r : rows)
      if (r.family == "quadric") any = true, nan = std::max(nan, r.nan_ppm);
    const Row* a = find(rows, "quadric", "cone_apex", "cone_capped", "double");
    const Row* b = find(rows, "quadric", "cone_apex", "cone", "double");
    const double mis = (a ? a->false_hit_ppm + a->false_miss_ppm : std::numeric_limits<double>::quiet_NaN()) + (b ? b->false_hit_ppm + b->false_miss_ppm : 0.0);
    t.push_back({"Cone and cylinder: no NaN t; 0 misclassified through the apex in double",
                 any ? fmt::format("NaN t: {} ppm; apex set, double: {} ppm misclassified", ppm(nan), ppm(mis)) : "not run",
                 any && nan == 0 && mis == 0});
  }
  return t;
}

// The evidence for the plan's spawn scheme in this run: over every kernel's secondary cases, the
// self-hits of the integer and the error-bound offsets and the integer offset's time over the error
// bound's (the report's plan section checks the plan's choice against it).
json spawn_evidence(const std::vector<Row>& rows) {
  std::vector<double> ratios;
  double wb_self = 0, bound_self = 0;
  for (const Row& b : rows) {
    if (b.case_name != "secondary_wb_offset" || b.precision != "float") continue;
    const Row* c = find(rows, b.family, "secondary_bound_offset", b.method, "float");
    if (!c) continue;
    wb_self = std::max(wb_self, b.self_hit_ppm), bound_self = std::max(bound_self, c->self_hit_ppm);
    if (std::isfinite(b.ns_per_test) && std::isfinite(c->ns_per_test) && c->ns_per_test > 0) ratios.push_back(b.ns_per_test / c->ns_per_test);
  }
  json j{{"kernels", ratios.size()}, {"integer_self_hit_ppm_max", wb_self}, {"bound_self_hit_ppm_max", bound_self}};
  if (!ratios.empty()) {
    std::sort(ratios.begin(), ratios.end());
    j["integer_over_bound_ns"] = {{"median", rb::median(ratios)}, {"lowest", ratios.front()}, {"highest", ratios.back()}};
  }
  return j;
}

// What storing a kind apart costs in this run (family "storage": accuracy/lab.hpp, storage_rows),
// per case: local frames and double over the kind in the frame, and local frames over double, each
// the ratio of the paired rounds' times with its interval (the report's plan section checks the
// plan's choice of storage against it).
json storage_evidence(const std::vector<Row>& rows) {
  json j = json::object();
  for (const Row& f : rows) {
    if (f.family != "storage" || f.method != acc::kStorageFloat) continue;
    const Row* l = find(rows, "storage", f.case_name, acc::kStorageLocal, f.precision);
    const Row* d = find(rows, "storage", f.case_name, acc::kStorageDouble, f.precision);
    if (!l || !d || f.round_seconds.empty()) continue;
    j[f.case_name] = {{"local_over_frame", stats::interval_json(stats::paired_ratio(l->round_seconds, f.round_seconds))},
                      {"double_over_frame", stats::interval_json(stats::paired_ratio(d->round_seconds, f.round_seconds))},
                      {"local_over_double", stats::interval_json(stats::paired_ratio(l->round_seconds, d->round_seconds))},
                      {"failure_ppm", {f.failure_ppm(), l->failure_ppm(), d->failure_ppm()}}};
  }
  return j;
}

}  // namespace

std::string report_section_accuracy(const ReportOptions& o, Record& rec, const fs::path& out, json& summary) {
  acc::Options ao;
  ao.scene_rounds = whole_scene_rounds(o);
  if (o.quick) ao.rays = 200, ao.real_meshes = false;  // the layout only: the real meshes' references take the longest
  const json kept = rec.take("accuracy", [&] {
    const auto t0 = std::chrono::steady_clock::now();
    json rj = json::array();
    for (const Row& r : run_accuracy(ao, "[report] accuracy lab")) rj.push_back(r.json());
    return json{{"rows", rj}, {"seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()}};
  });
  std::vector<Row> rows;
  for (const auto& r : kept["rows"]) rows.push_back(Row::from_json(r));
  const double secs = kept["seconds"].get<double>();
  write_output((out / "accuracy.json").string(), accuracy_json(ao, rows).dump(1) + "\n");
  std::string md = "## Accuracy and stability\n\n";
  md += fmt::format(
      "Produced by `raybench accuracy --json` (quick mode: {} rays per case, seed {}; {:.0f} s). Every case is a named, seeded set of "
      "adversarial rays (`raybench accuracy --list`); its reference comes from the same float inputs the kernels see (the stored ray "
      "and primitive): GMP rationals decide hit or miss at triangle edges and box slab planes, MPFR gives the quadrics' roots, a long "
      "double root isolation gives the torus roots. Each method runs as scalar float, scalar double (the same floats, widened) and "
      "8-lane float SIMD, compiled with FMA contraction on (as in the release build). Failure figure = false hits + false misses + "
      "self-hits + NaN t + wrong roots, per million tests (a hit exactly on an edge or a tangent point is neither); on closed meshes "
      "it is the leak rate per million rays through the mesh, plus NaN and wrong (farther) hits, since which of two faces a ray "
      "within rounding of their shared edge hits is arbitrary for every float method. ns per test is timed in the same run, on the "
      "case's own rays (family bvh: ns per ray through the tree). The chart's worst case is over the cases some method passes. "
      "Raw rows: "
      "[accuracy.json](accuracy.json).\n\n",
      ao.rays ? ao.rays : (ao.full ? 100000 : 10000), ao.seed, secs);
  md += "### Targets\n\n| target | this run | met |\n|---|---|---|\n";
  json tj = json::array();
  for (const Target& t : targets(rows)) {
    md += fmt::format("| {} | {} | {} |\n", t.name, t.measured, t.met ? "yes" : "**no**");
    tj.push_back({{"target", t.name}, {"measured", t.measured}, {"met", t.met}});
  }
  md += "\n";
  std::vector<std::string> fams;
  for (const Row& r : rows)
    if (std::find(fams.begin(), fams.end(), r.family) == fams.end()) fams.push_back(r.family);
  json best = json::object();
  for (const std::string& fam : fams) {
    const auto pts = family_points(rows, fam);
    md += fmt::format("### {}\n\n", fam);
    if (const Point* b = best_point(pts)) {
      md += fmt::format("Best: **{} {}**, {} ns per test (median over the cases), worst failure {} ppm, worst p99 t error {} ulp.\n\n",
                        b->method, b->precision, g3(b->ns), ppm(b->worst_fail), g3(b->worst_ulp99));
      best[fam] = {{"method", b->method}, {"precision", b->precision}, {"ns_per_test", b->ns}, {"worst_failure_ppm", b->worst_fail},
                   {"worst_t_err_ulp_p99", b->worst_ulp99}};
    }
    md += fmt::format("![{} speed against accuracy](accuracy_{}.png)\n\n", fam, fam);
    // Where each method fails: rows cases, columns method + precision, cells failure ppm.
    std::vector<std::string> cols, cases;
    for (const Row& r : rows) {
      if (r.family != fam || is_secondary(r)) continue;
      if (std::find(cols.begin(), cols.end(), col(r)) == cols.end()) cols.push_back(col(r));
      if (std::find(cases.begin(), cases.end(), r.case_name) == cases.end()) cases.push_back(r.case_name);
    }
    md += "Where each method fails (failure ppm; 0 = none; in brackets the p99 t error in ulps of the precision):\n\n| case |";
    for (const auto& c : cols) md += " " + c + " |";
    md += " passed by |\n|---|";
    for (std::size_t k = 0; k < cols.size(); ++k) md += "---:|";
    md += "---|\n";
    for (const auto& cs : cases) {
      md += "| " + cs + " |";
      int passing = 0;
      for (const auto& c : cols) {
        const Row* r = nullptr;
        for (const Row& x : rows)
          if (x.family == fam && x.case_name == cs && col(x) == c) r = &x;
        if (!r) {
          md += " |";
          continue;
        }
        passing += r->failure_ppm() == 0;
        md += fmt::format(" {} ({}) |", ppm(r->failure_ppm()), g3(r->t_err_ulp_p99));
      }
      md += passing ? fmt::format(" {} |\n", passing) : std::string(" none: ill-conditioned below every precision's resolution (tangent, grazing or clustered roots) |\n");
    }
    md += "\n";
    // Secondary rays.
    bool any2 = false;
    for (const Row& r : rows) any2 = any2 || (r.family == fam && is_secondary(r));
    if (any2) {
      md += "Secondary rays (float): self-hits per million rays spawned at the computed hit point, leaving on the side the ray came "
            "from: without an offset, with the Waechter-Binder integer offset, and with the error-bound offset (pbrt-style: the hit "
            "point recomputed in a form with a known rounding-error bound, moved along the normal by that bound and rounded one "
            "float further). ns per spawned test includes the scheme's work (without an offset, the self-hit rays run the "
            "kernel's longer positive path, so the change is not the scheme's cost alone).\n\n"
            "| method | no offset: self-hit ppm | ns | integer offset: self-hit ppm | ns | change | error-bound offset: self-hit ppm | ns | change |\n"
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
      std::set<std::string> ms;
      for (const Row& r : rows)
        if (r.family == fam && is_secondary(r)) ms.insert(r.method);
      auto change = [](const Row* a, const Row* b) {
        return b && std::isfinite(a->ns_per_test) && a->ns_per_test > 0 && std::isfinite(b->ns_per_test)
                   ? fmt::format("{:+.0f} %", 100 * (b->ns_per_test / a->ns_per_test - 1))
                   : std::string("-");
      };
      for (const auto& m : ms) {
        const Row* a = find(rows, fam, "secondary_no_offset", m, "float");
        const Row* b = find(rows, fam, "secondary_wb_offset", m, "float");
        const Row* c = find(rows, fam, "secondary_bound_offset", m, "float");
        if (!a) continue;
        md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", m, ppm(a->self_hit_ppm), g3(a->ns_per_test),
                          b ? ppm(b->self_hit_ppm) : "-", b ? g3(b->ns_per_test) : "-", change(a, b), c ? ppm(c->self_hit_ppm) : "-",
                          c ? g3(c->ns_per_test) : "-", change(a, c));
      }
      md += "\n";
    }
  }
  summary["accuracy"] = {{"best", best}, {"targets", tj}, {"seconds", secs}, {"rows", rows.size()}, {"spawn", spawn_evidence(rows)},
                         {"storage", storage_evidence(rows)}};
  if (o.charts && !readable_back((out / "accuracy.json").string())) {
    md += "_Accuracy charts were not drawn: accuracy.json, which they read, is not a regular file._\n\n";
  } else if (o.charts) {
    const std::string cmd = "/usr/bin/python3 " + shell_quote(tool_path("accuracy_charts.py")) + " " + shell_quote((out / "accuracy.json").string()) +
                            " " + shell_quote(out.string());
    if (run_command(cmd) != 0) md += "_Accuracy charts were not drawn: `" + cmd + "` failed (is python3-matplotlib installed?)._\n\n";
  }
  return md;
}

}  // namespace rb::app
