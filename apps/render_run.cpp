#include "apps/render_run.hpp"

#include "apps/cli.hpp"
#include "apps/progress.hpp"
#include "apps/rays_alone.hpp"
#include "apps/results/stats.hpp"
#include "tracer/parallel.hpp"
#include "tracer/ray_sets.hpp"
#include "scene/sources.hpp"
#ifdef RB_HAVE_MPI
#include "render/mpi.hpp"
#endif

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

namespace rb::app {

using json = nlohmann::json;

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
// "spd:balls:3" -> "balls"; "" for other sources.
std::string spd_name(const std::string& source) {
  if (source.rfind("spd:", 0) != 0) return "";
  const std::string rest = source.substr(4);
  return rest.substr(0, rest.find(':'));
}
}  // namespace

std::optional<HainesFigures> haines_figures(const std::string& name) {
  // Haines, "Standard Procedural Databases", ray tracing statistics (512 x 512 corner rays,
  // depth 5) and his own hierarchy's test counts where the README of the SPD gives them.
  static const HainesFigures kTable[] = {
      {"balls", 263169, 175095, 0, 954368, 822e3, 6197e3, 51.7e6},
      {"teapot", 161120, 225248, 0, 407656, -1, -1, -1},
      {"tetra", 49788, 0, 0, 46112, 965e3, -1, 7.64e6},
      {"tree", 169836, 0, 0, 1097419, -1, -1, -1},
  };
  for (const auto& f : kTable)
    if (name == f.scene) return f;
  return std::nullopt;
}

namespace {

// The image size: as given; the camera's own when neither is given; one of them given, the other
// from the camera's aspect ratio (square without one).
std::pair<int, int> image_size(const RenderRunOptions& o, const scene::Scene& s) {
  int w = o.width, h = o.height;
  const bool aspect = !o.spd && s.camera.width > 0 && s.camera.height > 0;
  if (aspect && w == 0 && h == 0) w = s.camera.width, h = s.camera.height;
  if (w == 0 && h > 0) w = aspect ? std::max(1, int(std::lround(double(h) * s.camera.width / s.camera.height))) : h;
  if (w == 0) w = 512;
  if (h == 0) h = aspect ? std::max(1, int(std::lround(double(w) * s.camera.height / s.camera.width))) : w;
  return {w, h};
}

// The image's float samples in one FNV-1a digest: the same for any thread or rank count and any
// packet sizes.
std::string image_digest(const std::vector<float>& img) {
  std::uint64_t digest = 1469598103934665603ull;
  for (const float v : img) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    for (int k = 0; k < 4; ++k) digest = (digest ^ ((bits >> (8 * k)) & 0xFFu)) * 1099511628211ull;
  }
  return fmt::format("{:016x}", digest);
}

// What the renders leave: the last render's samples and counts, the timed renders' seconds, the
// trial renders' rows and the machine's load over them.
struct RenderTimes {
  std::vector<float> samples;
  std::vector<double> trace_seconds;  // per timed repetition: its seconds over its renders
  std::vector<int> passes;            // renders per timed repetition (o.min_time)
  render::RenderStats st;
  json trial_rows = json::array();
  json machine_load;
  json alone;    // the render's rays traced alone (o.trace_alone), null otherwise
  json primary;  // the scene's primary rays traced (o.primary_rays), null otherwise
  int trials = 0;
  int ranks = 1;
  bool rank0 = true;
};

// The warm-up renders and the trial renders first (not in the median), then the timed ones; the
// image and the counts are those of the last render (every render computes the same image).
// Packet sizes: given, or (0: auto) the fastest in this run. The trial renders after the warm-up
// ones try the candidates (eye rays in packets of 64, 16 and 8; the eye rays' shadow rays one by
// one and in octant-ordered packets of 8 and 16; apart from them the other rays one by one and in
// packets of 8), a candidate per render in turn, and each of the three kinds takes the size whose
// trace time was least (summed over threads; under MPI each rank chooses from its own tiles). The
// kinds' rays do not depend on the sizes, so each kind's choice is independent of the others'.
// `ro` leaves with the packet sizes of the timed renders. Every one of these renders takes the plain
// traversal; with ro.count_tests one more render, untimed, takes the counting one for the box and
// primitive test counts (the image and the ray counts are the same).
RenderTimes time_renders(const RenderRunOptions& o, const scene::Scene& s, const tracer::SceneAccel& accel, render::RenderOptions& ro,
                         const render::MpiSession* mpi) {
  RenderTimes out;
  const std::vector<int> eye_sizes = o.eye_packet == 0 ? std::vector<int>{64, 16, 8} : std::vector<int>{o.eye_packet};
  const std::vector<int> sec_sizes = o.secondary_packet == 0 ? std::vector<int>{1, 8} : std::vector<int>{o.secondary_packet};
  const int eye_shadow = o.eye_shadow_packet < 0 ? o.secondary_packet : o.eye_shadow_packet;
  const std::vector<int> esh_sizes = eye_shadow == 0 ? std::vector<int>{1, 8, 16} : std::vector<int>{eye_shadow};
  const int trials = o.eye_packet == 0 || o.secondary_packet == 0 || eye_shadow == 0
                         ? int(std::max({eye_sizes.size(), sec_sizes.size(), esh_sizes.size()}))
                         : 0;
  out.trials = trials;
  const double never = std::numeric_limits<double>::infinity();
  // least seconds per candidate
  std::vector<double> eye_s(eye_sizes.size(), never), sec_s(sec_sizes.size(), never), esh_s(esh_sizes.size(), never);
  auto fastest = [](const std::vector<int>& sizes, const std::vector<double>& secs) {
    return sizes[std::size_t(std::min_element(secs.begin(), secs.end()) - secs.begin())];
  };
  ro.eye_packet = eye_sizes[0];
  ro.secondary_packet = sec_sizes[0];
  ro.eye_shadow_packet = esh_sizes[0];
  int rank = 0;
#ifdef RB_HAVE_MPI
  if (mpi) rank = mpi->rank(), out.ranks = mpi->size();
  // Every rank sees the same options, so every rank stops here alike (before any collective call).
  if (!o.rays_out.empty() && out.ranks > 1)
    throw std::invalid_argument("--rays-out needs every tile in one process: under MPI a rank renders only its own tiles");
  if (mpi) mpi->barrier();
#endif
  out.rank0 = rank == 0;
  const bool show = o.progress && rank == 0;
  ProgressBar bar(fmt::format("render {}", o.scene), show ? ProgressBar::Mode::automatic : ProgressBar::Mode::off);
  const bool count = ro.count_tests;
  ro.count_tests = false;
  const int warmup = std::max(0, o.warmup), untimed = warmup + trials, reps = std::max(1, o.repetitions);
  // Keeping the rays needs every tile in this process.
  const bool keep = (o.trace_alone || !o.rays_out.empty()) && out.ranks == 1;
  const bool alone = keep && o.trace_alone, primary = o.primary_rays > 0 && out.ranks == 1;
  const int runs = untimed + (keep ? 1 : 0) + reps * (1 + (alone ? 1 : 0) + (primary ? 1 : 0)) + (count ? 1 : 0);
  int run = 0;
  auto progress = [&](std::size_t done, std::size_t total) {
    bar.update((double(run) + double(done) / double(std::max<std::size_t>(1, total))) / double(runs));
  };
  auto render_once = [&]() {
    const render::Renderer r(s, accel, ro);
#ifdef RB_HAVE_MPI
    if (mpi) return render::render_tiles_mpi(*mpi, r, out.samples, o.threads, progress);
#else
    (void)mpi;
#endif
    return render::render_tiles(r, out.samples, o.threads, 0, 1, progress);
  };
  const LoadWatch watch;
  for (run = 0; run < untimed; ++run) {
    const bool trial = run >= warmup;
    const std::size_t e = std::size_t(run - warmup) % eye_sizes.size(), k = std::size_t(run - warmup) % sec_sizes.size(),
                      q = std::size_t(run - warmup) % esh_sizes.size();
    if (trial) ro.eye_packet = eye_sizes[e], ro.secondary_packet = sec_sizes[k], ro.eye_shadow_packet = esh_sizes[q];
    out.st = render_once();
    if (trial) {
      eye_s[e] = std::min(eye_s[e], out.st.eye_trace_s);
      sec_s[k] = std::min(sec_s[k], out.st.secondary_trace_s);
      esh_s[q] = std::min(esh_s[q], out.st.eye_shadow_trace_s);
      out.trial_rows.push_back({{"eye_packet", ro.eye_packet},
                                {"eye_shadow_packet", ro.eye_shadow_packet},
                                {"secondary_packet", ro.secondary_packet},
                                {"eye_trace_ms", 1e3 * out.st.eye_trace_s},
                                {"eye_shadow_trace_ms", 1e3 * out.st.eye_shadow_trace_s},
                                {"secondary_trace_ms", 1e3 * out.st.secondary_trace_s}});
    }
  }
  if (trials > 0) {
    ro.eye_packet = fastest(eye_sizes, eye_s);
    ro.secondary_packet = fastest(sec_sizes, sec_s);
    ro.eye_shadow_packet = fastest(esh_sizes, esh_s);
  }
  // The rays of one render with the chosen packets, kept (untimed) before the timed renders, so that
  // tracing them alone can alternate with the renders.
  tracer::RayFile kept;
  std::unique_ptr<RaysAlone> rays_alone;
  if (keep) {
    ro.keep_rays = true;
    const render::RenderStats st = render_once();
    ro.keep_rays = false;
    kept = render::Renderer(s, accel, ro).kept_rays(st);
    kept.scene = o.scene;
    kept.model = o.model;
    kept.origin = accel.plan().origin;
    if (!o.rays_out.empty()) tracer::write_ray_file(o.rays_out, kept);
    // At the render's own width (render::kRenderLanes).
    if (alone) rays_alone = std::make_unique<RaysAlone>(accel, kept, o.threads, render::kRenderLanes);
    ++run;
  }
  // The scene's primary rays (the trace command's primary set, 8-ray packets, the closest hit),
  // the cheapest rays there are, timed after each render as its rays alone are.
  tracer::RayFile primary_rays;
  std::unique_ptr<RaysAlone> primary_alone;
  if (primary) {
    const RaySoA r = tracer::make_rays(s, accel, tracer::RaySet::primary, o.primary_rays, 1);
    tracer::RaySection eye{"eye", 1, false, 8, {}};
    eye.rays.reserve(r.count);
    for (std::size_t i = 0; i < r.count; ++i) eye.rays.push_back(r.get(i));
    primary_rays.sections.push_back(std::move(eye));
    primary_alone = std::make_unique<RaysAlone>(accel, primary_rays, o.threads, render::kRenderLanes);
  }
  std::vector<double> alone_seconds, primary_seconds;
  for (int rep = 0; rep < reps; ++rep, ++run) {
    // A timed repetition renders the image again until it has lasted o.min_time: a short render
    // is timed over several, not one at the clock's and the scheduler's mercy.
    const auto t1 = std::chrono::steady_clock::now();
    out.st = render_once();
    int passes = 1;
    for (; ms_since(t1) < 1e3 * o.min_time && passes < 1000; ++passes) out.st = render_once();
    out.trace_seconds.push_back(ms_since(t1) / 1e3 / passes);
    out.passes.push_back(passes);
    if (rays_alone) {  // then its rays alone, in the same stretch of the machine's time
      ++run;
      progress(0, 1);
      alone_seconds.push_back(rays_alone->repetition(o.min_time));
    }
    if (primary_alone) {
      ++run;
      progress(0, 1);
      primary_seconds.push_back(primary_alone->repetition(o.min_time));
    }
  }
  if (count) {
    ro.count_tests = true;
    out.st.cost = render_once().cost;
  }
  if (rays_alone) {
    out.alone = rays_alone->figures();
    // The render's rate over the rate of the same rays traced alone, counted as the render counts
    // them: the traced-alone seconds over the render's, repetition by repetition (each pair timed
    // back to back), a ratio of medians with its interval.
    out.alone["render_over_alone"] = stats::interval_json(stats::paired_ratio(alone_seconds, out.trace_seconds));
  }
  if (primary_alone) {
    out.primary = primary_alone->figures();
    // The render's rate per ray over the primary rays' rate: the rounds' time ratios (primary over
    // render, each pair back to back) scaled by the rays each traced.
    stats::RatioInterval r = stats::paired_ratio(primary_seconds, out.trace_seconds);
    const double per = double(out.st.rays()) / double(std::max<std::size_t>(1, primary_rays.rays()));
    r.ratio *= per, r.lo *= per, r.hi *= per;
    out.primary["render_over_primary"] = stats::interval_json(r);
  }
  out.machine_load = watch.json();
  bar.done();
  return out;
}

// Where a render's time went, in thread milliseconds (summed over threads; under MPI, rank 0's own
// tiles): eye rays made, rays packed (octant sort and SoA copy), the BVH by kind of ray, shading and
// the shadow rays' light; and per generation (1: the eye rays) its rays, hits and shadow rays.
json time_split(const render::RenderStats& st) {
  double pack = 0, eye = 0, secondary = 0, shadow = 0, shade = 0, light = 0;
  json gens = json::array();
  for (std::size_t g = 0; g < st.generations.size(); ++g) {
    const render::GenerationStats& x = st.generations[g];
    pack += x.pack_s, (g == 0 ? eye : secondary) += x.traverse_s, shadow += x.shadow_traverse_s, shade += x.shade_s, light += x.shadow_light_s;
    gens.push_back({{"generation", g + 1},
                    {"rays", x.rays},
                    {"hits", x.hits},
                    {"hit_rate", x.rays ? double(x.hits) / double(x.rays) : 0.0},
                    {"shadow_rays", x.shadow_rays},
                    {"coherent_groups", x.groups ? double(x.coherent_groups) / double(x.groups) : 0.0},
                    {"shadow_coherent_groups", x.shadow_groups ? double(x.shadow_coherent_groups) / double(x.shadow_groups) : 0.0},
                    {"pack_ms", 1e3 * x.pack_s},
                    {"traverse_ms", 1e3 * x.traverse_s},
                    {"shadow_traverse_ms", 1e3 * x.shadow_traverse_s},
                    {"shade_ms", 1e3 * x.shade_s},
                    {"shadow_light_ms", 1e3 * x.shadow_light_s}});
  }
  return {{"thread_ms", 1e3 * (st.generate_s + pack + eye + secondary + shadow + shade + light)},
          {"generate_ms", 1e3 * st.generate_s},
          {"pack_ms", 1e3 * pack},
          {"traverse_eye_ms", 1e3 * eye},
          {"traverse_secondary_ms", 1e3 * secondary},
          {"traverse_shadow_ms", 1e3 * shadow},
          {"shade_ms", 1e3 * shade},
          {"shadow_light_ms", 1e3 * light},
          {"generations", gens}};
}

}  // namespace

json run_render(const RenderRunOptions& o, const render::MpiSession* mpi) {
  const auto t0 = std::chrono::steady_clock::now();
  scene::Scene s = scene::load_scene(o.scene);
  const double load_ms = ms_since(t0);
  if (s.primitive_count() == 0) throw NothingToDo("the scene has no primitives: nothing to render");

  const auto tp = std::chrono::steady_clock::now();
  const tracer::Plan plan = tracer::make_plan(s, tracer::parse_model(o.model));
  const double plan_ms = ms_since(tp);
  tracer::SceneAccel accel;
  {
    tracer::ThreadScope ts(o.threads);
    ts.run([&] { accel = tracer::SceneAccel::build(s, plan); });
  }
  const double build_ms = accel.build_ms;
  const auto [w, h] = image_size(o, s);
  render::RenderOptions ro;
  if (o.spd) ro = render::spd_options(s, w, h, o.depth);
  else ro.width = w, ro.height = h, ro.depth = o.depth;
  ro.count_tests = o.count_tests;
  ro.tile = o.tile;
  ro.secondary_order = o.secondary_order == "sfc" ? render::RenderOptions::Order::sfc : render::RenderOptions::Order::octant;
  const RenderTimes rt = time_renders(o, s, accel, ro, mpi);
  if (!rt.rank0) return json();
  const render::RenderStats& st = rt.st;
  const stats::Summary spread = stats::summarize(rt.trace_seconds);
  const double trace_ms = 1e3 * spread.median;
  const render::Renderer r(s, accel, ro);
  const std::vector<float> img = r.resolve(rt.samples);
  if (!o.out.empty()) render::write_png(o.out, w, h, img);

  json prim = json::object();
  // A kind's tests in both of its batches (leaf tags k and kKinds + k: its primitives stored apart).
  for (int k = 0; k < kinds::kKinds; ++k) prim[kinds::kind_name(kinds::Kind(k))] = st.cost.kind_prims[k] + st.cost.kind_prims[kinds::kKinds + k];
  const double rays = double(st.rays());
  json j{{"scene", o.scene},
         {"scene_name", s.name},
         {"image_fnv1a", image_digest(img)},
         {"width", w},
         {"height", h},
         {"depth", ro.depth},
         {"spd", o.spd},
         {"two_sided", ro.two_sided},
         {"threads", o.threads},
         {"ranks", rt.ranks},
         {"primitives", s.primitive_count()},
         {"eye_rays", st.eye},
         {"eye_hit_rays", st.eye_hit},
         {"reflect_rays", st.reflect},
         {"refract_rays", st.refract},
         {"shadow_rays", st.shadow},
         {"total_rays", st.rays()},
         {"tests_counted", ro.count_tests},
         {"secondary_packet", ro.secondary_packet},
         {"eye_shadow_packet", ro.packet_for(0, true)},
         {"eye_packet", ro.eye_packet},
         {"tile", ro.tile},
         {"secondary_order", ro.secondary_order == render::RenderOptions::Order::sfc ? "sfc" : "octant"},
         // The lanes per group the eye packets walked in: 16 (AVX-512) for a triangle mesh where the
         // binary and CPU have them; counted renders walk in 8.
         {"eye_group_lanes", ro.count_tests ? 8 : accel.group_lanes({.packet = ro.eye_packet, .lanes = render::kRenderLanes})},
         {"packet_choice", {{"eye", o.eye_packet == 0 ? "fastest in the trial renders" : "given"},
                            {"eye_shadow", (o.eye_shadow_packet < 0 ? o.secondary_packet : o.eye_shadow_packet) == 0
                                               ? "fastest in the trial renders"
                                               : "given"},
                            {"secondary", o.secondary_packet == 0 ? "fastest in the trial renders" : "given"},
                            {"trials", rt.trial_rows}}},
         {"node_visits", st.cost.nodes},
         {"box_tests", st.cost.boxes},
         {"prim_tests", prim},
         {"load_ms", load_ms},
         {"model", o.model},
         {"plan", plan.json()},
         {"plan_ms", plan_ms},
         {"build_ms", build_ms},
         {"preprocess_ms", load_ms + plan_ms + build_ms},
         {"trace_ms", trace_ms},
         {"mrays_per_s", trace_ms > 0 ? rays / (trace_ms * 1e3) : 0.0},
         {"warmup", std::max(0, o.warmup)},
         {"trial_renders", rt.trials},
         {"repetitions", rt.trace_seconds.size()},
         {"trace_seconds", rt.trace_seconds},
         {"min_time", o.min_time},
         {"passes", rt.passes},
         {"trace_ms_min", 1e3 * spread.min},
         {"trace_ms_max", 1e3 * spread.max},
         {"cv", std::isfinite(spread.cv) ? json(spread.cv) : json(nullptr)},
         {"machine_load", rt.machine_load}};
  j["time_split"] = time_split(st);
  if (!o.rays_out.empty() && rt.ranks == 1) j["rays_file"] = o.rays_out;
  if (!rt.alone.is_null()) j["alone"] = rt.alone;
  else if (o.trace_alone) j["alone"] = {{"skipped", "under MPI a rank renders only its own tiles"}};
  if (!rt.primary.is_null()) j["primary"] = rt.primary;
  else if (o.primary_rays > 0) j["primary"] = {{"skipped", "under MPI a rank renders only its own tiles"}};
  j["time_split"]["render_ms"] = 1e3 * rt.trace_seconds.back();  // the render the split is of: the last timed one
  if (!o.out.empty()) j["image"] = o.out;
  if (const auto f = haines_figures(spd_name(o.scene))) {
    j["haines"] = {{"eye_hit_rays", f->eye_hit}, {"reflect_rays", f->reflect}, {"refract_rays", f->refract},
                   {"shadow_rays", f->shadow}};
    if (f->poly_tests >= 0) j["haines"]["polygon_tests"] = f->poly_tests;
    if (f->sphere_tests >= 0) j["haines"]["sphere_tests"] = f->sphere_tests;
    if (f->box_tests >= 0) j["haines"]["box_tests"] = f->box_tests;
  }
  return j;
}

}  // namespace rb::app
