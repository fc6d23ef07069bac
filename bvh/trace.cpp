// Traversal of bvh::Accel: single rays and packets, binary and 8-wide, closest and any hit, fast
// and robust slab tests. Each combination is one instantiation of the templates below, chosen
// once per range of rays, so the hot loops carry no run-time switches but the leaf's kind.
#include "bvh/accel.hpp"
#include "bvh/slab.hpp"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rb::bvh {

using scene::Kind;

namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();
constexpr int kStack = 1024;

inline f8 safe_rcp8(const f8& d) {
  const f8 m = xsimd::select(xsimd::abs(d) < f8(kMinDir), xsimd::copysign(f8(kMinDir), d), d);
  return f8(1.0f) / m;
}

inline unsigned movemask(const f8_mask& m) { return unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_castps_si256(m)))); }
// Smallest lane and its index.
inline int argmin8(const f8& t, float& best) {
  const __m256 v = t;
  __m256 m = _mm256_min_ps(v, _mm256_permute_ps(v, 0xB1));
  m = _mm256_min_ps(m, _mm256_permute_ps(m, 0x4E));
  m = _mm256_min_ps(m, _mm256_permute2f128_ps(m, m, 1));
  best = _mm256_cvtss_f32(m);
  const unsigned bits = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(v, m, _CMP_EQ_OQ)));
  return bits ? __builtin_ctz(bits) : 0;
}
inline float hmin8(const f8& t) {
  float b;
  argmin8(t, b);
  return b;
}
inline float hmax8(const f8& t) {
  const __m256 v = t;
  __m256 m = _mm256_max_ps(v, _mm256_permute_ps(v, 0xB1));
  m = _mm256_max_ps(m, _mm256_permute_ps(m, 0x4E));
  m = _mm256_max_ps(m, _mm256_permute2f128_ps(m, m, 1));
  return _mm256_cvtss_f32(m);
}

struct Entry {
  std::uint32_t ref;
  float d;
};

// Sorts `n` (>= 2) entries by distance, farthest first (so the nearest is popped first).
inline void sort_far_first(Entry* e, int n) {
  for (int i = 1; i < n; ++i) {
    const Entry x = e[i];
    int j = i - 1;
    while (j >= 0 && e[j].d < x.d) { e[j + 1] = e[j]; --j; }
    e[j + 1] = x;
  }
}

template <class X>
RB_INLINE Hit<f8> cyl_hit(const Ray<f8>& r, const X& x) {
  return intersect_transformed(r, x, [](const Ray<f8>& l, const Cylinder<f8>& p) { return intersect_cylinder(l, p); });
}
template <class X>
RB_INLINE Hit<f8> cone_hit(const Ray<f8>& r, const X& x) {
  return intersect_transformed(r, x, [](const Ray<f8>& l, const Cone<f8>& p) { return intersect_cone(l, p); });
}

// ---- one ray against one 8-slot group (primitives in lanes) ------------------------------------
// B is Accel or BruteForce (same member names). Returns true on a hit closer than h.t; updates h
// and rb.tmax (closest) or only h (any).
// The ray broadcast to 8 lanes and its Woop precompute, made at the first leaf a ray reaches
// (most rays of a sparse view never reach one).
struct LeafRay {
  Ray<f8> rb{};
  WoopRay<f8> w{};
  bool ready = false;
  RB_INLINE void prepare(const Ray<float>& r, float tmax) {
    if (ready) return;
    rb = Ray<f8>::broadcast(r);
    rb.tmax = f8(tmax);
    w = make_woop_ray(rb);
    ready = true;
  }
};

template <bool Count, class B>
RB_INLINE bool group1(const B& a, int kind, std::size_t base, const Ray<float>& r, LeafRay& lr, HitRec& h, TraceCounters& c) {
  lr.prepare(r, h.t);
  Ray<f8>& rb = lr.rb;
  const WoopRay<f8>& w = lr.w;
  Hit<f8> hit;
  const auto& ids = a.id[kind];
  if constexpr (Count) {
    std::uint64_t n = 0;
    for (std::size_t j = 0; j < 8; ++j) n += ids[base + j] != UINT32_MAX;
    c.prims += n;
    c.kind_prims[kind] += n;
  }
  switch (Kind(kind)) {
    case Kind::triangle: hit = intersect_triangle_woop(w, rb, a.tri.template load<f8>(base)); break;
    case Kind::sphere: hit = intersect_sphere_geometric(rb, a.sph.template load<f8>(base)); break;
    case Kind::cylinder: hit = cyl_hit(rb, a.cyl.template load<f8>(base)); break;
    case Kind::cone: hit = cone_hit(rb, a.cone.template load<f8>(base)); break;
    case Kind::polygon: {
      bool any = false;
      Ray<float> rr = r;
      rr.tmax = h.t;
      for (std::size_t j = 0; j < 8; ++j) {
        std::uint32_t slot;
        if constexpr (std::is_same_v<B, Accel>) slot = a.poly_slot[base + j];
        else slot = base + j < a.poly.size() && a.poly.id[base + j] != UINT32_MAX ? std::uint32_t(base + j) : UINT32_MAX;
        if (slot == UINT32_MAX) continue;
        const Hit<float> hp = intersect_polygon(rr, a.poly.template broadcast<float>(slot));
        if (hp.mask && hp.t <= rr.tmax) {
          rr.tmax = hp.t;
          h.t = hp.t;
          const std::uint32_t sid = std::is_same_v<B, Accel> ? ids[base + j] : a.poly.id[slot];
          h.prim = prim_code(Kind::polygon, sid);
          any = true;
        }
      }
      if (any) rb.tmax = f8(h.t);
      return any;
    }
    case Kind::csg: {
      // A CSG tree per slot, one ray at a time (the scalar query with its early exits).
      bool any = false;
      Ray<float> rr = r;
      rr.tmax = h.t;
      for (std::size_t j = 0; j < 8; ++j) {
        const std::uint32_t sid = base + j < ids.size() ? ids[base + j] : UINT32_MAX;
        if (sid == UINT32_MAX) continue;
        float tag;
        const Hit<float> hc = csg_hit(*a.csg[sid], rr, tag);
        if (hc.mask && hc.t <= rr.tmax) {
          rr.tmax = hc.t;
          h.t = hc.t;
          h.prim = prim_code(Kind::csg, sid);
          any = true;
        }
      }
      if (any) rb.tmax = f8(h.t);
      return any;
    }
  }
  if (none_of<f8>(hit.mask)) return false;
  float t;
  const int lane = argmin8(hit.t, t);
  h.t = t;
  h.prim = prim_code(Kind(kind), ids[base + std::size_t(lane)]);
  rb.tmax = f8(t);
  return true;
}

// ---- the traversal stack, shared by the single-ray traversals ---------------------------------
// Pops entries until one is not beyond the current hit (NaN distances are kept, as `d > t` is
// false for them); false when the stack runs empty.
RB_INLINE bool pop_nearer(const Entry* stack, int& sp, float t, std::uint32_t& ref) {
  while (sp > 0) {
    --sp;
    if (!(stack[sp].d > t)) {
      ref = stack[sp].ref;
      return true;
    }
  }
  return false;
}
// The finished hit: t = +inf when nothing was hit (the contract of Hit).
RB_INLINE HitRec finished(HitRec h) {
  if (h.prim == kNoPrim) h.t = kInfF;
  return h;
}

// ---- single ray, 8-wide ------------------------------------------------------------------------
template <bool Robust, bool Any, bool Count>
HitRec trace1_wide(const Accel& a, const Ray<float>& r, TraceCounters& c) {
  HitRec h{r.tmax, kNoPrim};
  if (!(r.tmin <= r.tmax) || a.wide.nodes.empty()) return {kInfF, kNoPrim};
  const SlabRay sr = SlabRay::make(r);
  LeafRay lr;
  Entry stack[kStack];
  int sp = 0;
  std::uint32_t ref = 0;
  for (;;) {
    if (!is_leaf(ref)) {
      const WNode& n = a.wide.nodes[ref];
      if constexpr (Count) {
        ++c.nodes;
        for (int k = 0; k < 8; ++k) c.boxes += n.child[k] != kEmpty;
      }
      f8 tn;
      unsigned bits = slab8<Robust>(n, sr, h.t, tn);
      if (bits == 0) goto pop;
      if ((bits & (bits - 1)) == 0) {
        ref = n.child[__builtin_ctz(bits)];
        continue;
      }
      alignas(32) float dist[8];
      tn.store_aligned(dist);
      Entry e[8];
      int ne = 0;
      while (bits) {
        const int k = __builtin_ctz(bits);
        bits &= bits - 1;
        e[ne++] = {n.child[k], dist[k]};
      }
      sort_far_first(e, ne);
      for (int k = 0; k < ne - 1; ++k) stack[sp++] = e[k];
      ref = e[ne - 1].ref;
      continue;
    }
    if (group1<Count>(a, leaf_kind(ref), std::size_t(leaf_group(ref)) * 8, r, lr, h, c) && Any) return h;
  pop:
    if (!pop_nearer(stack, sp, h.t, ref)) return finished(h);
  }
}

// ---- single ray, binary ------------------------------------------------------------------------
template <bool Robust>
RB_INLINE bool slab1(const BNode& n, const Vec3f& o, const Vec3f& rd, const Vec3f& ord, float tmin, float tmax, float& tn) {
  float t0[3], t1[3];
  const float* lo = n.lo;
  const float* hi = n.hi;
  const float ov[3] = {o.x, o.y, o.z}, rv[3] = {rd.x, rd.y, rd.z}, orv[3] = {ord.x, ord.y, ord.z};
  for (int k = 0; k < 3; ++k) {
    if constexpr (Robust) {
      t0[k] = (lo[k] - ov[k]) * rv[k];
      t1[k] = (hi[k] - ov[k]) * rv[k];
    } else {
      t0[k] = std::fma(lo[k], rv[k], -orv[k]);
      t1[k] = std::fma(hi[k], rv[k], -orv[k]);
    }
  }
  float a = tmin, b = kInfF;
  for (int k = 0; k < 3; ++k) {
    const float near = t0[k] < t1[k] ? t0[k] : t1[k], far = t0[k] < t1[k] ? t1[k] : t0[k];
    a = near > a ? near : a;
    b = far < b ? far : b;
  }
  if constexpr (Robust) b *= kRobustScale;
  b = b < tmax ? b : tmax;
  tn = a;
  return a <= b;
}

template <bool Robust, bool Any, bool Count>
HitRec trace1_binary(const Accel& a, const Ray<float>& r, TraceCounters& c) {
  HitRec h{r.tmax, kNoPrim};
  if (!(r.tmin <= r.tmax) || a.bin.nodes.empty()) return {kInfF, kNoPrim};
  const Vec3f rd{safe_rcp(r.d.x), safe_rcp(r.d.y), safe_rcp(r.d.z)};
  const Vec3f ord{r.o.x * rd.x, r.o.y * rd.y, r.o.z * rd.z};
  LeafRay lr;
  Entry stack[kStack];
  int sp = 0;
  const BNode* nodes = a.bin.nodes.data();
  float t_root;
  if (!slab1<Robust>(nodes[0], r.o, rd, ord, r.tmin, r.tmax, t_root)) return {kInfF, kNoPrim};
  std::uint32_t ni = 0;
  for (;;) {
    const BNode& n = nodes[ni];
    if (!n.leaf()) {
      if constexpr (Count) { ++c.nodes; c.boxes += 2; }
      float d0, d1;
      const bool h0 = slab1<Robust>(nodes[n.first], r.o, rd, ord, r.tmin, h.t, d0);
      const bool h1 = slab1<Robust>(nodes[n.first + 1], r.o, rd, ord, r.tmin, h.t, d1);
      if (h0 && h1) {
        if (d0 <= d1) { stack[sp++] = {n.first + 1, d1}; ni = n.first; }
        else { stack[sp++] = {n.first, d0}; ni = n.first + 1; }
        continue;
      }
      if (h0) { ni = n.first; continue; }
      if (h1) { ni = n.first + 1; continue; }
    } else if (group1<Count>(a, n.kind, std::size_t(n.first) * 8, r, lr, h, c) && Any) {
      return h;
    }
    if (!pop_nearer(stack, sp, h.t, ni)) return finished(h);
  }
}

// ---- packets of 8 x H rays (rays in lanes), 8-wide ---------------------------------------------
template <int H>
struct Packet {
  Ray<f8> r[H];
  WoopRay<f8> w[H];
  f8 rdx[H], rdy[H], rdz[H], orx[H], ory[H], orz[H];
  f8 tbest[H];  // the ray's current tmax (the closest hit so far); -inf once an any-hit ray is done
  f8_mask active[H];
  std::uint32_t prim[8 * H];
};

template <int H>
RB_INLINE float packet_tmax(const Packet<H>& p) {
  f8 m = xsimd::select(p.active[0], p.tbest[0], f8(-kInfF));
  for (int k = 1; k < H; ++k) m = xsimd::max(m, xsimd::select(p.active[k], p.tbest[k], f8(-kInfF)));
  return hmax8(m);
}

template <bool Count, bool Any, int H>
RB_INLINE void group_packet(const Accel& a, int kind, std::size_t base, Packet<H>& p, TraceCounters& c) {
  const auto& ids = a.id[kind];
  for (std::size_t j = 0; j < 8; ++j) {
    const std::uint32_t sid = ids[base + j];
    if (sid == UINT32_MAX) continue;
    const std::size_t s = base + j;
    for (int k = 0; k < H; ++k) {
      if (none_of<f8>(p.active[k])) continue;
      if constexpr (Count) {
        const auto n = std::uint64_t(count_true<f8>(p.active[k]));
        c.prims += n;
        c.kind_prims[kind] += n;
      }
      Ray<f8> rr = p.r[k];
      rr.tmax = p.tbest[k];
      Hit<f8> hit;
      switch (Kind(kind)) {
        case Kind::triangle: hit = intersect_triangle_woop(p.w[k], rr, a.tri.broadcast<f8>(s)); break;
        case Kind::sphere: hit = intersect_sphere_geometric(rr, a.sph.broadcast<f8>(s)); break;
        case Kind::cylinder: hit = cyl_hit(rr, a.cyl.broadcast<f8>(s)); break;
        case Kind::cone: hit = cone_hit(rr, a.cone.broadcast<f8>(s)); break;
        case Kind::polygon: hit = intersect_polygon(rr, a.poly.broadcast<f8>(a.poly_slot[s])); break;
        case Kind::csg: {
          f8 tag;
          hit = csg_hit8(*a.csg[sid], rr, tag);  // the packet's 8 rays in lanes
          break;
        }
      }
      const f8_mask m = hit.mask & p.active[k];
      unsigned bits = movemask(m);
      if (!bits) continue;
      p.tbest[k] = xsimd::select(m, hit.t, p.tbest[k]);
      const std::uint32_t code = prim_code(Kind(kind), sid);
      while (bits) {
        const int l = __builtin_ctz(bits);
        bits &= bits - 1;
        p.prim[8 * k + l] = code;
      }
      if constexpr (Any) p.active[k] = p.active[k] & ~m;
    }
  }
}

template <bool Robust, bool Any, bool Count, int H>
void trace_packet(const Accel& a, const RaySoA& rays, std::size_t i, HitRec* out, TraceCounters& c) {
  Packet<H> p;
  bool live = false;
  for (int k = 0; k < H; ++k) {
    p.r[k] = rays.packet<f8>(i + 8 * std::size_t(k));
    p.w[k] = make_woop_ray(p.r[k]);
    p.rdx[k] = safe_rcp8(p.r[k].d.x);
    p.rdy[k] = safe_rcp8(p.r[k].d.y);
    p.rdz[k] = safe_rcp8(p.r[k].d.z);
    p.orx[k] = p.r[k].o.x * p.rdx[k];
    p.ory[k] = p.r[k].o.y * p.rdy[k];
    p.orz[k] = p.r[k].o.z * p.rdz[k];
    p.tbest[k] = p.r[k].tmax;
    p.active[k] = p.r[k].tmin <= p.r[k].tmax;
    live = live || any_of<f8>(p.active[k]);
  }
  for (auto& q : p.prim) q = kNoPrim;
  if (live && !a.wide.nodes.empty()) {
    Entry stack[kStack];
    int sp = 0;
    std::uint32_t ref = 0;
    for (;;) {
      if (!is_leaf(ref)) {
        const WNode& n = a.wide.nodes[ref];
        if constexpr (Count) ++c.nodes;
        Entry e[8];
        int ne = 0;
        for (int ch = 0; ch < 8; ++ch) {
          const std::uint32_t cr = n.child[ch];
          if (cr == kEmpty) break;
          const f8 lx(n.b[0][ch]), hx(n.b[1][ch]), ly(n.b[2][ch]), hy(n.b[3][ch]), lz(n.b[4][ch]), hz(n.b[5][ch]);
          float dmin = kInfF;
          for (int k = 0; k < H; ++k) {
            if constexpr (Count) c.boxes += std::uint64_t(count_true<f8>(p.active[k]));
            f8 x0, x1, y0, y1, z0, z1;
            if constexpr (!Robust) {
              x0 = xsimd::fms(lx, p.rdx[k], p.orx[k]); x1 = xsimd::fms(hx, p.rdx[k], p.orx[k]);
              y0 = xsimd::fms(ly, p.rdy[k], p.ory[k]); y1 = xsimd::fms(hy, p.rdy[k], p.ory[k]);
              z0 = xsimd::fms(lz, p.rdz[k], p.orz[k]); z1 = xsimd::fms(hz, p.rdz[k], p.orz[k]);
            } else {
              x0 = (lx - p.r[k].o.x) * p.rdx[k]; x1 = (hx - p.r[k].o.x) * p.rdx[k];
              y0 = (ly - p.r[k].o.y) * p.rdy[k]; y1 = (hy - p.r[k].o.y) * p.rdy[k];
              z0 = (lz - p.r[k].o.z) * p.rdz[k]; z1 = (hz - p.r[k].o.z) * p.rdz[k];
            }
            const f8 tn = xsimd::max(xsimd::max(xsimd::min(x0, x1), xsimd::min(y0, y1)), xsimd::max(xsimd::min(z0, z1), p.r[k].tmin));
            f8 tf = xsimd::min(xsimd::min(xsimd::max(x0, x1), xsimd::max(y0, y1)), xsimd::max(z0, z1));
            if constexpr (Robust) tf = tf * f8(kRobustScale);
            tf = xsimd::min(tf, p.tbest[k]);
            const f8_mask m = (tn <= tf) & p.active[k];
            if (any_of<f8>(m)) dmin = std::min(dmin, hmin8(xsimd::select(m, tn, f8(kInfF))));
          }
          if (dmin < kInfF) e[ne++] = {cr, dmin};
        }
        if (ne == 0) goto pop;
        if (ne > 1) {
          sort_far_first(e, ne);
          for (int k = 0; k < ne - 1; ++k) stack[sp++] = e[k];
        }
        ref = e[ne - 1].ref;
        continue;
      }
      group_packet<Count, Any>(a, leaf_kind(ref), std::size_t(leaf_group(ref)) * 8, p, c);
      if constexpr (Any) {
        bool alive = false;
        for (int k = 0; k < H; ++k) alive = alive || any_of<f8>(p.active[k]);
        if (!alive) break;
      }
    pop:
      {
        const float tm = packet_tmax(p);
        do {
          if (sp == 0) goto done;
          --sp;
        } while (stack[sp].d > tm);
        ref = stack[sp].ref;
      }
    }
  }
done:
  for (int k = 0; k < H; ++k) {
    alignas(32) float t[8];
    p.tbest[k].store_aligned(t);
    for (int l = 0; l < 8; ++l) {
      const std::size_t r = i + 8 * std::size_t(k) + std::size_t(l);
      const std::uint32_t pr = p.prim[8 * k + l];
      out[r] = {pr == kNoPrim ? kInfF : t[l], pr};
    }
  }
}

template <bool Robust, bool Any, bool Count>
void trace_range(const Accel& a, const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, const TraceOptions& o,
                 TraceCounters& c) {
  if (o.packet == 1) {
    for (std::size_t i = begin; i < end; ++i) {
      const Ray<float> r = rays.get(i);
      out[i] = o.layout == Layout::wide ? trace1_wide<Robust, Any, Count>(a, r, c) : trace1_binary<Robust, Any, Count>(a, r, c);
    }
    return;
  }
  if (o.layout != Layout::wide) throw std::invalid_argument("packets traverse the wide layout only");
  // A packet whose valid rays do not share one direction octant is incoherent: its rays would
  // part ways at the first nodes, so they traverse one by one (as Embree does for incoherent
  // packets). Coherent packets (camera tiles, rays towards one light) traverse together.
  auto coherent = [&](std::size_t i, std::size_t n) {
    int oct = -1;
    for (std::size_t k = i; k < i + n; ++k) {
      if (!(rays.tmin[k] <= rays.tmax[k])) continue;
      const int q = (rays.dx[k] < 0) | (rays.dy[k] < 0) << 1 | (rays.dz[k] < 0) << 2;
      if (oct >= 0 && q != oct) return false;
      oct = q;
    }
    return true;
  };
  auto singles = [&](std::size_t i, std::size_t n) {
    for (std::size_t k = i; k < i + n; ++k) out[k] = trace1_wide<Robust, Any, Count>(a, rays.get(k), c);
  };
  std::size_t i = begin;
  if (o.packet == 16)
    for (; i + 16 <= end; i += 16) {
      if (coherent(i, 16)) trace_packet<Robust, Any, Count, 2>(a, rays, i, out, c);
      else singles(i, 16);
    }
  for (; i < end; i += 8) {  // rays are padded to 8
    if (coherent(i, 8)) trace_packet<Robust, Any, Count, 1>(a, rays, i, out, c);
    else singles(i, 8);
  }
}

template <bool Count>
void dispatch(const Accel& a, const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, const TraceOptions& o,
              TraceCounters& c) {
  if (o.robust) {
    if (o.any) trace_range<true, true, Count>(a, rays, begin, end, out, o, c);
    else trace_range<true, false, Count>(a, rays, begin, end, out, o, c);
  } else {
    if (o.any) trace_range<false, true, Count>(a, rays, begin, end, out, o, c);
    else trace_range<false, false, Count>(a, rays, begin, end, out, o, c);
  }
}

}  // namespace

void Accel::trace(const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, const TraceOptions& o) const {
  TraceCounters c;
  dispatch<false>(*this, rays, begin, end, out, o, c);
}
void Accel::trace_counted(const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, const TraceOptions& o,
                          TraceCounters& c) const {
  dispatch<true>(*this, rays, begin, end, out, o, c);
}

HitRec BruteForce::trace(const Ray<float>& r, bool any) const {
  HitRec h{r.tmax, kNoPrim};
  if (!(r.tmin <= r.tmax)) return {kInfF, kNoPrim};
  LeafRay lr;
  TraceCounters c;
  const std::size_t sizes[scene::kKinds] = {tri.size(), sph.size(), cyl.size(), cone.size(), poly.size(), id[5].size()};
  for (int k = 0; k < scene::kKinds; ++k)
    for (std::size_t g = 0; g < sizes[k]; g += 8)
      if (group1<false>(*this, k, g, r, lr, h, c) && any) return h;
  return finished(h);
}

}  // namespace rb::bvh
