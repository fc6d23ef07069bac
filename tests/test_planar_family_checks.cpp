// The planar kernel family, the checks beyond the hand-worked cases (those:
// tests/test_planar_hand_worked.cpp):
//   - seeded random rays against an independent double-precision reference;
//   - every SIMD lane equals the scalar result, in both mappings (bit for bit with
//     -ffp-contract=off);
//   - Woop is watertight on rays aimed exactly at shared edges and vertices of a fan;
//   - golden operation counts (Counted<float>) of every ops-table row of the family.
#include "bench/ops_table.hpp"
#include "bench/specs_planar.hpp"
#include "kernels/box.hpp"
#include "planar_test_util.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace rb::test {
namespace {

// ---- seeded random rays against double-precision references -----------------------------------

using Rng = bench::Rng;
float uf(Rng& g, float a, float b) { return bench::uni(g, a, b); }
Vec3f rand3(Rng& g, float a, float b) { return {uf(g, a, b), uf(g, a, b), uf(g, a, b)}; }

// Ray t and the 3x3 solve e + t d = a + beta (b - a) + gamma (c - a) in double on the float data.
struct RefTri {
  bool ok;
  double t, beta, gamma;
};
RefTri ref_solve(const Ray<float>& r, Vec3d a, Vec3d e1, Vec3d e2) {
  const Vec3d d = to_double(r.d), s = to_double(r.o) - a;
  const Vec3d p = cross(d, e2);
  const double det = dot(e1, p);
  if (det == 0.0) return {false, 0, 0, 0};
  const Vec3d q = cross(s, e1);
  return {true, dot(e2, q) / det, dot(s, p) / det, dot(d, q) / det};
}

// Double crossing test with the distance of the point to the boundary (to skip near-edge cases).
bool ref_inside(const std::vector<std::array<double, 2>>& v, double px, double py, double& dist) {
  bool in = false;
  dist = kInfD;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto& p = v[i];
    const auto& q = v[(i + 1) % v.size()];
    if ((p[1] > py) != (q[1] > py) && px < (q[0] - p[0]) * (py - p[1]) / (q[1] - p[1]) + p[0]) in = !in;
    const double ex = q[0] - p[0], ey = q[1] - p[1], l2 = ex * ex + ey * ey;
    const double s = std::clamp(((px - p[0]) * ex + (py - p[1]) * ey) / l2, 0.0, 1.0);
    dist = std::min(dist, std::hypot(px - p[0] - s * ex, py - p[1] - s * ey));
  }
  return in;
}

// A gear: 4 vertices per tooth (SPD `gears` uses 36 teeth: 144 vertices, concave).
std::vector<Vec3f> gear(Vec3d c, Vec3d u, Vec3d v, int teeth, double r_in, double r_out) {
  std::vector<Vec3f> out;
  for (int i = 0; i < teeth; ++i) {
    const double a = 2 * std::numbers::pi * i / teeth, da = 2 * std::numbers::pi / teeth;
    for (auto [f, rr] : {std::pair{0.0, r_in}, std::pair{0.25, r_out}, std::pair{0.5, r_out}, std::pair{0.75, r_in}}) {
      const double ang = a + f * da;
      out.push_back(to_float(c + u * (rr * std::cos(ang)) + v * (rr * std::sin(ang))));
    }
  }
  return out;
}

TEST(PlanarRandom, TrianglesAndParallelogramsAgainstDoubleReference) {
  Rng g(12345);
  std::size_t hits = 0, checked = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Vec3f a = rand3(g, -2, 2), b = rand3(g, -2, 2), c = rand3(g, -2, 2);
    const auto cr = make_triangle(a, b, c);
    const auto wv = make_tri_verts(a, b, c);
    int ax = 0;
    const auto pg = make_tri_lecture(a, b, c, ax);
    const Vec3f o = rand3(g, -6, 6), target = rand3(g, -1.5f, 1.5f);
    const Ray<float> r = make_ray(o, target - o);
    const Vec3d A = to_double(a), E1 = to_double(b) - A, E2 = to_double(c) - A;
    const RefTri ref = ref_solve(r, A, E1, E2);
    if (!ref.ok) continue;
    const double margin = 1e-4;
    const Hit<float> hc = intersect_triangle_cramer(r, cr);
    const Hit<float> hw = intersect_triangle_woop(r, wv);
    const Hit<float> hp = intersect_parallelogram(r, pg, ax);
    const bool in_range = ref.t >= 0;
    const bool tri = in_range && ref.beta >= 0 && ref.gamma >= 0 && ref.beta + ref.gamma <= 1;
    const bool par = in_range && ref.beta >= 0 && ref.gamma >= 0 && ref.beta <= 1 && ref.gamma <= 1;
    const double dtri = std::min({std::abs(ref.beta), std::abs(ref.gamma), std::abs(1 - ref.beta - ref.gamma), std::abs(ref.t)});
    const double dpar = std::min({std::abs(ref.beta), std::abs(ref.gamma), std::abs(1 - ref.beta), std::abs(1 - ref.gamma), std::abs(ref.t)});
    const double scale = std::max(1.0, std::abs(ref.t));
    if (dtri > margin) {
      ++checked;
      EXPECT_EQ(hc.mask, tri) << trial;
      EXPECT_EQ(hw.mask, tri) << trial;
      if (tri) {
        ++hits;
        EXPECT_NEAR(hc.t, ref.t, 1e-4 * scale);
        EXPECT_NEAR(hw.t, ref.t, 1e-4 * scale);
        EXPECT_NEAR(hc.u, ref.beta, 1e-3);
        EXPECT_NEAR(hc.v, ref.gamma, 1e-3);
        EXPECT_NEAR(hw.u, ref.beta, 1e-3);
        EXPECT_NEAR(hw.v, ref.gamma, 1e-3);
      } else {
        EXPECT_EQ(hc.t, kInfF);
        EXPECT_EQ(hw.t, kInfF);
      }
    }
    if (dpar > margin && !(pg.n.x == 0.f && pg.n.y == 0.f && pg.n.z == 0.f)) {
      EXPECT_EQ(hp.mask, par) << trial;
      if (par) {
        EXPECT_NEAR(hp.t, ref.t, 1e-4 * scale);
        // The hit point lies on the plane of the parallelogram (double check).
        const Vec3d P = to_double(r.o) + to_double(r.d) * double(hp.t);
        const Vec3d n = cross(E1, E2);
        EXPECT_NEAR(dot(n, P - A) / std::sqrt(dot(n, n)), 0.0, 1e-4 * scale);
        EXPECT_NEAR(hp.u, ref.beta, 1e-3);
        EXPECT_NEAR(hp.v, ref.gamma, 1e-3);
      }
    }
  }
  EXPECT_GT(checked, 2000u);
  EXPECT_GT(hits, 300u);
}

TEST(PlanarRandom, PolygonsAgainstDoubleReference) {
  Rng g(777);
  // Concave gears (144 vertices), stars and random convex-ish polygons, in random planes.
  std::vector<std::vector<Vec3f>> polys;
  for (int i = 0; i < 24; ++i) {
    const Vec3d c = to_double(rand3(g, -1, 1));
    Vec3d u = to_double(rand3(g, -1, 1)), w = to_double(rand3(g, -1, 1));
    u = u * (1.0 / std::sqrt(dot(u, u)));
    Vec3d v = cross(w, u);
    v = v * (1.0 / std::sqrt(dot(v, v)));
    if (i % 3 == 0) polys.push_back(gear(c, u, v, 36, 1.0, 1.3));
    else if (i % 3 == 1) polys.push_back(gear(c, u, v, 5 + i, 0.5, 1.5));  // deep teeth
    else {
      std::vector<Vec3f> p;
      const int n = 3 + i % 9;
      for (int k = 0; k < n; ++k) {
        const double a = 2 * std::numbers::pi * k / n, rr = 0.5 + 0.8 * double(uf(g, 0, 1));
        p.push_back(to_float(c + u * (rr * std::cos(a)) + v * (rr * std::sin(a))));
      }
      polys.push_back(p);
    }
  }
  const auto s = PolygonSoA::build(polys);
  EXPECT_EQ(s.degenerate, 0u);
  std::size_t checked = 0, hits = 0, edges_checked = 0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    if (s.id[j] == UINT32_MAX) continue;
    const auto& P = polys[s.id[j]];
    const auto pr = s.broadcast<float>(j);
    const int a = (s.axis_of(j) + 1) % 3, b = (s.axis_of(j) + 2) % 3;
    const Vec3d n = to_double(pr.pl.n);
    std::vector<std::array<double, 2>> v2;
    for (const auto& p : P) v2.push_back({double(p[a]), double(p[b])});
    for (int k = 0; k < 150; ++k) {
      const Vec3f o = rand3(g, -5, 5), target = rand3(g, -1.6f, 1.6f);
      const Ray<float> r = make_ray(o, target - o);
      const Hit<float> h = intersect_polygon(r, pr);
      // The edges-in-lanes form (single rays, polygons of kEdgeLanes or more vertices) answers as
      // the kernel does, bit for bit.
      const Hit<float> he = intersect_polygon_edges(r, s, j);
      ASSERT_EQ(he.mask, h.mask) << "polygon " << s.id[j] << " ray " << k;
      ASSERT_EQ(std::bit_cast<std::uint32_t>(he.t), std::bit_cast<std::uint32_t>(h.t));
      edges_checked += P.size() >= kEdgeLanes;
      // Reference: the plane of the float data in double (n, D as stored), the point in double.
      const double den = dot(n, to_double(r.d));
      if (std::abs(den) < 1e-3) continue;
      const double t = -(dot(n, to_double(r.o)) + double(pr.pl.D)) / den;
      const Vec3d X = to_double(r.o) + to_double(r.d) * t;
      double dist = 0;
      const bool in = t >= 0 && ref_inside(v2, X[a], X[b], dist);
      if (dist < 1e-4 || std::abs(t) < 1e-4) continue;
      ++checked;
      EXPECT_EQ(h.mask, in) << "polygon " << s.id[j] << " ray " << k;
      if (in) {
        ++hits;
        EXPECT_NEAR(h.t, t, 1e-4 * std::max(1.0, t));
        // The hit point lies on the plane through the polygon's own vertex 0.
        const Vec3d Xh = to_double(r.o) + to_double(r.d) * double(h.t);
        EXPECT_NEAR(dot(n, Xh - to_double(P[0])), 0.0, 1e-4 * std::max(1.0, t));
      }
    }
  }
  EXPECT_GT(checked, 2500u);
  EXPECT_GT(hits, 400u);
  EXPECT_GT(edges_checked, 1500u);
  // Eight rays in lanes (packets): each lane as the 8-lane kernel answers it, rays that reach the
  // plane and rays that do not mixed in one batch.
  std::size_t lanes_in = 0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    if (s.id[j] == UINT32_MAX) continue;
    for (int k = 0; k < 40; ++k) {
      alignas(kSimdAlign) float f[11][8];
      for (int l = 0; l < 8; ++l) {
        const Vec3f o = rand3(g, -5, 5), target = rand3(g, -1.6f, 1.6f);
        const Ray<float> r = make_ray(o, target - o);
        const float v[11] = {r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.rd.x, r.rd.y, r.rd.z, r.tmin, r.tmax};
        for (int c = 0; c < 11; ++c) f[c][l] = v[c];
      }
      auto at = [&](int c) { return load<f8>(f[c]); };
      const Ray<f8> r{{at(0), at(1), at(2)}, {at(3), at(4), at(5)}, {at(6), at(7), at(8)}, at(9), at(10)};
      const Hit<f8> h = intersect_polygon(r, s.broadcast<f8>(j)), he = intersect_polygon_edges(r, s, j);
      for (int l = 0; l < 8; ++l) {
        ASSERT_EQ(lane_mask<f8>(he.mask, l), lane_mask<f8>(h.mask, l)) << "polygon " << s.id[j] << " lane " << l;
        ASSERT_EQ(std::bit_cast<std::uint32_t>(lane(he.t, l)), std::bit_cast<std::uint32_t>(lane(h.t, l)));
        lanes_in += lane_mask<f8>(h.mask, l) && polys[s.id[j]].size() >= kEdgeLanes;
      }
    }
  }
  EXPECT_GT(lanes_in, 200u);
  // Rays through every vertex and every edge's midpoint: points on the boundary, where the crossing
  // answer rests on exact ties, take the same side in both forms.
  std::size_t boundary = 0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    if (s.id[j] == UINT32_MAX) continue;
    const auto& P = polys[s.id[j]];
    const auto pr = s.broadcast<float>(j);
    for (std::size_t k = 0; k < P.size(); ++k) {
      const Vec3f o = rand3(g, -5, 5);
      for (const Vec3f target : {P[k], (P[k] + P[(k + 1) % P.size()]) * 0.5f}) {
        const Ray<float> r = make_ray(o, target - o);
        const Hit<float> h = intersect_polygon(r, pr), he = intersect_polygon_edges(r, s, j);
        ASSERT_EQ(he.mask, h.mask) << "polygon " << s.id[j] << " vertex " << k;
        ASSERT_EQ(std::bit_cast<std::uint32_t>(he.t), std::bit_cast<std::uint32_t>(h.t));
        boundary += h.mask;
      }
    }
  }
  EXPECT_GT(boundary, 100u);
}

TEST(PlanarRandom, BoxAsHalfspacesAndSlabsAgreesWithBoxKernel) {
  Rng g(4242);
  std::size_t hits = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3f lo = rand3(g, -2, 0), hi = lo + rand3(g, 0.2f, 2);
    const auto bx = make_box(lo, hi);
    const auto hs = make_box_halfspaces(lo, hi);
    const auto sl = make_box_slabs(lo, hi);
    const Vec3f o = rand3(g, -6, 6);
    // Aim at the box's interior (a hit unless behind/tmax) or well beside it.
    Vec3f target = (lo + hi) * 0.5f + Vec3f{uf(g, -0.4f, 0.4f) * (hi.x - lo.x), uf(g, -0.4f, 0.4f) * (hi.y - lo.y),
                                            uf(g, -0.4f, 0.4f) * (hi.z - lo.z)};
    if (i % 2) target = target + Vec3f{uf(g, 3, 5), uf(g, -5, 5), uf(g, -5, 5)};
    const Ray<float> r = make_ray(o, target - o, 0.f, i % 7 == 0 ? 1.f : kInfF);
    const Hit<float> hb = intersect_box(r, bx), hh = intersect_polyhedron(r, hs), hl = intersect_slabs(r, sl);
    const bool clear = std::abs(hb.t - r.tmax) > 1e-3f;  // skip the rare exit-at-tmax boundary
    if (!clear) continue;
    EXPECT_EQ(hh.mask, hb.mask) << i;
    EXPECT_EQ(hl.mask, hb.mask) << i;
    if (hb.mask) {
      ++hits;
      EXPECT_NEAR(hh.t, hb.t, 1e-5 * double(std::max(1.f, hb.t)));
      EXPECT_NEAR(hl.t, hb.t, 1e-5 * double(std::max(1.f, hb.t)));
      // Entry/exit roots agree with the box's first crossing: the entry, or the exit from inside.
      const auto rt = polyhedron_roots(r, hs);
      const auto rs = slabs_roots(r, sl);
      // (with the exit when the origin is inside: the first crossing)
      EXPECT_NEAR(rt.t[0] >= 0.f ? rt.t[0] : rt.t[1], hb.t, 1e-5 * double(std::max(1.f, hb.t)));
      if (rt.t[0] >= 0.f) {
        EXPECT_EQ(rt.t[0], rs.t[0]);
        EXPECT_EQ(rt.t[1], rs.t[1]);
      }
    }
  }
  EXPECT_GT(hits, 1000u);
}

// ---- SIMD lanes equal scalar results, both mappings ------------------------------------------

// Contracted builds: 64 ulps.
template <class Spec>
void check_lanes(const std::vector<typename Spec::Input>& in, const RaySoA& rays) {
  const auto prims = Spec::build(in);
  Tally rl{64}, pl{64};
  tally_lanes<Spec>(prims, rays, rl, pl);
  rl.expect_ok(std::string(Spec::kernel) + "/" + Spec::method + " rays in lanes");
  pl.expect_ok(std::string(Spec::kernel) + "/" + Spec::method + " prims in lanes");
}

TEST(PlanarSimd, EveryLaneEqualsScalar) {
  bench::for_each_spec_planar([]<class Spec>() {
    bench::Rng g(99);
    std::vector<typename Spec::Input> in;
    for (int k = 0; k < 24; ++k) in.push_back(Spec::make(k % 3 == 2 ? 1 : 0, k, g));
    RaySoA rays;
    for (int i = 0; i < 96; ++i) {
      if (i % 3 == 0) {
        rays.push(Spec::ray(i % 2, g));
      } else {
        // Directions of every octant and dominant axis (mixed Woop permutations in a packet).
        const Vec3f o{bench::uni(g, -3, 13), bench::uni(g, -3, 3), bench::uni(g, -30, -10)};
        const Vec3f to{bench::uni(g, -2, 12), bench::uni(g, -2, 2), bench::uni(g, -5, 40)};
        const Vec3f d = i % 3 == 1 ? to - o : Vec3f{bench::uni(g, -1, 1), bench::uni(g, -1, 1), bench::uni(g, -1, 1)};
        rays.push(o, d);
      }
    }
    check_lanes<Spec>(in, rays);
  });
}

// Polygons of very different vertex counts (3 .. 144) in one lane group, and every dropped axis.
TEST(PlanarSimd, PolygonGroupsOfMixedVertexCounts) {
  Rng g(31);
  std::vector<std::vector<Vec3f>> polys;
  const Vec3d axes[3][2] = {{{0, 1, 0}, {0, 0, 1}}, {{0, 0, 1}, {1, 0, 0}}, {{1, 0, 0}, {0, 1, 0}}};
  for (int i = 0; i < 30; ++i) {
    const Vec3d c{double(uf(g, -0.5f, 0.5f)), double(uf(g, -0.5f, 0.5f)), double(uf(g, -0.5f, 0.5f))};
    const auto& uv = axes[i % 3];
    polys.push_back(i % 4 == 0 ? gear(c, uv[0], uv[1], 36, 1.0, 1.4) : gear(c, uv[0], uv[1], 1 + i % 7, 0.4, 1.5));
    if (i % 4 == 1) polys.back().resize(3);  // a triangle
  }
  RaySoA rays;
  for (int i = 0; i < 64; ++i) rays.push(rand3(g, -4, 4), rand3(g, -1, 1) - rand3(g, -4, 4));
  check_lanes<bench::PolygonSpec>(polys, rays);
}

// ---- Woop: watertight ------------------------------------------------------------------------

// A fan of triangles around a centre vertex, in a tilted plane, with float vertices shared
// exactly. Rays aimed at the centre vertex and at points of the shared edges must hit at least
// one triangle: no leak.
TEST(PlanarWoop, WatertightOnSharedEdgesAndVertices) {
  Rng g(2013);
  std::size_t leaks_f = 0, leaks_simd = 0, leaks_d = 0, leaks_mt = 0, rays_n = 0;
  for (int fan = 0; fan < 12; ++fan) {
    const Vec3f c = rand3(g, -1, 1);
    const int n = 5 + fan % 6;
    Vec3d u = to_double(rand3(g, -1, 1)), w = to_double(rand3(g, -1, 1));
    u = u * (1.0 / std::sqrt(dot(u, u)));
    Vec3d v = cross(w, u);
    v = v * (1.0 / std::sqrt(dot(v, v)));
    std::vector<Vec3f> rim;
    for (int k = 0; k < n; ++k) {
      const double a = 2 * std::numbers::pi * (k + 0.3 * double(uf(g, 0, 1))) / n;
      rim.push_back(to_float(to_double(c) + u * std::cos(a) * 2.0 + v * std::sin(a) * 2.0));
    }
    PrimSoA<TriVerts> tv;
    PrimSoA<Triangle> mt;
    for (int k = 0; k < n; ++k) {
      tv.push(make_tri_verts(c, rim[std::size_t(k)], rim[std::size_t((k + 1) % n)]));
      mt.push(make_triangle(c, rim[std::size_t(k)], rim[std::size_t((k + 1) % n)]));
    }
    RaySoA rays;
    for (int i = 0; i < 256; ++i) {
      // Target: the centre vertex, or a point of a shared edge c -> rim[k] (the float nearest).
      const int k = int(g() % unsigned(n));
      const float s = i % 4 == 0 ? 0.f : uf(g, 0.f, 0.9f);  // not at the fan's outer rim
      const Vec3f target = to_float(to_double(c) + (to_double(rim[std::size_t(k)]) - to_double(c)) * double(s));
      // Origins on both sides and at grazing-ish angles; axis-aligned directions sometimes.
      Vec3f o = rand3(g, -6, 6);
      if (i % 16 == 1) o = target - Vec3f{0, 0, 3};
      if (i % 16 == 2) o = target + Vec3f{4, 0, 0};
      rays.push(make_ray(o, target - o));
    }
    // Scalar float and double, and 8-ray packets (mixed permutations).
    for (std::size_t i = 0; i < rays.count; ++i) {
      const Ray<float> r = rays.get(i);
      bool hf = false, hd = false, hm = false;
      const WoopRay<float> wf = make_woop_ray(r);
      const Ray<double> rd = Ray<double>::broadcast(r);
      const WoopRay<double> wd = make_woop_ray(rd);
      for (std::size_t j = 0; j < std::size_t(n); ++j) {
        hf = hf || intersect_triangle_woop(wf, r, tv.broadcast<float>(j)).mask;
        hd = hd || intersect_triangle_woop(wd, rd, tv.broadcast<double>(j)).mask;
        hm = hm || intersect_triangle_mt(r, mt.broadcast<float>(j)).mask;
      }
      ++rays_n;
      leaks_f += !hf;
      leaks_d += !hd;
      leaks_mt += !hm;
    }
    for (std::size_t i = 0; i < rays.size(); i += 8) {
      const Ray<f8> r = rays.packet<f8>(i);
      const WoopRay<f8> w8 = make_woop_ray(r);
      f8_mask any = mask_false<f8>();
      for (std::size_t j = 0; j < std::size_t(n); ++j) any = any | intersect_triangle_woop(w8, r, tv.broadcast<f8>(j)).mask;
      for (int k = 0; k < 8; ++k)
        if (i + std::size_t(k) < rays.count) leaks_simd += !lane_mask<f8>(any, k);
    }
  }
  EXPECT_EQ(leaks_f, 0u) << "of " << rays_n;
  EXPECT_EQ(leaks_simd, 0u) << "of " << rays_n;
  EXPECT_EQ(leaks_d, 0u) << "of " << rays_n;
  RecordProperty("moller_trumbore_leaks", int(leaks_mt));
  std::printf("watertight: %zu rays at shared edges/vertices: woop leaks float %zu, simd8 %zu, double %zu; moller-trumbore %zu\n",
              rays_n, leaks_f, leaks_simd, leaks_d, leaks_mt);
}

// Rays exactly through an edge in float: U == 0 exactly, the double fallback runs; in a packet it
// runs on those lanes only and every lane equals the scalar result.
TEST(PlanarWoop, DoubleFallbackPerLane) {
  const auto tv = one(make_tri_verts(Vec3f{0, 0, 5}, Vec3f{2, 0, 5}, Vec3f{0, 2, 5}));
  RaySoA rays;
  const float xs[8] = {1.f, 0.5f, 0.f, 0.25f, 1.5f, 0.3f, 1.f, 2.5f};
  const float ys[8] = {0.f, 0.5f, 0.75f, 0.25f, 0.5f, 0.f, 1.f, 0.f};
  for (int k = 0; k < 8; ++k) rays.push(zray(xs[k], ys[k]));
  const Ray<f8> r8 = rays.packet<f8>(0);
  const Hit<f8> h8 = intersect_triangle_woop(make_woop_ray(r8), r8, tv.broadcast<f8>(0));
  for (int k = 0; k < 8; ++k) {
    const Ray<float> r = rays.get(std::size_t(k));
    const Hit<float> h = intersect_triangle_woop(r, tv.broadcast<float>(0));
    EXPECT_EQ(h.mask, k != 7) << k;  // (2.5, 0) is outside, all others on an edge, a vertex or inside
    EXPECT_EQ(lane_mask<f8>(h8.mask, k), h.mask);
    EXPECT_TRUE(same_bits(lane(h8.t, k), h.t));
    if (h.mask) {
      EXPECT_TRUE(same_bits(lane(h8.u, k), h.u));  // a scalar miss exits early with u = 0
    }
  }
}

// ---- golden operation counts ------------------------------------------------------------------

TEST(PlanarOps, GoldenScalarCounts) {
  EXPECT_EQ(gold(find_row("plane", "uv", "hit").measured), Golden(11, 12, 3, 0, 3, 0, 1, 0));
  EXPECT_EQ(gold(find_row("plane", "uv", "miss").measured), Golden(2, 3, 0, 0, 1, 0, 0, 0));
  EXPECT_EQ(gold(find_row("plane", "uv_solve", "hit").measured), Golden(4, 4, 2, 0, 0, 0, 0, 0));
  EXPECT_EQ(gold(find_row("parallelogram", "lecture", "hit").measured), Golden(11, 12, 3, 0, 7, 0, 1, 0));
  EXPECT_EQ(gold(find_row("parallelogram", "lecture", "miss").measured), Golden(11, 12, 3, 0, 7, 0, 1, 0));
  EXPECT_EQ(gold(find_row("triangle", "cramer", "hit").measured), Golden(18, 24, 3, 0, 6, 0, 1, 0));
  EXPECT_EQ(gold(find_row("triangle", "cramer", "miss").measured), Golden(18, 24, 3, 0, 6, 0, 1, 0));
  EXPECT_EQ(gold(find_row("triangle", "woop", "hit").measured), Golden(22, 21, 1, 0, 12, 0, 1, 0));
  EXPECT_EQ(gold(find_row("triangle", "woop", "miss").measured), Golden(20, 12, 0, 0, 10, 0, 0, 0));
  EXPECT_EQ(gold(find_row("triangle", "woop_precompute", "hit").measured), Golden(0, 0, 3, 0, 4, 0, 6, 0));
  EXPECT_EQ(gold(find_row("polygon", "plane", "hit").measured), Golden(7, 8, 1, 0, 3, 0, 0, 0));
  EXPECT_EQ(gold(find_row("polygon", "crossing", "hit").measured), Golden(57, 32, 1, 0, 28, 0, 1, 0));
  EXPECT_EQ(gold(find_row("polygon", "crossing", "miss").measured), Golden(57, 32, 1, 0, 28, 0, 1, 0));
  EXPECT_EQ(gold(find_row("parallel_planes", "lecture", "hit").measured), Golden(8, 6, 4, 0, 9, 4, 5, 0));
  EXPECT_EQ(gold(find_row("parallel_planes", "lecture", "miss").measured), Golden(2, 3, 0, 0, 1, 0, 0, 0));
  // Halfspaces and slabs: + the first crossing in [tmin, tmax] (the exit from inside) 3 cmp 1 select.
  EXPECT_EQ(gold(find_row("polyhedron", "halfspaces", "hit").measured), Golden(40, 48, 8, 0, 43, 16, 18, 0));
  EXPECT_EQ(gold(find_row("polyhedron", "slabs", "hit").measured), Golden(18, 18, 6, 0, 6, 12, 2, 0));
  EXPECT_EQ(gold(find_row("polyhedron", "halfspaces", "miss").measured), Golden(25, 30, 5, 0, 25, 10, 10, 0));
  EXPECT_EQ(gold(find_row("polyhedron", "slabs", "miss").measured), Golden(12, 12, 4, 0, 2, 8, 0, 0));
}

TEST(PlanarOps, RowsMatchTheSlideWhereTheyShould) {
  // The parallel-planes arithmetic is exactly the slide's: 5+-6*1/ + 3 x (1+-1/).
  const auto d = opstable::diff(find_row("parallel_planes", "lecture", "hit"));
  EXPECT_EQ(std::make_tuple(d.add, d.mul, d.div), std::make_tuple(0L, 0L, 0L));
  for (const auto& r : ops_rows())
    if (r.lecture && !opstable::diff(r).zero()) {
      EXPECT_FALSE(r.note.empty()) << r.kernel << "/" << r.method;
    }
  // A mixed packet pays the whole path; a uniform missing packet exits like the scalar code.
  EXPECT_EQ(gold(find_row("plane", "uv", "miss", "simd8").measured), gold(find_row("plane", "uv", "hit").measured));
  EXPECT_EQ(gold(*find_row("plane", "uv", "miss", "simd8").uniform), gold(find_row("plane", "uv", "miss").measured));
}

}  // namespace
}  // namespace rb::test
