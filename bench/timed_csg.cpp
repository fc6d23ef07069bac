#include "bench/timed_csg.hpp"

#include "core/median.hpp"

#include <cmath>
#include <random>
#include <vector>

#include <time.h>

namespace rb::bench {

namespace {
// CPU time of this thread: on a shared machine a time slice given to another process is not
// counted (wall time was dominated by preemption while other builds ran).
double thread_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}
}  // namespace

// Rays from a sphere twice the size of the object's box towards random points inside the box.
RaySoA csg_rays(const CsgTree& T, std::size_t n, unsigned seed) {
  const CsgNode& b = T.nodes[T.root];
  const Vec3d lo{b.lo[0], b.lo[1], b.lo[2]}, hi{b.hi[0], b.hi[1], b.hi[2]};
  const Vec3d c = (lo + hi) * 0.5, e = (hi - lo) * 0.5;
  const double R = 2.0 * std::sqrt(dot(e, e));
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  RaySoA rays;
  while (rays.size() < n) {
    const Vec3d s{u(g), u(g), u(g)};
    const double l = std::sqrt(dot(s, s));
    if (l > 1 || l < 1e-3) continue;
    const Vec3d o = c + s * (R / l);
    const Vec3d t = c + Vec3d{e.x * u(g), e.y * u(g), e.z * u(g)};
    rays.push(make_ray(o, t - o));
  }
  return rays;
}

// Primary rays of the scene's camera over a w x h image, row by row: 8 consecutive rays are 8
// neighbouring pixels (coherent packets).
RaySoA camera_rays(const scene::Camera& c, int w, int h) {
  const Vec3d from = to_double(c.from), fwd0 = to_double(c.at) - from;
  const Vec3d fwd = fwd0 * (1.0 / std::sqrt(dot(fwd0, fwd0)));
  Vec3d right = cross(fwd, to_double(c.up));
  right = right * (1.0 / std::sqrt(dot(right, right)));
  const Vec3d up = cross(right, fwd);
  const double half = std::tan(double(c.angle) * 3.14159265358979323846 / 360.0);
  RaySoA rays;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double u = (2.0 * (x + 0.5) / w - 1.0) * half, v = (1.0 - 2.0 * (y + 0.5) / h) * half;
      rays.push(make_ray(from, fwd + right * u + up * v));
    }
  return rays;
}

CsgSpeed time_csg_queries(const CsgTree& T, const RaySoA& rays, int repetitions) {
  CsgSpeed r;
  r.n = rays.size() / 8 * 8;
  std::vector<double> ts, tp;
  for (int rep = 0; rep < repetitions; ++rep) {
    const double t0 = thread_seconds();
    std::size_t h = 0;
    for (std::size_t i = 0; i < r.n; ++i) {
      float tag;
      const Hit<float> q = csg_hit(T, rays.get(i), tag);
      h += q.mask;
      r.sink += q.mask ? double(q.t) : 0.0;
    }
    const double t1 = thread_seconds();
    std::size_t h8 = 0;
    for (std::size_t i = 0; i < r.n; i += 8) {
      f8 tag;
      const Hit<f8> q = csg_hit8(T, rays.packet<f8>(i), tag);
      h8 += std::size_t(count_true<f8>(q.mask));
      r.sink += double(lane(q.t, 0) < kInf<float> ? lane(q.t, 0) : 0.0f);
    }
    const double t2 = thread_seconds();
    ts.push_back(t1 - t0);
    tp.push_back(t2 - t1);
    r.hits = h;
    r.hits8 = h8;
  }
  r.scalar = double(r.n) / rb::median(ts);
  r.simd = double(r.n) / rb::median(tp);
  return r;
}

}  // namespace rb::bench
