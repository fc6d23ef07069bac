// Whole scenes through the tracer (family "scene"): the scenes of scene/precision_scenes.cpp (small
// objects on a planet, a mesh and spheres 1e3..1e7 from the origin, small spheres seen from far, a
// thin torus from 500 sizes, cylinders seen from 1e4 radii, a scene mixing scales, scanned-like
// meshes, small meshes scattered over a wide world, and a plain one), and real meshes (the Stanford
// bunny and the 202k dragon from the embedded data, the scanned-like mesh, long thin pipes as a CAD
// export tessellates them) as they are, moved far and scaled, traced under each model
// (tracer/plan.hpp: fast, auto, exact) and checked ray by ray against an
// exact reference: the scene's own double geometry, every primitive against the ray in long double
// (a brute-force loop over the scene). A model's ray is the float ray it traces, lifted to world
// coordinates exactly (its frame origin plus its float origin, its float direction): the reference
// answers the question the model was asked, so what differs is the model's geometry and arithmetic.
//
// Per ray: a false hit or miss, a wrong hit (another primitive than the reference's first, or the
// same one, at a distance off by more than 1e-5 of (t + the smallest object), the precision a shaded
// point needs, unless the model's hit point lies within 2^-12 of the primitives' size of the
// reference's surface: two surfaces that touch, or a grazing ray); then a secondary ray spawned at the model's own hit point by the model's spawn offset,
// leaving on the side the primary ray came from in a random direction: a self-hit when it hits
// its own primitive within 1e-4 of that primitive's size. Mrays/s: the model's primary rays in
// 8-ray packets on one thread. Method = the model, precision = the frame it chose.
#include "accuracy/common.hpp"
#include "accuracy/exact.hpp"
#include "accuracy/kind_reference.hpp"
#include "core/median.hpp"
#include "scene/camera.hpp"
#include "scene/sources.hpp"
#include "scene/scene_transform.hpp"
#include "tracer/accel.hpp"
#include "tracer/profile.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace rb::acc {

namespace {

using reference::LD;
using reference::V3;
V3 vl(const Vec3d& v) { return {LD(v.x), LD(v.y), LD(v.z)}; }
V3 vl(const Vec3f& v) { return {LD(v.x), LD(v.y), LD(v.z)}; }

// The first hit of the whole scene: every primitive's reference (its kind's, accuracy/kind_reference.hpp)
// against the ray, brute force. Its t, and the primitive code (bvh::prim_code). Primitives whose
// bounding sphere (about its box; radius widened by 2^-40 of the largest coordinate of the scene and
// the ray's origin, far more than double's rounding of the ray and of the distance) the ray's line
// misses are skipped, by one pass over them all in double that the compiler vectorises: on a mesh
// of 200k triangles the long double tests run on a few dozen.
struct Reference {
  const scene::Scene& s;
  std::vector<double> cx, cy, cz, rad;  // bounding spheres (rad +inf: unbounded, always tested)
  std::vector<std::uint32_t> codes;
  double coord_max = 0;
  mutable std::vector<std::uint32_t> cand;
  explicit Reference(const scene::Scene& sc) : s(sc) {
    kinds::AllKinds::each([&]<class K>() {
      K::each(s, [&](std::uint32_t i) {
        const scene::Bounds b = K::bounds(s, i);
        codes.push_back(kinds::code(K::id, i));
        if (b.empty() || !std::isfinite(b.lo.x + b.lo.y + b.lo.z + b.hi.x + b.hi.y + b.hi.z)) {
          cx.push_back(0), cy.push_back(0), cz.push_back(0), rad.push_back(HUGE_VAL);
          return;
        }
        const Vec3d c = b.centre(), h = (b.hi - b.lo) * 0.5;
        cx.push_back(c.x), cy.push_back(c.y), cz.push_back(c.z), rad.push_back(std::sqrt(dot(h, h)) * (1 + 0x1p-40));
        coord_max = std::max({coord_max, std::fabs(b.lo.x), std::fabs(b.lo.y), std::fabs(b.lo.z), std::fabs(b.hi.x), std::fabs(b.hi.y),
                              std::fabs(b.hi.z)});
      });
    });
    cand.resize(codes.size());
  }
  bvh::HitRec trace(V3 o, V3 d, LD lo, LD hi, LD& t) const {
    t = reference::kNone;
    std::uint32_t prim = bvh::kNoPrim;
    const reference::Ray r{o, d, lo, hi};
    const double ox = double(o.x), oy = double(o.y), oz = double(o.z), dx = double(d.x), dy = double(d.y), dz = double(d.z);
    const double w = 0x1p-40 * std::max({coord_max, std::fabs(ox), std::fabs(oy), std::fabs(oz)});
    const double dd = dx * dx + dy * dy + dz * dz;
    // The line meets the sphere: |(c - o) x d|^2 <= (r + w)^2 |d|^2.
    std::size_t n = 0;
    const std::size_t N = codes.size();
    for (std::size_t i = 0; i < N; ++i) {
      const double px = cx[i] - ox, py = cy[i] - oy, pz = cz[i] - oz;
      const double qx = py * dz - pz * dy, qy = pz * dx - px * dz, qz = px * dy - py * dx;
      const double rw = rad[i] + w;
      cand[n] = std::uint32_t(i);
      n += qx * qx + qy * qy + qz * qz <= rw * rw * dd;
    }
    for (std::size_t k = 0; k < n; ++k) {  // ascending: kinds in order, each in scene order (ties: the first)
      const std::uint32_t code = codes[cand[k]];
      const LD tt = kinds::AllKinds::at<LD>(kinds::kind_of(code), [&]<class K>() { return reference::first_of<K>(s, kinds::index_of(code), r); });
      if (tt < t) t = tt, prim = code;
    }
    return {float(t), prim};
  }
};

double feature_size(const scene::Scene& s, std::uint32_t code) {
  double f = 0;
  const kinds::Kind k = kinds::kind_of(code);
  kinds::AllKinds::each([&]<class K>() {
    if (K::id == k) f = K::feature(s, kinds::index_of(code)).size;
  });
  return f;
}

double feature_extent(const scene::Scene& s, std::uint32_t code) {
  double f = 0;
  const kinds::Kind k = kinds::kind_of(code);
  kinds::AllKinds::each([&]<class K>() {
    if (K::id == k) f = K::feature(s, kinds::index_of(code)).extent;
  });
  return f;
}

// A hit off the reference's first one that is still right within the plan's representation: the
// model's hit point lies within 2^-12 of the smaller primitive's size of the reference's surface
// (where two surfaces touch, such as a ball resting on a floor, or a ray grazes one, the order of
// hits between surfaces that close is decided by the float rounding of the geometry).
bool near_tie(const scene::Scene& s, const tracer::SceneAccel& a, const Ray<float>& fr, const bvh::HitRec& got, std::uint32_t ref) {
  kinds::HitQuery q;
  q.scene = &s;
  q.origin = a.origin();
  q.ray = fr;
  q.t = got.t;
  q.p = a.world_point(fr, got.t);
  const kinds::Kind k = kinds::kind_of(ref);
  Vec3d on = q.p;
  kinds::AllKinds::each([&]<class K>() {
    if constexpr (!K::custom || std::is_same_v<K, kinds::PolygonKind>)
      if (K::id == k) on = K::surface(q, kinds::index_of(ref)).p;
  });
  const Vec3d gap = q.p - on;
  const double tol = 0x1p-12 * std::min(feature_extent(s, got.prim), feature_extent(s, ref));
  return std::sqrt(dot(gap, gap)) <= tol;
}

}  // namespace

namespace {

// A case: a base scene (a precision scene, or an embedded mesh under Options::data_dir), moved by
// `move` (along a direction with no float coordinates) or scaled by `scale`.
struct SceneCase {
  const char* name;
  const char* what;
  const char* precision = nullptr;  // scene/precision_scenes.cpp's name, or
  const char* mesh = nullptr;       // a file in data_dir/meshes
  double move = 0, scale = 1;
  bool full_only = false;           // `--full` only (the reference's cost on 202k triangles)
};

const std::vector<SceneCase>& scene_case_table() {
  static const std::vector<SceneCase> t = {
      {"ball_ground", "a ball resting on a floor near the origin, a second ball, one light (needs nothing special)", "ball_ground"},
      {"ball_ground_far", "the same scene 6.4e6 from the origin", "ball_ground_far"},
      {"kinds_ground", "the balls with a cylinder, a cone, a mesh (320 triangles) and a torus on their floor", "kinds_ground"},
      {.name = "kinds_ground_far_1e5", .what = "the same 1e5 from the origin", .precision = "kinds_ground", .move = 1e5},
      {.name = "kinds_ground_far_1e7", .what = "the same 1e7 from the origin", .precision = "kinds_ground", .move = 1e7},
      {.name = "kinds_ground_scaled_1e-4", .what = "the same scaled by 1e-4", .precision = "kinds_ground", .scale = 1e-4},
      {"planet", "the balls on a planet of radius 6.4e6, the camera 4 above its surface", "planet"},
      {"mesh_spheres_1e3", "a closed mesh (1,280 triangles), four spheres and a floor, 1e3 from the origin", "mesh_spheres_1e3"},
      {"mesh_spheres_1e5", "the same 1e5 from the origin", "mesh_spheres_1e5"},
      {"mesh_spheres_1e7", "the same 1e7 from the origin", "mesh_spheres_1e7"},
      {"far_spheres", "64 small spheres (radius 0.01..0.1) seen from 5e3 away", "far_spheres"},
      {"thin_torus", "two tori with tubes 100 times thinner than their rings, seen from 500 sizes", "thin_torus"},
      {"far_cylinders", "NFF cylinders and cone frusta seen from 1e4 radii", "far_cylinders"},
      {"mixed_scales", "a planet, a moon 3.8e8 away, a mesh, spheres and a cylinder on the planet", "mixed_scales"},
      {"scanned", "a scanned-like mesh (20,480 triangles, float coordinates) with 3 % slivers and 100 collapsed triangles", "scanned"},
      {"scanned_double", "the same mesh with its coordinates in double", "scanned_double"},
      {"scattered", "230 small meshes, 30 of them in a cluster 3.7e4 from the origin and the rest within 800 of it", "scattered"},
      {"cluster_ground", "balls on a floor 3.7e4 above 200 small meshes near the origin, seen from 200 away", "cluster_ground"},
      {"pipes", "long thin pipes as a CAD export tessellates them (facets 1e4 times longer than wide)", "pipes"},
      {.name = "pipes_far_1e4", .what = "the pipes 1e4 from the origin", .precision = "pipes", .move = 1e4},
      {.name = "scanned_far_1e5", .what = "the scanned-like mesh in double, 1e5 from the origin", .precision = "scanned_double", .move = 1e5},
      {.name = "bunny", .what = "the Stanford bunny (69,451 triangles)", .mesh = "stanford-bunny.obj"},
      {.name = "bunny_far_1e4", .what = "the bunny 1e4 from the origin", .mesh = "stanford-bunny.obj", .move = 1e4},
      {.name = "bunny_far_1e7", .what = "the bunny 1e7 from the origin", .mesh = "stanford-bunny.obj", .move = 1e7},
      {.name = "bunny_scaled_1e-4", .what = "the bunny scaled by 1e-4", .mesh = "stanford-bunny.obj", .scale = 1e-4},
      {.name = "bunny_scaled_1e4", .what = "the bunny scaled by 1e4", .mesh = "stanford-bunny.obj", .scale = 1e4},
      {.name = "dragon", .what = "the Stanford dragon (202,520 triangles; --full)", .mesh = "dragon_vrip_res2_bin.ply", .full_only = true},
      {.name = "dragon_far_1e6", .what = "the dragon 1e6 from the origin (--full)", .mesh = "dragon_vrip_res2_bin.ply", .move = 1e6,
       .full_only = true},
  };
  return t;
}

scene::Scene case_scene(const SceneCase& c, const std::string& data_dir) {
  scene::Scene s = c.precision ? scene::precision_scene(c.precision) : scene::load_scene(data_dir + "/meshes/" + c.mesh);
  if (c.move == 0 && c.scale == 1) return s;
  // The view the scene is seen from, made explicit so that it moves with the scene.
  if (!scene::has_camera(s)) {
    const scene::View v = scene::view_of(s);
    s.camera.from = v.from, s.camera.at = v.from + v.w, s.camera.up = v.v, s.camera.angle = v.angle;
  }
  if (c.scale != 1) s = scene::scaled(s, c.scale);
  if (c.move != 0) s = scene::translated(s, Vec3d{c.move * 1.0000003, 0.31 * c.move + 0.1, -0.57 * c.move});
  return s;
}

// Timed rounds: in each, every model traces its primary rays in 8-ray packets `reps` times, the
// first model of the round turning from round to round; one untimed run each before. `reps` makes
// the fast model's turn last about kWholeSceneTurn (a few thousand rays take well under a
// millisecond, where a timer's and the host's jitter would decide the ratio); a round's figure is
// the seconds of one trace.
void time_rows(std::vector<Row>& rows, const std::vector<tracer::SceneAccel>& accels, const std::vector<RaySoA>& primaries, int timed_rounds) {
  tracer::TraceOptions to;
  to.packet = 8;
  std::vector<bvh::HitRec> hits;
  auto run = [&](std::size_t k, int reps) {
    hits.resize(primaries[k].size());
    const auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) accels[k].trace(primaries[k], 0, primaries[k].size(), hits.data(), to);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / reps;
  };
  const double first = run(0, 1);
  for (std::size_t k = 1; k < accels.size(); ++k) run(k, 1);
  const int reps = int(std::clamp(std::ceil(kWholeSceneTurn / std::max(first, 1e-9)), 1.0, 1000.0));
  for (int round = 0; round < timed_rounds; ++round)
    for (std::size_t i = 0; i < accels.size(); ++i) {
      const std::size_t k = (i + std::size_t(round)) % accels.size();
      rows[k].round_seconds.push_back(run(k, reps));
    }
  for (std::size_t k = 0; k < rows.size(); ++k)
    rows[k].ns_per_test = rb::median(rows[k].round_seconds) * 1e9 / double(std::max<std::size_t>(primaries[k].count, 1));
}

}  // namespace

// A kind's primitives, to time their storage (family "storage"): an embedded mesh under
// Options::data_dir, or an SPD scene at its default size.
struct StorageCase {
  const char* name;
  const char* what;
  kinds::Kind kind;
  const char* mesh = nullptr;
  const char* spd = nullptr;
};

const std::vector<StorageCase>& storage_case_table() {
  static const std::vector<StorageCase> t = {
      {"triangle", "the Stanford bunny's 69,451 triangles in the frame, in local frames, in double", kinds::Kind::triangle,
       "stanford-bunny.obj"},
      {"sphere", "spd:balls' 7,381 spheres in the frame, in local frames, in double", kinds::Kind::sphere, nullptr, "balls"},
  };
  return t;
}

std::vector<CaseInfo> scene_cases() {
  std::vector<CaseInfo> v;
  for (const SceneCase& c : scene_case_table()) v.push_back({"scene", c.name, c.what});
  for (const StorageCase& c : storage_case_table()) v.push_back({"storage", c.name, c.what});
  return v;
}

namespace {

using LabelledPlans = std::vector<std::pair<std::string, tracer::Plan>>;

// A scene traced under each of `plans` (rows in their order, method = the plan's label) against the
// exact reference, then timed in rounds in which the plans take turns.
std::vector<Row> plan_rows(const scene::Scene& s, const tracer::Profile& prof, const char* family, const std::string& case_name,
                           const std::string& what, const LabelledPlans& plans, std::size_t nrays, int timed_rounds, std::uint64_t seed) {
  std::vector<Row> rows;
  const Reference ref{s};
  const scene::View view = scene::view_of(s);
  const double small = prof.object_min > 0 ? prof.object_min : 1.0;
  // Each plan's tree and primary rays, kept for the timed rounds after the accuracy figures.
  std::vector<tracer::SceneAccel> accels;
  std::vector<RaySoA> primaries;
  accels.reserve(plans.size());
  for (const auto& [label, plan] : plans) {
    std::mt19937_64 rng(seed);
    accels.push_back(tracer::SceneAccel::build(s, plan));
    const tracer::SceneAccel& a = accels.back();
    // Primary rays: jittered through the image, the same directions for every model.
    const int side = std::max(4, int(std::sqrt(double(nrays))));
    RaySoA rays;
    for (int py = 0; py < side; ++py)
      for (int px = 0; px < side; ++px) {
        const double u = 2 * (px + urand(rng, 0, 1)) / side - 1, v = 1 - 2 * (py + urand(rng, 0, 1)) / side;
        rays.push(a.frame_ray(view.from, view.dir(u, v)));
      }
    const std::size_t n = rays.count;
    std::vector<bvh::HitRec> hits(rays.size());
    tracer::TraceOptions to;
    to.packet = 8;
    a.trace(rays, 0, rays.size(), hits.data(), to);
    Row r;
    r.family = family, r.case_name = case_name, r.what = what;
    r.method = label;
    r.precision = tracer::frame_name(a.plan().frame);
    r.rays = r.tests = n;
    std::vector<double> err;
    std::size_t spawned = 0;
    RaySoA second;
    std::vector<std::uint32_t> source;
    for (std::size_t i = 0; i < n; ++i) {
      const Ray<float> fr = rays.get(i);
      const V3 o = vl(a.origin()) + vl(fr.o), d = vl(fr.d);
      LD tref;
      const bvh::HitRec h = ref.trace(o, d, LD(fr.tmin), LD(fr.tmax), tref);
      const bool got = hits[i].prim != bvh::kNoPrim, want = h.prim != bvh::kNoPrim;
      if (got && !want) ++r.false_hits;
      if (!got && want) ++r.false_misses;
      if (got && want) {
        const double dt = std::fabs(double(hits[i].t) - double(tref));
        const double tol = 1e-5 * (double(tref) + small);
        if (dt > tol && !near_tie(s, a, fr, hits[i], h.prim)) ++r.wrong_roots;
        err.push_back(dt / (double(std::numeric_limits<float>::epsilon()) * (double(tref) + small)));
      }
      if (!got) continue;
      // The secondary ray: from the model's hit point by its spawn offset, into the hemisphere the
      // primary ray came from.
      const kinds::Surface sf = a.surface(hits[i], fr);
      const Vec3f side_n = dot(sf.ng, fr.d) <= 0.0f ? sf.ng : -sf.ng;
      Vec3d dir = unit_rand(rng);
      if (dot(dir, to_double(side_n)) < 0) dir = dir * -1.0;
      second.push(make_ray(a.spawn_point(sf, side_n), to_float(dir)));
      source.push_back(hits[i].prim);
      ++spawned;
    }
    std::vector<bvh::HitRec> sh(second.size());
    tracer::TraceOptions so;
    if (second.count) a.trace(second, 0, second.size(), sh.data(), so);
    for (std::size_t k = 0; k < second.count; ++k)
      if (sh[k].prim == source[k] && double(sh[k].t) < 1e-4 * feature_size(s, source[k])) ++r.self_hits;
    const double N = double(std::max<std::size_t>(n, 1));
    r.false_hit_ppm = 1e6 * double(r.false_hits) / N;
    r.false_miss_ppm = 1e6 * double(r.false_misses) / N;
    r.wrong_root_ppm = 1e6 * double(r.wrong_roots) / N;
    r.self_hit_ppm = spawned ? 1e6 * double(r.self_hits) / double(spawned) : 0.0;
    r.leak_ppm = r.multi_hit_ppm = r.nan_ppm = std::numeric_limits<double>::quiet_NaN();
    r.iterations = std::numeric_limits<double>::quiet_NaN();
    r.t_err_ulp_p50 = r.t_err_ulp_p99 = r.t_err_ulp_max = std::numeric_limits<double>::quiet_NaN();
    if (!err.empty()) {
      std::sort(err.begin(), err.end());
      r.scaled_err_p99 = err[std::min(err.size() - 1, std::size_t(0.99 * double(err.size())))];
    } else {
      r.scaled_err_p99 = std::numeric_limits<double>::quiet_NaN();
    }
    r.ns_per_test = std::numeric_limits<double>::quiet_NaN();
    rows.push_back(r);
    primaries.push_back(std::move(rays));
  }
  if (timed_rounds > 0) time_rows(rows, accels, primaries, timed_rounds);
  return rows;
}

}  // namespace

std::vector<Row> whole_scene_rows(const scene::Scene& s, const std::string& case_name, const std::string& what, std::size_t nrays,
                                  int timed_rounds, std::uint64_t seed) {
  const tracer::Profile prof = tracer::make_profile(s);
  // The three models, and where the auto model stores primitives apart in local frames, the same
  // plan with them in double (the storage those frames replace: what they cost and save).
  LabelledPlans plans;
  for (tracer::Model m : {tracer::Model::fast, tracer::Model::automatic, tracer::Model::exact})
    plans.emplace_back(tracer::model_name(m), tracer::make_plan(s, prof, m));
  tracer::Plan apart64 = plans[1].second;
  bool local = false;
  for (tracer::KindPlan& kp : apart64.kinds) {
    local = local || (!kp.split.empty() && kp.split_local);
    kp.split_local = false;
  }
  if (local) plans.emplace_back(kApartInDouble, apart64);
  return plan_rows(s, prof, "scene", case_name, what, plans, nrays, timed_rounds, seed);
}

std::vector<Row> storage_rows(const scene::Scene& s, kinds::Kind k, const std::string& case_name, const std::string& what,
                              std::size_t nrays, int timed_rounds, std::uint64_t seed) {
  const tracer::Profile prof = tracer::make_profile(s);
  // The auto plan with the kind whole in its batch, and the same with every primitive of the kind
  // stored apart: in local frames, and in double.
  tracer::Plan whole = tracer::make_plan(s, prof, tracer::Model::automatic);
  tracer::KindPlan& kp = whole.kinds[std::size_t(k)];
  kp.split.clear();
  kp.split_method = kp.method;
  tracer::Plan local = whole, dbl = whole;
  for (tracer::Plan* p : {&local, &dbl}) {
    tracer::KindPlan& x = p->kinds[std::size_t(k)];
    x.split.resize(x.count);
    for (std::size_t i = 0; i < x.count; ++i) x.split[i] = std::uint32_t(i);
    x.split_local = p == &local;
  }
  const LabelledPlans plans = {{kStorageFloat, whole}, {kStorageLocal, local}, {kStorageDouble, dbl}};
  return plan_rows(s, prof, "storage", case_name, what, plans, nrays, timed_rounds, seed);
}

void run_scenes(Ctx& x) {
  for (const SceneCase& c : scene_case_table()) {
    if (!x.selected("scene", c.name)) continue;
    x.tick("scene", c.name);
    if ((c.mesh && (x.o->data_dir.empty() || !x.o->real_meshes)) || (c.full_only && !x.o->full)) continue;
    x.reseed("scene", c.name);
    for (Row& r : whole_scene_rows(case_scene(c, x.o->data_dir), c.name, c.what, x.rays, x.o->timing ? x.o->scene_rounds : 0, x.rng()))
      x.rows->push_back(std::move(r));
  }
  for (const StorageCase& c : storage_case_table()) {
    if (!x.selected("storage", c.name)) continue;
    x.tick("storage", c.name);
    if (c.mesh && (x.o->data_dir.empty() || !x.o->real_meshes)) continue;
    x.reseed("storage", c.name);
    const scene::Scene s = c.mesh ? scene::load_scene(x.o->data_dir + "/meshes/" + c.mesh)
                                  : scene::generate_spd(c.spd, scene::spd_default_size(c.spd));
    for (Row& r : storage_rows(s, c.kind, c.name, c.what, x.rays, x.o->timing ? x.o->scene_rounds : 0, x.rng()))
      x.rows->push_back(std::move(r));
  }
}

}  // namespace rb::acc
