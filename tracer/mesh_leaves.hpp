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
// Per group of a packet: the shear (made at the group's first leaf) and, for a group whose rays
// share the permutation, the origin's coordinates in that order.
// Per ray of a packet, for the leaves it meets with few rays: the scalar shear and the origin in its
// order (made at the ray's first such leaf).
struct MeshPacketCache {
  std::uint32_t ready = 0;  // bit g: group g's entry is made
  WoopRay<f8> w[bvh::kMaxGroups];
  f8 o[bvh::kMaxGroups][3];
  std::uint32_t ray_ready[bvh::kMaxGroups] = {};  // bit l of [g]: ray g * 8 + l's entry is made
  struct One {
    float S[3], o[3];
    int k[3];
    RB_INLINE void make(const Ray<f8>& r, int l) {  // lane l of r
      alignas(32) float v[6][8];
      r.o.x.store_aligned(v[0]); r.o.y.store_aligned(v[1]); r.o.z.store_aligned(v[2]);
      r.d.x.store_aligned(v[3]); r.d.y.store_aligned(v[4]); r.d.z.store_aligned(v[5]);
      const Vec3f org{v[0][l], v[1][l], v[2][l]};
      const WoopShear w = woop_shear<true>(Vec3f{v[3][l], v[4][l], v[5][l]});
      for (int a = 0; a < 3; ++a) S[a] = w.S[a], k[a] = w.k[a], o[a] = org[k[a]];
    }
  } one[8 * bvh::kMaxGroups];
  MeshPacketCache() {}
};
struct MeshLeaves {
  using Tri = kinds::TriangleKind;
  const StdBatch<Tri>* tri = nullptr;
  const StdBatch<Tri>* apart = nullptr;  // the triangles stored apart (tag apart_tag)
  using RayCache = MeshRayCache;
  using PacketCache = MeshPacketCache;
  static bool is_apart(std::uint32_t ref) { return bvh::leaf_kind(ref) != int(Tri::id); }
  RB_INLINE bool single(std::uint32_t ref, const Ray<float>& r, RayCache& c, HitRec& h) const {
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
  // Whichever needs fewer 8-lane kernel calls: fewer rays than triangle x group pairs, one ray at
  // a time against the 8 triangles in lanes (the single-ray kernel); otherwise rays in lanes, one
  // triangle at a time: a group sharing the shear's permutation loads the triangle's coordinates
  // in that order (scalars, then broadcast); another permutes per lane. The same arithmetic either
  // way: the same t for each ray and triangle.
  template <bool Any>
  RB_INLINE void packet(std::uint32_t ref, bvh::PacketRays& p, PacketCache& c) const {
    const std::size_t base = std::size_t(bvh::leaf_group(ref)) * 8;
    if (is_apart(ref)) [[unlikely]] {
      apart_packet<Tri, 0, Any>(*apart, base, p);
      return;
    }
    int rays = 0;
    for (int q = 0; q < p.n; ++q) rays += count_true<f8>(p.active[p.list[q]]);
    const int tris = int(real_slots(*tri, base));
    if (rays < tris * p.n) {
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
        if (none_of<f8>(p.active[k])) continue;
        const WoopRay<f8>& w = c.w[k];
        Ray<f8> rr = p.r[k];
        rr.tmax = p.tbest[k];
        Vec3<f8> v[3];
        if (w.uniform) {
          for (int i = 0; i < 3; ++i)
            v[i] = {f8(g[8 * (3 * i + w.kx)]) - c.o[k][0], f8(g[8 * (3 * i + w.ky)]) - c.o[k][1], f8(g[8 * (3 * i + w.kz)]) - c.o[k][2]};
        } else {
          for (int i = 0; i < 3; ++i)
            v[i] = woop_permute(w, Vec3<f8>{f8(g[8 * (3 * i)]), f8(g[8 * (3 * i + 1)]), f8(g[8 * (3 * i + 2)])} - rr.o);
        }
        const Hit<f8> hit = intersect_triangle_woop_permuted(w, rr, v[0], v[1], v[2]);
        bvh::packet_update<Any>(p, k, hit.mask, hit.t, code);
      }
    }
  }
  std::uint32_t slots(std::uint32_t ref) const { return real_slots(is_apart(ref) ? *apart : *tri, std::size_t(bvh::leaf_group(ref)) * 8); }

  template <bool Any>
  RB_INLINE void packet_by_ray(std::size_t base, bvh::PacketRays& p, PacketCache& c) const {
    const float* gr = tri->f32.field(0, base);  // the group: field i at gr + 8 i
    prefetch_ids(*tri, base);
    for (int q = 0; q < p.n; ++q) {
      const int g = p.list[q];
      unsigned bits = lanes::bits(p.active[g]);
      if (!bits) continue;
      alignas(32) float tb[8], tm[8];
      p.tbest[g].store_aligned(tb);
      p.r[g].tmin.store_aligned(tm);
      while (bits) {
        const int l = __builtin_ctz(bits);
        bits &= bits - 1;
        MeshPacketCache::One& one = c.one[8 * g + l];
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
        bvh::HitRec h{tb[l], p.prim[8 * g + l]};
        if (!bvh::take_nearest(hit.t, h, [&](int lane) { return kinds::code(kinds::TriangleKind::id, tri->id[base + std::size_t(lane)]); }))
          continue;
        const f8_mask one_lane = lanes::of(1u << l);
        tb[l] = h.t;
        p.prim[8 * g + l] = h.prim;
        p.improved = true;
        if constexpr (Any) p.active[g] = p.active[g] & ~one_lane;
      }
      p.tbest[g] = f8::load_aligned(tb);
    }
  }
};

}  // namespace rb::tracer
