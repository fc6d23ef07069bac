// Report section "What each scene needs": per embedded scene and per precision scene, the plan of
// the auto model (frame, each kind's method and precision), its speed against the fast and exact
// models and the failures of all three against the exact reference (the accuracy lab's whole-scene
// runner), a chart of speed against failures per model, and a far and scaled copy of a scene
// rendered beside the original.
#include "core/output_file.hpp"
#include "accuracy/lab.hpp"
#include "apps/paths.hpp"
#include "apps/report/report.hpp"
#include "apps/report/report_record.hpp"
#include "apps/report/report_doc.hpp"
#include "apps/report/report_sections.hpp"
#include "apps/results/stats.hpp"
#include "render/render.hpp"
#include "scene/sources.hpp"
#include "scene/scene_transform.hpp"
#include "tracer/accel.hpp"
#include "tracer/plan.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

namespace rb::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string plan_ppm(double x) { return x == 0 ? "0" : x >= 100 ? fmt::format("{:.0f}", x) : fmt::format("{:.2g}", x); }

// "sphere hearn_baker, polygon crossing (float); triangle woop (double, stored in double)".
std::string plan_kinds_text(const tracer::Plan& p) {
  std::string o;
  for (int k = 0; k < kinds::kKinds; ++k) {
    const tracer::KindPlan& kp = p.kinds[std::size_t(k)];
    if (!kp.count) continue;
    std::string m;
    kinds::AllKinds::each([&]<class K>() {
      if (int(K::id) == k) m = K::methods[std::size_t(kp.method)].name;
    });
    o += fmt::format("{}{} {}{}", o.empty() ? "" : "; ", kinds::kind_name(kinds::Kind(k)), m,
                     kp.f64_storage ? " (double, stored in double)" : kp.f64 ? " (double)" : "");
    // The primitives' classes where they are not all alike (tracer/profile.hpp).
    const tracer::KindClasses& c = kp.classes;
    std::vector<std::string> parts;
    if (c.as_input && c.as_input < kp.count) parts.push_back(fmt::format("{} as input", c.as_input));
    if (c.coarse)
      parts.push_back(fmt::format("{} coarse{}", c.coarse, c.negligible ? ", negligible" : !kp.split.empty() ? (kp.split_local ? ", stored apart in local frames" : ", stored apart in double") : ""));
    if (c.degenerate) parts.push_back(fmt::format("{} degenerate", c.degenerate));
    for (std::size_t i = 0; i < parts.size(); ++i) o += (i ? ", " : " [") + parts[i] + (i + 1 == parts.size() ? "]" : "");
  }
  return o;
}

// The goal of auto against fast on a mesh where fast fails no ray: auto keeps at least 0.97 of its
// speed and at most 1.05 of its memory.
constexpr double kAutoSpeedGoal = 0.97, kAutoMemoryGoal = 1.05;

// The goal's verdicts on the meshes, with the scenes of each verdict but "met".
std::string plan_goal_text(std::map<int, std::vector<std::string>>& by_verdict) {
  std::string md;
  md += fmt::format("\n**Goal: on every mesh where fast fails no ray, auto keeps at least {:.2f}x its speed and at most {:.2f}x its "
                    "memory** (the speed's interval clears it: met; lies below it, or more memory: not met; straddles it: undecided): ",
                    kAutoSpeedGoal, kAutoMemoryGoal);
  for (int v : {doc::kGoalMet, doc::kGoalUndecided, doc::kGoalNotMet, doc::kGoalNotMeasured}) {
    if (by_verdict[v].empty()) continue;
    md += fmt::format("{} on {} mesh(es)", doc::goal_word(v), by_verdict[v].size());
    if (v != doc::kGoalMet) {
      md += " (";
      for (std::size_t i = 0; i < by_verdict[v].size(); ++i) md += (i ? "; " : "") + by_verdict[v][i];
      md += ")";
    }
    md += "; ";
  }
  md += "auto's cost where fast fails nothing is the price of its checks and choices, and where fast does fail, the price of the "
        "right answer. On scenes of a few analytic primitives auto / fast is shown, not judged: there auto runs the methods that "
        "the lab finds right at the scene's distances (a robust torus, a re-centred cylinder), which is its answer, not a cost of "
        "looking.\n";
  return md;
}

// The plan's spawn scheme (a fixed rule) against this run's lab, from the accuracy section's
// evidence in `summary`; `spawn_check` gets the verdict.
std::string plan_spawn_check(const json& summary, json& spawn_check) {
  std::string md;
  // The error-bound offset is chosen for being free of self-hits while sized to each hit's own
  // error; say so when the lab finds self-hits.
  if (summary.contains("accuracy") && summary["accuracy"].contains("spawn") && summary["accuracy"]["spawn"].contains("integer_over_bound_ns")) {
    const json& sp = summary["accuracy"]["spawn"];
    const json& q = sp["integer_over_bound_ns"];
    const bool holds = sp["bound_self_hit_ppm_max"].get<double>() == 0;
    md += fmt::format(
        "\nThe spawn offset against this run's lab (section Accuracy and stability, secondary rays, {} kernels): the error-bound "
        "offset the plan uses has at most {} self-hits per million (the integer offset {}). In the lab, where the error bound "
        "recomputes each hit point in a form with a known bound, the integer offset takes {:.2f}x its time (median; {:.2f}x..{:.2f}x "
        "over the kernels); the tracer starts every hit point from its surface in double, so there both cost the same, and the "
        "integer offset's 256 float steps would lift a shadow ray past objects small against the coordinates where they lie "
        "(`precision:cluster_ground`): {}.\n",
        sp["kernels"].get<std::size_t>(), plan_ppm(sp["bound_self_hit_ppm_max"].get<double>()),
        plan_ppm(sp["integer_self_hit_ppm_max"].get<double>()), q["median"].get<double>(), q["lowest"].get<double>(),
        q["highest"].get<double>(),
        holds ? "the plan's choice is the lab's" : "**on this machine the lab does not support the plan's choice** (self-hits)");
    spawn_check = {{"evidence", sp}, {"plan_choice_holds", holds}};
  }
  return md;
}

// The plan's storage of coarse primitives (local frames or double, whichever the kind's measured
// costs make cheaper: kinds::StorageCost) against this run's lab, from the accuracy section's
// evidence in `summary`; `storage_check` gets the figures and verdicts.
std::string plan_storage_check(const json& summary, json& storage_check) {
  if (!summary.contains("accuracy") || !summary["accuracy"].contains("storage") || summary["accuracy"]["storage"].empty()) return "";
  const json& ev = summary["accuracy"]["storage"];
  std::string md =
      "\nWhere a kind's coarse primitives go apart, the plan stores them in float in local frames or in double, whichever costs "
      "less, from figures the lab measured once (`raybench accuracy --filter storage/KIND`: primary rays in 8-ray packets with "
      "every primitive of the kind stored each way, in rounds in which the three take turns) and kept with the kind; frames that "
      "represent a scene equally are ranked by what they leave apart at the same costs. The same cases in this run, each ratio "
      "the median of the rounds' own with its 95 % interval:\n\n"
      "| kind | case | local frames / in the frame | double / in the frame | local frames / double | the plan's figures "
      "(local frames, double) | the plan stores apart in | this run's lab says |\n|---|---|---:|---:|---:|---|---|---|\n";
  storage_check = json::array();
  bool all_hold = true;
  for (int k = 0; k < kinds::kKinds; ++k) {
    const kinds::StorageCost& c = tracer::storage_costs()[std::size_t(k)];
    const std::string evidence = c.evidence, cs = evidence.substr(evidence.find('/') + 1);
    if (evidence.empty() || !ev.contains(cs)) continue;
    const auto lf = stats::interval_from_json(ev[cs]["local_over_frame"]), df = stats::interval_from_json(ev[cs]["double_over_frame"]),
               ld = stats::interval_from_json(ev[cs]["local_over_double"]);
    const bool plan_local = c.local <= c.f64;
    // Local frames / double judged against 1: below it, local frames are cheaper here; above, double;
    // straddling it (or unmeasured), either.
    const stats::Verdict v = stats::verdict(ld, 1.0);
    const std::string here = v == stats::Verdict::not_met ? "local frames"
                             : v == stats::Verdict::met   ? "double"
                                                          : "either (the interval holds 1)";
    const bool holds = v == stats::Verdict::not_met ? plan_local : v == stats::Verdict::met ? !plan_local : true;
    all_hold = all_hold && holds;
    md += fmt::format("| {} | `{}` | {} | {} | {} | {:.2f}x, {:.2f}x ({}) | {} | {} |\n", kinds::kind_name(kinds::Kind(k)), evidence,
                      stats::interval_text(lf), stats::interval_text(df), stats::interval_text(ld), c.local, c.f64, c.measured_on,
                      plan_local ? "local frames" : "double", holds ? here + ": the plan's choice holds" : "**" + here + ": not the plan's choice**");
    storage_check.push_back({{"kind", kinds::kind_name(kinds::Kind(k))}, {"evidence", evidence}, {"plan_local", c.local},
                             {"plan_double", c.f64}, {"plan_stores_in", plan_local ? "local frames" : "double"},
                             {"local_over_double", stats::interval_json(ld)}, {"plan_choice_holds", holds}});
  }
  if (!all_hold) md += "\n**On this machine the lab does not support the plan's storage for every kind** (its figures were measured elsewhere).\n";
  return md;
}

// A far and a scaled copy of precision:kinds_ground rendered beside the original, as a table of
// images with the share of pixels that differ (`copies_json`).
std::string plan_copies(const ReportOptions& o, Record& rec, const fs::path& out, json& copies_json) {
  std::string md;
  std::cerr << "[report plan] far and scaled copies\n";
  const int size = o.quick ? 64 : 160;
  // Each copy rendered (its image written) and compared with the original: {copy, image, differing_pixels}.
  copies_json = rec.take("plan/copies", [&] {
    const scene::Scene base = scene::precision_scene("kinds_ground");
    const auto ref = render::render_rgb8(base, tracer::Model::automatic, size, 2);
    struct Copy {
      std::string label, file;
      scene::Scene s;
      tracer::Model m;
    };
    const std::vector<Copy> copies = {
        {"auto, at the origin", "plan_copy_origin.png", base, tracer::Model::automatic},
        {"auto, moved by (1e3, -2e3, 4e3)", "plan_copy_1e3.png", scene::translated(base, {1e3, -2e3, 4e3}), tracer::Model::automatic},
        {"auto, moved by (1e7, -2e7, 4e7)", "plan_copy_1e7.png", scene::translated(base, {1e7, -2e7, 4e7}), tracer::Model::automatic},
        {"auto, scaled by 1e-3", "plan_copy_small.png", scene::scaled(base, 1e-3), tracer::Model::automatic},
        {"auto, scaled by 1e4", "plan_copy_large.png", scene::scaled(base, 1e4), tracer::Model::automatic},
        {"fast, moved by (6.4e6, 0, 0)", "plan_copy_fast_far.png", scene::translated(base, {6.4e6, 0, 0}), tracer::Model::fast},
    };
    json cj = json::array();
    for (const auto& c : copies) {
      const auto img = c.label.rfind("auto, at", 0) == 0 ? ref : render::render_rgb8(c.s, c.m, size, 2);
      std::vector<float> f(img.size());
      for (std::size_t i = 0; i < img.size(); ++i) f[i] = float(img[i]) / 255.0f;
      render::write_png((out / c.file).string(), size, size, f);
      cj.push_back({{"copy", c.label}, {"image", c.file}, {"differing_pixels", render::differing_pixels(img, ref)}});
    }
    return cj;
  });
  md += fmt::format("The same scene (`precision:kinds_ground`: a ball resting on a floor, a smaller ball, a cylinder, a cone, a mesh and a "
                    "torus, one light) moved far from the origin and scaled, each copy built in double and rendered at {} x {}; below "
                    "each image the share of pixels that differ from the original by more than 4/255 in a channel. The last copy is "
                    "the fast model 6.4e6 away: the float step there is half a unit and its spawn offset 64 units.\n\n", size, size);
  std::string head = "|", sep = "|", imgs = "|", diffs = "|";
  for (const auto& c : copies_json) {
    const std::string label = c["copy"].get<std::string>(), file = c["image"].get<std::string>();
    head += " " + label + " |";
    sep += "---|";
    imgs += fmt::format(" ![{}]({}) |", label, file);
    diffs += fmt::format(" {:.2f} % |", 100 * c["differing_pixels"].get<double>());
  }
  md += head + "\n" + sep + "\n" + imgs + "\n" + diffs + "\n\n";
  return md;
}

// A scene of the table: where it comes from, and how many primary rays the lab traces through it.
struct PlanSource {
  std::string label;
  std::function<scene::Scene()> make;
  std::size_t rays;
};
// What the table's rows add up to: their JSON, the lab's rows, the goal's verdicts per mesh and the
// rows of primitives stored apart.
struct PlanTally {
  json rows = json::array(), lab_rows = json::array();
  std::map<int, std::vector<std::string>> by_verdict;
  std::vector<std::string> local_lines;
};

// One scene's row: its plan, its models' speed and failures against the reference, and memory.
std::string plan_scene_row(const ReportOptions& o, Record& rec, const PlanSource& src, PlanTally& t) {
  // The scene's plan, its models' rows against the reference, and their memory.
  const json kept = rec.take("plan/" + src.label, [&] {
    const scene::Scene s = src.make();
    const tracer::Plan plan = tracer::make_plan(s, tracer::Model::automatic);
    json rj = json::array();
    for (const acc::Row& x : acc::whole_scene_rows(s, src.label, s.name, o.quick ? src.rays / 16 : src.rays, whole_scene_rounds(o), 1)) rj.push_back(x.json());
    // The memory each model's tree and batches take (tracer/accel.hpp), per primitive.
    auto bytes = [&](tracer::Model m) -> json {
      return double(tracer::SceneAccel::build(s, tracer::make_plan(s, m)).bytes()) / double(std::max<std::size_t>(1, s.primitive_count()));
    };
    // Two more builds per scene: left out of --quick (the layout only).
    return json{{"primitives", s.primitive_count()},  {"triangles", s.triangles.size()}, {"frame", tracer::frame_name(plan.frame)},
                {"kinds", plan_kinds_text(plan)},     {"plan", plan.json()},              {"rows", rj},
                {"bytes_fast", o.quick ? json(nullptr) : bytes(tracer::Model::fast)},
                {"bytes_auto", o.quick ? json(nullptr) : bytes(tracer::Model::automatic)}};
  });
  std::vector<acc::Row> r;
  for (const auto& x : kept["rows"]) r.push_back(acc::Row::from_json(x));
  const std::size_t primitives = kept["primitives"].get<std::size_t>();
  auto speed = [](const acc::Row& x) { return 1e3 / x.ns_per_test; };
  auto number = [](const json& x) { return x.is_number() ? x.get<double>() : double(NAN); };
  const double bytes_fast = number(kept["bytes_fast"]), bytes_auto = number(kept["bytes_auto"]);
  const auto b1 = [](double x) { return std::isfinite(x) ? fmt::format("{:.1f}", x) : std::string("-"); };
  // auto / fast round by round: fast's seconds over auto's.
  const stats::RatioInterval auto_fast = stats::paired_ratio(r[0].round_seconds, r[1].round_seconds);
  // The goal is the mesh's (every primitive a triangle): a scan's slivers must not cost its speed or
  // memory. On scenes of a few analytic primitives auto's robust methods are its answer, not a cost
  // of looking.
  const bool mesh = kept["triangles"].get<std::size_t>() == primitives && primitives > 0;
  if (mesh && r[0].failure_ppm() == 0) {
    stats::Verdict v = stats::verdict(auto_fast, kAutoSpeedGoal);
    const bool heavier = std::isfinite(bytes_auto) && bytes_auto > kAutoMemoryGoal * bytes_fast;
    if (heavier) v = stats::Verdict::not_met;
    t.by_verdict[v == stats::Verdict::met ? doc::kGoalMet : v == stats::Verdict::not_met ? doc::kGoalNotMet
               : v == stats::Verdict::undecided ? doc::kGoalUndecided : doc::kGoalNotMeasured]
        .push_back(src.label + " " + stats::interval_text(auto_fast) +
                   (std::isfinite(bytes_auto) ? fmt::format(", memory {:.2f}x", bytes_auto / bytes_fast) : std::string()) +
                   (heavier ? " (memory above the goal)" : ""));
  }
  const std::string md = fmt::format("| {} | {} | {} | {} | {:.2f} / {:.2f} / {:.2f} | {} | {} / {} | {} / {} / {} |\n", src.label,
                    primitives, kept["frame"].get<std::string>(), kept["kinds"].get<std::string>(), speed(r[0]), speed(r[1]), speed(r[2]),
                    stats::interval_text(auto_fast), b1(bytes_fast), b1(bytes_auto), plan_ppm(r[0].failure_ppm()), plan_ppm(r[1].failure_ppm()),
                    plan_ppm(r[2].failure_ppm()));
  json j{{"scene", src.label}, {"primitives", primitives}, {"plan", kept["plan"]}, {"auto_vs_fast", stats::interval_json(auto_fast)}};
  if (r.size() > 3) {
    const stats::RatioInterval local_double = stats::paired_ratio(r[3].round_seconds, r[1].round_seconds);
    j["apart_local_vs_double"] = stats::interval_json(local_double);
    t.local_lines.push_back(fmt::format("| {} | {:.2f} | {:.2f} | {} | {} / {} |", src.label, speed(r[1]), speed(r[3]),
                                      stats::interval_text(local_double), plan_ppm(r[1].failure_ppm()), plan_ppm(r[3].failure_ppm())));
  }
  if (!o.quick) j["bytes_per_prim"] = {{"fast", bytes_fast}, {"auto", bytes_auto}};
  for (const auto& x : r) {
    j[x.method] = {{"mrays_per_s", speed(x)}, {"failure_ppm", x.failure_ppm()}, {"false_hit_ppm", x.false_hit_ppm},
                   {"false_miss_ppm", x.false_miss_ppm}, {"wrong_hit_ppm", x.wrong_root_ppm}, {"self_hit_ppm", x.self_hit_ppm},
                   {"frame", x.precision}, {"rays", x.rays}};
    t.lab_rows.push_back(x.json());
  }
  t.rows.push_back(j);
  return md;
}

}  // namespace

int whole_scene_rounds(const ReportOptions& o) { return o.quick ? 3 : acc::kWholeSceneRounds; }

std::string report_section_plan(const ReportOptions& o, Record& rec, const fs::path& out, json& summary) {
  std::string md = "## What each scene needs: the plan, its cost and its failures\n\n";
  md += "Model no more than a scene needs. Before tracing, raybench reads the scene's numerical profile (per primitive kind: the "
        "float step at its coordinates against its sizes, how far away it is seen, how large it is against the smallest object) "
        "and makes a plan (`raybench plan SCENE` prints it with a reason per choice): the frame of reference, whose origin is "
        "subtracted from every coordinate in double before it is rounded to float (world, the scene's centre or the camera); "
        "each kind's method and precision, the cheapest that the accuracy lab measures with no failure under the scene's "
        "conditions (each choice cites the lab cases it rests on, and a test runs them); a batch of their own for the primitives "
        "that no frame represents in float (a far cluster of small meshes, a planet under a ball), in float in local frames or in "
        "double, whichever the kind's measured storage costs make cheaper (below), while the rest stays in float, or double for "
        "the whole kind when over a quarter of it is coarse and some of those are huge; node boxes widened for the scene's ray origins, so the fast slab test "
        "loses no hit; and the spawn offset of secondary rays (hit points projected onto their surface in double, then moved by "
        "their own error bound). `--model fast` is the fixed choice of a tracer that does not look (world coordinates, the "
        "cheapest method of every kind in float, an offset of 1e-5 of the scene's size); `--model exact` is the most accurate "
        "of everything.\n\n";
  md += "Failures are counted against an exact reference: the scene's own double geometry, every primitive against the ray in long "
        "double (a brute-force loop). Per primary ray through the scene's view: a false hit or miss, or a wrong hit (another "
        "surface than the first, or the right one off by more than 1e-5 of the distance); per hit, a secondary ray spawned at the "
        "model's hit point that hits its own surface again. Speed: the model's primary rays in 8-ray packets on one thread, Mrays/s, "
        "the median of " + std::to_string(whole_scene_rounds(o)) + " rounds in which the three models take turns (each turn traces the "
        "rays as often as makes the fast model's last about " + fmt::format("{:.0f}", 1e3 * acc::kWholeSceneTurn) + " ms); auto / fast is "
        "the median of the rounds' own ratios with its 95 % interval (the sign test's; the range of the rounds where they are "
        "too few). CSG scenes have no reference and are left out.\n\n";

  std::vector<PlanSource> srcs;
  const std::string data = data_dir() + "/meshes/";
  srcs.push_back({"stanford-bunny.obj", [data] { return scene::load_scene(data + "stanford-bunny.obj"); }, 4096});
  if (!o.quick)  // its reference is a brute-force loop over 202,520 triangles per ray: fewer rays
    srcs.push_back({"dragon_vrip_res2_bin.ply", [data] { return scene::load_scene(data + "dragon_vrip_res2_bin.ply"); }, 1024});
  for (const auto& n : scene::spd_names())
    srcs.push_back({"spd:" + n, [n] { return scene::generate_spd(n, scene::spd_default_size(n)); }, n == "gears" ? 1024u : 4096u});
  for (const auto& n : scene::lecture_scene_names()) srcs.push_back({"lecture:" + n, [n] { return scene::lecture_scene(n); }, 4096});
  for (const auto& n : scene::precision_scene_names())
    if (n != "mesh_spheres") srcs.push_back({"precision:" + n, [n] { return scene::precision_scene(n); }, 4096});

  md += "| scene | primitives | frame | auto: each kind's method | Mrays/s fast / auto / exact | auto / fast | bytes per primitive "
        "fast / auto | failures per million rays: fast / auto / exact |\n|---|---:|---|---|---:|---:|---:|---:|\n";
  PlanTally tally;
  std::size_t step = 0;
  json spawn_check;
  for (const auto& src : srcs) {
    std::cerr << fmt::format("[report plan {}/{}] {}\n", ++step, srcs.size(), src.label);
    md += plan_scene_row(o, rec, src, tally);
  }
  md += plan_goal_text(tally.by_verdict);
  md += plan_spawn_check(summary, spawn_check);
  json storage_check;
  md += plan_storage_check(summary, storage_check);
  // Where auto stores primitives apart in local frames: their speed against the same plan with them
  // in double (the lab's fourth row).
  if (!tally.local_lines.empty()) {
    md += "\nPrimitives stored apart in local frames (each leaf's primitives in float relative to an origin of its own, the ray "
          "re-based there) against the same plan with them in double, in the same rounds:\n\n| scene | Mrays/s local frames | "
          "Mrays/s double | local / double | failures per million: local / double |\n|---|---:|---:|---:|---:|\n";
    for (const auto& l : tally.local_lines) md += l + "\n";
  }
  md += "\nThe precision scenes (`raybench info precision:NAME` describes each; `raybench render precision:NAME` renders it) are "
        "built to need something: a ball on a planet of radius 6.4e6, a scene 6.4e6 or 1e3..1e7 from the origin, small spheres "
        "5e3 away, thin tori 500 sizes away, cylinders seen from 1e4 radii, a scene mixing scales, a scanned mesh with "
        "slivers and collapsed triangles (its coordinates floats, or in double), small meshes scattered over a world 3.7e4 wide. "
        "In brackets, a kind's primitives by class "
        "in the chosen frame: as the input holds them (float keeps every vertex), coarse (float step over size above 2^-12; "
        "negligible when together they can change under 0.1 hit per million: kept in float; otherwise stored apart in local "
        "frames, float relative to an origin per leaf, when none of them is huge or they are at most a quarter of the kind; "
        "primitives under one float step are coarse unless the input held them as floats), degenerate (no area: slots no ray hits); `raybench plan` names the worst of each. The embedded scenes need "
        "nothing special; on them auto costs what the kinds' chosen methods cost (the table's auto / fast; the lab's "
        "`ns_per_test` compares the methods themselves).\n\n";
  md += "![speed against failures per model](plan_models.png)\n\n";
  write_output((out / "plan.json").string(), json{{"scenes", tally.rows}, {"rows", tally.lab_rows}}.dump(2) + "\n");

  json copies_json;
  md += plan_copies(o, rec, out, copies_json);
  json goal = {{"target", kAutoSpeedGoal}, {"memory_target", kAutoMemoryGoal}};
  for (const auto& [v, scenes] : tally.by_verdict) goal[doc::goal_word(v)] = scenes;
  summary["plan"] = {{"scenes", tally.rows}, {"copies", copies_json}, {"auto_speed_goal", goal}, {"spawn_check", spawn_check}, {"storage_check", storage_check}};
  return md;
}

}  // namespace rb::app
