#include "tracer/ray_sets.hpp"

#include "core/fpenv.hpp"
#include "core/par.hpp"
#include "scene/camera.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace rb::tracer {

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

bool is_ray_set_name(const std::string& s) {
  for (const char* n : kRaySetNames)
    if (s == n) return true;
  return false;
}

namespace {
Vec3d unit(Vec3d a) { return a * (1.0 / std::sqrt(dot(a, a))); }
}  // namespace

RaySoA make_rays(const scene::Scene& s, const SceneAccel& accel, RaySet set, std::size_t count, std::uint64_t seed,
                 RaySetInfo* info) {
  RaySoA rays;
  const scene::Bounds b = s.bounds();
  if (b.empty() || count == 0) {
    rays.push(Vec3f{0, 0, 0}, Vec3f{0, 0, 1});  // one ray into an empty scene: a defined miss
    return rays;
  }
  const Vec3d lo = b.lo, hi = b.hi;
  const Vec3d centre = (lo + hi) * 0.5;
  const double R = std::max(1e-30, 0.5 * std::sqrt(dot(hi - lo, hi - lo)));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  RaySetInfo local;
  RaySetInfo& inf = info ? *info : local;
  auto push = [&](RaySoA& soa, const Vec3d& o, const Vec3d& d, double tmin = 0, double tmax = std::numeric_limits<double>::infinity()) {
    soa.push(accel.frame_ray(o, d, tmin, tmax));
  };

  if (set == RaySet::random) {
    rays.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
      const Vec3d o{lo.x + (hi.x - lo.x) * U(rng), lo.y + (hi.y - lo.y) * U(rng), lo.z + (hi.z - lo.z) * U(rng)};
      const double z = 2 * U(rng) - 1, ph = 2 * M_PI * U(rng), rr = std::sqrt(std::max(0.0, 1 - z * z));
      push(rays, o, Vec3d{rr * std::cos(ph), rr * std::sin(ph), z});
    }
    return rays;
  }

  // The camera (scene/camera.hpp): jittered pixel centres of a square image, in 4x4 pixel tiles.
  const scene::View view = scene::view_of(s);
  inf.camera = view.stated ? "stated" : "scene";
  int side = int(std::ceil(std::sqrt(double(count)) / 16.0)) * 16;
  side = std::max(side, 16);
  inf.width = inf.height = side;
  RaySoA prim;
  prim.reserve(std::size_t(side) * std::size_t(side));
  for (int by = 0; by < side; by += 16)
    for (int bx = 0; bx < side; bx += 16)
      for (int q = 0; q < 16; ++q) {  // the 4x4 tiles of a 16x16 block in Z order
        const int tx = bx + 4 * ((q & 1) | (q >> 1 & 2)), ty = by + 4 * ((q >> 1 & 1) | (q >> 2 & 2));
        for (int y = ty; y < ty + 4; ++y)
          for (int x = tx; x < tx + 4; ++x) {
            const double px = 2 * (x + U(rng)) / side - 1, py = 1 - 2 * (y + U(rng)) / side;
            push(prim, view.from, view.dir(px, py));
          }
      }
  if (set == RaySet::primary) return prim;

  // Primary hits.
  std::vector<HitRec> hits(prim.size());
  TraceOptions o;
  // Each task traces in the tracer's floating-point environment (FTZ/DAZ, core/fpenv.hpp) whatever
  // thread runs it, and gives the thread its own back: the hits, and so the rays made from them, are
  // the same for any thread count.
  par::for_range(0, prim.size() / 16, 1, [&](std::size_t first, std::size_t last) {
    const FtzScope ftz;
    accel.trace(prim, first * 16, last * 16, hits.data(), o);
  });
  Vec3d light;
  if (!s.lights.empty()) {
    inf.light = "scene";
    light = s.lights[0].pos;
  } else {
    inf.light = "stated";
    light = centre + unit(Vec3d{0.5, 1.0, -0.7}) * (2 * R);
  }
  const double eps = 1e-4 * R;
  rays.reserve(prim.count);
  for (std::size_t i = 0; i < prim.count; ++i) {
    if (hits[i].prim == kNoPrim) continue;
    const Ray<float> r = prim.get(i);
    const Vec3d p = accel.world_point(r, hits[i].t);
    if (set == RaySet::shadow) {
      const Vec3d d = light - p;
      const double len = std::sqrt(dot(d, d));
      if (!(len > 2 * eps)) continue;
      push(rays, p, d * (1.0 / len), eps, len * 0.9999);
      continue;
    }
    // diffuse: about the geometric normal facing the incoming ray.
    Vec3d n = to_double(accel.surface(hits[i], r).ng);
    if (!(dot(n, n) > 0)) n = to_double(r.d) * -1.0;
    n = unit(n);
    if (dot(n, to_double(r.d)) > 0) n = n * -1.0;
    const Vec3d t1 = unit(std::fabs(n.x) > 0.5 ? cross(n, Vec3d{0, 1, 0}) : cross(n, Vec3d{1, 0, 0}));
    const Vec3d t2 = cross(n, t1);
    const double u1 = U(rng), u2 = U(rng), rr = std::sqrt(u1), ph = 2 * M_PI * u2;
    const Vec3d d = t1 * (rr * std::cos(ph)) + t2 * (rr * std::sin(ph)) + n * std::sqrt(std::max(0.0, 1 - u1));
    push(rays, p, d, eps);
  }
  if (rays.count == 0) rays.push(Vec3f{0, 0, 0}, Vec3f{0, 0, 0});  // no hits: one invalid ray
  return rays;
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

}  // namespace rb::tracer
