// The leaf source of a triangle-only scene traced with Woop in float (MeshLeaves): the kernel
// inlined into the traversal loop, each vertex coordinate loaded in the ray's shear order; the
// triangles the plan stores apart go to the double kernel of tracer/leaves.hpp. SceneAccel uses it
// when the scene has triangles only and the plan runs them in float (tracer/accel.cpp).
#pragma once

#include "tracer/leaves.hpp"

namespace rb::tracer {

// The shear of make_woop_ray<float> for one ray: the axis of the largest |d| (the first of equal
// ones) is kz, kx and ky follow it cyclically and swap when d[kz] < 0. Two forms with the same
// values (test WoopShearFormsEqualTheKernelsOwn):
// - Coherent = false, for single rays of any direction: kx and ky are shifted out of one constant,
//   with no conditional on kz. With one (even a select in the source), GCC cloned the set-up per
//   axis and those branches mispredicted on random directions. (A table load in place of the shift
//   lengthens the set-up's chain; docs/DESIGN.md section 12 has both measurements.)
// - Coherent = true, for the rays of a packet (one direction octant, mostly one dominant axis):
//   conditionals, predicted there. The packet loop keeps the instructions it had with them
//   (with the table form, primary packets of 64 ran 0.91x).
// The callers permute the ray's origin the same way: by an indexed load for single rays, by Vec3's
// operator[] (conditionals) for a packet's rays.
struct WoopShear {
  float S[3];
  int k[3];  // kx, ky, kz
};
// kx | ky << 2 in the 4 bits at 4 i, for i = 2 kz + (d[kz] < 0): (1, 2), (2, 1), (2, 0), (0, 2),
// (0, 1), (1, 0).
inline constexpr unsigned kPackedAxes = 0x148269u;
template <bool Coherent>
RB_INLINE WoopShear woop_shear(const Vec3f& d) {
  const float v[3] = {d.x, d.y, d.z};
  const float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
  const int z0 = (ax >= ay) & (ax >= az);
  const int z1 = (1 - z0) & (ay >= az);
  const int kz = 2 - 2 * z0 - z1;
  const float dkz = v[kz];
  WoopShear w;
  if constexpr (Coherent) {
    const int n1 = kz == 2 ? 0 : kz + 1, n2 = n1 == 2 ? 0 : n1 + 1;
    const bool neg = dkz < 0.0f;
    w.k[0] = neg ? n2 : n1;
    w.k[1] = neg ? n1 : n2;
    w.k[2] = kz;
  } else {
    const unsigned e = kPackedAxes >> (4 * (2 * kz + (dkz < 0.0f)));
    w.k[0] = int(e & 3u);
    w.k[1] = int(e >> 2 & 3u);
    w.k[2] = kz;
  }
  w.S[0] = v[w.k[0]] / dkz;
  w.S[1] = v[w.k[1]] / dkz;
  w.S[2] = 1.0f / dkz;
  return w;
}

// A scene of triangles only, Woop in float: the kernel inlined into the loop. One ray against a
// leaf's 8 triangles loads each vertex coordinate already in the ray's shear order (the batch is
// stored by coordinate), with the shear computed once per ray in scalar code (when the ray starts:
// a cheap scalar set-up, no check per leaf).
struct MeshRayCache {
  Ray<f8> rb;  // the kernel reads only its tmin (set here) and tmax (set per leaf)
  WoopRay<f8> w;
  f8 o[3];  // the origin's coordinates in the shear order
  int k[3];
  explicit MeshRayCache(const Ray<float>& r) {
    const WoopShear s = woop_shear<false>(r.d);
    w.Sx = f8(s.S[0]); w.Sy = f8(s.S[1]); w.Sz = f8(s.S[2]);
    w.uniform = true;
    const float org[3] = {r.o.x, r.o.y, r.o.z};
    k[0] = s.k[0]; k[1] = s.k[1]; k[2] = s.k[2];
    for (int a = 0; a < 3; ++a) o[a] = f8(org[k[a]]);
    rb.tmin = f8(r.tmin);
  }
};
// Per group of a packet (groups of V: 8 or 16 rays): the shear (made at the group's first leaf)
// and, for a group whose rays share the permutation, the origin's coordinates in that order.
// Per ray of a packet, for the leaves it meets with few rays: the scalar shear and the origin in its
// order (made at the ray's first such leaf).
template <class V>
struct MeshPacketCache {
  static constexpr int N = lanes::Group<V>::N, kGroups = bvh::kMaxRays / N;
  std::uint32_t ready = 0;  // bit g: group g's entry is made
  WoopRay<V> w[kGroups];
  V o[kGroups][3];
  std::uint32_t ray_ready[kGroups] = {};  // bit l of [g]: ray N g + l's entry is made
  struct One {
    float S[3], o[3];
    int k[3];
    RB_INLINE void make(const Ray<V>& r, int l) {  // lane l of r
      alignas(64) float v[6][N];
      r.o.x.store_aligned(v[0]); r.o.y.store_aligned(v[1]); r.o.z.store_aligned(v[2]);
      r.d.x.store_aligned(v[3]); r.d.y.store_aligned(v[4]); r.d.z.store_aligned(v[5]);
      const Vec3f org{v[0][l], v[1][l], v[2][l]};
      const WoopShear w = woop_shear<true>(Vec3f{v[3][l], v[4][l], v[5][l]});
      for (int a = 0; a < 3; ++a) S[a] = w.S[a], k[a] = w.k[a], o[a] = org[k[a]];
    }
  } one[bvh::kMaxRays];
  MeshPacketCache() {}
};
struct MeshLeaves {
  using Tri = kinds::TriangleKind;
  const StdBatch<Tri>* tri = nullptr;
  const StdBatch<Tri>* apart = nullptr;  // the triangles stored apart (tag apart_tag)
  using RayCache = MeshRayCache;
  template <class V>
  using PacketCacheFor = MeshPacketCache<V>;
  static bool is_apart(std::uint32_t ref) { return bvh::leaf_kind(ref) != int(Tri::id); }
  RB_INLINE bool single(std::uint32_t ref, const Ray<float>& r, RayCache& c, bvh::Closest& h) const {
    const std::size_t base = std::size_t(bvh::leaf_group(ref)) * 8;
    if (is_apart(ref)) [[unlikely]]
      return apart_single<Tri, 0>(*apart, base, r, h);
    c.rb.tmax = f8(h.t);
    prefetch_ids(*tri, base);
    const float* g = tri->f32.field(0, base);  // the group: field i at g + 8 i
    auto vertex = [&](int v) {
      return Vec3<f8>{load<f8>(g + 8 * (3 * v + c.k[0])) - c.o[0], load<f8>(g + 8 * (3 * v + c.k[1])) - c.o[1],
                      load<f8>(g + 8 * (3 * v + c.k[2])) - c.o[2]};
    };
    const Hit<f8> hit = intersect_triangle_woop_permuted(c.w, c.rb, vertex(0), vertex(1), vertex(2));
    if (none_of<f8>(hit.mask)) return false;
    return bvh::take_nearest(hit.t, h, [&](int lane) { return kinds::code(kinds::TriangleKind::id, tri->id[base + std::size_t(lane)]); });
  }
  // Whichever needs fewer kernel calls: fewer rays than triangle x group pairs, one ray at a time
  // against the 8 triangles in lanes (the single-ray kernel); otherwise rays in lanes (8 or 16, V),
  // one triangle at a time: a group sharing the shear's permutation loads the triangle's
  // coordinates in that order (scalars, then broadcast); another permutes per lane. The same
  // arithmetic either way: the same t for each ray and triangle. Triangles stored apart run their
  // 8-lane leaf function (a 16-ray group as its two halves).
  template <bool Any, class V>
  RB_INLINE void packet(std::uint32_t ref, bvh::PacketRaysT<V>& p, MeshPacketCache<V>& c) const {
    const std::size_t base = std::size_t(bvh::leaf_group(ref)) * 8;
    if (is_apart(ref)) [[unlikely]] {
      if constexpr (std::is_same_v<V, f8>) apart_packet<Tri, 0, Any>(*apart, base, p);
      else apart_in_halves<Any>(base, p);
      return;
    }
    int rays = 0;
    for (int q = 0; q < p.n; ++q) rays += count_true<V>(p.active[p.list[q]]);
    const int tris = int(real_slots(*tri, base));
    const int calls = lanes::Group<V>::N == 16 && Any ? (rays + 1) / 2 : rays;  // any hit in 16 lanes: rays in pairs
    if (calls < tris * p.n) {
      packet_by_ray<Any>(base, p, c);
      return;
    }
    for (int q = 0; q < p.n; ++q) {
      const int k = p.list[q];
      if (c.ready >> k & 1u) continue;
      c.w[k] = make_woop_ray(p.r[k]);
      if (c.w[k].uniform) {
        const int perm[3] = {c.w[k].kx, c.w[k].ky, c.w[k].kz};
        for (int a = 0; a < 3; ++a) c.o[k][a] = perm[a] == 0 ? p.r[k].o.x : perm[a] == 1 ? p.r[k].o.y : p.r[k].o.z;
      }
      c.ready |= 1u << k;
    }
    for (std::size_t j = base; j < base + 8; ++j) {
      const std::uint32_t sid = tri->id[j];
      if (sid == UINT32_MAX) continue;
      const float* g = tri->f32.field(0, j);  // slot j's field i at g[8 i]
      const std::uint32_t code = kinds::code(kinds::TriangleKind::id, sid);
      for (int q = 0; q < p.n; ++q) {
        const int k = p.list[q];
        if (none_of<V>(p.active[k])) continue;
        const WoopRay<V>& w = c.w[k];
        Ray<V> rr = p.r[k];
        rr.tmax = p.tbest[k];
        Vec3<V> v[3];
        if (w.uniform) {
          for (int i = 0; i < 3; ++i)
            v[i] = {V(g[8 * (3 * i + w.kx)]) - c.o[k][0], V(g[8 * (3 * i + w.ky)]) - c.o[k][1], V(g[8 * (3 * i + w.kz)]) - c.o[k][2]};
        } else {
          for (int i = 0; i < 3; ++i)
            v[i] = woop_permute(w, Vec3<V>{V(g[8 * (3 * i)]), V(g[8 * (3 * i + 1)]), V(g[8 * (3 * i + 2)])} - rr.o);
        }
        const Hit<V> hit = intersect_triangle_woop_permuted(w, rr, v[0], v[1], v[2]);
        bvh::packet_update<Any>(p, k, hit.mask, hit.t, code);
      }
    }
  }
  std::uint32_t slots(std::uint32_t ref) const { return real_slots(is_apart(ref) ? *apart : *tri, std::size_t(bvh::leaf_group(ref)) * 8); }

  template <bool Any, class V>
  RB_INLINE void packet_by_ray(std::size_t base, bvh::PacketRaysT<V>& p, MeshPacketCache<V>& c) const {
    using Lanes = lanes::Group<V>;
    constexpr int N = Lanes::N;
    if constexpr (N == 16 && Any) {
      packet_by_ray_pairs<Any>(base, p, c);
      return;
    }
    const float* gr = tri->f32.field(0, base);  // the group: field i at gr + 8 i
    prefetch_ids(*tri, base);
    for (int q = 0; q < p.n; ++q) {
      const int g = p.list[q];
      unsigned bits = Lanes::bits(p.active[g]);
      if (!bits) continue;
      alignas(64) float tb[N], tm[N];
      p.tbest[g].store_aligned(tb);
      p.r[g].tmin.store_aligned(tm);
      while (bits) {
        const int l = __builtin_ctz(bits);
        bits &= bits - 1;
        typename MeshPacketCache<V>::One& one = c.one[N * g + l];
        if (!(c.ray_ready[g] >> l & 1u)) {
          one.make(p.r[g], l);
          c.ray_ready[g] |= 1u << l;
        }
        WoopRay<f8> w;
        w.Sx = f8(one.S[0]); w.Sy = f8(one.S[1]); w.Sz = f8(one.S[2]);
        w.uniform = true;
        Ray<f8> rr;
        rr.tmin = f8(tm[l]);
        rr.tmax = f8(tb[l]);
        auto vertex = [&](int v) {
          return Vec3<f8>{load<f8>(gr + 8 * (3 * v + one.k[0])) - f8(one.o[0]), load<f8>(gr + 8 * (3 * v + one.k[1])) - f8(one.o[1]),
                          load<f8>(gr + 8 * (3 * v + one.k[2])) - f8(one.o[2])};
        };
        const Hit<f8> hit = intersect_triangle_woop_permuted(w, rr, vertex(0), vertex(1), vertex(2));
        if (none_of<f8>(hit.mask)) continue;
        bvh::Closest h{tb[l], p.prim[N * g + l]};
        if (!bvh::take_nearest(hit.t, h, [&](int lane) { return kinds::code(kinds::TriangleKind::id, tri->id[base + std::size_t(lane)]); }))
          continue;
        tb[l] = h.t;
        p.prim[N * g + l] = h.prim;
        p.improved = true;
        if constexpr (Any) p.active[g] = p.active[g] & ~Lanes::of(1u << l);
      }
      p.tbest[g] = V::load_aligned(tb);
    }
  }

  // Any hit in 16 lanes: two rays at a time against the leaf's 8 triangles, one in the low 8 lanes
  // and the other in the high 8, each with its own shear and origin (an odd last ray pairs with
  // itself); where the two share the shear's permutation, as a coherent packet's rays mostly do,
  // each coordinate row is loaded once into both halves. Half the kernel calls of one ray at a
  // time, the same arithmetic in every lane. Closest-hit packets keep one ray at a time: in pairs
  // their primary packets of 16 and 64 ran 4-10 % slower on the bunny and the dragon, choosing
  // between the two loops either way (docs/DESIGN.md section 12).
  template <bool Any, class V>
  RB_INLINE void packet_by_ray_pairs(std::size_t base, bvh::PacketRaysT<V>& p, MeshPacketCache<V>& c) const {
    using Lanes = lanes::Group<V>;
    constexpr int N = Lanes::N;
    static_assert(N == 16);
    const float* gr = tri->f32.field(0, base);  // the group: field i at gr + 8 i
    prefetch_ids(*tri, base);
    alignas(64) float tb[bvh::kMaxRays / N][N], tm[bvh::kMaxRays / N][N];
    std::uint16_t todo[bvh::kMaxRays];  // q N + l: lane l of the q-th listed group
    int n = 0;
    std::uint32_t stored = 0;  // bit q: the q-th listed group's distances are in tb[q]
    for (int q = 0; q < p.n; ++q) {
      const int g = p.list[q];
      unsigned bits = Lanes::bits(p.active[g]);
      if (!bits) continue;
      stored |= 1u << q;
      p.tbest[g].store_aligned(tb[q]);
      p.r[g].tmin.store_aligned(tm[q]);
      for (; bits; bits &= bits - 1) {
        const int l = __builtin_ctz(bits);
        if (!(c.ray_ready[g] >> l & 1u)) {
          c.one[N * g + l].make(p.r[g], l);
          c.ray_ready[g] |= 1u << l;
        }
        todo[n++] = std::uint16_t(N * q + l);
      }
    }
    auto code_of = [&](int lane) { return kinds::code(kinds::TriangleKind::id, tri->id[base + std::size_t(lane)]); };
    // Ray j of todo (its hits in lanes t8) taken where nearer. The same steps as packet_by_ray's,
    // written out in each: one shared inline helper (and one for the lazily made shear) changed the
    // packet loops' code and ran 1-3 % slower in 5 alternating rounds on the bunny's primary
    // packets of 8 and shadow packets of 16.
    auto take = [&](int j, const f8& t8) {
      const int q = todo[j] / N, l = todo[j] % N, g = p.list[q];
      bvh::Closest h{tb[q][l], p.prim[N * g + l]};
      if (!bvh::take_nearest(t8, h, code_of)) return;
      tb[q][l] = h.t;
      p.prim[N * g + l] = h.prim;
      p.improved = true;
      if constexpr (Any) p.active[g] = p.active[g] & ~Lanes::of(1u << l);
    };
    for (int j = 0; j < n; j += 2) {
      const int b = j + 1 < n ? j + 1 : j;  // an odd last ray pairs with itself
      const int qa = todo[j] / N, la = todo[j] % N, qb = todo[b] / N, lb = todo[b] % N;
      const typename MeshPacketCache<V>::One& ra = c.one[N * p.list[qa] + la];
      const typename MeshPacketCache<V>::One& rb = c.one[N * p.list[qb] + lb];
      auto both = [](float x, float y) { return Lanes::join(f8(x), f8(y)); };
      WoopRay<V> w;
      w.Sx = both(ra.S[0], rb.S[0]); w.Sy = both(ra.S[1], rb.S[1]); w.Sz = both(ra.S[2], rb.S[2]);
      w.uniform = false;
      Ray<V> rr;
      rr.tmin = both(tm[qa][la], tm[qb][lb]);
      rr.tmax = both(tb[qa][la], tb[qb][lb]);
      const V o[3] = {both(ra.o[0], rb.o[0]), both(ra.o[1], rb.o[1]), both(ra.o[2], rb.o[2])};
      Hit<V> hit;
      if (ra.k[0] == rb.k[0] && ra.k[1] == rb.k[1]) {  // one permutation: each row loaded once into both halves
        auto coord = [&](int v, int a) { return Lanes::twice(load<f8>(gr + 8 * (3 * v + ra.k[a]))) - o[a]; };
        auto vertex = [&](int v) { return Vec3<V>{coord(v, 0), coord(v, 1), coord(v, 2)}; };
        hit = intersect_triangle_woop_permuted(w, rr, vertex(0), vertex(1), vertex(2));
      } else {
        auto coord = [&](int v, int a) { return Lanes::join(load<f8>(gr + 8 * (3 * v + ra.k[a])), load<f8>(gr + 8 * (3 * v + rb.k[a]))) - o[a]; };
        auto vertex = [&](int v) { return Vec3<V>{coord(v, 0), coord(v, 1), coord(v, 2)}; };
        hit = intersect_triangle_woop_permuted(w, rr, vertex(0), vertex(1), vertex(2));
      }
      const unsigned hb = Lanes::bits(hit.mask);
      if (hb & 0xFFu) take(j, Lanes::half(hit.t, 0));
      if (b != j && hb >> 8) take(b, Lanes::half(hit.t, 1));
    }
    for (; stored; stored &= stored - 1) {
      const int q = __builtin_ctz(stored);
      p.tbest[p.list[q]] = V::load_aligned(tb[q]);
    }
  }

  // The 8-lane leaf function of the triangles stored apart on a packet of 16-lane groups: each
  // group as its two halves (8-lane groups 2 k and 2 k + 1 share its rays' slots in prim).
  template <bool Any, class V>
  void apart_in_halves(std::size_t base, bvh::PacketRaysT<V>& p) const {
    using Lanes = lanes::Group<V>;
    static_assert(Lanes::N == 16);
    Ray<f8> r8[bvh::kMaxGroups];
    f8 tb8[bvh::kMaxGroups];
    f8_mask act8[bvh::kMaxGroups];
    bvh::PacketRays v;
    v.r = r8;
    v.tbest = tb8;
    v.active = act8;
    v.prim = p.prim;
    for (int q = 0; q < p.n; ++q) {
      const int k = p.list[q];
      const Ray<V>& r = p.r[k];
      for (int h = 0; h < 2; ++h) {
        auto half = [&](const V& x) { return Lanes::half(x, h); };
        const int s = 2 * k + h;
        r8[s].o = {half(r.o.x), half(r.o.y), half(r.o.z)};
        r8[s].d = {half(r.d.x), half(r.d.y), half(r.d.z)};
        r8[s].rd = {half(r.rd.x), half(r.rd.y), half(r.rd.z)};
        r8[s].tmin = half(r.tmin);
        r8[s].tmax = half(r.tmax);
        tb8[s] = half(p.tbest[k]);
        act8[s] = lanes::of(Lanes::bits(p.active[k]) >> (8 * h) & 0xFFu);
        v.list[v.n++] = std::uint8_t(s);
      }
    }
    apart_packet<Tri, 0, Any>(*apart, base, v);
    for (int q = 0; q < p.n; ++q) {
      const int k = p.list[q];
      p.tbest[k] = Lanes::join(tb8[2 * k], tb8[2 * k + 1]);
      p.active[k] = Lanes::of(lanes::bits(act8[2 * k]) | lanes::bits(act8[2 * k + 1]) << 8);
    }
    p.improved = p.improved || v.improved;
  }
};

}  // namespace rb::tracer
