#include "core/output_file.hpp"
#include "apps/interrupt.hpp"
#include "apps/report/report.hpp"

#include "apps/cli.hpp"
#include "apps/results/machine.hpp"
#include "apps/build_info.hpp"
#include "apps/paths.hpp"
#include "apps/progress.hpp"
#include "apps/report/report_doc.hpp"
#include "apps/report/report_record.hpp"
#include "apps/report/report_sections.hpp"
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

// What the terminal shows at the end of a report: the headline figures; index.md and the JSON
// beside it hold everything.
std::string terminal_summary(const json& summary, const std::vector<doc::Goal>& goals, std::size_t op_rows, double seconds) {
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
  return t;
}

// With --no-charts the page names each chart it would have shown instead of linking a file that
// was never drawn (an image the report writes itself, such as a rendering, stays).
std::string without_undrawn_charts(const std::string& md, const fs::path& out) {
  static const std::regex image(R"re(!\[([^\]]*)\]\(([^)\s]+\.png)\))re");
  std::string r;
  auto last = md.begin();
  for (std::sregex_iterator it(md.begin(), md.end(), image), e; it != e; ++it) {
    r.append(last, md.begin() + it->position());
    const std::string file = (*it)[2];
    r += fs::is_regular_file(out / file) ? it->str() : "_Chart not drawn (`--no-charts`): " + std::string((*it)[1]) + " (`" + file + "`)._";
    last = md.begin() + it->position() + it->length();
  }
  r.append(last, md.end());
  return r;
}

// The goals every section checks, for the summary at the top of the report: those of section
// "Scalar against SIMD" (its speed goals and 4x target, report_simd.cpp), the tracing goals (checked
// by that section), the rendering goal and the accuracy lab's targets.
std::vector<doc::Goal> report_goals(const std::vector<doc::Goal>& simd, const json& summary) {
  std::vector<doc::Goal> g = simd;
  // The tracing goals are checked by the section itself, each against its worst row.
  if (summary.contains("tracing") && summary["tracing"].contains("goals"))
    for (const auto& r : summary["tracing"]["goals"])
      g.push_back({"Tracing whole scenes", r["goal"].get<std::string>(), r["measured"].get<std::string>(), r["met"].get<int>(),
                   "trace_matrix.png"});
  if (summary.contains("render_goal_half_of_primary")) {
    const auto& r = summary["render_goal_half_of_primary"];
    const int met = r["met"].get<int>(), n = r["scenes"].get<int>(), no = r.value("not_met", n - met), und = r.value("undecided", 0);
    g.push_back({"Rendering", "rendering at least half as fast per ray as primary-ray tracing, every scene",
                 fmt::format("met on {} of {} scenes, not met on {}, undecided on {}", met, n, no, und),
                 doc::goal_over(std::size_t(n), std::size_t(met), std::size_t(no)), "render_spd_balls.png"});
  }
  if (summary.contains("render_goal_alone")) {
    const auto& r = summary["render_goal_alone"];
    const int met = r["met"].get<int>(), n = r["scenes"].get<int>(), no = r["not_met"].get<int>();
    g.push_back({"Rendering", "each render at least 0.8x the rate of its own rays traced alone (overhead under 20 %), every scene",
                 fmt::format("met on {} of {} scenes, not met on {}, undecided on {}", met, n, no, r["undecided"].get<int>()),
                 doc::goal_over(std::size_t(n), std::size_t(met), std::size_t(no)), "render_speed.png"});
  }
  if (summary.contains("plan") && summary["plan"].contains("auto_speed_goal")) {
    // Met on every mesh it applies to, not met on one, undecided otherwise.
    const json& a = summary["plan"]["auto_speed_goal"];
    auto n = [&](int v) { return a.contains(doc::goal_word(v)) ? a[doc::goal_word(v)].size() : std::size_t(0); };
    const std::size_t met = n(doc::kGoalMet), no = n(doc::kGoalNotMet), und = n(doc::kGoalUndecided);
    g.push_back({"What each scene needs", "on every mesh where fast fails no ray, auto keeps >= 0.97x its speed and <= 1.05x its memory",
                 fmt::format("met on {}, not met on {}, undecided on {} mesh(es)", met, no, und),
                 no ? doc::kGoalNotMet : und ? doc::kGoalUndecided : met ? doc::kGoalMet : doc::kGoalNotMeasured, "plan_models.png"});
  }
  if (summary.contains("accuracy"))
    for (const auto& t : summary["accuracy"]["targets"])
      g.push_back({"Accuracy and stability", t["target"].get<std::string>(), t["measured"].get<std::string>(), int(t["met"].get<bool>()), ""});
  return g;
}

// The profile-guided optimisation section is measured by `./run.sh pgo` (its own builds and paired
// rounds of the normal and PGO binaries), which `./run.sh report` runs before the report: it writes
// OUT/pgo.md and OUT/pgo.json, and the report carries that section between markers (so that
// `./run.sh pgo` alone can also refresh an existing index.md). A section measured on another
// revision than this binary's says so. Its ratios (per kernel family and trace row) go into the
// summary (`pgo`), for the section on how precise the ratios are.
std::string pgo_section(const fs::path& out, json& summary) {
  std::string body;
  std::ifstream f;
  if (readable_back((out / "pgo.md").string())) f.open(out / "pgo.md");  // never block on a FIFO there
  if (f.is_open()) {  // (a stream never opened is not in a failed state)
    std::stringstream ss;
    ss << f.rdbuf();
    body = ss.str();
    std::string measured;
    try {
      std::ifstream j;
      if (readable_back((out / "pgo.json").string())) j.open(out / "pgo.json");
      if (j.is_open()) {
        const json p = json::parse(j);
        measured = p.at("context").at("normal").value("raybench_git", "");
        for (const char* k : {"families", "traces"})
          if (p.contains(k) && p[k].is_array()) summary["pgo"][k] = p[k];
      }
    } catch (const std::exception&) {
      measured = "";  // an unreadable record: the section stands as written
    }
    const std::string here = build_info().git();
    if (!measured.empty() && measured != here) {
      const auto eol = body.find('\n');
      body.insert(eol == std::string::npos ? body.size() : eol + 1,
                  fmt::format("\n**Measured on revision `{}`, not on this report's `{}`**: run `./run.sh pgo` again.\n", measured, here));
    }
  } else {
    body = "## Profile-guided optimisation\n\nNot measured for this report: `./run.sh report` measures it first unless it is "
           "given `--no-pgo` or `--quick`; `./run.sh pgo` alone builds an instrumented binary, trains it on a workload apart "
           "from the measured one, rebuilds with the profile and runs both builds in paired rounds of kernel benchmarks and "
           "traces, then fills this section (docs/BUILD.md gives its time).\n\n";
  }
  return "<!-- pgo-section -->\n" + body + "<!-- /pgo-section -->\n\n";
}

// Section "Operations per intersection": the ops table's rows (ops.json beside the page).
std::string section_ops(const std::vector<rb::opstable::Row>& rows, const fs::path& out) {
  write_file(out / "ops.json", rb::opstable::to_json(rows).dump(2));
  std::string md = "## 1. Operations per intersection\n\n"
                   "Lecture counts (seed 000) beside the counts measured by running each kernel with `Counted<float>` on one ray that hits "
                   "and one that misses, and with `Counted<simd8>` (per lane: SIMD code runs the whole kernel when its lanes disagree). "
                   "`\u00b1` add/sub, `*` mul, `/` div, cmp comparisons; min/max, selects and FMAs are listed separately "
                   "(an FMA is compared with the slide as 1\u00b1 + 1*). Negation and sign operations are free. Raw rows: [ops.json](ops.json).\n\n";
  md += rb::opstable::to_markdown(rows) + "\n";
  return md;
}

// The kernel benchmarks of section "Scalar against SIMD" (every repetition kept: `raybench compare`
// tests two reports' repetitions); `rc` gets run_benchmarks' status.
json measure_bench(const ReportOptions& o, const std::string& label, int& rc) {
  BenchOptions bo;
  bo.repetitions = o.repetitions;
  bo.min_time = o.min_time;
  bo.extra_rounds = o.extra_rounds;
  bo.within = o.within;
  bo.filter = o.filter;
  bo.every_repetition = true;
  bo.what = label + " benchmarks";
  bo.command = "report";
  json doc;
  rc = run_benchmarks(bo, doc);
  return doc;
}

// The record a report measures into, or (--from) the folder's record to replay, whose options then
// replace the command line's. 0, or the exit status of an unreadable record.
int open_record(const ReportOptions& opts, Record& rec, ReportOptions& o) {
  if (!opts.from.empty()) {
    o.out = opts.from;
    try {
      rec = Record::replaying((fs::path(opts.from) / kRecordFile).string());
    } catch (const std::exception& e) {
      std::cerr << error_line("report", "", e.what()) << "\n";
      return kExitError;
    }
  }
  const json kept_options = rec.take("options", [&] {
    return json{{"quick", o.quick}, {"repetitions", o.repetitions}, {"min_time", o.min_time}, {"extra_rounds", o.extra_rounds},
                {"within", o.within}, {"filter", o.filter}};
  });
  o.quick = kept_options["quick"], o.repetitions = kept_options["repetitions"], o.min_time = kept_options["min_time"];
  o.extra_rounds = kept_options.value("extra_rounds", 0), o.within = kept_options.value("within", 0.05);  // none in older records
  o.filter = kept_options["filter"];
  return 0;
}

}  // namespace

int run_report(const ReportOptions& opts) {
  const Clock clock;
  // Measuring, or replaying a folder's record (--from): then the options are the record's.
  Record rec;
  ReportOptions o = opts;
  if (const int rc = open_record(opts, rec, o); rc != 0) return rc;
  const fs::path out = o.out;
  // Nothing to do is found before the work starts: a --filter that selects no benchmark.
  if (!rec.replay() && benchmark_names(o.filter).empty()) {
    std::cerr << error_line("report", "", fmt::format("--filter '{}' selects no benchmark (raybench bench --list shows them)", o.filter))
              << "\n";
    return kExitNothing;
  }
  fs::create_directories(out);
  // The numbered stages, each with the report's elapsed time.
  constexpr int kStages = 9;
  int stage = 0;
  auto next_stage = [&](const std::string& what) {
    std::cerr << fmt::format("[report {}/{}, {}] {}{}\n", ++stage, kStages, format_duration(clock.s()), rec.replay() ? "(from the record) " : "", what);
    return fmt::format("[report {}/{}]", stage, kStages);
  };
  const json m = rec.take("machine", [] {
    const Machine here = machine();
    return json{{"json", here.json()}, {"markdown", here.markdown()}};
  });
  json summary;
  summary["machine"] = m["json"];
  std::string md = "# raybench report\n\n";
  if (o.quick)
    md += "**Quick mode** (`--quick`): few repetitions, few rays and small images, to check the report's layout; its figures "
          "are not the ones to quote.\n\n";
  md += "Produced by `raybench report` on the embedded default scenes; every figure below was measured in this run. "
        "Speeds are medians over " + std::to_string(o.repetitions) + " repetitions, ratios are taken within this run.\n\n";
  md += "## Machine and build\n\n" + m["markdown"].get<std::string>() + "\n";

  next_stage("operations per intersection (Counted<float>, Counted<simd8>)");
  const auto rows = rb::opstable::from_json(rec.take("ops", [] { return rb::opstable::to_json(rb::opstable::build()); }));
  md += section_ops(rows, out);

  const std::string bench_label = next_stage(fmt::format("scalar vs SIMD benchmarks ({} repetitions x {} s each{})", o.repetitions, o.min_time,
                                                         o.extra_rounds > 0 ? fmt::format(", up to {} more where wide", o.extra_rounds) : ""));
  const fs::path bj = out / "bench.json";
  int bench_rc = 0;
  json bench = rec.take("bench", [&] { return measure_bench(o, bench_label, bench_rc); });
  if (bench_rc != 0) return bench_rc;
  bench["machine"] = summary["machine"];  // bench.json is a result of its own: the block every result carries
  write_file(bj, bench.dump(2));
  std::vector<doc::Goal> goals;
  md += report_section_simd(bench, summary, goals);

  next_stage("scenes: load and generation times, memory");
  md += report_section_scenes(o, rec, out, summary);

  next_stage("tracing whole scenes (raybench BVH beside Embree)");
  md += report_section_tracing(o, rec, out, summary);
  next_stage("rendering: SPD, lecture and CSG scenes");
  md += report_section_render(o, rec, out, summary);

  next_stage("accuracy lab");
  md += report_section_accuracy(o, rec, out, summary);

  next_stage("what each scene needs: plans, their cost and their failures");
  md += report_section_plan(o, rec, out, summary);

  next_stage("CSG queries, scalar against 8-ray packets");
  md += report_section_csg(o, rec, out, summary, rows);

  md += pgo_section(out, summary);
  md += report_section_precision(summary, goals);

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
  const double seconds = rec.take("seconds", [&] { return json(clock.s()); });
  // What was measured, for `raybench report --from` (a replay keeps the record it read).
  if (!rec.replay()) write_file(out / kRecordFile, rec.document().dump(1) + "\n");
  md += fmt::format("---\n\nReport measured in {:.0f} s by `raybench report --out {}{}`.\n", seconds, o.out, o.quick ? " --quick" : "");
  if (rec.replay()) md += fmt::format("Written again from its record ({}) by `raybench report --from {}`.\n", kRecordFile, o.out);
  std::vector<doc::Goal> page_goals = all_goals;
  if (!o.charts) {
    md = without_undrawn_charts(md, out);
    for (auto& g : page_goals)
      if (!g.figure.empty() && !fs::is_regular_file(out / g.figure)) g.figure.clear();
  }
  // One model, two pages: index.md and the self-contained index.html beside it.
  doc::Document page = doc::parse_markdown(md);
  doc::organise(page, page_goals, out);
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
