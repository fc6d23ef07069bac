#include "apps/results/compare.hpp"

#include "apps/cli.hpp"
#include "apps/results/stats.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>

namespace rb::app {

using nlohmann::json;

namespace {

const char* kind_label(const std::string& k) { return k == "report" ? "a report folder" : "a result"; }

std::string value_text(double v) {
  if (!std::isfinite(v)) return "-";
  const double a = std::fabs(v);
  if (a >= 1e5) return fmt::format("{:.0f}", v);
  if (a >= 100) return fmt::format("{:.1f}", v);
  if (a >= 1 || a == 0) return fmt::format("{:.3f}", v);
  if (a >= 1e-3) return fmt::format("{:.4f}", v);
  return fmt::format("{:.3g}", v);
}
std::string ratio_text(double r) { return std::isfinite(r) ? fmt::format("{:.3f}", r) : "-"; }
// B/A's interval as "lo-hi" ("-" without one).
std::string interval_cell(const stats::RatioInterval& r) {
  return r.valid() ? fmt::format("{}-{}", ratio_text(r.lo), ratio_text(r.hi)) : "-";
}
std::string direction_text(int d) { return d > 0 ? "higher is better" : d < 0 ? "lower is better" : "should not change"; }

std::string describe(const ResultSet& r) {
  const json& m = r.machine;
  if (!m.is_object()) return "no machine block";
  std::string s = "git " + m.value("git", std::string("?"));
  if (m.contains("date")) s += ", " + m["date"].get<std::string>();
  if (m.contains("build_type")) s += ", " + m["build_type"].get<std::string>();
  return s;
}

// Notes on what differs between the two runs apart from the code.
void machine_notes(const Comparison& c, std::vector<std::string>& notes) {
  const json &a = c.a.machine, &b = c.b.machine;
  if (!a.is_object() || !b.is_object())
    notes.push_back("one side has no machine and build block: check that both ran on the same machine and build settings");
  for (const char* k : {"cpu", "cores", "build_type", "build_flags", "fp_contract", "pgo", "compiler"})
    if (a.is_object() && b.is_object() && a.contains(k) && b.contains(k) && a[k] != b[k])
      notes.push_back(fmt::format("A and B differ in {} ({} / {}): the ratios compare that too, not only the code", k, a[k].dump(),
                                  b[k].dump()));
  for (const auto& [k, v] : c.a.config.items())
    if (c.b.config.contains(k) && c.b.config[k] != v)
      notes.push_back(fmt::format("A and B ran with different {} ({} / {})", k, v.dump(), c.b.config[k].dump()));
}

}  // namespace

namespace {

// One trace or render each: runs of other settings measure other things, and are refused unless
// --force, which matches their figures by metric alone and says so first.
void check_settings(const ResultSet& a, ResultSet& b, const CompareOptions& o, Comparison& c) {
  if (a.kind != "trace" && a.kind != "render") return;
  std::vector<std::string> differ;
  for (const char* k : {"scene", "ray_set", "packet", "threads", "rays", "model", "slab", "width", "height"}) {
    const json va = a.config.value(k, json(nullptr)), vb = b.config.value(k, json(nullptr));
    if (va != vb) differ.push_back(fmt::format("{} {} / {}", k, va.dump(), vb.dump()));
  }
  if (differ.empty()) return;
  std::string what;
  for (const auto& d : differ) what += (what.empty() ? "" : ", ") + d;
  if (!o.force)
    throw std::runtime_error(fmt::format("{} and {} are runs of other settings ({}): their figures measure different things; "
                                         "--force compares them anyway",
                                         a.source, b.source, what));
  c.notes.insert(c.notes.begin(), fmt::format("FORCED: A and B are runs of other settings ({}); their figures are matched by "
                                              "metric and measure different things",
                                              what));
  if (!a.figures.empty())
    for (auto& f : b.figures) f.name = a.figures[0].name;
}

// A timing row's verdict. With repetitions on both sides: B/A's interval (the ratio of medians,
// the Mann-Whitney test inverted on logarithms at level 1 - alpha); faster or slower when it lies
// wholly on one side of 1, within noise when it holds 1 or has too few repetitions to reach its
// level; a regression when all of it is worse than
// the threshold, a possible one when only its median is. A single figure: beyond --noise.
void judge_timing(ComparedRow& r, const CompareOptions& o) {
  const bool higher = r.a.direction > 0;
  if (r.a.samples.size() >= 2 && r.b.samples.size() >= 2) {
    r.interval = stats::unpaired_ratio(r.b.samples, r.a.samples, 1 - o.alpha);
    // Below the level (3 and 3 repetitions: the range of the ratios, 90 %) no verdict: a note says so.
    if (!r.interval.valid() || r.interval.coverage < 1 - o.alpha) return;
    // The interval of the gain (how much better B is): B/A's, or its inverse for lower-is-better.
    const double glo = higher ? r.interval.lo : 1 / r.interval.hi, ghi = higher ? r.interval.hi : 1 / r.interval.lo;
    if (glo > 1) r.verdict = "faster";
    if (ghi < 1) r.verdict = "slower";
    if (o.threshold >= 0 && r.judged && r.verdict == "slower") {
      const double limit = 1 / (1 + o.threshold);  // the gain of a time that rose by the threshold
      r.regression = ghi < limit;
      r.possible_regression = !r.regression && std::isfinite(r.gain) && r.gain < limit;
    }
    return;
  }
  if (std::isfinite(r.gain) && r.gain != 1 && std::fabs(r.gain - 1) > o.noise) r.verdict = r.gain > 1 ? "faster" : "slower";
  if (o.threshold >= 0 && r.judged && r.verdict == "slower") r.regression = 1 / r.gain - 1 > o.threshold;
}

// A deterministic (seeded) figure: equal, or better, worse or changed; a regression when worse by
// more than the threshold (a failure rate that rose from 0 is infinitely worse).
void judge_figure(ComparedRow& r, const CompareOptions& o) {
  const double va = r.a.value, vb = r.b.value;
  const bool both_finite = std::isfinite(va) && std::isfinite(vb);
  const bool differ = both_finite ? std::fabs(vb - va) > 1e-12 * std::max(std::fabs(va), std::fabs(vb)) : std::isfinite(va) != std::isfinite(vb);
  if (differ) r.verdict = r.a.direction == 0 ? "changed" : ((vb > va) == (r.a.direction > 0) ? "better" : "worse");
  if (o.threshold >= 0 && r.judged && r.verdict == "worse") {
    const double worse = std::isfinite(r.gain) && r.gain > 0 ? 1 / r.gain - 1 : std::numeric_limits<double>::infinity();
    r.regression = worse > o.threshold;
  }
}

ComparedRow compare_row(const Figure& fa, const Figure& fb, const CompareOptions& o) {
  ComparedRow r;
  r.a = fa;
  r.b = fb;
  const double va = r.a.value, vb = r.b.value;
  r.ratio = va != 0 && std::isfinite(va) && std::isfinite(vb) ? vb / va : stats::kNaN;
  r.gain = r.a.direction > 0 ? r.ratio : r.a.direction < 0 ? (vb != 0 && std::isfinite(vb) ? va / vb : stats::kNaN) : stats::kNaN;
  r.judged = r.a.judged || (!o.metric.empty() && r.a.metric == o.metric);
  if (r.a.timing) judge_timing(r, o);
  else judge_figure(r, o);
  return r;
}

// Two reports: their goals' verdicts side by side.
void compare_goals(Comparison& c) {
  for (const auto& ga : c.a.goals)
    for (const auto& gb : c.b.goals) {
      if (ga.value("section", "") != gb.value("section", "") || ga.value("goal", "") != gb.value("goal", "")) continue;
      ComparedGoal g{ga.value("section", ""), ga.value("goal", ""), ga.value("verdict", ""), gb.value("verdict", "")};
      g.flipped = (g.a == "met" && g.b == "not met") || (g.a == "not met" && g.b == "met");
      c.goal_flips += g.flipped;
      c.goal_moves += !g.flipped && g.a != g.b;
      c.goals.push_back(g);
      break;
    }
}

// What the reader needs to weigh the rows: unjudged rows, too few repetitions for the level,
// possible regressions, figures on one side only.
void add_notes(Comparison& c) {
  std::size_t unjudged = 0, possible = 0, short_level = 0;
  double least = 1;
  for (const auto& r : c.rows) {
    unjudged += !r.judged;
    possible += r.possible_regression;
    if (r.interval.valid() && r.interval.coverage < 1 - c.options.alpha) {
      ++short_level;
      least = std::min(least, r.interval.coverage);
    }
  }
  if (unjudged)
    c.notes.push_back(fmt::format("{} row(s) shown, not judged (in brackets): Embree's figures are the yardstick, and a build time "
                                  "is one measurement; --metric NAME judges that metric",
                                  unjudged));
  if (short_level)
    c.notes.push_back(fmt::format("{} row(s) have too few repetitions for a {:.0f} % interval and are not judged: theirs is the "
                                  "range of the ratios, which holds the true ratio with {:.1f} % confidence; run more repetitions "
                                  "(5 or more a side)",
                                  short_level, 100 * (1 - c.options.alpha), 100 * least));
  if (possible)
    c.notes.push_back(fmt::format("{} possible regression(s) (marked ?): the median is worse than the threshold but the interval "
                                  "reaches it; not counted",
                                  possible));
  if (!c.a.figures.empty() || !c.b.figures.empty())
    c.notes.push_back(fmt::format("{} figures only in A, {} only in B (not compared)", c.a.figures.size(), c.b.figures.size()));
}

}  // namespace

Comparison compare_results(ResultSet a, ResultSet b, const CompareOptions& o) {
  if (a.kind != b.kind)
    throw std::runtime_error(fmt::format("{} is {} of kind {}, {} {} of kind {}: compare two results of one kind", a.source, kind_label(a.kind),
                                         a.kind, b.source, kind_label(b.kind), b.kind));
  Comparison c;
  c.kind = a.kind;
  c.options = o;
  std::regex re;
  const bool filtered = !o.filter.empty();
  if (filtered) re = filter_regex(o.filter);
  auto keep = [&](const Figure& f) {
    return (o.metric.empty() || f.metric == o.metric) && (!filtered || filter_matches(re, f.section + "/" + f.name));
  };
  check_settings(a, b, o, c);
  std::map<std::string, std::size_t> in_b;
  for (std::size_t i = 0; i < b.figures.size(); ++i) in_b[b.figures[i].key()] = i;
  std::vector<Figure> only_a;
  std::set<std::size_t> used_b;
  for (auto& fa : a.figures) {
    if (!keep(fa)) continue;
    const auto it = in_b.find(fa.key());
    if (it == in_b.end()) {
      only_a.push_back(fa);
      continue;
    }
    used_b.insert(it->second);
    ComparedRow r = compare_row(fa, b.figures[it->second], o);
    if (r.a.timing) c.timings += r.judged;
    else ++c.figures;
    if (r.verdict == "faster") c.faster += r.judged;
    if (r.verdict == "slower") c.slower += r.judged;
    if (r.verdict == "better") ++c.better;
    if (r.verdict == "worse") ++c.worse;
    if (r.verdict == "changed") ++c.changed;
    c.regressions += r.regression;
    c.rows.push_back(std::move(r));
  }
  std::vector<Figure> only_b;
  for (std::size_t i = 0; i < b.figures.size(); ++i)
    if (!used_b.count(i) && keep(b.figures[i])) only_b.push_back(b.figures[i]);
  a.figures = std::move(only_a);
  b.figures = std::move(only_b);
  c.a = std::move(a);
  c.b = std::move(b);
  if (c.rows.empty())
    throw NothingToDo(fmt::format("no row is in both {} and {}{}", c.a.source, c.b.source,
                                  filtered || !o.metric.empty() ? " (after --filter / --metric)" : ""));
  std::vector<double> gains;
  for (const auto& r : c.rows)
    if (r.a.timing && r.judged) gains.push_back(r.gain);
  c.geomean_gain = stats::geometric_mean(gains);
  machine_notes(c, c.notes);
  compare_goals(c);
  add_notes(c);
  return c;
}

std::string compare_summary_line(const Comparison& c) {
  std::string s = fmt::format("{} rows compared", c.rows.size());
  if (c.timings) {
    const double g = c.geomean_gain;
    s += fmt::format("; timings: B/A speed, geometric mean {} ({}); {} faster, {} slower beyond noise, {} within noise",
                     ratio_text(g), std::isfinite(g) ? fmt::format("B {:.1f} % {}", std::fabs(g - 1) * 100, g >= 1 ? "faster" : "slower") : "-",
                     c.faster, c.slower, c.timings - c.faster - c.slower);
  }
  if (c.figures)
    s += fmt::format("; seeded figures: {} better, {} worse, {} changed, {} equal", c.better, c.worse, c.changed,
                     c.figures - c.better - c.worse - c.changed);
  if (c.options.threshold >= 0) s += fmt::format("; {} regression(s) beyond {:.3g} %", c.regressions, 100 * c.options.threshold);
  if (!c.goals.empty())
    s += fmt::format("; goals: {} in both, {} flipped between met and not met, {} moved to or from undecided", c.goals.size(),
                     c.goal_flips, c.goal_moves);
  return s;
}

namespace {

struct Group {
  std::string section, metric, unit;
  int direction;
  bool timing;
  std::vector<const ComparedRow*> rows;
};
std::vector<Group> groups(const Comparison& c) {
  std::vector<Group> g;
  std::map<std::string, std::size_t> at;
  for (const auto& r : c.rows) {
    const std::string k = r.a.section + "\t" + r.a.metric;
    if (!at.count(k)) {
      at[k] = g.size();
      g.push_back({r.a.section, r.a.metric, r.a.unit, r.a.direction, r.a.timing, {}});
    }
    g[at[k]].rows.push_back(&r);
  }
  return g;
}
bool shown(const Comparison& c, const ComparedRow& r) { return c.options.all || r.a.timing || !r.verdict.empty(); }

}  // namespace

std::string compare_text(const Comparison& c) {
  std::string t = fmt::format("raybench compare: {} results\n", c.kind);
  t += wrap_words(fmt::format("A  {}  ({})", c.a.source, describe(c.a)), 80, "     ");
  t += wrap_words(fmt::format("B  {}  ({})", c.b.source, describe(c.b)), 80, "     ");
  // Within 80 columns: the name, then A, B (units in the two-line header), B/A, p and the verdict.
  constexpr std::size_t kName = 31;
  const char* const kRow = "{:<31} {:>9} {:>9} {:>6} {:>11} {}\n";
  for (const Group& g : groups(c)) {
    std::size_t hidden = 0;
    std::string body;
    for (const ComparedRow* r : g.rows) {
      if (!shown(c, *r)) {
        ++hidden;
        continue;
      }
      std::string name = r->a.name;
      if (display_width(name) > kName) {
        body += name + "\n";
        name.clear();
      }
      std::string verdict = r->verdict.empty() ? (r->a.timing ? "~" : "=") : r->verdict + (r->regression ? "!" : r->possible_regression ? "?" : "");
      if (!r->judged) verdict = "(" + verdict + ")";
      body += fmt::format(fmt::runtime(kRow), name, value_text(r->a.value * r->a.scale), value_text(r->b.value * r->b.scale),
                          ratio_text(r->ratio), interval_cell(r->interval), verdict);
    }
    t += fmt::format("\n{}: {} ({}, {}{})\n", g.section, g.metric, g.unit, direction_text(g.direction), g.timing ? "" : ", seeded");
    if (!body.empty()) {
      t += fmt::format(fmt::runtime(kRow), "", "A", "B", "", "", "");
      t += fmt::format(fmt::runtime(kRow), "row", g.unit.substr(0, 9), g.unit.substr(0, 9), "B/A", fmt::format("{:.0f} % CI", 100 * (1 - c.options.alpha)), "verdict");
      t += body;
    }
    if (hidden) t += fmt::format("({} unchanged figures not listed; --all lists them)\n", hidden);
  }
  for (const auto& g : c.goals)
    if (g.a != g.b)
      t += wrap_words(fmt::format("goal {}: {}: {} -> {}", g.flipped ? "FLIPPED" : "moved", g.goal, g.a, g.b), 80, "  ");
  t += "\n" + wrap_words("summary: " + compare_summary_line(c), 80, "  ");
  for (const auto& n : c.notes) t += wrap_words("note: " + n, 80, "  ");
  for (const auto& r : c.rows)
    if (r.regression)
      t += wrap_words(fmt::format("regression: {} {}: {} -> {} {} ({}; threshold {:.3g} %)", r.a.name, r.a.metric, value_text(r.a.value * r.a.scale),
                            value_text(r.b.value * r.b.scale), r.a.unit, r.verdict, 100 * c.options.threshold),
                80, "  ");
  t += wrap_words("CI: B/A's confidence interval over the repetitions (the ratio of medians; the Mann-Whitney test inverted on "
                  "logarithms); faster or slower when it excludes 1, ~ within noise, = equal; ! a regression beyond --threshold "
                  "(the whole interval), ? a possible one (its median only)");
  return t;
}

std::string compare_markdown(const Comparison& c) {
  std::string md = fmt::format("## raybench compare: {} results\n\n", c.kind);
  md += fmt::format("- A: `{}` ({})\n- B: `{}` ({})\n\n", c.a.source, describe(c.a), c.b.source, describe(c.b));
  md += "**Summary:** " + compare_summary_line(c) + ".\n\n";
  for (const auto& n : c.notes) md += "- " + n + "\n";
  if (!c.notes.empty()) md += "\n";
  for (const Group& g : groups(c)) {
    md += fmt::format("### {}: {} ({}, {})\n\n| row | A ({}) | B ({}) | B/A | interval | verdict |\n|---|---:|---:|---:|---:|---|\n", g.section, g.metric,
                      g.unit, direction_text(g.direction), g.unit, g.unit);
    std::size_t hidden = 0;
    for (const ComparedRow* r : g.rows) {
      if (!shown(c, *r)) {
        ++hidden;
        continue;
      }
      md += fmt::format("| {} | {} | {} | {} | {} | {} |\n", r->a.name, value_text(r->a.value * r->a.scale), value_text(r->b.value * r->b.scale),
                        ratio_text(r->ratio), interval_cell(r->interval),
                        r->regression ? "**" + r->verdict + " (regression)**" : r->judged ? r->verdict : "(" + r->verdict + ", not judged)");
    }
    if (hidden) md += fmt::format("\n{} unchanged figures not listed.\n", hidden);
    md += "\n";
  }
  if (!c.goals.empty()) {
    md += "### Goals\n\n| section | goal | A | B | |\n|---|---|---|---|---|\n";
    for (const auto& g : c.goals)
      md += fmt::format("| {} | {} | {} | {} | {} |\n", g.section, g.goal, g.a, g.b, g.flipped ? "**flipped**" : g.a != g.b ? "moved" : "");
    md += "\n";
  }
  return md;
}

json compare_json(const Comparison& c) {
  json j;
  j["kind"] = c.kind;
  j["a"] = {{"source", c.a.source}, {"machine", c.a.machine}, {"config", c.a.config}};
  j["b"] = {{"source", c.b.source}, {"machine", c.b.machine}, {"config", c.b.config}};
  j["options"] = {{"alpha", c.options.alpha}, {"noise", c.options.noise},
                  {"threshold", c.options.threshold >= 0 ? json(c.options.threshold) : json(nullptr)}, {"filter", c.options.filter},
                  {"metric", c.options.metric}};
  auto num = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  json rows = json::array();
  for (const auto& r : c.rows)
    rows.push_back({{"section", r.a.section}, {"name", r.a.name}, {"metric", r.a.metric}, {"unit", r.a.unit}, {"scale", r.a.scale},
                    {"direction", r.a.direction}, {"timing", r.a.timing}, {"a", num(r.a.value)}, {"b", num(r.b.value)},
                    {"a_samples", r.a.samples}, {"b_samples", r.b.samples}, {"ratio", num(r.ratio)}, {"gain", num(r.gain)},
                    {"interval", stats::interval_json(r.interval)}, {"verdict", r.verdict}, {"regression", r.regression}, {"judged", r.judged}});
  j["rows"] = rows;
  auto names = [](const std::vector<Figure>& f) {
    json a = json::array();
    for (const auto& x : f) a.push_back(x.section + "/" + x.name + " " + x.metric);
    return a;
  };
  json goals = json::array();
  for (const auto& g : c.goals) goals.push_back({{"section", g.section}, {"goal", g.goal}, {"a", g.a}, {"b", g.b}, {"flipped", g.flipped}});
  j["goals"] = goals;
  j["only_in_a"] = names(c.a.figures);
  j["only_in_b"] = names(c.b.figures);
  j["summary"] = {{"rows", c.rows.size()},       {"timings", c.timings},   {"geomean_speed_ratio", num(c.geomean_gain)},
                  {"faster", c.faster},           {"slower", c.slower},     {"seeded_figures", c.figures},
                  {"better", c.better},           {"worse", c.worse},       {"changed", c.changed},
                  {"regressions", c.regressions}, {"goal_flips", c.goal_flips}, {"goal_moves", c.goal_moves},
                  {"text", compare_summary_line(c)}};
  j["notes"] = c.notes;
  return j;
}

}  // namespace rb::app
