#include "render/render.hpp"

#include "render/optics.hpp"
#include "render/surface.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <xmmintrin.h>
#include <pmmintrin.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

namespace rb::render {

namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();
constexpr int kMaxCrossings = 16;  // transmitting occluders followed per shadow ray

Vec3d unit_d(const Vec3d& a) {
  const double l = std::sqrt(dot(a, a));
  return l > 0 ? a * (1.0 / l) : a;
}

bool has_camera(const scene::Scene& s) {
  const scene::Camera d{};
  const auto& c = s.camera;
  return !(c.from.x == d.from.x && c.from.y == d.from.y && c.from.z == d.from.z && c.at.x == d.at.x && c.at.y == d.at.y &&
           c.at.z == d.at.z);
}

// Writes rays into a RaySoA in one go (RaySoA::push appends one at a time), padded to 8 lanes with
// invalid rays.
void fill(RaySoA& soa, const std::vector<Ray<float>>& rays) {
  const std::size_t n = rays.size(), padded = round_up(std::max<std::size_t>(n, 1), kPadLanes);
  for (auto* a : {&soa.ox, &soa.oy, &soa.oz, &soa.dx, &soa.dy, &soa.dz, &soa.rx, &soa.ry, &soa.rz, &soa.tmin, &soa.tmax})
    a->resize(padded);
  const Ray<float> invalid = make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 0});
  for (std::size_t i = 0; i < padded; ++i) {
    const Ray<float>& r = i < n ? rays[i] : invalid;
    soa.ox[i] = r.o.x; soa.oy[i] = r.o.y; soa.oz[i] = r.o.z;
    soa.dx[i] = r.d.x; soa.dy[i] = r.d.y; soa.dz[i] = r.d.z;
    soa.rx[i] = r.rd.x; soa.ry[i] = r.rd.y; soa.rz[i] = r.rd.z;
    soa.tmin[i] = r.tmin; soa.tmax[i] = r.tmax;
  }
  soa.count = n;
}

// A ray of the ray tree waiting to be traced: the sample it adds to and its weight there.
struct PathRay {
  std::uint32_t sample;
  int depth;
  Vec3f w;
};
// A shadow ray: what its light adds to the sample when nothing opaque is in the way.
struct ShadowRay {
  std::uint32_t sample;
  Vec3f add;
};

Vec3f mul(const Vec3f& a, const Vec3f& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }

// Reorders rays (and their payload, in step) by direction octant, stably: the BVH traces 8
// consecutive rays as one packet only when they share an octant, and a generation interleaves
// reflection with refraction rays and each hit's shadow rays towards different lights.
template <class P>
void sort_by_octant(std::vector<Ray<float>>& rays, std::vector<P>& payload, std::vector<Ray<float>>& tmp_r, std::vector<P>& tmp_p) {
  std::size_t count[9] = {};
  auto oct = [](const Ray<float>& r) { return std::size_t((r.d.x < 0) | (r.d.y < 0) << 1 | (r.d.z < 0) << 2); };
  for (const auto& r : rays) ++count[oct(r) + 1];
  if (std::count(count + 1, count + 9, rays.size()) == 1) return;  // one octant: nothing to do
  for (int k = 1; k < 9; ++k) count[k] += count[k - 1];
  tmp_r.resize(rays.size());
  tmp_p.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const std::size_t at = count[oct(rays[i])]++;
    tmp_r[at] = rays[i];
    tmp_p[at] = payload[i];
  }
  rays.swap(tmp_r);
  payload.swap(tmp_p);
}

}  // namespace

RenderOptions spd_options(const scene::Scene& s, int width, int height, int depth) {
  RenderOptions o;
  o.width = width;
  o.height = height;
  o.depth = depth;
  o.spd = true;
  // Haines: "all opaque objects are one-sided, except the teapot's patches".
  o.two_sided = s.name.find("teapot") != std::string::npos;
  return o;
}

Renderer::Renderer(const scene::Scene& s, const bvh::Accel& a, const RenderOptions& o) : s_(s), a_(a), o_(o) {
  if (o.width < 1 || o.height < 1 || o.width > 16384 || o.height > 16384)
    throw std::invalid_argument("image size " + std::to_string(o.width) + " x " + std::to_string(o.height) +
                                " is outside 1 .. 16384");
  if (o.depth < 1 || o.depth > 64) throw std::invalid_argument("depth " + std::to_string(o.depth) + " is outside 1 .. 64");
  if (o.tile < 1 || o.tile > 1024) throw std::invalid_argument("tile size is outside 1 .. 1024");
  gw_ = o.width + (o.spd ? 1 : 0);
  gh_ = o.height + (o.spd ? 1 : 0);
  tx_ = (gw_ + o.tile - 1) / o.tile;
  ty_ = (gh_ + o.tile - 1) / o.tile;

  // Camera: the scene's (NFF `v`: angle is the full field of view across the larger image side),
  // or for scenes without one the stated camera of `raybench trace`.
  const scene::Bounds b = s.bounds();
  Vec3d lo{-1, -1, -1}, hi{1, 1, 1};
  if (!b.empty()) lo = to_double(b.lo), hi = to_double(b.hi);
  const Vec3d centre = (lo + hi) * 0.5;
  double angle;
  if (has_camera(s)) {
    from_ = to_double(s.camera.from);
    w_ = unit_d(to_double(s.camera.at) - from_);
    angle = double(s.camera.angle);
    Vec3d u = cross(w_, to_double(s.camera.up));
    if (dot(u, u) == 0) u = cross(w_, Vec3d{0, 1, 0});
    if (dot(u, u) == 0) u = cross(w_, Vec3d{1, 0, 0});
    u_ = unit_d(u);
  } else {
    angle = 45;
    const Vec3d dir = unit_d(Vec3d{0.3, 0.4, -1.0});
    const double h = 0.5 * std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    from_ = centre + dir * (h / std::tan(angle * M_PI / 360.0) + h);
    w_ = dir * -1.0;
    u_ = unit_d(cross(w_, Vec3d{0, 1, 0}));
  }
  if (!(angle > 0 && angle < 180)) angle = 45;
  v_ = cross(u_, w_);
  // Image plane at distance 1: the larger side spans 2 tan(angle / 2) from pixel edge to edge
  // (centres) or from the first to the last corner (SPD).
  const double half = std::tan(angle * M_PI / 360.0);
  const double step = 2.0 * half / double(std::max(o.width, o.height));
  u_ = u_ * step;
  v_ = v_ * -step;  // rows go down
  const double off = o.spd ? 0.0 : 0.5;
  x0_ = off - 0.5 * double(o.width);
  y0_ = off - 0.5 * double(o.height);

  const double ext = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, std::fabs(lo.x), std::fabs(lo.y), std::fabs(lo.z),
                               std::fabs(hi.x), std::fabs(hi.y), std::fabs(hi.z)});
  eps_ = float(std::max(1e-5 * ext, 1e-7));

  mats_ = s.materials;
  if (mats_.empty()) mats_.push_back(scene::Material{});
  transparent_ = false;
  for (const auto& m : mats_) transparent_ = transparent_ || m.t > 0;
  // NFF: each light's intensity is 1 / sqrt(number of lights); a scene without lights gets one
  // at the eye.
  const float li = s.lights.empty() ? 1.0f : float(1.0 / std::sqrt(double(s.lights.size())));
  for (const auto& L : s.lights) {
    light_pos_.push_back(L.pos);
    light_col_.push_back(L.color * li);
  }
  if (s.lights.empty()) {
    light_pos_.push_back(to_float(from_));
    light_col_.push_back(Vec3f{1, 1, 1});
  }
}

void Renderer::render_tile(std::size_t t, float* samples, RenderStats& st) const {
  const int tx = int(t % std::size_t(tx_)), ty = int(t / std::size_t(tx_));
  const int x0 = tx * o_.tile, y0 = ty * o_.tile;
  const int x1 = std::min(gw_, x0 + o_.tile), y1 = std::min(gh_, y0 + o_.tile);

  // Per-thread scratch arrays, reused from tile to tile (allocation churn cost more than shading).
  struct Scratch {
    std::vector<Ray<float>> rays, next_rays, srays, more;
    std::vector<PathRay> path, next_path;
    std::vector<ShadowRay> shadow;
    std::vector<bvh::HitRec> hits;
    std::vector<float> pass;
    std::vector<std::uint32_t> live, more_live;
    std::vector<Ray<float>> tmp_r;
    std::vector<PathRay> tmp_path;
    std::vector<ShadowRay> tmp_shadow;
    RaySoA soa;
  };
  thread_local Scratch sc;
  auto& rays = sc.rays;
  auto& next_rays = sc.next_rays;
  auto& srays = sc.srays;
  auto& path = sc.path;
  auto& next_path = sc.next_path;
  auto& shadow = sc.shadow;
  auto& hits = sc.hits;
  auto& soa = sc.soa;
  rays.clear();
  path.clear();
  rays.reserve(std::size_t(x1 - x0) * std::size_t(y1 - y0));

  // Eye rays, row-major in the tile: 8 neighbours on a row form a packet.
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const Vec3d d = w_ + u_ * (x0_ + double(x)) + v_ * (y0_ + double(y));
      rays.push_back(make_ray(to_float(from_), to_float(d)));  // NFF's hither plane is for scan converters: not used
      path.push_back({std::uint32_t(y * gw_ + x), 1, Vec3f{1, 1, 1}});
    }
  st.eye += rays.size();

  bvh::TraceOptions closest;
  closest.packet = 8;
  bvh::TraceOptions second = closest;
  second.packet = o_.secondary_packet == 8 ? 8 : 1;
  const bool sort = second.packet == 8;
  bvh::TraceOptions any = second;
  any.any = true;

  auto trace = [&](const RaySoA& batch, std::vector<bvh::HitRec>& out, const bvh::TraceOptions& to, RenderStats& s) {
    if (o_.count_tests) a_.trace_counted(batch, 0, batch.size(), out.data(), to, s.cost);
    else a_.trace(batch, 0, batch.size(), out.data(), to);
  };
  auto add = [&](std::uint32_t sample, const Vec3f& c) {
    float* px = samples + 3 * std::size_t(sample);
    px[0] += c.x; px[1] += c.y; px[2] += c.z;
  };

  while (!rays.empty()) {
    fill(soa, rays);
    hits.resize(soa.size());
    trace(soa, hits, path.empty() || path[0].depth == 1 ? closest : second, st);
    next_path.clear();
    next_rays.clear();
    shadow.clear();
    srays.clear();
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const PathRay& pr = path[i];
      const Ray<float>& r = rays[i];
      if (hits[i].prim == bvh::kNoPrim) {
        add(pr.sample, mul(pr.w, s_.background));
        continue;
      }
      if (pr.depth == 1) ++st.eye_hit;
      const Surface sf = surface_at(s_, hits[i].prim, r, hits[i].t);
      const scene::Material& m = mats_[sf.mat < mats_.size() ? sf.mat : 0];
      const Vec3f base = surface_color(m, sf.p);
      const bool front = dot(sf.ng, r.d) <= 0.0f;  // the ray arrives on the side ng points to
      const Vec3f ng_in = front ? sf.ng : -sf.ng;  // normals turned towards the incoming ray
      const Vec3f ns_in = front ? sf.ns : -sf.ns;
      // The normal of the light test: one-sided opaque surfaces keep theirs.
      const bool two = o_.two_sided || m.t > 0;
      const Vec3f nl = two ? ns_in : sf.ns;
      const Vec3f ngl = two ? ng_in : sf.ng;

      // Ambient.
      add(pr.sample, mul(pr.w, base * (o_.ambient * m.kd)));
      // Lights: Lambert + Phong, each behind a shadow ray.
      const Vec3f view = -r.d;
      for (std::size_t l = 0; l < light_pos_.size(); ++l) {
        const Vec3f to = light_pos_[l] - sf.p;
        const float dist = length(to);
        if (!(dist > 0.0f)) continue;
        const Vec3f L = to * (1.0f / dist);
        const float ndl = dot(nl, L);
        if (!(ndl > 0.0f)) continue;
        float spec = 0.0f;
        if (m.ks > 0.0f) {
          const float rv = dot(reflect(-L, nl), view);
          if (rv > 0.0f) spec = m.ks * std::pow(rv, m.shine);
        }
        const Vec3f local = base * (m.kd * ndl) + Vec3f{spec, spec, spec};
        const Vec3f o = sf.p + ngl * eps_;
        shadow.push_back({pr.sample, mul(mul(pr.w, light_col_[l]), local)});
        srays.push_back(make_ray(o, light_pos_[l] - o, 0.0f, 1.0f - 1e-6f));
      }
      // Reflection and refraction below the depth limit.
      if (pr.depth >= o_.depth) continue;
      const bool reflective = m.ks > 0.0f, transmits = m.t > 0.0f;
      bool tir = false;
      if (transmits) {
        const float eta_i = front ? 1.0f : m.ior, eta_t = front ? m.ior : 1.0f;
        const auto dt = refract(r.d, ns_in, eta_i, eta_t);
        if (dt) {
          const Vec3f o = sf.p + (dot(*dt, ng_in) < 0.0f ? -ng_in : ng_in) * eps_;
          next_rays.push_back(make_ray(o, *dt));
          next_path.push_back({pr.sample, pr.depth + 1, pr.w * m.t});
          ++st.refract;
        } else {
          tir = true;
        }
      }
      const float kr = m.ks + (tir ? m.t : 0.0f);
      if (o_.spd ? (reflective || transmits) : kr > 0.0f) {
        const Vec3f dr = reflect(r.d, ns_in);
        const Vec3f o = sf.p + (dot(dr, ng_in) < 0.0f ? -ng_in : ng_in) * eps_;
        next_rays.push_back(make_ray(o, dr));
        next_path.push_back({pr.sample, pr.depth + 1, pr.w * kr});
        ++st.reflect;
      }
    }

    // Shadow rays: any hit blocks, unless the scene has transmitting materials: then the closest
    // occluder is found, a transmitting one scales the light by its T and the ray goes on.
    st.shadow += srays.size();
    if (sort) sort_by_octant(srays, shadow, sc.tmp_r, sc.tmp_shadow);
    auto& pass = sc.pass;
    auto& live = sc.live;
    auto& cur = srays;
    auto& more = sc.more;
    auto& more_live = sc.more_live;
    pass.assign(srays.size(), 1.0f);
    live.resize(srays.size());
    for (std::size_t i = 0; i < srays.size(); ++i) live[i] = std::uint32_t(i);
    for (int round = 0; !cur.empty(); ++round) {
      fill(soa, cur);
      hits.resize(soa.size());
      trace(soa, hits, transparent_ ? second : any, st);
      more.clear();
      more_live.clear();
      for (std::size_t k = 0; k < cur.size(); ++k) {
        const std::uint32_t j = live[k];
        if (hits[k].prim == bvh::kNoPrim) continue;
        if (!transparent_) { pass[j] = 0.0f; continue; }
        const Surface sf = surface_at(s_, hits[k].prim, cur[k], hits[k].t);
        const scene::Material& m = mats_[sf.mat < mats_.size() ? sf.mat : 0];
        pass[j] *= m.t;
        if (!(m.t > 0.0f) || round + 1 >= kMaxCrossings) { pass[j] = m.t > 0.0f ? pass[j] : 0.0f; continue; }
        // Go on from just beyond the occluder to the light.
        const Vec3f end = cur[k].o + cur[k].d * cur[k].tmax;
        const Vec3f o = sf.p + cur[k].d * eps_;
        const Vec3f d = end - o;
        if (!(dot(d, cur[k].d) > 0.0f)) continue;
        more.push_back(make_ray(o, d, 0.0f, 1.0f));
        more_live.push_back(j);
      }
      cur.swap(more);
      live.swap(more_live);
    }
    for (std::size_t i = 0; i < shadow.size(); ++i)
      if (pass[i] > 0.0f) add(shadow[i].sample, shadow[i].add * pass[i]);

    rays.swap(next_rays);
    path.swap(next_path);
    if (sort) sort_by_octant(rays, path, sc.tmp_r, sc.tmp_path);
  }
}

std::vector<float> Renderer::resolve(const std::vector<float>& samples) const {
  if (!o_.spd) return samples;
  std::vector<float> img(std::size_t(o_.width) * std::size_t(o_.height) * 3);
  for (int y = 0; y < o_.height; ++y)
    for (int x = 0; x < o_.width; ++x)
      for (int c = 0; c < 3; ++c) {
        auto at = [&](int xx, int yy) { return samples[3 * (std::size_t(yy) * std::size_t(gw_) + std::size_t(xx)) + std::size_t(c)]; };
        img[3 * (std::size_t(y) * std::size_t(o_.width) + std::size_t(x)) + std::size_t(c)] =
            0.25f * ((at(x, y) + at(x + 1, y)) + (at(x, y + 1) + at(x + 1, y + 1)));
      }
  return img;
}

RenderStats render_tiles(const Renderer& r, std::vector<float>& samples, int threads, int part, int parts,
                         const std::function<void(std::size_t, std::size_t)>& progress) {
  if (parts < 1 || part < 0 || part >= parts) throw std::invalid_argument("render_tiles: bad part");
  samples.assign(r.samples() * 3, 0.0f);
  std::vector<std::size_t> mine;
  for (std::size_t t = std::size_t(part); t < r.tiles(); t += std::size_t(parts)) mine.push_back(t);
  std::vector<RenderStats> per(mine.size());
  std::atomic<std::size_t> done{0};
  const auto caller = std::this_thread::get_id();
  tbb::task_arena arena(std::max(1, threads));
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mine.size(), 1), [&](const tbb::blocked_range<std::size_t>& br) {
      // The same floating-point environment on every thread (as `raybench trace` sets it).
      _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
      _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
      for (std::size_t i = br.begin(); i != br.end(); ++i) {
        r.render_tile(mine[i], samples.data(), per[i]);
        const std::size_t d = ++done;
        if (progress && std::this_thread::get_id() == caller) progress(d, mine.size());
      }
    });
  });
  if (progress) progress(mine.size(), mine.size());
  RenderStats st;
  for (const auto& p : per) st.add(p);
  return st;
}

std::vector<std::uint8_t> to_rgb8(const std::vector<float>& rgb) {
  std::vector<std::uint8_t> out(rgb.size());
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    const float v = std::isnan(rgb[i]) ? 0.0f : std::clamp(rgb[i], 0.0f, 1.0f);
    out[i] = std::uint8_t(std::lround(v * 255.0f));
  }
  return out;
}

}  // namespace rb::render
