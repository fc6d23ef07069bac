#include "tracer/plan.hpp"

#include "core/spawn.hpp"
#include "tracer/profile.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rb::tracer {

const char* model_name(Model m) { return m == Model::fast ? "fast" : m == Model::automatic ? "auto" : "exact"; }
Model parse_model(const std::string& s) {
  if (s == "fast") return Model::fast;
  if (s == "auto") return Model::automatic;
  if (s == "exact") return Model::exact;
  throw std::invalid_argument("unknown model '" + s + "' (auto, fast, exact)");
}
const char* spawn_name(SpawnScheme s) {
  return s == SpawnScheme::extent_eps ? "extent_epsilon" : "error_bound_offset";
}
const char* frame_name(FrameKind f) { return f == FrameKind::world ? "world" : f == FrameKind::centre ? "scene_centre" : "camera"; }

// Each kind's options, from its header (tracer/kinds/*.hpp, `plan`).
std::span<const PlanOption> plan_options(Kind k) {
  return kinds::AllKinds::at<std::span<const PlanOption>>(k, [&]<class K>() { return std::span<const PlanOption>(K::plan); });
}

const StorageCosts& storage_costs() {
  static const StorageCosts c = [] {
    StorageCosts t{};
    kinds::AllKinds::each([&]<class K>() {
      if constexpr (requires { K::storage; }) t[std::size_t(K::id)] = K::storage;
    });
    return t;
  }();
  return c;
}

namespace {

constexpr double kTauEye = 1.0 / 16;  // the eye's rounding shifts the view by at most 1/16 of a pixel

// Whether method m of kind k stores its primitives in double; m < 0: any of the kind's methods.
bool stores_double(Kind k, int m = -1) {
  bool s = false;
  kinds::AllKinds::each([&]<class K>() {
    if (K::id != k) return;
    for (std::size_t i = 0; i < K::methods.size(); ++i)
      if (m < 0 || int(i) == m) s = s || K::methods[i].f64_storage;
  });
  return s;
}
std::string method_name(Kind k, int m) {
  std::string n;
  kinds::AllKinds::each([&]<class K>() {
    if (K::id == k && m >= 0 && m < int(K::methods.size())) n = K::methods[std::size_t(m)].name;
  });
  return n;
}
std::string fmt_ratio(double x) { return x >= 1e4 || (x > 0 && x < 1e-2) ? fmt::format("{:.1e}", x) : fmt::format("{:.3g}", x); }
std::string fmt_pow2(double x) { return x > 0 ? fmt::format("2^{:.1f}", std::log2(x)) : "0"; }

bool covers(const PlanOption& o, const KindProfile& kp) {
  return kp.far_ratio <= o.far && kp.scale_ratio <= o.scale && kp.aspect_max <= o.aspect;
}

}  // namespace

// The classes of a kind's primitives in the chosen frame, each counted, with its worst primitive.
std::string KindPlan::classes_text() const {
  const KindClasses& c = classes;
  const bool stored64 = f64_storage, apart = !split.empty();
  std::vector<std::string> parts;
  if (c.as_input) parts.push_back(fmt::format("{} as the input holds them (float keeps every vertex)", c.as_input));
  if (c.fine) parts.push_back(fmt::format("{} with float step over size at most {}", c.fine, fmt_pow2(kFloatTolerance)));
  if (c.coarse)
    parts.push_back(fmt::format("{} above it (worst #{}: {}), which can change {:.2g} of a million hits{}", c.coarse, c.worst_coarse,
                                fmt_pow2(c.worst_coarse_ratio), 1e6 * c.moved_share,
                                stored64     ? ": they put the kind in double"
                                : apart      ? (split_local ? ": stored apart, in local frames" : ": stored apart, in double")
                                : c.negligible ? ": negligible, kept in float with the rest"
                                               : ""));
  if (c.degenerate)
    parts.push_back(fmt::format("{} degenerate (no area: kept as slots no ray hits; smallest #{}, {:.3g} across)",
                                c.degenerate, c.worst_degenerate, c.worst_degenerate_extent));
  std::string t;
  for (const auto& p : parts) t += (t.empty() ? "" : "; ") + p;
  return t;
}

Plan make_plan(const scene::Scene& s, Model m) { return make_plan(s, make_profile(s), m); }

namespace {

// A primitive stored apart costs this many primitives in float: the cheaper of its two storages.
double cheaper_storage(const kinds::StorageCost& c) { return std::min(c.local, c.f64); }

// Whether the coarse primitives of kind k in a frame go to a batch of their own: they can change
// more than a negligible share of its hits, and are either fine relative to an origin near them
// (none of them huge: local frames hold them) or a few (at most kSplitShare of the kind); the rest
// stays in float, so the frame is judged by the rest.
bool splits(const FrameError& e, const Profile& p, Model m, int k) {
  const KindClasses& c = e.classes[std::size_t(k)];
  return m != Model::exact && c.coarse > 0 && !c.negligible && stores_double(Kind(k)) &&
         (c.coarse_huge == 0 || double(c.coarse) <= kSplitShare * double(p.kinds[std::size_t(k)].count));
}

// The frame the plan traces in, and what it leaves to double.
struct FrameChoice {
  FrameKind kind = FrameKind::world;
  Vec3d origin{0, 0, 0};
  FrameError e;
  std::array<bool, kKinds> store64{};  // kinds that no frame represents in float, stored in double
  std::string reason;
};

// The reason's list: each kind's float step over its size in a frame.
std::string per_kind_steps(const FrameError& e, const Profile& p, Model m, const std::array<bool, kKinds>& store64) {
  std::string t;
  for (int k = 0; k < kKinds; ++k)
    if (p.kinds[std::size_t(k)].count)
      t += fmt::format("{}{} {}{}", t.empty() ? "" : ", ", kinds::kind_name(Kind(k)), fmt_pow2(e.contact[std::size_t(k)]),
                       store64[std::size_t(k)] ? " (stored in double)"
                       : splits(e, p, m, k)    ? fmt::format(" ({} coarse stored apart)", e.classes[std::size_t(k)].coarse)
                                               : "");
  return t + fmt::format("; the eye's rounding shifts the view by {} pixel", fmt_ratio(e.eye));
}

// World, the scene's centre or the camera: the first that represents the scene in float, else the
// best; among those that represent it, the one whose primitives stored apart cost least at the
// kinds' measured storage costs.
FrameChoice choose_frame(const scene::Scene& s, const Profile& p, Model m, const StorageCosts& costs) {
  std::vector<FrameChoice> cand(3);
  cand[0].kind = FrameKind::world;
  cand[1].kind = FrameKind::centre;
  cand[1].origin = p.bounds.empty() ? Vec3d{0, 0, 0} : p.bounds.centre();
  cand[2].kind = FrameKind::camera;
  cand[2].origin = p.camera;
  for (auto& c : cand) {
    c.e = frame_error(s, p, c.origin);
    for (int k = 0; k < kKinds; ++k)
      if (splits(c.e, p, m, k)) c.e.contact[std::size_t(k)] = c.e.contact_fine[std::size_t(k)];
  }
  // What a frame's primitives stored apart cost beyond the kind in float: each at the cheaper of its
  // kind's two measured storages (kinds::StorageCost), in units of a primitive in float.
  auto apart_cost = [&](const FrameError& e) {
    double c = 0;
    for (int k = 0; k < kKinds; ++k)
      if (splits(e, p, m, k))
        c += double(e.classes[std::size_t(k)].coarse) * std::max(0.0, cheaper_storage(costs[std::size_t(k)]) - 1.0);
    return c;
  };
  // Kinds that no frame represents in float but that can be stored in double.
  std::array<bool, kKinds> store64{};
  for (int k = 0; k < kKinds; ++k) {
    double best = 1e300;
    for (const auto& c : cand) best = std::min(best, c.e.contact[std::size_t(k)]);
    const bool present = p.kinds[std::size_t(k)].count > 0 && stores_double(Kind(k));
    store64[std::size_t(k)] = present && (m == Model::exact || best > kFloatTolerance);
  }
  auto score = [&](const FrameChoice& c) { return std::max(c.e.worst(store64) / kFloatTolerance, c.e.eye / kTauEye); };
  std::size_t pick = 0;
  if (m == Model::exact || score(cand[0]) > 1) {
    pick = 1;  // the scene's centre unless the camera is clearly better
    if (score(cand[2]) * 2 < score(cand[1])) pick = 2;
    if (m != Model::exact && score(cand[0]) <= score(cand[pick])) pick = 0;
  }
  if (m != Model::exact)
    for (std::size_t i = 0; i < cand.size(); ++i)
      if (score(cand[i]) <= 1 && (score(cand[pick]) > 1 || apart_cost(cand[i].e) < apart_cost(cand[pick].e))) pick = i;
  FrameChoice f = cand[pick];
  f.store64 = store64;
  if (pick == 0)
    f.reason = fmt::format("world coordinates represent the scene (float step over each primitive's size at most {}: {})",
                           fmt_pow2(kFloatTolerance), per_kind_steps(cand[0].e, p, m, store64));
  else
    f.reason = fmt::format("{}: in world coordinates the float step over a primitive's size is {}; relative to the {} it is {}",
                           m == Model::exact ? "the exact model re-centres" : "re-centred", per_kind_steps(cand[0].e, p, m, store64),
                           pick == 1 ? "scene's centre" : "camera", per_kind_steps(f.e, p, m, store64));
  // Where several frames represent the scene and leave primitives apart, the ranking by cost.
  std::string ranked;
  for (std::size_t i = 0; m != Model::exact && i < cand.size(); ++i)
    if (score(cand[i]) <= 1 && apart_cost(cand[pick].e) > 0)
      ranked += fmt::format("{}{} {:.0f}", ranked.empty() ? "" : ", ", frame_name(cand[i].kind), apart_cost(cand[i].e));
  if (ranked.find(',') != std::string::npos)
    f.reason += fmt::format("; of the frames that represent it, the one whose primitives stored apart cost least (their cost beyond "
                            "float, counted in primitives stored in float, at the kinds' storage costs: {})",
                            ranked);
  return f;
}

// The split-off primitives of a kind: in local frames or in double, whichever the kind's measured
// storage costs make cheaper, running the cheapest option in double whose method stores double and
// whose lab conditions cover the kind (the most accurate such when none does).
void plan_split(KindPlan& kp, Kind k, const KindProfile& kpro, const FrameError& fe, const kinds::StorageCost& cost) {
  const auto& opts = plan_options(k);
  const PlanOption* o64 = nullptr;
  auto stores64 = [&](const PlanOption& o) { return o.f64 && stores_double(k, o.method); };
  for (const auto& o : opts)
    if (!o64 && stores64(o) && covers(o, kpro)) o64 = &o;
  for (auto o = opts.rbegin(); !o64 && o != opts.rend(); ++o)
    if (stores64(*o)) o64 = &*o;
  kp.split = fe.coarse_ids[std::size_t(k)];
  kp.split_method = o64 ? o64->method : 0;
  // Coarse where they lie in the frame, they are fine relative to an origin near them: stored in
  // float in local frames, the ray re-based at each of their leaves, or in double; both give the
  // reference's hits (the lab's scene/scattered and storage cases), so the cheaper one.
  kp.split_local = cost.local <= cost.f64;
  kp.split_cost = cost;
  const KindClasses& c = kp.classes;
  kp.split_reason = fmt::format(
      "{} coarse of {} ({:.2g} %) stored in a batch of their own {}, {}: in world float their surfaces would move by up to {} "
      "of their size (#{}) and together could change {:.2g} of a million hits; the other {} stay in {}. Stored apart, a ray "
      "costs {:.2f}x the kind in the frame in local frames and {:.2f}x in double (measured on {}: `raybench accuracy --filter {}`)",
      c.coarse, kpro.count, 100.0 * double(c.coarse) / double(kpro.count),
      kp.split_local ? "in local frames (float relative to an origin per leaf, kept in double; a leaf whose primitives no such "
                       "origin holds in float stays in double)"
                     : "in double",
      method_name(k, kp.split_method), fmt_pow2(c.worst_coarse_ratio), c.worst_coarse, 1e6 * c.moved_share, kpro.count - c.coarse,
      kp.f64 ? "double" : "float", cost.local, cost.f64, *cost.measured_on ? cost.measured_on : "not measured", cost.evidence);
}

// A kind's method and precision: the cheapest option the lab shows without failure under the
// kind's conditions (in double where the frame cannot hold it in float), with the reason.
void plan_kind(KindPlan& kp, Kind k, const KindProfile& kpro, const FrameChoice& f, const Profile& p, Model m,
               const kinds::StorageCost& cost) {
  const FrameError& fe = f.e;
  const bool need64 = m == Model::exact ? f.store64[std::size_t(k)] : fe.contact[std::size_t(k)] > kFloatTolerance && stores_double(k);
  const auto& opts = plan_options(k);
  const PlanOption* chosen = nullptr;
  if (m == Model::exact) {
    chosen = &opts.back();
  } else {
    for (const auto& o : opts) {
      if (need64 && !o.f64) continue;
      if (covers(o, kpro)) {
        chosen = &o;
        break;
      }
    }
  }
  const bool beyond = !chosen;
  if (beyond) chosen = &opts.back();
  kp.method = chosen->method;
  kp.f64 = chosen->f64;
  kp.f64_storage = chosen->f64 && need64;
  kp.evidence = chosen->evidence;
  std::string cond = fmt::format("seen from up to {} sizes", fmt_ratio(kpro.far_ratio));
  if (kpro.scale_ratio > 1e3) cond += fmt::format(", {} times the smallest object", fmt_ratio(kpro.scale_ratio));
  if (k == Kind::torus) cond += fmt::format(", aspect {}", fmt_ratio(kpro.aspect_max));
  if (m == Model::exact)
    kp.reason = fmt::format("the exact model: the most accurate method, {}", chosen->f64 ? "in double" : "(float only)");
  else if (beyond)
    kp.reason = fmt::format("{}: beyond the lab's cases, so the most accurate method", cond);
  else
    kp.reason = fmt::format("{}: {}", cond, chosen->why);
  if (kp.f64_storage)
    kp.reason += fmt::format("; stored in double: in float the surface would move by {} of {}", fmt_pow2(fe.contact[std::size_t(k)]),
                             kpro.scale_ratio > 1e3 ? "the smallest object" : "its size");
  kp.classes = fe.classes[std::size_t(k)];
  if (splits(fe, p, m, int(k))) plan_split(kp, k, kpro, fe, cost);
}

// The fast model's fixed choices: world coordinates, method 0 in float, the slab test on boxes as
// built, an offset of 1e-5 of the scene's size.
void plan_fast(Plan& plan, double ext) {
  plan.frame = FrameKind::world;
  plan.frame_reason = "the fast model traces in world coordinates";
  for (auto& k : plan.kinds) {
    k.reason = "the fast model's fixed choice: the cheapest method, in float";
    k.method = 0;
    k.f64 = k.f64_storage = false;
  }
  plan.slab = bvh::Slab::fast;
  plan.slab_reason = "the fast model's slab test on boxes as built";
  plan.spawn = SpawnScheme::extent_eps;
  plan.spawn_eps = float(std::max(1e-5 * ext, 1e-7));
  plan.spawn_reason = fmt::format("the fast model's offset: 1e-5 of the scene's size and distance from the origin ({:.3g})", plan.spawn_eps);
}

// Conservative boxes for every ray origin the scene produces, and the spawn offset.
void plan_slab_and_spawn(Plan& plan, const Profile& p, double ext) {
  plan.slab = bvh::Slab::conservative;
  const Vec3d lo = p.origins.empty() ? Vec3d{0, 0, 0} : p.origins.lo - plan.origin, hi = p.origins.empty() ? Vec3d{0, 0, 0} : p.origins.hi - plan.origin;
  const double ob = std::max({std::fabs(lo.x), std::fabs(lo.y), std::fabs(lo.z), std::fabs(hi.x), std::fabs(hi.y), std::fabs(hi.z)});
  plan.origin_bound = float(std::min(ob * (1 + 0x1p-10) + 1e-30, double(std::numeric_limits<float>::max())));
  plan.slab_reason = fmt::format(
      "the fast slab test on node boxes widened for ray origins up to {:.3g} from the frame origin (the scene, the camera and the lights): "
      "no box that the ray meets is culled (lab: bvh/* method default); rays from farther use the robust test",
      plan.origin_bound);
  plan.spawn_eps = float(std::max(1e-5 * ext, 1e-7));
  // Each hit's own bound, in both models: the integer offset (256 float steps of the hit's
  // coordinates) is as free of self-hits and costs the same here, where every hit point starts in
  // double, but where coordinates are large against nearby objects it lifts a shadow ray past them
  // (precision:cluster_ground: a ball of radius 0.7 on a floor 3.7e4 up lost its shadow to a
  // 1-unit offset).
  plan.spawn = SpawnScheme::error_bound;
  plan.spawn_reason =
      "the error-bound offset, per hit: the hit point projected onto its surface in double, rounded to the frame's float, "
      "and moved along the normal by that rounding plus its primitive's own (float or double storage, in the frame or a "
      "local frame): no self-hit in the lab (*/secondary_bound_offset, scene/*), and small objects keep their shadows at "
      "any distance from the frame's origin";
}

}  // namespace

Plan make_plan(const scene::Scene& s, const Profile& p, Model m) { return make_plan(s, p, m, storage_costs()); }

Plan make_plan(const scene::Scene& s, const Profile& p, Model m, const StorageCosts& costs) {
  Plan plan;
  plan.model = m;
  plan.object_min = smallest_object(p);
  for (int k = 0; k < kKinds; ++k) plan.kinds[std::size_t(k)].count = p.kinds[std::size_t(k)].count;
  const double ext = std::max(p.extent, p.coord_max);
  if (m == Model::fast) {
    plan_fast(plan, ext);
    return plan;
  }
  const FrameChoice f = choose_frame(s, p, m, costs);
  plan.frame = f.kind;
  plan.origin = f.origin;
  plan.frame_reason = f.reason;
  for (int k = 0; k < kKinds; ++k)
    if (p.kinds[std::size_t(k)].count)
      plan_kind(plan.kinds[std::size_t(k)], Kind(k), p.kinds[std::size_t(k)], f, p, m, costs[std::size_t(k)]);
  plan_slab_and_spawn(plan, p, ext);
  return plan;
}

nlohmann::json Plan::json() const {
  using nlohmann::json;
  json k = json::array();
  for (int i = 0; i < kKinds; ++i) {
    const KindPlan& kp = kinds[std::size_t(i)];
    if (!kp.count) continue;
    k.push_back({{"kind", kinds::kind_name(Kind(i))},
                 {"count", kp.count},
                 {"method", method_name(Kind(i), kp.method)},
                 {"precision", kp.f64 ? "double" : "float"},
                 {"storage", kp.f64_storage ? "double" : "float"},
                 {"reason", kp.reason},
                 {"evidence", kp.evidence},
                 {"classes",
                  {{"as_input", kp.classes.as_input},
                   {"fine", kp.classes.fine},
                   {"coarse", kp.classes.coarse},
                   {"degenerate", kp.classes.degenerate},
                   {"worst_coarse", kp.classes.coarse ? json(kp.classes.worst_coarse) : json(nullptr)},
                   {"worst_coarse_step_over_size", kp.classes.worst_coarse_ratio},
                   {"coarse_share_of_hits", kp.classes.moved_share},
                   {"coarse_negligible", kp.classes.negligible},
                   {"worst_degenerate", kp.classes.degenerate ? json(kp.classes.worst_degenerate) : json(nullptr)},
                   {"summary", kp.classes_text()}}},
                 {"split", kp.split.empty() ? json(nullptr)
                                            : json{{"count", kp.split.size()},
                                                   {"method", method_name(Kind(i), kp.split_method)},
                                                   {"precision", kp.split_local ? "float" : "double"},
                                                   {"storage", kp.split_local ? "local frames" : "double"},
                                                   {"cost", {{"local_frames", kp.split_cost.local},
                                                             {"double", kp.split_cost.f64},
                                                             {"evidence", kp.split_cost.evidence},
                                                             {"measured_on", kp.split_cost.measured_on}}},
                                                   {"reason", kp.split_reason}}}});
  }
  return {{"model", model_name(model)},
          {"frame", {{"kind", frame_name(frame)}, {"origin", {origin.x, origin.y, origin.z}}, {"reason", frame_reason}}},
          {"kinds", k},
          {"slab", {{"test", bvh::slab_name(slab)}, {"origin_bound", origin_bound}, {"reason", slab_reason}}},
          {"spawn", {{"scheme", spawn_name(spawn)}, {"epsilon", spawn_eps}, {"reason", spawn_reason}}}};
}

std::string Plan::text() const {
  std::string o = fmt::format("model   {}\n", model_name(model));
  o += fmt::format("frame   {} (origin {:.9g} {:.9g} {:.9g})\n        {}\n", frame_name(frame), origin.x, origin.y, origin.z, frame_reason);
  for (int i = 0; i < kKinds; ++i) {
    const KindPlan& kp = kinds[std::size_t(i)];
    if (!kp.count) continue;
    o += fmt::format("{:<8}{} x {}: {} in {}{}\n        {}\n", kinds::kind_name(Kind(i)), kp.count, kinds::kind_name(Kind(i)),
                     method_name(Kind(i), kp.method), kp.f64 ? "double" : "float", kp.f64_storage ? " (stored in double)" : "", kp.reason);
    if (const std::string c = kp.classes_text(); !c.empty()) o += fmt::format("        classes: {}\n", c);
    if (!kp.split.empty()) o += fmt::format("        apart:   {}\n", kp.split_reason);
    if (!kp.evidence.empty()) o += fmt::format("        lab: {}\n", kp.evidence);
  }
  o += fmt::format("slab    {}\n        {}\n", bvh::slab_name(slab), slab_reason);
  o += fmt::format("spawn   {}\n        {}\n", spawn_name(spawn), spawn_reason);
  return o;
}

}  // namespace rb::tracer
