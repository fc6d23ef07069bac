#include "render/render.hpp"

#include "bvh/traverse.hpp"
#include "core/lanes.hpp"
#include "render/batch_order.hpp"
#include "render/hit_lanes.hpp"
#include "render/optics.hpp"
#include "tracer/parallel.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

namespace rb::render {

namespace {

constexpr int kMaxCrossings = 16;  // transmitting occluders followed per shadow ray

// A ray of the ray tree waiting to be traced: the sample it adds to and its weight there.
struct PathRay {
  std::uint32_t sample;
  int depth;
  Vec3f w;
};
// A shadow ray: what its light adds to the sample when nothing opaque is in the way.
struct ShadowRay {
  std::uint32_t sample;
  std::uint32_t light;
  Vec3f add;
};

Vec3f mul(const Vec3f& a, const Vec3f& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void add_to(float* samples, std::uint32_t sample, const Vec3f& c) {
  float* px = samples + 3 * std::size_t(sample);
  px[0] += c.x; px[1] += c.y; px[2] += c.z;
}

}  // namespace

// A tile's rays in flight, reused from tile to tile on each thread (allocation churn cost more
// than shading).
struct Renderer::Work {
  std::vector<Ray<float>> rays, next_rays, srays, more;
  std::vector<PathRay> path, next_path;
  std::vector<ShadowRay> shadow;
  std::vector<bvh::HitRec> hits, sorted_hits;
  std::vector<std::uint32_t> order;  // the order of a batch traced in packets
  std::vector<std::uint64_t> keys;    // its sort keys (RenderOptions::Order::sfc)
  std::vector<std::uint32_t> bucket;  // the octant order's buckets per ray
  std::vector<std::size_t> buckets;   // and where each begins
  std::vector<std::uint32_t> light;   // the light of each shadow ray being traced
  std::vector<float> pass;
  avec<double> dx, dy, dz;  // the eye rays' directions (world), before they are made
  std::vector<std::uint32_t> live, more_live;
  RaySoA soa;
  HitLanes lanes;  // the generation's hits, shaded in lanes
  std::size_t gen = 0;  // the generation being traced (0: the eye rays)
};

RenderOptions spd_options(const scene::Scene& s, int width, int height, int depth) {
  RenderOptions o;
  o.width = width;
  o.height = height;
  o.depth = depth;
  o.spd = true;
  o.count_tests = true;  // his counts are the protocol's point
  // Haines: "all opaque objects are one-sided, except the teapot's patches".
  o.two_sided = s.name.find("teapot") != std::string::npos;
  return o;
}

Vec3f surface_color(const scene::Material& m, const Vec3d& p) {
  if (!(m.checker > 0)) return m.color;
  const double c = double(m.checker);
  // Beyond 2^62 cells (and for NaN) a cell counts as even, as every double that large is: no
  // overflowing cast.
  const auto cell = [&](double x) {
    const double f = std::floor(x / c);
    return std::fabs(f) < 0x1p62 ? static_cast<long long>(f) : 0LL;
  };
  const long long parity = cell(p.x) + cell(p.y) + cell(p.z);
  return (parity & 1) ? m.color2 : m.color;
}

namespace {
tracer::RayKey frame_key(const scene::Scene& s, const tracer::SceneAccel& a) {
  const scene::Bounds b = s.bounds();
  return tracer::RayKey(a.to_frame(b.lo), a.to_frame(b.hi));
}
}  // namespace

Renderer::Renderer(const scene::Scene& s, const tracer::SceneAccel& a, const RenderOptions& o)
    : s_(s), a_(a), o_(o), key_(frame_key(s, a)) {
  if (o.width < 1 || o.height < 1 || o.width > 16384 || o.height > 16384)
    throw std::invalid_argument("image size " + std::to_string(o.width) + " x " + std::to_string(o.height) +
                                " is outside 1 .. 16384");
  if (o.depth < 1 || o.depth > 64) throw std::invalid_argument("depth " + std::to_string(o.depth) + " is outside 1 .. 64");
  if (o.tile < 1 || o.tile > 1024) throw std::invalid_argument("tile size is outside 1 .. 1024");
  gw_ = o.width + (o.spd ? 1 : 0);
  gh_ = o.height + (o.spd ? 1 : 0);
  tx_ = (gw_ + o.tile - 1) / o.tile;
  ty_ = (gh_ + o.tile - 1) / o.tile;
  // The camera (scene/camera.hpp). Image plane at distance 1: the larger side spans 2 tan(angle / 2)
  // from pixel edge to edge (centres) or from the first to the last corner (SPD).
  view_ = scene::view_of(s);
  step_ = 2.0 / double(std::max(o.width, o.height));
  const double off = o.spd ? 0.0 : 0.5;
  x0_ = off - 0.5 * double(o.width);
  y0_ = off - 0.5 * double(o.height);

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
    light_pos_.push_back(view_.from);
    light_col_.push_back(Vec3f{1, 1, 1});
  }
  for (const auto& p : light_pos_) light_frame_.push_back(a_.to_frame(p));
}

// Eye rays, row-major in the tile: neighbours on a row (and the rows below them) form a packet. NFF's hither plane is for
// scan converters: not used. Made eight at a time (each the frame_ray of its direction, bit for bit)
// straight into the SoA batch the first trace() takes; those that hit are copied to w.rays for
// shading after it (hit_rays). The directions are computed one by one into arrays first and read
// as lanes in a loop of their own: read right after they were written, each 4-lane load would wait
// for four stores to reach the cache (a store-forwarding stall per half packet).
void Renderer::eye_rays(int x0, int y0, int x1, int y1, Work& w) const {
  const std::size_t tw = std::size_t(x1 - x0), n = tw * std::size_t(y1 - y0);
  w.rays.clear();
  w.path.clear();
  RaySoA& soa = w.soa;
  soa.resize(n);
  for (auto* a : {&w.dx, &w.dy, &w.dz}) a->resize(soa.size());
  std::size_t i = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x, ++i) {
      const Vec3d v = view_.dir((x0_ + double(x)) * step_, -(y0_ + double(y)) * step_);
      w.dx[i] = v.x, w.dy[i] = v.y, w.dz[i] = v.z;
      w.path.push_back({std::uint32_t(y * gw_ + x), 1, Vec3f{1, 1, 1}});
    }
  for (; i < soa.size(); ++i) w.dx[i] = w.dy[i] = w.dz[i] = 0.0;  // padding: a zero direction, the invalid ray
  const Vec3d from = view_.from - a_.origin();
  const Vec3<d4> o[2] = {Vec3<d4>::from(from), Vec3<d4>::from(from)};
  for (std::size_t k = 0; k < soa.size(); k += 8) {
    const Vec3<d4> dir[2] = {{load<d4>(&w.dx[k]), load<d4>(&w.dy[k]), load<d4>(&w.dz[k])},
                             {load<d4>(&w.dx[k + 4]), load<d4>(&w.dy[k + 4]), load<d4>(&w.dz[k + 4])}};
    soa.store_packet(k, lanes::make_rays(o, dir));
  }
  w.rays.resize(n);
}

// The eye rays that hit, copied from the SoA batch to the records shading reads (a miss only adds
// the background). Shading reads each ray as one record: the same Ray read back from the SoA's
// arrays there would be written to memory field by field and read whole, a store-forwarding stall
// per hit; copied in a loop of their own, the stores are done before shading reads them.
void Renderer::hit_rays(Work& w) const {
  for (std::size_t k = 0; k < w.rays.size(); ++k)
    if (w.hits[k].prim != bvh::kNoPrim) w.rays[k] = w.soa.get(k);
}

// RT_trace for a batch: the closest (or any) hit of every ray (the eye rays, not `secondary`, are in
// the SoA batch already: eye_rays() made them there).
// Secondary rays in packets (of 8, or 16) are traced in octant order and their hits put back in
// the batch's order, so that shading (and the sum of each sample's terms) runs in the same order
// in every mode: the image does not depend on the packet size (but where a ray meets two faces at
// the same distance: which one wins can depend on the traversal order).
void Renderer::trace(Work& w, const std::vector<Ray<float>>& rays, bool any, bool secondary, bool shadow, RenderStats& st,
                     GenerationStats& g) const {
  const auto t0 = Clock::now();
  tracer::TraceOptions to;
  to.packet = secondary ? o_.packet_for(w.gen, shadow) : o_.eye_packet;
  to.any = any;
  to.lanes = kRenderLanes;
  w.order.clear();
  if (secondary && to.packet >= 8 && o_.secondary_order == RenderOptions::Order::octant) {
    octant_pack(rays, w.soa, w.order, w.bucket, w.buckets, shadow ? w.light.data() : nullptr, shadow ? light_pos_.size() : 1);
  } else if (secondary) {
    if (to.packet >= 8) key_order(rays, key_, w.keys, w.order);
    fill(w.soa, rays, w.order.empty() ? nullptr : w.order.data());
  }
  const bool sorted = !w.order.empty();
  std::uint64_t coherent = 0, groups = 0;
  for (std::size_t i = 0; i < w.soa.size(); i += 8, ++groups) coherent += bvh::shared_octant(w.soa, i, 8);
  (shadow ? g.shadow_groups : g.groups) += groups;
  (shadow ? g.shadow_coherent_groups : g.coherent_groups) += coherent;
  if (o_.keep_rays) {
    std::vector<Ray<float>>& kept = shadow ? g.kept_shadow : g.kept;
    for (std::size_t i = 0; i < w.soa.count; ++i) kept.push_back(w.soa.get(i));
  }
  const auto t1 = Clock::now();
  std::vector<bvh::HitRec>& out = sorted ? w.sorted_hits : w.hits;
  out.resize(w.soa.size());
  if (o_.count_tests) a_.trace_counted(w.soa, 0, w.soa.size(), out.data(), to, st.cost);
  else a_.trace(w.soa, 0, w.soa.size(), out.data(), to);
  if (sorted) {
    w.hits.resize(w.soa.size());
    for (std::size_t i = 0; i < rays.size(); ++i) w.hits[w.order[i]] = out[i];
  }
  const double packed = std::chrono::duration<double>(t1 - t0).count(), s = seconds_since(t0);
  (!secondary ? st.eye_trace_s : shadow && w.gen == 0 ? st.eye_shadow_trace_s : st.secondary_trace_s) += s;
  g.pack_s += packed;
  (shadow ? g.shadow_traverse_s : g.traverse_s) += s - packed;
}

// RT_shade for every ray of the generation, in three passes over its hits:
//  1. one hit at a time: the background on a miss; else the surface (its point, normals and
//     material), the ambient term, and the hit's row in the SoA lanes;
//  2. eight hits at a time (optics.hpp): per light its direction (in double: world points) and
//     local light (Lambert + Phong, in float); the mirror direction, the refracted direction (in
//     double), and where the shadow, mirror and refracted rays start (the plan's spawn scheme);
//  3. one hit at a time, in the order of pass 1: a shadow ray per light the surface faces (their
//     light is added by shadows()) and below the depth limit the reflection and refraction rays of
//     the next generation.
// Each lane computes what one hit shaded alone computes, bit for bit, and sums and rays come in
// the same order: the image does not depend on where a hit falls in the lanes.
void Renderer::shade(float* samples, Work& w, RenderStats& st) const {
  w.next_path.clear();
  w.next_rays.clear();
  w.shadow.clear();
  w.srays.clear();
  const std::size_t lights = light_pos_.size();
  HitLanes& h = w.lanes;
  h.reset(w.rays.size(), lights);
  for (std::size_t i = 0; i < w.rays.size(); ++i) {
    const PathRay& pr = w.path[i];
    const Ray<float>& r = w.rays[i];
    if (w.hits[i].prim == bvh::kNoPrim) {
      add_to(samples, pr.sample, mul(pr.w, s_.background));
      continue;
    }
    if (pr.depth == 1) ++st.eye_hit;
    const kinds::Surface sf = a_.surface(w.hits[i], r);
    const scene::Material& m = mats_[sf.mat < mats_.size() ? sf.mat : 0];
    const Vec3f base = surface_color(m, sf.p);
    const bool front = dot(sf.ng, r.d) <= 0.0f;  // the ray arrives on the side ng points to
    const Vec3f ng_in = front ? sf.ng : -sf.ng;  // normals turned towards the incoming ray
    const Vec3f ns_in = front ? sf.ns : -sf.ns;
    // The normals of the light test: one-sided opaque surfaces keep theirs.
    const bool two = o_.two_sided || m.t > 0;
    add_to(samples, pr.sample, mul(pr.w, base * (o_.ambient * m.kd)));
    const std::size_t k = h.n++;
    h.ray[k] = std::uint32_t(i);
    h.mat[k] = &m;
    h.px[k] = sf.p.x, h.py[k] = sf.p.y, h.pz[k] = sf.p.z;
    h.eta[k] = !(m.t > 0.0f) ? 1.0 : front ? 1.0 / double(m.ior) : double(m.ior) / 1.0;
    h.nl.set(k, two ? ns_in : sf.ns);
    h.ns.set(k, ns_in);
    h.d.set(k, r.d);
    h.base.set(k, base);
    h.kd[k] = m.kd, h.ks[k] = m.ks, h.shine[k] = m.shine;
    const tracer::SceneAccel::SpawnBase sb = a_.spawn_base(sf);
    h.bp.set(k, sb.p);
    h.err.set(k, sb.err);
    h.ng.set(k, sb.ng);
    h.ng_in.set(k, ng_in);
    h.ngl.set(k, two ? ng_in : sf.ng);
  }
  const std::size_t n = h.n;
  h.pad();
  for (std::size_t k = 0; k < n; k += 8) {
    const Vec3<f8> nl = h.nl.load8(k), ns = h.ns.load8(k), d = h.d.load8(k), base = h.base.load8(k);
    const f8 kd = load<f8>(&h.kd[k]), ks = load<f8>(&h.ks[k]), shine = load<f8>(&h.shine[k]);
    for (std::size_t l = 0; l < lights; ++l) {
      alignas(kSimdAlign) float L[3][8];
      for (std::size_t j = 0; j < 8; j += 4) {  // the direction to the light, in double
        const Vec3<d4> p{load<d4>(&h.px[k + j]), load<d4>(&h.py[k + j]), load<d4>(&h.pz[k + j])};
        const Vec3<d4> to = Vec3<d4>::from(light_pos_[l]) - p;
        const Vec3<d4> u = to * (d4(1.0) / vsqrt(dot_fma(to, to)));  // NaN at the light: no light
        store(L[0] + j, u.x), store(L[1] + j, u.y), store(L[2] + j, u.z);
      }
      Vec3<f8> local;
      const std::size_t at = l * h.stride + k;
      store(&h.ndl[at], local_light<f8>({load<f8>(L[0]), load<f8>(L[1]), load<f8>(L[2])}, nl, -d, kd, ks, shine, base, local));
      h.local.store8(at, local);
    }
    for (std::size_t j = 0; j < 8; j += 4) {  // Snell, in double
      Vec3<d4> t;
      const Vec3<d4> dd{load<d4>(&h.d.x[k + j]), load<d4>(&h.d.y[k + j]), load<d4>(&h.d.z[k + j])};
      const Vec3<d4> nn{load<d4>(&h.ns.x[k + j]), load<d4>(&h.ns.y[k + j]), load<d4>(&h.ns.z[k + j])};
      const d4 kk = refract_k(dd, nn, load<d4>(&h.eta[k + j]), t);
      store(&h.dt.x[k + j], t.x), store(&h.dt.y[k + j], t.y), store(&h.dt.z[k + j], t.z);
      store(&h.tok[k + j], vselect(kk >= d4(0.0), d4(1.0), d4(0.0)));
    }
    // Every ray leaves on the side of the geometric normal (towards the ray) it goes to; shadow
    // rays on the light test's side.
    const Vec3<f8> dr = reflect(d, ns), dt = h.dt.load8(k), ng_in = h.ng_in.load8(k);
    const Vec3<f8> bp = h.bp.load8(k), err = h.err.load8(k), ng = h.ng.load8(k);
    auto side = [&](const Vec3<f8>& dir) { return vselect3(dot_fma(dir, ng_in) < f8(0.0f), -ng_in, ng_in); };
    h.dr.store8(k, dr);
    h.from_shadow.store8(k, a_.spawn_point(bp, err, ng, h.ngl.load8(k)));
    h.from_mirror.store8(k, a_.spawn_point(bp, err, ng, side(dr)));
    h.from_refracted.store8(k, a_.spawn_point(bp, err, ng, side(dt)));
  }
  for (std::size_t k = 0; k < n; ++k) {
    const PathRay& pr = w.path[h.ray[k]];
    const scene::Material& m = *h.mat[k];
    // Lights: each behind a shadow ray from the surface to the light, in the frame.
    for (std::size_t l = 0; l < lights; ++l) {
      const std::size_t at = l * h.stride + k;
      if (!(h.ndl[at] > 0.0f)) continue;
      const Vec3f o = h.from_shadow.get(k);
      w.shadow.push_back({pr.sample, std::uint32_t(l), mul(mul(pr.w, light_col_[l]), h.local.get(at))});
      w.srays.push_back(make_ray(o, light_frame_[l] - o, 0.0f, 1.0f - 1e-6f));
    }
    // Reflection and refraction below the depth limit.
    if (pr.depth >= o_.depth) continue;
    const bool reflective = m.ks > 0.0f, transmits = m.t > 0.0f;
    bool tir = false;
    if (transmits) {
      if (h.tok[k] > 0.0f) {
        w.next_rays.push_back(make_ray(h.from_refracted.get(k), h.dt.get(k)));
        w.next_path.push_back({pr.sample, pr.depth + 1, pr.w * m.t});
        ++st.refract;
      } else {
        tir = true;
      }
    }
    const float kr = m.ks + (tir ? m.t : 0.0f);
    if (o_.spd ? (reflective || transmits) : kr > 0.0f) {
      w.next_rays.push_back(make_ray(h.from_mirror.get(k), h.dr.get(k)));
      w.next_path.push_back({pr.sample, pr.depth + 1, pr.w * kr});
      ++st.reflect;
    }
  }
}

// The shadow rays of a generation: any hit blocks, unless the scene has transmitting materials:
// then the closest occluder is found, a transmitting one scales the light by its T and the ray
// goes on from beyond it.
void Renderer::shadows(float* samples, Work& w, RenderStats& st, GenerationStats& g) const {
  const auto t0 = Clock::now();
  const double traced0 = g.pack_s + g.shadow_traverse_s;
  st.shadow += w.srays.size();
  g.shadow_rays += w.srays.size();
  auto& cur = w.srays;
  w.pass.assign(w.srays.size(), 1.0f);
  w.live.resize(w.srays.size());
  for (std::size_t i = 0; i < w.srays.size(); ++i) w.live[i] = std::uint32_t(i);
  for (int round = 0; !cur.empty(); ++round) {
    w.light.resize(cur.size());
    for (std::size_t k = 0; k < cur.size(); ++k) w.light[k] = w.shadow[w.live[k]].light;
    trace(w, cur, !transparent_, true, true, st, g);
    w.more.clear();
    w.more_live.clear();
    for (std::size_t k = 0; k < cur.size(); ++k) {
      const std::uint32_t j = w.live[k];
      if (w.hits[k].prim == bvh::kNoPrim) continue;
      if (!transparent_) { w.pass[j] = 0.0f; continue; }
      // The occluder's material first: an opaque one ends the ray without its surface.
      const std::uint32_t mi = a_.material(w.hits[k], cur[k]);
      const scene::Material& m = mats_[mi < mats_.size() ? mi : 0];
      w.pass[j] *= m.t;
      if (!(m.t > 0.0f) || round + 1 >= kMaxCrossings) { w.pass[j] = m.t > 0.0f ? w.pass[j] : 0.0f; continue; }
      // Go on from just beyond the occluder to the light.
      const kinds::Surface sf = a_.surface(w.hits[k], cur[k]);
      const Vec3f end = cur[k].o + cur[k].d * cur[k].tmax;
      const Vec3f o = a_.spawn_point(sf, cur[k].d);
      const Vec3f d = end - o;
      if (!(dot(d, cur[k].d) > 0.0f)) continue;
      w.more.push_back(make_ray(o, d, 0.0f, 1.0f));
      w.more_live.push_back(j);
    }
    cur.swap(w.more);
    w.live.swap(w.more_live);
  }
  for (std::size_t i = 0; i < w.shadow.size(); ++i)
    if (w.pass[i] > 0.0f) add_to(samples, w.shadow[i].sample, w.shadow[i].add * w.pass[i]);
  g.shadow_light_s += seconds_since(t0) - (g.pack_s + g.shadow_traverse_s - traced0);
}

void Renderer::render_tile(std::size_t t, float* samples, RenderStats& st) const {
  const int tx = int(t % std::size_t(tx_)), ty = int(t / std::size_t(tx_));
  const int x0 = tx * o_.tile, y0 = ty * o_.tile;
  const int x1 = std::min(gw_, x0 + o_.tile), y1 = std::min(gh_, y0 + o_.tile);
  thread_local Work w;
  const auto t0 = Clock::now();
  eye_rays(x0, y0, x1, y1, w);
  st.generate_s += seconds_since(t0);
  st.eye += w.rays.size();
  for (std::size_t gen = 0; !w.rays.empty(); ++gen) {
    GenerationStats& g = st.generation(gen);
    w.gen = gen;
    g.rays += w.rays.size();
    trace(w, w.rays, false, gen > 0, false, st, g);
    if (gen == 0) {
      const auto tc = Clock::now();
      hit_rays(w);
      st.generate_s += seconds_since(tc);
    }
    for (std::size_t i = 0; i < w.rays.size(); ++i) g.hits += w.hits[i].prim != bvh::kNoPrim;
    const auto t1 = Clock::now();
    shade(samples, w, st);
    g.shade_s += seconds_since(t1);
    shadows(samples, w, st, g);
    w.rays.swap(w.next_rays);
    w.path.swap(w.next_path);
  }
}

tracer::RayFile Renderer::kept_rays(const RenderStats& st) const {
  tracer::RayFile f;
  for (std::size_t g = 0; g < st.generations.size(); ++g) {
    const GenerationStats& x = st.generations[g];
    tracer::RaySection rays{g == 0 ? "eye" : "secondary", int(g + 1), false, g == 0 ? o_.eye_packet : o_.packet_for(g, false), x.kept};
    tracer::RaySection shadow{"shadow", int(g + 1), !transparent_, o_.packet_for(g, true), x.kept_shadow};
    for (auto* s : {&rays, &shadow})
      if (!s->rays.empty()) f.sections.push_back(std::move(*s));
  }
  return f;
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
  tracer::ThreadScope ts(threads);
  ts.parallel_for(mine.size(), 1, [&](std::size_t i) {
    r.render_tile(mine[i], samples.data(), per[i]);
    const std::size_t d = ++done;
    if (progress && std::this_thread::get_id() == caller) progress(d, mine.size());
  });
  if (progress) progress(mine.size(), mine.size());
  RenderStats st;
  for (const auto& p : per) st.add(p);
  return st;
}

std::vector<std::uint8_t> render_rgb8(const scene::Scene& s, tracer::Model m, int size, int threads) {
  const tracer::SceneAccel a = tracer::SceneAccel::build(s, tracer::make_plan(s, m));
  RenderOptions o;
  o.width = o.height = size;
  const Renderer r(s, a, o);
  std::vector<float> samples;
  render_tiles(r, samples, threads);
  return to_rgb8(r.resolve(samples));
}

double differing_pixels(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, int tolerance) {
  std::size_t bad = 0;
  const std::size_t pixels = std::min(a.size(), b.size()) / 3;
  for (std::size_t p = 0; p < pixels; ++p) {
    int worst = 0;
    for (std::size_t c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(a[3 * p + c]) - int(b[3 * p + c])));
    bad += worst > tolerance;
  }
  return double(bad) / double(std::max<std::size_t>(1, pixels));
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
