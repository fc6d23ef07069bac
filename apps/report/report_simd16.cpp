// The report's "Scalar against SIMD" section, 16 AVX-512 lanes against 8 AVX2 lanes: per method and
// case the 16-lane rate over the 8-lane rate with its interval, the operations per lane at both
// widths and the reason where 16 lanes give less than 1.6x; the best basic methods at 16 lanes
// against the true scalar form.
#include "apps/report/report.hpp"
#include "apps/report/report_doc.hpp"
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

namespace rb::app::simd_report {
using nlohmann::json;

namespace {

// A median counter of one benchmark row; NaN where the row or the counter is missing.
double row_counter(const std::map<std::string, json>& counters, const std::string& name, const char* key) {
  const auto it = counters.find(name);
  return it != counters.end() && it->second.contains(key) && it->second[key].is_number() ? it->second[key].get<double>()
                                                                                          : stats::kNaN;
}

// Nanoseconds per instruction of one kind at 8 or 16 lanes, from the run's instruction rows.
double instruction_ns(const std::map<std::string, json>& counters, const char* kind, int lanes) {
  return 1e9 / row_counter(counters, fmt::format("instruction/{}{}/reg", kind, lanes), "instructions_per_s");
}

// What a method's divisions and square roots allow at 16 lanes. On a CPU whose divider is half as
// wide as an AVX-512 register, a 16-lane division costs two 8-lane ones: the instruction rows
// (instruction/div8/reg ... sqrt16/reg, bench/bench_instructions.cpp) measure it in the same run.
// From the 8-lane row's time per test t8 and the 16-lane row's divisions d and square roots s per
// test per lane: the divider's time per test at w lanes is D(w) = (d * div_w + s * sqrt_w) / w;
// `estimate` prices t8's divider share at the 16-lane rate and halves the rest,
// t8 / ((t8 - D(8)) / 2 + D(16)) (no overlap of the divider with the rest); `cap` is what the
// divider alone allows, t8 / D(16) (full overlap). NaN without divisions, square roots or rates.
DividerModel divider_model(const std::map<std::string, json>& counters, const std::string& row16, const std::string& row8) {
  DividerModel m;
  m.div = row_counter(counters, row16, "div_per_test");
  m.sqrt = row_counter(counters, row16, "sqrt_per_test");
  m.instructions = row_counter(counters, row16, "instructions_per_test");
  const double t8 = 1e9 / row_counter(counters, row8, "tests_per_s");  // ns per test
  if (!(m.div + m.sqrt > 0) || !std::isfinite(t8)) return m;
  auto divider = [&](int w) {
    return (m.div * instruction_ns(counters, "div", w) + m.sqrt * instruction_ns(counters, "sqrt", w)) / w;
  };
  const double d8 = divider(8), d16 = divider(16);
  m.estimate = t8 / (std::max(0.0, t8 - d8) / 2 + d16);
  m.cap = t8 / d16;
  return m;
}

// The per-instruction rates as a sentence, and their 16-lane over 8-lane cost.
std::string instruction_rates_text(const std::map<std::string, json>& counters, json& summary) {
  std::string t;
  json out = json::object();
  for (const char* k : {"fma", "div", "sqrt"}) {
    const double n8 = instruction_ns(counters, k, 8), n16 = instruction_ns(counters, k, 16);
    if (!std::isfinite(n8) || !std::isfinite(n16)) return "";
    t += fmt::format("{}{} {:.2f} ns at 8 lanes, {:.2f} ns at 16 ({:.2f}x)", t.empty() ? "" : "; ", k, n8, n16, n16 / n8);
    out[k] = {{"ns_8", n8}, {"ns_16", n16}};
  }
  summary["simd16_instruction_ns"] = out;
  return t;
}

// The best triangle, sphere and box method at 16 lanes against the true scalar form: per method the
// better 16-lane mapping in its worst case, the best method of each kernel judged against 10x.
std::string sixteen_over_scalar(const json& bench, json& summary, std::vector<doc::Goal>& goals) {
  const auto speedup = simd_speedups(bench);
  std::string md =
      "The best method of each basic kernel in 16 lanes against its true-scalar form (the better 16-lane mapping, the lowest "
      "of its cases; the median of the rounds' ratios with its 95 % interval): 16 lanes should reach 10x where 8 reach 6x.\n\n"
      "| kernel | best method at 16 lanes | its lowest case over scalar | >= 10x |\n|---|---|---:|---|\n";
  json out = json::object();
  for (const std::string kernel : {"triangle", "sphere", "box"}) {
    // method -> case -> the better 16-lane mapping's speedup over scalar
    std::map<std::string, std::map<std::string, stats::RatioInterval>> by;
    for (const auto& [name, r] : speedup) {
      const auto p = bench::BenchName::parse(name);
      if (!p || p->kernel != kernel || !std::isfinite(r.ratio)) continue;
      if (p->variant != "rays_in_lanes16" && p->variant != "prims_in_lanes16") continue;
      auto& slot = by[p->method][p->kase];
      if (!std::isfinite(slot.ratio) || r.ratio > slot.ratio) slot = r;
    }
    std::string best;
    stats::RatioInterval best_low;
    for (const auto& [method, cases] : by) {
      stats::RatioInterval low;
      for (const auto& [c, r] : cases)
        if (!std::isfinite(low.ratio) || r.ratio < low.ratio) low = r;
      if (best.empty() || low.ratio > best_low.ratio) best = method, best_low = low;
    }
    if (best.empty()) continue;
    const int verdict = all_clear({best_low}, 10);
    md += fmt::format("| {} | {} | {} | {} |\n", kernel, best, stats::interval_text(best_low), doc::goal_cell(verdict));
    out[kernel] = {{"method", best}, {"lowest", stats::interval_json(best_low)}, {"verdict", doc::goal_word(verdict)}};
    goals.push_back({"Scalar against SIMD", fmt::format("best {} method in 16 AVX-512 lanes >= 10x true scalar, every case", kernel),
                     fmt::format("{} {} (its lowest case)", best, stats::interval_text(best_low)), verdict, "simd_speedup.png"});
  }
  if (out.empty()) return "";
  summary["simd16_vs_scalar_best"] = out;
  return md + "\n";
}

}  // namespace

// Per method: each case's better 16-lane mapping over its 8-lane form, the verdict against 1.6x in
// every case and the reason where it falls short: stated (a loop to the slowest lane), measured (its
// lowest case runs more operations per lane at 16 lanes than at 8: an early exit that needs every
// lane comes later) or the divider model's. Empty when the run has no 16-lane rows.
std::vector<Simd16Method> simd16_methods(const json& bench) {
  const auto ratios = simd16_speedups(bench);
  // kernel/method -> case -> the better mapping's interval, and that row's name
  std::map<std::string, std::map<std::string, stats::RatioInterval>> best;
  std::map<std::string, std::map<std::string, std::string>> row_of;
  for (const auto& [name, r] : ratios) {
    const auto p = bench::BenchName::parse(name);
    if (!p || !std::isfinite(r.ratio)) continue;
    auto& slot = best[p->kernel_method()][p->kase];
    if (!std::isfinite(slot.ratio) || r.ratio > slot.ratio) slot = r, row_of[p->kernel_method()][p->kase] = name;
  }
  const auto counters = medians(bench);
  auto eight_lane_name = [](const std::string& name16) {
    auto p = bench::BenchName::parse(name16);
    if (!p || p->variant.size() < 2) return std::string();
    p->variant.resize(p->variant.size() - 2);  // "rays_in_lanes16" -> "rays_in_lanes"
    return p->str();
  };
  std::vector<Simd16Method> out;
  for (const auto& [km, cases] : best) {
    Simd16Method m;
    m.km = km;
    m.cases = cases;
    std::vector<stats::RatioInterval> iv;
    for (const auto& [c, r] : cases) {
      iv.push_back(r);
      if (m.low_case.empty() || r.ratio < cases.at(m.low_case).ratio) m.low_case = c;
    }
    m.verdict = all_clear(iv, 1.6);
    const std::string low16 = row_of[km][m.low_case];  // kernel/method/mapping16/case
    const auto low_parts = bench::BenchName::parse(low16);
    m.mapping = low_parts ? low_parts->variant : "";
    // Operations per test per lane of the lowest case at both widths: more at 16 lanes where an
    // early exit or a loop waits for every lane of the packet.
    m.ops16 = row_counter(counters, low16, "ops_per_test");
    m.ops8 = row_counter(counters, eight_lane_name(low16), "ops_per_test");
    m.model = divider_model(counters, low16, eight_lane_name(low16));
    // The model holds a measurement within 0.05 of its range; above its cap, fewer divisions ran than
    // were counted (the compiler moved some out of the loop) or the divider overlaps more than the
    // chains show; below its lower figure, something besides the divider costs too.
    const double low_ratio = cases.at(m.low_case).ratio;
    m.model_fits = m.model.valid() && low_ratio >= m.model.estimate - 0.05 && low_ratio <= m.model.cap + 0.05;
    const bool more_ops = m.ops16 > 1.05 * m.ops8;
    const std::string measured_why =
        more_ops ? fmt::format("{:.0f} operations per test per lane at 16 lanes against {:.0f} at 8 ({}, {}): lanes wait for each other", m.ops16,
                               m.ops8, m.low_case, m.mapping)
                 : "";
    const auto it = structural_reasons().find(km);
    const DividerModel& dm = m.model;
    if (m.verdict == doc::kGoalMet) m.why = Simd16Method::Why::met;
    else if (m.verdict == doc::kGoalUndecided) m.why = Simd16Method::Why::undecided, m.reason = "undecided: an interval straddles 1.6x";
    else if (it != structural_reasons().end())
      m.why = Simd16Method::Why::explained, m.reason = it->second + (more_ops ? "; measured: " + measured_why : "");
    else if (more_ops) m.why = Simd16Method::Why::explained, m.reason = "early exits need every lane: " + measured_why;
    else if (m.model_fits && dm.estimate < 1.6)
      m.why = Simd16Method::Why::explained,
      m.reason = fmt::format("divisions and square roots ({:.0f} div and {:.0f} sqrt of {:.0f} instructions per test per lane) cost as much "
                             "per lane at 16 lanes as at 8: the model gives {:.2f}x to {:.2f}x, measured {:.2f}x",
                             dm.div, dm.sqrt, dm.instructions, dm.estimate, dm.cap, low_ratio);
    else if (dm.valid())
      m.why = Simd16Method::Why::unexplained,
      m.reason = fmt::format("**unexplained**: measured {:.2f}x, outside the divider model's {:.2f}x to {:.2f}x{}", low_ratio, dm.estimate, dm.cap,
                             low_ratio > dm.cap ? " (above its cap: fewer divisions ran than were counted)" : "");
    else m.why = Simd16Method::Why::unexplained, m.reason = "**unexplained**";
    out.push_back(std::move(m));
  }
  return out;
}

// 16 AVX-512 lanes against 8 AVX2 lanes, per method and case: the better mapping's ratio of the
// rounds (16-lane rate over the 8-lane rate of the same mapping) with its interval; the goal on the
// median method (each method's figure: the median of its cases). Empty when the run has no
// 16-lane rows (--isa avx2, or a CPU or build without AVX-512).
std::string simd16_section(const json& bench, json& summary, std::vector<doc::Goal>& goals) {
  const auto methods = simd16_methods(bench);
  if (methods.empty()) return "";
  const auto counters = medians(bench);
  std::string md =
      "| kernel/method | hit | miss | half | ops/test per lane, 8 -> 16 lanes (lowest case) | divider model | >= 1.6x | why not |\n"
      "|---|---:|---:|---:|---:|---:|---|---|\n";
  std::vector<std::pair<double, std::string>> figure;  // a method's median case, and the method
  std::map<std::string, int> verdict_of;  // kernel/method -> its verdict against 1.6x in every case
  json out = json::array();
  int met = 0, undecided = 0, explained = 0, unexplained = 0, modelled = 0, within = 0;
  for (const Simd16Method& m : methods) {
    auto cell = [&](const char* c) { return m.cases.count(c) ? stats::interval_text(m.cases.at(c)) : std::string("-"); };
    std::vector<double> v;
    json row = {{"kernel_method", m.km}};
    for (const auto& [c, r] : m.cases) v.push_back(r.ratio), row[c] = stats::interval_json(r);
    verdict_of[m.km] = m.verdict;
    met += m.why == Simd16Method::Why::met;
    undecided += m.why == Simd16Method::Why::undecided;
    explained += m.why == Simd16Method::Why::explained;
    unexplained += m.why == Simd16Method::Why::unexplained;
    modelled += m.model.valid();
    within += m.model_fits;
    const DividerModel& dm = m.model;
    if (std::isfinite(m.ops16)) row["lowest_case"] = {{"case", m.low_case}, {"ops_per_test_16", m.ops16}, {"ops_per_test_8", m.ops8}};
    if (dm.valid()) row["divider_model"] = {{"estimate", dm.estimate}, {"cap", dm.cap}, {"div_per_test", dm.div}, {"sqrt_per_test", dm.sqrt}};
    const std::string ops_cell =
        std::isfinite(m.ops16) && std::isfinite(m.ops8) ? fmt::format("{:.0f} -> {:.0f} ({})", m.ops8, m.ops16, m.low_case) : "-";
    const std::string model_cell = dm.valid() ? fmt::format("{:.2f} - {:.2f}", dm.estimate, dm.cap) : "-";
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", m.km, cell("hit"), cell("miss"), cell("half"), ops_cell, model_cell,
                      doc::goal_cell(m.verdict), m.reason);
    row["verdict"] = doc::goal_word(m.verdict);
    row["reason"] = m.reason;
    figure.push_back({stats::median(v), m.km});
    out.push_back(row);
  }
  md += fmt::format("\n{} of {} methods reach 1.6x in every case; {} undecided; {} fall short for the structural reason given; {} "
                    "unexplained.\n",
                    met, methods.size(), undecided, explained, unexplained);
  const std::string rates = instruction_rates_text(counters, summary);
  if (modelled > 0)
    md += fmt::format("The divider model's range holds the measured lowest case (within 0.05) on {} of the {} methods with divisions "
                      "or square roots.\n", within, modelled);
  std::sort(figure.begin(), figure.end());
  const auto& [med, med_km] = figure[figure.size() / 2];
  // The median method's verdict: its cases' intervals against 1.6 (every case clears it: met).
  const int verdict = verdict_of[med_km];
  summary["simd16_vs_simd8"] = {{"rows", out},
                                {"median_method", med_km},
                                {"median", med},
                                {"verdict", doc::goal_word(verdict)},
                                {"counts", {{"methods", methods.size()}, {"met", met}, {"undecided", undecided}, {"explained", explained},
                                            {"unexplained", unexplained}}},
                                {"divider_model", {{"methods", modelled}, {"within_range", within}}}};
  const std::string measured = fmt::format("median method {} ({:.2f}x over its cases; lowest of {} methods {:.2f}x ({}), highest {:.2f}x ({}))",
                                           med_km, med, figure.size(), figure.front().first, figure.front().second, figure.back().first,
                                           figure.back().second);
  goals.push_back({"Scalar against SIMD", "16 AVX-512 lanes >= 1.6x 8 AVX2 lanes on the median method", measured, verdict, "simd_speedup.png"});
  const std::string vs_scalar = sixteen_over_scalar(bench, summary, goals);
  return "### AVX-512 against AVX2: 16 lanes against 8\n\n"
         "The same kernels and data in 16 float lanes (xsimd's `avx512dq` batch: 16 rays x 1 primitive, or 1 ray x 16 primitives), "
         "compiled in translation units of their own and chosen at run time (`raybench bench --isa`). Per method and case: "
         "the better mapping's 16-lane rate over its 8-lane rate, the median of the rounds' ratios with its 95 % interval "
         "(`raybench bench --json`: raybench_simd16_vs_simd8). The polygon's primitives-in-lanes form has no 16-lane row: its "
         "vertices are interleaved per group of 8. Operations per test per lane, counted with `Counted<f8>` and `Counted<f16>` "
         "on the rows' own data, in the method's lowest case: equal where every lane does the same work; more at 16 lanes where "
         "an early exit needs every lane of the packet or a loop runs until the packet's slowest lane is done, which is then "
         "the reason a method stays below 1.6x. The divider model: a division or square root costs the same per lane at 16 lanes "
         "as at 8 where the CPU's divider is half as wide as an AVX-512 register; the instruction rows of this run (eight "
         "independent chains in registers, `raybench bench --filter instruction`) measure it: " +
         (rates.empty() ? std::string("not measured in this run") : rates) +
         ". From the 8-lane row's time per test and the 16-lane row's divisions and square roots per test per lane (counted), "
         "the model's lower figure prices the 8-lane time's divider share at the 16-lane rate and halves the rest (no overlap); "
         "its upper figure is what the divider alone allows (full overlap). A method below 1.6x whose lowest case lies in that "
         "range (within 0.05) and whose lower figure is below 1.6x falls short for this reason; one outside it is unexplained "
         "(above the cap: fewer divisions ran than `Counted` counted, e.g. those of the primitive that the compiler moves out "
         "of the loop over rays).\n\n" +
         md + fmt::format("\nGoal: 16 lanes at least 1.6x 8 lanes on the median method: {}; {}.\n\n", measured, doc::goal_word(verdict)) +
         vs_scalar;
}

}  // namespace rb::app::simd_report
