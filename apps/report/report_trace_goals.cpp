// Report section "Tracing": its goals, each judged from the section's rows by their 95 % intervals.
#include "apps/report/report_doc.hpp"
#include "apps/report/report_trace.hpp"
#include "apps/results/stats.hpp"
#include "core/median.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace rb::app {

using nlohmann::json;

std::string trace_goals(const TraceRows& x, json& goal_rows) {
  const json& rows = x.rows;
  const json& matrix_builds = x.builds;
  const json& scaling = x.scaling;
  const int reps = x.reps;
  std::string md;
  auto add = [&](const std::string& goal, const std::pair<double, std::string>& w, double target) {
    const bool have = std::isfinite(w.first);
    goal_rows.push_back({{"goal", goal},
                         {"measured", have ? fmt::format("lowest {:.2f}x ({})", w.first, w.second) : std::string("not measured")},
                         {"met", have ? int(w.first >= target) : doc::kGoalNotMeasured}});
  };
  // A goal on a ratio over rows, by each row's 95 % interval: met when every row's interval clears
  // the target, not met when one lies below it, undecided otherwise. `items`: (interval, where).
  // `control` (optional, per item): the same ratio of a yardstick measured in the same rounds; a
  // row below the target whose control also lies below it is undecided (the machine, not the
  // subject), and the text counts such rows.
  auto judge_items = [&](const std::string& goal, const std::vector<std::pair<stats::RatioInterval, std::string>>& items, double target,
                         std::string extra = "", const std::vector<stats::RatioInterval>& control = {}) {
    std::size_t n = 0, cleared = 0, below = 0, excused = 0;
    stats::RatioInterval low;
    std::string where;
    for (std::size_t i = 0; i < items.size(); ++i) {
      const auto& [r, w] = items[i];
      if (!r.valid()) continue;
      ++n;
      const stats::Verdict v = stats::verdict(r, target);
      const bool machine = v == stats::Verdict::not_met && i < control.size() && control[i].valid() &&
                           stats::verdict(control[i], target) == stats::Verdict::not_met;
      cleared += v == stats::Verdict::met;
      below += v == stats::Verdict::not_met && !machine;
      excused += machine;
      if (!std::isfinite(low.ratio) || r.ratio < low.ratio) low = r, where = w;
    }
    if (excused)
      extra += fmt::format("; {} row(s) below it undecided: the yardstick's control in the same rounds lay below it too", excused);
    const int met = doc::goal_over(n, cleared, below);
    goal_rows.push_back(
        {{"goal", goal},
         {"measured", n == 0 ? fmt::format("no interval ({} round(s) per row)", reps)
                             : fmt::format("lowest {} ({}{}); {} of {} rows clear {}x, {} below", stats::interval_text(low), where,
                                           extra, cleared, n, fmt::format(fmt::runtime(target * 10 == std::round(target * 10) ? "{:.1f}" : "{:.2f}"), target), below)},
         {"met", met},
         {"verdict", doc::goal_word(met)},
         {"lowest", stats::interval_json(low)}});
  };
  // raybench / Embree over the matrix's rows.
  auto judge = [&](const std::string& goal, auto pick, double target) {
    std::vector<std::pair<stats::RatioInterval, std::string>> items;
    for (const auto& j : rows)
      if (pick(j) && j.contains("vs_embree"))
        items.push_back({stats::interval_from_json(j["vs_embree"]),
                         fmt::format("{}, {}, packet {}, {} thread(s)", j["mesh"].get<std::string>(), j["ray_set"].get<std::string>(),
                                     j["packet"].get<int>(), j["threads"].get<int>())});
    judge_items(goal, items, target);
  };
  judge("single rays >= 1.0x Embree, every mesh, ray set and thread count", [](const json& j) { return j["packet"] == 1; }, 1.0);
  judge("8-ray packets >= 1.0x Embree's 8-wide call, every row", [](const json& j) { return j["packet"] == 8; }, 1.0);
  judge("8-ray packets >= 1.2x Embree on primary and shadow rays",
        [](const json& j) { return j["packet"] == 8 && (j["ray_set"] == "primary" || j["ray_set"] == "shadow"); }, 1.2);
  judge(fmt::format("{}-ray packets >= 1.5x Embree on primary rays", kLargePacket),
        [](const json& j) { return j["packet"] == kLargePacket && j["ray_set"] == "primary"; }, 1.5);
  auto coherent = [](const json& j) { return j["ray_set"] == "primary" || j["ray_set"] == "shadow"; };
  judge("16-ray packets >= 1.3x Embree's 16-ray call on primary and shadow rays",
        [&](const json& j) { return j["packet"] == 16 && coherent(j); }, 1.3);
  judge("16-ray packets >= 1.0x Embree on diffuse and random rays", [&](const json& j) { return j["packet"] == 16 && !coherent(j); }, 1.0);
  {
    // The 16-lane walk over the 8-lane one on the same rows, same rounds (rows where both ran).
    std::vector<std::pair<stats::RatioInterval, std::string>> items;
    for (const auto& j : rows)
      if (j.contains("lanes8"))
        items.push_back({stats::interval_from_json(j["lanes8"]["speedup_16_over_8"]),
                         fmt::format("{}, {}, packet {}, {} thread(s)", j["mesh"].get<std::string>(), j["ray_set"].get<std::string>(),
                                     j["packet"].get<int>(), j["threads"].get<int>())});
    const std::string goal =
        fmt::format("coherent packets of 16 and {} rays in 16 AVX-512 lanes >= 1.0x the same packets in 8 lanes, every row", kLargePacket);
    if (items.empty())
      goal_rows.push_back({{"goal", goal},
                           {"measured", "not measured: no row walked in 16 lanes (a CPU or build without AVX-512)"},
                           {"met", doc::kGoalNotMeasured}});
    else judge_items(goal, items, 1.0);
  }
  {
    std::vector<std::pair<stats::RatioInterval, std::string>> items;
    for (const auto& j : x.sorted)
      if (j.contains("vs_embree"))
        items.push_back({stats::interval_from_json(j["vs_embree"]), fmt::format("{}, {}, {} thread(s)", j["mesh"].get<std::string>(),
                                                                                 j["ray_set"].get<std::string>(), j["threads"].get<int>())});
    judge_items("sorted streams of diffuse and random rays (sort included) >= 1.25x Embree's best mode on the given order", items, 1.25);
  }
  double wm = std::numeric_limits<double>::infinity();
  std::string wmw;
  std::vector<std::pair<stats::RatioInterval, std::string>> build_items, scaling_items;
  for (const auto& b : matrix_builds) {
    for (int th : {1, 2}) {
      if (b[fmt::format("embree_build_ms_{}t", th)].is_null()) continue;
      // (One build each under --quick: no interval, the goal not measured.)
      build_items.push_back({stats::interval_from_json(b[fmt::format("embree_over_ours_{}t", th)]),
                             fmt::format("{}, {} thread(s)", b["mesh"].get<std::string>(), th)});
    }
    if (!b["embree_bytes_per_prim"].is_null()) {
      const double r = b["embree_bytes_per_prim"].get<double>() / b["bytes_per_prim"].get<double>();
      if (r < wm) wm = r, wmw = b["mesh"].get<std::string>();
    }
  }
  // The lowest row, with Embree's scaling on that row and both engines' medians over all rows.
  std::vector<double> ours_sc, embree_sc;
  std::vector<stats::RatioInterval> scaling_control;
  for (const auto& sc : scaling) {
    const bool paired = sc.contains("embree_interval") && !sc["embree_interval"].is_null();
    scaling_control.push_back(paired ? stats::interval_from_json(sc["embree_interval"]) : stats::RatioInterval{});
    scaling_items.push_back({stats::interval_from_json(sc["ours_interval"]),
                             fmt::format("{}, {}, packet {}; Embree {} on that row", sc["mesh"].get<std::string>(),
                                         sc["ray_set"].get<std::string>(), sc["packet"].get<int>(),
                                         paired ? stats::interval_text(scaling_control.back()) + " in the same rounds"
                                         : sc["embree"].is_null() ? std::string("-")
                                                                  : fmt::format("{:.2f}x", sc["embree"].get<double>()))});
    ours_sc.push_back(sc["ours"].get<double>());
    if (!sc["embree"].is_null()) embree_sc.push_back(sc["embree"].get<double>());
  }
  std::string all_rows;
  if (!ours_sc.empty())
    all_rows = fmt::format("; median of all rows {:.2f}x, Embree's {}", rb::median(ours_sc),
                           embree_sc.empty() ? std::string("-") : fmt::format("{:.2f}x", rb::median(embree_sc)));
  judge_items("build no slower than Embree's, one and two threads (Embree's time / ours, paired builds)", build_items, 1.0);
  add("bytes per triangle <= Embree's (Embree's / ours)", {wm, wmw}, 1.0);
  judge_items("two threads >= 1.8x one thread for tracing (paired rounds in the one-thread row)", scaling_items, 1.8, all_rows,
              scaling_control);
  double mm = 0;
  for (const auto& j : rows)
    if (!j["mismatch_rate"].is_null()) mm = std::max(mm, j["mismatch_rate"].get<double>());
  goal_rows.push_back({{"goal", "under 0.01 % of rays disagreeing with Embree, every row"},
                       {"measured", fmt::format("highest {:.4f} %", 100 * mm)},
                       {"met", int(mm < 1e-4)}});
  md += "Goals of this section, each with its worst row; a goal on a ratio is met when every row's 95 % interval clears the target, "
        "not met when one lies below it, undecided otherwise (memory and disagreement are counts, judged as they are):\n\n"
        "| goal | measured | met |\n|---|---|---|\n";
  for (const auto& g : goal_rows)
    md += fmt::format("| {} | {} | {} |\n", g["goal"].get<std::string>(), g["measured"].get<std::string>(),
                      doc::goal_cell(g["met"].get<int>()));
  md += "\n";
  return md;
}

}  // namespace rb::app
