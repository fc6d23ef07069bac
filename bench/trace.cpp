#include "bench/trace.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include <pmmintrin.h>
#include <unistd.h>
#include <xmmintrin.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <stdexcept>

namespace rb::trace {

using bvh::HitRec;
using bvh::kNoPrim;

const char* ray_set_name(RaySet s) {
  switch (s) {
    case RaySet::primary: return "primary";
    case RaySet::shadow: return "shadow";
    case RaySet::diffuse: return "diffuse";
    case RaySet::random: return "random";
  }
  return "?";
}
RaySet parse_ray_set(const std::string& s) {
  for (RaySet r : {RaySet::primary, RaySet::shadow, RaySet::diffuse, RaySet::random})
    if (s == ray_set_name(r)) return r;
  throw std::invalid_argument("unknown ray set '" + s + "' (primary, shadow, diffuse, random)");
}

namespace {
void set_ftz() {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

struct Frame {
  Vec3d from, u, v, w;  // w: view direction; u, v: image plane axes scaled to the half-size at distance 1
};

bool has_camera(const scene::Scene& s) {
  const scene::Camera d{};
  const auto& c = s.camera;
  return !(c.from.x == d.from.x && c.from.y == d.from.y && c.from.z == d.from.z && c.at.x == d.at.x && c.at.y == d.at.y &&
           c.at.z == d.at.z);
}

Vec3d unit(Vec3d a) { return a * (1.0 / std::sqrt(dot(a, a))); }
}  // namespace

RaySoA make_rays(const scene::Scene& s, const bvh::Accel& accel, RaySet set, std::size_t count, std::uint64_t seed, RaySetInfo* info) {
  RaySoA rays;
  const scene::Bounds b = s.bounds();
  if (b.empty() || count == 0) {
    rays.push(Vec3f{0, 0, 0}, Vec3f{0, 0, 1});  // one ray into an empty scene: a defined miss
    return rays;
  }
  const Vec3d lo = to_double(b.lo), hi = to_double(b.hi);
  const Vec3d centre = (lo + hi) * 0.5;
  const double R = std::max(1e-30, 0.5 * std::sqrt(dot(hi - lo, hi - lo)));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  RaySetInfo local;
  RaySetInfo& inf = info ? *info : local;

  if (set == RaySet::random) {
    rays.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
      const Vec3d o{lo.x + (hi.x - lo.x) * U(rng), lo.y + (hi.y - lo.y) * U(rng), lo.z + (hi.z - lo.z) * U(rng)};
      const double z = 2 * U(rng) - 1, ph = 2 * M_PI * U(rng), rr = std::sqrt(std::max(0.0, 1 - z * z));
      rays.push(to_float(o), to_float(Vec3d{rr * std::cos(ph), rr * std::sin(ph), z}));
    }
    return rays;
  }

  // The camera.
  Frame f;
  double angle;
  if (has_camera(s)) {
    inf.camera = "scene";
    f.from = to_double(s.camera.from);
    f.w = unit(to_double(s.camera.at) - f.from);
    angle = double(s.camera.angle);
    Vec3d up = to_double(s.camera.up);
    f.u = cross(f.w, up);
    if (dot(f.u, f.u) == 0) f.u = cross(f.w, Vec3d{0, 1, 0});
    f.u = unit(f.u);
    f.v = cross(f.u, f.w);
  } else {
    inf.camera = "stated";
    angle = 45;
    const Vec3d dir = unit(Vec3d{0.3, 0.4, -1.0});
    // The bounding box's largest half extent h fills the view: distance h / tan(angle / 2) + h.
    const double h = 0.5 * std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    f.from = centre + dir * (h / std::tan(angle * M_PI / 360.0) + h);
    f.w = dir * -1.0;
    f.u = unit(cross(f.w, Vec3d{0, 1, 0}));
    f.v = cross(f.u, f.w);
  }
  const double half = std::tan(angle * M_PI / 360.0);
  int side = int(std::ceil(std::sqrt(double(count)) / 4.0)) * 4;
  side = std::max(side, 4);
  inf.width = inf.height = side;
  RaySoA prim;
  prim.reserve(std::size_t(side) * std::size_t(side));
  for (int ty = 0; ty < side; ty += 4)
    for (int tx = 0; tx < side; tx += 4)
      for (int y = ty; y < ty + 4; ++y)
        for (int x = tx; x < tx + 4; ++x) {
          const double px = (2 * (x + U(rng)) / side - 1) * half, py = (1 - 2 * (y + U(rng)) / side) * half;
          prim.push(to_float(f.from), to_float(f.w + f.u * px + f.v * py));
        }
  if (set == RaySet::primary) return prim;

  // Primary hits.
  std::vector<HitRec> hits(prim.size());
  bvh::TraceOptions o;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, prim.size() / 16), [&](const tbb::blocked_range<std::size_t>& r) {
    accel.trace(prim, r.begin() * 16, r.end() * 16, hits.data(), o);
  });
  Vec3d light;
  if (!s.lights.empty()) {
    inf.light = "scene";
    light = to_double(s.lights[0].pos);
  } else {
    inf.light = "stated";
    light = centre + unit(Vec3d{0.5, 1.0, -0.7}) * (2 * R);
  }
  const double eps = 1e-4 * R;
  rays.reserve(prim.count);
  for (std::size_t i = 0; i < prim.count; ++i) {
    if (hits[i].prim == kNoPrim) continue;
    const Ray<float> r = prim.get(i);
    const Vec3d p = to_double(r.o) + to_double(r.d) * double(hits[i].t);
    if (set == RaySet::shadow) {
      const Vec3d d = light - p;
      const double len = std::sqrt(dot(d, d));
      if (!(len > 2 * eps)) continue;
      rays.push(to_float(p), to_float(d * (1.0 / len)), float(eps), float(len * 0.9999));
      continue;
    }
    // diffuse: geometric normal facing the incoming ray.
    Vec3d n = to_double(r.d) * -1.0;
    const auto kind = scene::Kind(hits[i].prim >> bvh::kKindShift);
    const std::uint32_t idx = hits[i].prim & bvh::kGroupMask;
    if (kind == scene::Kind::triangle) {
      const auto& t = s.triangles[idx];
      const Vec3d a = to_double(s.verts[t.v[0]]);
      n = cross(to_double(s.verts[t.v[1]]) - a, to_double(s.verts[t.v[2]]) - a);
    } else if (kind == scene::Kind::sphere) {
      n = p - to_double(s.spheres[idx].c);
    }
    if (!(dot(n, n) > 0)) n = to_double(r.d) * -1.0;
    n = unit(n);
    if (dot(n, to_double(r.d)) > 0) n = n * -1.0;
    const Vec3d t1 = unit(std::fabs(n.x) > 0.5 ? cross(n, Vec3d{0, 1, 0}) : cross(n, Vec3d{1, 0, 0}));
    const Vec3d t2 = cross(n, t1);
    const double u1 = U(rng), u2 = U(rng), rr = std::sqrt(u1), ph = 2 * M_PI * u2;
    const Vec3d d = t1 * (rr * std::cos(ph)) + t2 * (rr * std::sin(ph)) + n * std::sqrt(std::max(0.0, 1 - u1));
    rays.push(to_float(p), to_float(d), float(eps));
  }
  if (rays.count == 0) rays.push(Vec3f{0, 0, 0}, Vec3f{0, 0, 0});  // no hits: one invalid ray
  return rays;
}

namespace {
struct FtzObserver : tbb::task_scheduler_observer {
  explicit FtzObserver(tbb::task_arena& a) : tbb::task_scheduler_observer(a) { observe(true); }
  ~FtzObserver() override { observe(false); }
  void on_scheduler_entry(bool) override { set_ftz(); }
};
}  // namespace

struct ThreadScope::Impl {
  tbb::task_arena arena;
  std::unique_ptr<FtzObserver> obs;
  explicit Impl(int threads) : arena(threads) {
    arena.initialize();
    obs = std::make_unique<FtzObserver>(arena);
  }
};

ThreadScope::ThreadScope(int threads) : impl(new Impl(std::max(1, threads))) { set_ftz(); }
ThreadScope::~ThreadScope() { delete impl; }
void ThreadScope::run_fn(const std::function<void()>& f) {
  impl->arena.execute([&] {
    set_ftz();
    f();
  });
}

std::vector<double> time_runs(ThreadScope& ts, const Tracer& t, std::size_t rays, std::vector<HitRec>& out, int reps, std::size_t tile,
                              const std::function<void(int, int)>& progress) {
  out.resize(round_up(rays, 16));
  const std::size_t tiles = (rays + tile - 1) / tile;
  std::vector<double> secs;
  for (int r = 0; r < reps; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    ts.run([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tiles, 1), [&](const tbb::blocked_range<std::size_t>& br) {
        for (std::size_t k = br.begin(); k < br.end(); ++k) t(k * tile, std::min(rays, (k + 1) * tile), out.data());
      });
    });
    secs.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    if (progress) progress(r + 1, reps);
  }
  return secs;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

Compare compare(const std::vector<HitRec>& a, const std::vector<HitRec>& b, std::size_t n, bool any, float rel_tol) {
  Compare c;
  c.rays = n;
  for (std::size_t i = 0; i < n; ++i) {
    const bool ha = a[i].prim != kNoPrim, hb = b[i].prim != kNoPrim;
    if (ha != hb) { ++c.mismatches; continue; }
    if (!ha || any) continue;
    const float tol = rel_tol * std::max(1.0f, std::fabs(a[i].t));
    if (std::fabs(a[i].t - b[i].t) > tol) { ++c.mismatches; continue; }
    if (a[i].prim != b[i].prim) ++c.other_prim;
  }
  return c;
}

Progress::Progress(std::string l) : label(std::move(l)), tty(isatty(2) != 0) {}
void Progress::update(double fraction) {
  if (!tty) return;
  const int w = 30, k = int(fraction * w + 0.5);
  std::fprintf(stderr, "\r%-40.40s [%.*s%*s] %3d%%", label.c_str(), k, "##############################", w - k, "", int(fraction * 100 + 0.5));
  std::fflush(stderr);
}
void Progress::done() {
  if (!tty) return;
  std::fprintf(stderr, "\r%*s\r", 80, "");
  std::fflush(stderr);
}

}  // namespace rb::trace
