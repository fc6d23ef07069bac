// `raybench history`: the runs kept in the results history, and one metric across them
// (apps/history.hpp; the chart: tools/history_plot.py).
#include "apps/interrupt.hpp"
#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "apps/results/history.hpp"
#include "apps/paths.hpp"
#include "apps/results/stats.hpp"
#include "core/output_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <unistd.h>

namespace rb::app {

using nlohmann::json;

namespace {

std::string short_time(const std::string& iso) {  // 2024-12-02T05:39:40Z -> 2024-12-02 05:39
  std::string t = iso.substr(0, 16);
  if (t.size() > 10 && t[10] == 'T') t[10] = ' ';
  return t;
}
std::string revision(const History::Run& r) { return r.git_revision + (r.git_dirty ? "*" : ""); }
std::string hnum(double v) {
  if (!std::isfinite(v)) return "-";
  const double a = std::fabs(v);
  return a >= 1e5 ? fmt::format("{:.0f}", v) : a >= 100 ? fmt::format("{:.1f}", v) : a >= 1 ? fmt::format("{:.3f}", v) : fmt::format("{:.4g}", v);
}
json run_json(const History::Run& r) {
  return {{"id", r.id},           {"time", r.time},     {"kind", r.kind},         {"command", r.command},
          {"version", r.version}, {"git_revision", r.git_revision}, {"git_dirty", r.git_dirty}, {"git_time", r.git_time},
          {"build_type", r.build_type}, {"build_flags", r.build_flags}, {"fp_contract", r.fp_contract}, {"pgo", r.pgo},
          {"compiler", r.compiler}, {"cpu", r.cpu}, {"isa", r.isa}, {"cores", r.cores}, {"figures", r.figures}};
}

std::string runs_text(const std::vector<History::Run>& runs, const std::string& path, bool filtered,
                      const std::vector<std::pair<std::string, long long>>& metrics) {
  // Within 80 columns: the machine of each run is a number, named below the table.
  std::vector<std::string> machines;
  auto machine_no = [&](const History::Run& r) {
    const std::string m = fmt::format("{}, {} hardware threads, {}", r.cpu, r.cores, r.isa);
    auto it = std::find(machines.begin(), machines.end(), m);
    if (it == machines.end()) return machines.push_back(m), machines.size();
    return std::size_t(it - machines.begin()) + 1;
  };
  std::string t = fmt::format("{} run(s) in {}\n", runs.size(), path);
  const char* const kRow = "{:>4}  {:<16} {:<8} {:<13} {:<7} {:<8} {:>7} {:>7}\n";
  t += fmt::format(fmt::runtime(kRow), "id", "time (UTC)", "kind", "revision", "build", "PGO", filtered ? "matches" : "figures", "machine");
  bool dirty = false;
  for (const auto& r : runs) {
    dirty |= r.git_dirty;
    t += fmt::format(fmt::runtime(kRow), r.id, short_time(r.time), r.kind, revision(r), r.build_type.substr(0, 7), r.pgo.substr(0, 8),
                     r.figures, machine_no(r));
  }
  for (std::size_t i = 0; i < machines.size(); ++i) t += wrap_words(fmt::format("machine {}: {}", i + 1, machines[i]), 80, "  ");
  if (dirty) t += "* dirty: tracked files differed from the revision when that binary was built\n";
  std::string names;
  for (const auto& [m, n] : metrics) names += (names.empty() ? "" : ", ") + m;
  t += wrap_words("Metrics stored: " + names + ". One across the runs: raybench history --metric NAME [--plot FILE.png]", 80, "  ");
  return t;
}

// One row per run: the metric's value, or over several matching figures their geometric mean and
// range.
struct RunValue {
  const History::Run* run;
  std::vector<double> values;  // shown units
  std::vector<double> cvs;
};

}  // namespace

int run_history_command(const HistoryOptions& o, const JsonOut& json_out) {
  JsonOut out = json_out;  // the table moves to stderr when the chart is standard output
  if (!stdout_for_one_output("history", "--plot", o.plot, out)) return kExitError;
  const std::string path = history_path(o.path, kReportHistory);
  try {
    const History h(path, false);
    if (o.metric.empty()) {
      const auto runs = h.runs(o.filter);
      if (runs.empty())
        throw NothingToDo(o.filter.empty() ? "no run stored yet" : fmt::format("--filter '{}' matches no figure of any run", o.filter));
      const auto metrics = h.metrics();
      return write_result("history", out, [&] { return runs_text(runs, path, !o.filter.empty(), metrics); }, [&] {
        json j = {{"history", path}, {"filter", o.filter}, {"runs", json::array()}};
        for (const auto& r : runs) j["runs"].push_back(run_json(r));
        return j;
      });
    }
    const auto points = h.series(o.metric, o.filter);
    if (points.empty()) {
      std::string stored;
      for (const auto& [m, n] : h.metrics()) stored += (stored.empty() ? "" : ", ") + m;
      throw NothingToDo(fmt::format("no figure of metric '{}'{} (stored metrics: {})", o.metric,
                                    o.filter.empty() ? "" : " matches --filter '" + o.filter + "'", stored.empty() ? "none" : stored));
    }
    const auto runs = h.runs();
    std::map<long long, const History::Run*> by_id;
    for (const auto& r : runs) by_id[r.id] = &r;
    std::vector<RunValue> rows;
    std::map<long long, std::size_t> at;
    std::vector<std::string> names;
    std::map<std::string, std::size_t> name_at;
    for (const auto& p : points) {
      if (!at.count(p.run)) {
        at[p.run] = rows.size();
        rows.push_back({by_id[p.run], {}, {}});
      }
      rows[at[p.run]].values.push_back(p.value * p.scale);
      rows[at[p.run]].cvs.push_back(p.cv);
      const std::string n = p.section + "/" + p.name;
      if (!name_at.count(n)) name_at[n] = names.size(), names.push_back(n);
    }
    const auto& p0 = points.front();
    const std::string dir = p0.direction > 0 ? "higher is better" : p0.direction < 0 ? "lower is better" : "should not change";
    const bool one = names.size() == 1;
    json doc = {{"history", path}, {"metric", o.metric}, {"unit", p0.unit}, {"direction", p0.direction}, {"filter", o.filter},
                {"runs", json::array()}, {"series", json::array()}};
    for (const auto& r : rows) doc["runs"].push_back(run_json(*r.run));
    for (const auto& n : names) doc["series"].push_back({{"name", n}, {"values", json::array()}});
    for (auto& s : doc["series"]) s["values"] = json(std::vector<json>(rows.size(), json(nullptr)));
    for (const auto& p : points)
      if (std::isfinite(p.value)) doc["series"][name_at[p.section + "/" + p.name]]["values"][at[p.run]] = p.value * p.scale;

    if (!o.plot.empty()) {
      // The chart: tools/history_plot.py reads the series as JSON on its standard input and gives
      // the PNG back on its standard output; the image is then written by the one output rule.
      const std::string cmd = "/usr/bin/python3 " + shell_quote(tool_path("history_plot.py")) + " - -";
      const std::string series = doc.dump() + "\n";
      std::string png;
      const int rc = run_command(cmd, &series, &png);
      if (rc != 0 || png.empty())
        throw std::runtime_error(o.plot + ": the chart was not drawn (`" + cmd + "` failed; is python3-matplotlib installed?)");
      write_output(o.plot, png);
      std::cerr << "wrote " << (is_standard_output(o.plot) ? std::string("the chart to standard output") : o.plot) << " (" << o.metric << " across " << rows.size() << " run(s))\n";
    }
    auto text = [&] {
      std::string t = wrap_words(fmt::format("{} ({}, {}){}", o.metric, p0.unit, dir,
                                             one ? ": " + names[0]
                                                 : fmt::format(": {} figures{}, per run their geometric mean and range", names.size(),
                                                               o.filter.empty() ? "" : " matching '" + o.filter + "'")),
                                 80, "  ");
      if (one)
        t += fmt::format("{:>4}  {:<16}  {:<13}  {:<8}  {:>12}  {:>6}\n", "id", "time (UTC)", "revision", "kind", p0.unit, "CV %");
      else
        t += fmt::format("{:>4}  {:<16}  {:<13}  {:>10}  {:>10}  {:>10}  {:>4}\n", "id", "time (UTC)", "revision", "geomean", "min", "max", "n");
      for (const auto& r : rows) {
        if (one) {
          const double cv = r.cvs.front();
          t += fmt::format("{:>4}  {:<16}  {:<13}  {:<8}  {:>12}  {:>6}\n", r.run->id, short_time(r.run->time), revision(*r.run), r.run->kind,
                           hnum(r.values.front()), std::isfinite(cv) ? fmt::format("{:.1f}", 100 * cv) : "-");
        } else {
          double lo = INFINITY, hi = -INFINITY;
          for (double v : r.values)
            if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
          t += fmt::format("{:>4}  {:<16}  {:<13}  {:>10}  {:>10}  {:>10}  {:>4}\n", r.run->id, short_time(r.run->time), revision(*r.run),
                           hnum(stats::geometric_mean(r.values)), hnum(lo), hnum(hi), r.values.size());
        }
      }
      return t;
    };
    return write_result("history", out, text, [&] { return doc; });
  } catch (const NothingToDo& e) {
    std::cerr << error_line("history", path, e.what()) << "\n";
    return kExitNothing;
  } catch (const std::exception& e) {
    std::cerr << error_line("history", path, e.what()) << "\n";
    return kExitError;
  }
}

}  // namespace rb::app
