// `raybench plan SCENE`: the scene's numerical profile and how the tracer models it (tracer/plan.hpp),
// each choice with its reason and the lab cases it rests on; --verify runs those cases.
#include "accuracy/lab.hpp"
#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "scene/sources.hpp"
#include "tracer/plan.hpp"
#include "tracer/profile.hpp"

#include <fmt/format.h>

#include <iostream>
#include <set>
#include <sstream>

namespace rb::app {

namespace {
using nlohmann::json;

std::string g(double x) { return x == 0 ? "0" : (x >= 1e5 || x < 1e-3) ? fmt::format("{:.2e}", x) : fmt::format("{:.4g}", x); }

std::string profile_text(const tracer::Profile& p) {
  std::string o;
  o += fmt::format("scene   {}: {} primitives, extent {}, largest coordinate {} (float step there {})\n", p.scene, p.primitives,
                   g(p.extent), g(p.coord_max), g(tracer::float_step(p.coord_max)));
  o += fmt::format("camera  ({}, {}, {}){}, {} from the bounds; lights up to {} from the centre; smallest object {}\n", g(p.camera.x),
                   g(p.camera.y), g(p.camera.z), p.stated_camera ? " (stated: the scene has none)" : "", g(p.camera_distance),
                   g(p.light_distance_max), g(p.object_min));
  o += fmt::format("input   {}\n", p.input.summary());
  o += fmt::format("{:<9}{:>8} {:>19} {:>8} {:>10} {:>10} {:>10}\n", "kind", "count", "size min..max", "aspect", "coord max", "seen from",
                   "step/size");
  for (int k = 0; k < kinds::kKinds; ++k) {
    const tracer::KindProfile& q = p.kinds[std::size_t(k)];
    if (!q.count) continue;
    o += fmt::format("{:<9}{:>8} {:>19} {:>8} {:>10} {:>10} {:>10}\n", kinds::kind_name(kinds::Kind(k)), q.count,
                     g(q.size_min) + ".." + g(q.size_max), g(q.aspect_max), g(q.coord_max), g(q.far_ratio), g(q.world_step_ratio));
    if (q.degenerate)
      o += fmt::format("{:<9}{:>9} of them degenerate (no area, or under one float step where they lie): left out of the figures\n", "",
                       q.degenerate);
  }
  o += "        (seen from: the farthest ray origin over the primitive's size; step/size:\n"
       "         the float step at the kind's largest coordinate over its smallest size,\n"
       "         in world coordinates)\n";
  return o;
}

// The lab rows of every case the plan cites, for the chosen method and precision.
json verify(const tracer::Plan& plan) {
  json out = json::array();
  for (int k = 0; k < kinds::kKinds; ++k) {
    const tracer::KindPlan& kp = plan.kinds[std::size_t(k)];
    if (!kp.count || kp.evidence.empty()) continue;
    std::string method;
    kinds::AllKinds::each([&]<class K>() {
      if (int(K::id) == k) method = K::methods[std::size_t(kp.method)].name;
    });
    std::istringstream cases(kp.evidence);
    std::string c;
    while (cases >> c) {
      acc::Options o;
      o.filter = c;
      o.rays = 4000;
      o.timing = false;
      o.tracer = &acc::tracer_cases();
      for (const acc::Row& r : acc::run_lab(o)) {
        if (r.family + "/" + r.case_name != c || r.method != method) continue;
        const bool ours = kp.f64 ? r.precision == "double" : r.precision != "double";
        if (!ours) continue;
        out.push_back({{"kind", kinds::kind_name(kinds::Kind(k))}, {"case", c}, {"method", r.method}, {"precision", r.precision},
                       {"rays", r.rays}, {"failure_ppm", r.failure_ppm()}});
      }
    }
  }
  return out;
}
}  // namespace

int run_plan_command(const std::string& scene, const std::string& model, bool do_verify, const JsonOut& out) {
  json j;
  std::string text;
  try {
    const rb::scene::Scene s = rb::scene::load_scene(scene);
    const tracer::Profile p = tracer::make_profile(s);
    const tracer::Plan plan = tracer::make_plan(s, p, tracer::parse_model(model));
    j = {{"source", scene}, {"profile", p.json()}, {"plan", plan.json()}};
    text = profile_text(p) + "\n" + plan.text();
    if (do_verify) {
      const json v = verify(plan);
      j["verify"] = v;
      text += "\nlab cases of the choices (4000 rays each; failures per million: misclassified, wrong roots, leaks, self-hits):\n";
      for (const auto& r : v)
        text += fmt::format("  {:<9} {:<30} {:<12} {:<7} {:>10}\n", r["kind"].get<std::string>(), r["case"].get<std::string>(),
                            r["method"].get<std::string>(), r["precision"].get<std::string>(), g(r["failure_ppm"].get<double>()));
    }
  } catch (const std::exception& e) {
    const std::string what = e.what();
    std::cerr << "raybench plan: " << (what.find(scene) == std::string::npos ? scene + ": " : "") << what << "\n";
    return 1;
  }
  return write_result("plan", out.json, out.file, [&] { return fit_columns(text, 9); }, [&] { return j; });
}

}  // namespace rb::app
