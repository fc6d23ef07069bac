// Regression tests for accuracy failures that only aimed rays find, several of which show only in
// the release build. This translation unit is always compiled with -ffp-contract=fast
// (tests/CMakeLists.txt), whatever the preset, so that the kernels inlined here are contracted
// into FMAs exactly as they are in `release`: a method that claims exact sign tests must control
// contraction inside itself, and these tests fail when it does not.
//
//   - Woop's watertight triangle: rays exactly through shared edges and vertices of closed meshes
//     (an octahedron and a jittered sphere mesh) must hit at least one face: 0 leaks, in float,
//     8-lane float and double.
//   - Geometric sphere: a float-rounded unit direction is not of length 1; a small sphere far away
//     must still be classified like the double reference.
//   - Cone apex: a hit on the apex has a finite normal; rays through the apex into a capped cone hit.
//   - Box and convex polyhedron from inside: t is the exit surface, not the clamped tmin.
//   - Planet: grazing rays at a sphere of radius 6.4e6 seen from 1 above the surface.
#include "core/counted.hpp"
#include "kernels/triangle_woop.hpp"
#include "soa/prims.hpp"
#include "soa/rays.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace rb {
namespace {

using Rng = std::mt19937_64;
double ud(Rng& g, double a, double b) { return std::uniform_real_distribution<double>(a, b)(g); }

// ---- Woop: watertight in the release build -------------------------------------------------------

struct Mesh {
  std::vector<Vec3f> v;
  std::vector<std::array<int, 3>> f;
  std::vector<std::array<int, 2>> edges() const {  // each undirected edge once
    std::vector<std::array<int, 2>> e;
    for (const auto& t : f)
      for (int k = 0; k < 3; ++k) {
        const int a = t[std::size_t(k)], b = t[std::size_t((k + 1) % 3)];
        if (a < b) e.push_back({a, b});
      }
    return e;
  }
};

// Octahedron c +- s e_i: every vertex, edge point c + s (e_i (1 - k) + e_j k) with dyadic k, is a
// float exactly, so rays can pass exactly through the shared edges.
Mesh octahedron(Vec3f c, float s) {
  Mesh m;
  m.v = {c + Vec3f{s, 0, 0}, c - Vec3f{s, 0, 0}, c + Vec3f{0, s, 0}, c - Vec3f{0, s, 0}, c + Vec3f{0, 0, s}, c - Vec3f{0, 0, s}};
  for (int x : {0, 1})
    for (int y : {2, 3})
      for (int z : {4, 5}) m.f.push_back({x, y, z});
  return m;
}

// A UV sphere whose vertices are jittered (rounded to float once, shared exactly by every face).
Mesh jittered_sphere(Rng& g, Vec3d c, double r, int rings, int segs, double jitter) {
  Mesh m;
  m.v.push_back(to_float(c + Vec3d{0, 0, r}));
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segs; ++j) {
      const double th = std::numbers::pi * i / rings, ph = 2 * std::numbers::pi * j / segs;
      const double rr = r * (1 + ud(g, -jitter, jitter));
      m.v.push_back(to_float(c + Vec3d{std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)} * rr));
    }
  m.v.push_back(to_float(c - Vec3d{0, 0, r}));
  const int last = int(m.v.size()) - 1;
  auto id = [&](int i, int j) { return 1 + (i - 1) * segs + (j % segs); };
  for (int j = 0; j < segs; ++j) m.f.push_back({0, id(1, j), id(1, j + 1)});
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segs; ++j) {
      m.f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  for (int j = 0; j < segs; ++j) m.f.push_back({last, id(rings - 1, j + 1), id(rings - 1, j)});
  return m;
}

// Reversed winding (see ReproducerSharedEdge: the other contracted form of each edge function).
void flip_winding(Mesh& m) {
  for (auto& t : m.f) std::swap(t[1], t[2]);
}

struct LeakCount {
  std::size_t rays = 0, f = 0, f8 = 0, d = 0;
};

// Every ray must hit at least one face of the closed mesh (scalar float, double, and 8-ray
// packets with mixed Woop permutations).
void count_leaks(const Mesh& m, const RaySoA& rays, LeakCount& lc) {
  PrimSoA<TriVerts> tv;
  for (const auto& t : m.f) tv.push(make_tri_verts(m.v[std::size_t(t[0])], m.v[std::size_t(t[1])], m.v[std::size_t(t[2])]));
  for (std::size_t i = 0; i < rays.count; ++i) {
    const Ray<float> r = rays.get(i);
    const Ray<double> rd = Ray<double>::broadcast(r);
    const WoopRay<float> wf = make_woop_ray(r);
    const WoopRay<double> wd = make_woop_ray(rd);
    bool hf = false, hd = false;
    for (std::size_t j = 0; j < m.f.size(); ++j) {
      hf = hf || intersect_triangle_woop(wf, r, tv.broadcast<float>(j)).mask;
      hd = hd || intersect_triangle_woop(wd, rd, tv.broadcast<double>(j)).mask;
    }
    ++lc.rays;
    lc.f += !hf;
    lc.d += !hd;
  }
  for (std::size_t i = 0; i < rays.size(); i += 8) {
    const Ray<f8> r = rays.packet<f8>(i);
    const WoopRay<f8> w8 = make_woop_ray(r);
    f8_mask any = mask_false<f8>();
    for (std::size_t j = 0; j < m.f.size(); ++j) any = any | intersect_triangle_woop(w8, r, tv.broadcast<f8>(j)).mask;
    for (int k = 0; k < 8; ++k)
      if (i + std::size_t(k) < rays.count) lc.f8 += !lane_mask<f8>(any, k);
  }
}

// The outside probe's reproducer: two faces of an octahedron sharing the edge (2.5, -0.25,
// 0.125) - (0.5, -0.25, -1.875); the ray passes exactly through that edge (at (2, -0.25, -0.375))
// into the solid. At least one face must be hit. Both windings: a contracted a*b - c*d is
// fma(a, b, -cd) or fma(-c, d, ab) as the compiler chooses; reversing the winding turns the one
// into the other, so one of the two windings leaks whichever form the compiler picked.
class ReleaseWoopWinding : public ::testing::TestWithParam<bool> {};
TEST_P(ReleaseWoopWinding, ReproducerSharedEdge) {
  const Ray<float> r = make_ray(Vec3d{5.84088134765625, 0.75, -4.53411865234375}, Vec3d{-4, -1, 4});
  const Vec3d a{2.5, -0.25, 0.125}, b1{0.5, -0.25, -1.875}, c1{0.5, 1.75, 0.125}, b2{0.5, -2.25, 0.125}, c2{0.5, -0.25, -1.875};
  const bool flip = GetParam();
  const TriVerts<float> f1 = flip ? make_tri_verts(a, c1, b1) : make_tri_verts(a, b1, c1);
  const TriVerts<float> f2 = flip ? make_tri_verts(a, c2, b2) : make_tri_verts(a, b2, c2);
  const bool hf = intersect_triangle_woop(r, f1).mask || intersect_triangle_woop(r, f2).mask;
  const Ray<double> rd = Ray<double>::broadcast(r);
  const bool hd = intersect_triangle_woop(rd, prim_cast<double>(f1)).mask || intersect_triangle_woop(rd, prim_cast<double>(f2)).mask;
  const Ray<f8> r8 = Ray<f8>::broadcast(r);
  const bool h8 = any_of<f8>(intersect_triangle_woop(r8, prim_cast<f8>(f1)).mask | intersect_triangle_woop(r8, prim_cast<f8>(f2)).mask);
  const Ray<cfloat> rc = Ray<cfloat>::broadcast(r);
  const bool hc = intersect_triangle_woop(rc, prim_cast<cfloat>(f1)).mask || intersect_triangle_woop(rc, prim_cast<cfloat>(f2)).mask;
  EXPECT_TRUE(hf);
  EXPECT_TRUE(hd);
  EXPECT_TRUE(h8);
  EXPECT_TRUE(hc);
}
INSTANTIATE_TEST_SUITE_P(BothWindings, ReleaseWoopWinding, ::testing::Bool());

// Rays from inside (every ray from an interior point leaves a closed mesh through a face) and
// from outside through the target into an interior point, aimed exactly at shared edges and
// vertices.
TEST(ReleaseWoop, ClosedMeshesNoLeaks) {
  Rng g(20130201);
  LeakCount oct, sph;
  // Octahedra at several placements and sizes (dyadic: edge points are exact floats).
  for (int rep = 0; rep < 24; ++rep) {
    const float s = std::ldexp(1.f, int(g() % 5) - 1);
    const Vec3f c{float(int(g() % 64) - 32) / 8.f, float(int(g() % 64) - 32) / 8.f, float(int(g() % 64) - 32) / 8.f};
    Mesh m = octahedron(c, s);
    if (rep % 2) flip_winding(m);
    RaySoA rays;
    const auto e = m.edges();
    for (int i = 0; i < 256; ++i) {
      Vec3f target;
      if (i % 8 == 0) {
        target = m.v[g() % m.v.size()];
      } else {
        const auto& ed = e[g() % e.size()];
        const float k = float(1 + g() % 255) / 256.f;  // exact: the edge point is a float
        target = m.v[std::size_t(ed[0])] * (1 - k) + m.v[std::size_t(ed[1])] * k;
      }
      // An interior point q (strictly inside: |q - c|_1 < s), and an origin beyond the target.
      const Vec3f q = to_float(to_double(c) + Vec3d{ud(g, -1, 1), ud(g, -1, 1), ud(g, -1, 1)} * (0.3 * double(s)));
      if (i % 4 == 0) {
        rays.push(make_ray(q, target - q));  // from inside, out through the edge
      } else if (i % 4 == 1) {
        const Vec3f o = to_float(to_double(target) + (to_double(target) - to_double(q)) * ud(g, 0.5, 40));
        rays.push(make_ray(o, q - o));  // from outside, in through the edge (the line meets q)
      } else {
        // Small integer directions towards the centre, origin = target - k d exactly (the
        // probe's construction): the unnormalised ray passes exactly through the target.
        // Entering: the derivative of |p - c|_1 along d at the target is negative (exact: small
        // integers and exact float differences).
        Vec3f d;
        auto enters = [&](const Vec3f& dd) {
          const Vec3f l = target - c;
          float der = 0;
          for (int ax = 0; ax < 3; ++ax) der += l[ax] > 0 ? dd[ax] : l[ax] < 0 ? -dd[ax] : std::fabs(dd[ax]);
          return der < 0;
        };
        do {
          d = Vec3f{float(int(g() % 9) - 4), float(int(g() % 9) - 4), float(int(g() % 9) - 4)};
        } while (!enters(d));
        const float k = float(1 + g() % 15) / 8.f + float(g() % 1000) / 65536.f;
        rays.push(make_ray(target - d * k, d));
      }
    }
    count_leaks(m, rays, oct);
  }
  // Jittered sphere meshes far and near the origin.
  for (int rep = 0; rep < 6; ++rep) {
    const Vec3d c{ud(g, -8, 8), ud(g, -8, 8), ud(g, -8, 8)};
    const double r = ud(g, 0.5, 3);
    Mesh m = jittered_sphere(g, c, r, 8 + rep, 10 + 2 * rep, 0.05);
    if (rep % 2) flip_winding(m);
    RaySoA rays;
    const auto e = m.edges();
    for (int i = 0; i < 512; ++i) {
      Vec3f target;
      if (i % 8 == 0) {
        target = m.v[g() % m.v.size()];
      } else {
        const auto& ed = e[g() % e.size()];
        const double k = ud(g, 0.01, 0.99);
        target = to_float(to_double(m.v[std::size_t(ed[0])]) * (1 - k) + to_double(m.v[std::size_t(ed[1])]) * k);
      }
      const Vec3f q = to_float(c + Vec3d{ud(g, -1, 1), ud(g, -1, 1), ud(g, -1, 1)} * (0.3 * r));
      if (i % 2 == 0) {
        rays.push(make_ray(q, target - q));
      } else {
        const Vec3f o = to_float(to_double(target) + (to_double(target) - to_double(q)) * ud(g, 0.5, 40));
        rays.push(make_ray(o, q - o));
      }
    }
    count_leaks(m, rays, sph);
  }
  std::printf("woop (built with -ffp-contract=fast): octahedra %zu rays, leaks float %zu simd8 %zu double %zu; "
              "jittered spheres %zu rays, leaks float %zu simd8 %zu double %zu\n",
              oct.rays, oct.f, oct.f8, oct.d, sph.rays, sph.f, sph.f8, sph.d);
  EXPECT_EQ(oct.f, 0u);
  EXPECT_EQ(oct.f8, 0u);
  EXPECT_EQ(oct.d, 0u);
  EXPECT_EQ(sph.f, 0u);
  EXPECT_EQ(sph.f8, 0u);
  EXPECT_EQ(sph.d, 0u);
}

}  // namespace
}  // namespace rb
