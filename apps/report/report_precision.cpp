// Report section "How precise the ratios are": every family of ratios the report gives with a 95 %
// interval, the half-widths of its rows (median, largest with its row, how many over 5 %), and the
// goal that trace and kernel rows stay within 5 %. It reads only the summary the other sections
// wrote, so a replay (`report --from`) shows the same.
#include "apps/report/report_doc.hpp"
#include "apps/report/report_sections.hpp"
#include "apps/results/stats.hpp"
#include "core/median.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace rb::app {

using nlohmann::json;

namespace {

constexpr double kTarget = 0.05;  // the half-width trace and kernel rows are held to

// One family of ratios: where its rows lie in the summary and how a row is named.
struct Family {
  const char* name;
  const char* kind;  // "trace", "kernel" or "other" (shown, not held to the target)
  std::function<void(const json& summary, std::vector<std::pair<const json*, std::string>>& rows)> rows;
};

std::string str(const json& j, const char* k) {
  if (!j.contains(k)) return "?";
  return j[k].is_string() ? j[k].get<std::string>() : j[k].dump();
}
// j[k0][k1]..., or nullptr where a key is missing.
const json* at_keys(const json& j, const std::vector<const char*>& keys) {
  const json* v = &j;
  for (const char* k : keys) {
    if (!v->is_object() || !v->contains(k)) return nullptr;
    v = &(*v)[k];
  }
  return v;
}
// Rows of the array at `array`, whose interval sits at `sub` inside each element.
auto each(std::vector<const char*> array, std::vector<const char*> sub, std::function<std::string(const json&)> label) {
  return [array, sub, label](const json& s, std::vector<std::pair<const json*, std::string>>& out) {
    const json* a = at_keys(s, array);
    if (!a || !a->is_array()) return;
    for (const json& e : *a)
      if (const json* v = at_keys(e, sub)) out.push_back({v, label(e)});
  };
}

std::vector<Family> families() {
  // A trace row: its mesh (or scene, and the tree's builder where it is not raybench's own), rays,
  // packet and threads.
  auto trace_row = [](const json& e) {
    std::string what = str(e, e.contains("mesh") ? "mesh" : "scene");
    if (e.contains("builder") && e["builder"] != "sah") what += " (" + str(e, "builder") + " tree)";
    return fmt::format("{}, {}, packet {}, {} thread(s)", what, str(e, "ray_set"), str(e, "packet"), str(e, "threads"));
  };
  auto kernel_row = [](const json& e) { return fmt::format("{}/{}/{}", str(e, "kernel"), str(e, "method"), str(e, "case")); };
  std::vector<Family> f;
  f.push_back({"SIMD (rays in lanes) over true scalar, per kernel, method and case", "kernel",
               each({"simd_vs_scalar"}, {"speedup_rays_in_lanes_interval"}, kernel_row)});
  f.push_back({"SIMD (primitives in lanes) over true scalar", "kernel", each({"simd_vs_scalar"}, {"speedup_prims_in_lanes_interval"}, kernel_row)});
  for (const auto& [c, name] : {std::pair{"hit", "16 AVX-512 lanes over 8 AVX2 lanes, per method, all-hit case"},
                                std::pair{"miss", "16 over 8 lanes, all-miss case"}, std::pair{"half", "16 over 8 lanes, half-hit case"}})
    f.push_back({name, "kernel", each({"simd16_vs_simd8", "rows"}, {c}, [](const json& e) { return str(e, "kernel_method"); })});
  f.push_back({"kernel rates (tests per second) of the rate goals", "kernel", [](const json& s, auto& out) {
                 if (const json* r = at_keys(s, {"rate_goals"}); r && r->is_object())
                   for (auto it = r->begin(); it != r->end(); ++it) out.push_back({&it.value(), it.key()});
               }});
  f.push_back({"raybench / Embree's best mode, trace matrix", "trace", each({"tracing", "matrix"}, {"vs_embree"}, trace_row)});
  f.push_back({"two threads over one, trace matrix (paired in the one-thread row)", "trace",
               each({"tracing", "matrix"}, {"threads_beside", "speedup"}, trace_row)});
  f.push_back({"16 lanes over 8, coherent packets of the trace matrix", "trace", each({"tracing", "matrix"}, {"lanes8", "speedup_16_over_8"}, trace_row)});
  f.push_back({"sorted stream / Embree on the given order", "trace", each({"tracing", "sorted"}, {"vs_embree"}, trace_row)});
  f.push_back({"sorted stream / Embree on the sorted order", "trace", each({"tracing", "sorted"}, {"embree_sorted", "vs_embree_sorted"}, trace_row)});
  f.push_back({"Embree's tree through raybench's traversal / Embree", "trace", each({"tracing", "tree_vs_kernel"}, {"vs_embree"}, trace_row)});
  for (const auto& [key, name] : {std::pair{"embree_over_ours_1t", "Embree's build time / raybench's, one thread"},
                                  std::pair{"embree_over_ours_2t", "Embree's build time / raybench's, two threads"}})
    f.push_back({name, "trace", each({"tracing", "builds"}, {key}, [](const json& e) { return str(e, "mesh"); })});
  f.push_back({"PGO build / normal build, per kernel family (./run.sh pgo)", "kernel",
               each({"pgo", "families"}, {"pgo"}, [](const json& e) { return str(e, "kernel"); })});
  f.push_back({"PGO build / normal build, per trace row (./run.sh pgo)", "trace", each({"pgo", "traces"}, {"pgo"}, [](const json& e) {
                 return fmt::format("{}, {}, packet {}, 1 thread", str(e, "scene"), str(e, "ray_set"), str(e, "packet"));
               })});
  f.push_back({"render / its own rays traced alone", "other", each({"render"}, {"alone", "render_over_alone"}, [](const json& e) { return str(e, "scene"); })});
  f.push_back({"render / the scene's primary rays", "other",
               each({"render"}, {"primary", "render_over_primary"}, [](const json& e) { return str(e, "scene"); })});
  f.push_back({"auto model / fast model, per scene", "other", each({"plan", "scenes"}, {"auto_vs_fast"}, [](const json& e) { return str(e, "scene"); })});
  return f;
}

}  // namespace

std::string report_section_precision(json& summary, std::vector<doc::Goal>& goals) {
  std::string md = "## How precise the ratios are\n\n";
  md += fmt::format(
      "Every ratio above with a 95 % interval, by what it compares: the rows, the median half-width of their intervals ((hi - lo) "
      "/ 2, relative to the ratio), the largest with its row, and the rows over {:.0f} %. An interval is the sign test's over "
      "the paired rounds of one run (docs/DESIGN.md, the measurement protocol): it says how well this run pins its ratio down, "
      "not how far another run may land. Trace and kernel rows are held to {:.0f} %.\n\n"
      "| ratio | kind | rows | median half-width | largest (row) | over {:.0f} % |\n|---|---|---:|---:|---|---:|\n",
      100 * kTarget, 100 * kTarget, 100 * kTarget);
  json out = json::array();
  std::size_t held = 0, over = 0;
  std::string worst_row;
  double worst = 0;
  for (const Family& f : families()) {
    std::vector<std::pair<const json*, std::string>> rows;
    f.rows(summary, rows);
    std::vector<double> hw;
    double big = -1;
    std::string big_row;
    std::size_t n_over = 0;
    for (const auto& [j, label] : rows) {
      const stats::RatioInterval r = stats::interval_from_json(*j);
      const double h = stats::half_width(r);
      if (!std::isfinite(h)) continue;  // no interval, or no positive ratio
      hw.push_back(h);
      n_over += stats::too_wide(r, kTarget);
      if (h > big) big = h, big_row = label;
    }
    if (hw.empty()) continue;
    const bool target = std::string(f.kind) != "other";
    if (target) {
      held += hw.size(), over += n_over;
      if (big > worst) worst = big, worst_row = std::string(f.name) + ": " + big_row;
    }
    md += fmt::format("| {} | {} | {} | {:.1f} % | {:.1f} % ({}) | {} |\n", f.name, f.kind, hw.size(), 100 * rb::median(hw), 100 * big, big_row,
                      n_over);
    out.push_back({{"ratio", f.name}, {"kind", f.kind}, {"rows", hw.size()}, {"median_half_width", rb::median(hw)},
                   {"largest_half_width", big}, {"largest_row", big_row}, {"over_target", n_over}});
  }
  md += "\n";
  summary["precision"] = {{"target_half_width", kTarget}, {"families", out}};
  const std::string goal = fmt::format("every trace and kernel ratio's 95 % interval within +-{:.0f} % (half-width)", 100 * kTarget);
  if (held == 0)
    goals.push_back({"How precise the ratios are", goal, "no row with an interval (fewer than 2 rounds)", doc::kGoalNotMeasured, ""});
  else
    goals.push_back({"How precise the ratios are", goal,
                     fmt::format("{} of {} rows over; largest {:.1f} % ({})", over, held, 100 * worst, worst_row),
                     over == 0 ? doc::kGoalMet : doc::kGoalNotMet, ""});
  return md;
}

}  // namespace rb::app
