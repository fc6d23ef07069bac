// The planar kernel family, hand-worked: plane with [u,v], parallelogram, triangle by Cramer's rule
// and by Woop-Benthin-Wald, general polygon (crossing test), parallel planes, convex polyhedron
// (halfspaces, slabs).
//   - hand-worked hit / miss / t / [u,v] cases, typed over the value types
//     (float, double, f8, d4; Counted<T> computes what T computes: tests/kernel_test_util.hpp);
//   - degenerate primitives and bad rays: a defined miss (t = +inf) or a construction error.
// Random references, SIMD lanes, watertightness and op counts: tests/test_planar_family_checks.cpp.
#include "kernels/parallel_planes.hpp"
#include "kernels/plane_uv.hpp"
#include "kernels/polygon.hpp"
#include "kernels/polyhedron.hpp"
#include "kernels/triangle_cramer.hpp"
#include "kernels/triangle_woop.hpp"
#include "planar_test_util.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

namespace rb::test {
namespace {

constexpr double kTolPlanar = 1e-5;

template <class F>
struct Planar : ::testing::Test {};
TYPED_TEST_SUITE(Planar, ValueNumbers);

// Runs a kernel on one ray and one primitive of a batch (primitive broadcast to every lane).
template <class F, class Soa, class Fn>
HitF run_soa(Fn fn, const Soa& soa, std::size_t j, const Ray<float>& r) {
  const Hit<F> h = fn(Ray<F>::broadcast(r), soa.template broadcast<F>(j), j);
  const HitF h0 = lane_hit(h, 0);
  for (int k = 1; k < lanes_v<F>; ++k) {
    EXPECT_EQ(lane_hit(h, k).hit, h0.hit);
    EXPECT_EQ(lane_hit(h, k).t, h0.t);
  }
  if (!h0.hit) {
    EXPECT_EQ(h0.t, kInfD);
  }
  return h0;
}

// A one-primitive batch of a [u,v] plane; the slot of polygon `id` in a batch.
TriLectureSoA uv_soa(Vec3f p0, Vec3f u, Vec3f v) {
  int ax = 0;
  const auto q = make_plane_uv(p0, u, v, ax);
  return TriLectureSoA::from({q}, {ax});
}
std::size_t slot_of(const PolygonSoA& s, std::size_t id) {
  for (std::size_t j = 0; j < s.size(); ++j)
    if (s.id[j] == id) return j;
  ADD_FAILURE() << "no polygon " << id;
  return 0;
}

// ---- hand-worked cases ------------------------------------------------------------------------

TYPED_TEST(Planar, PlaneUV) {
  using F = TypeParam;
  // PI0 = (1, 2, 5), U = (2, 0, 0), V = (0, 4, 0): P = (2, 4, 5) is u = 0.5, v = 0.5.
  const auto s = uv_soa(Vec3f{1, 2, 5}, Vec3f{2, 0, 0}, Vec3f{0, 4, 0});
  auto k = [](const auto& r, const auto& q, std::size_t) { return intersect_plane_uv(r, q, 2); };
  HitF h = run_soa<F>(k, s, 0, zray(2, 4));
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 5.0, kTolPlanar);
  EXPECT_NEAR(h.u, 0.5, kTolPlanar);
  EXPECT_NEAR(h.v, 0.5, kTolPlanar);
  // Unbounded: u = -2, v = 1.5; from behind.
  h = run_soa<F>(k, s, 0, zray(-3, 8, 9, -1));
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 4.0, kTolPlanar);
  EXPECT_NEAR(h.u, -2.0, kTolPlanar);
  EXPECT_NEAR(h.v, 1.5, kTolPlanar);
  // A frame in the plane x = 3 (dropped axis x): U = (0, 0, 2), V = (0, 1, 0), oblique ray.
  int ax = -1;
  const auto q = make_plane_uv(Vec3f{3, 0, 0}, Vec3f{0, 0, 2}, Vec3f{0, 1, 0}, ax);
  EXPECT_EQ(ax, 0);
  const auto s2 = TriLectureSoA::from({q}, {ax});
  // From (0, 1, 1) along (3, 0, 4)/5: t = 5, P = (3, 1, 5): u = 2.5, v = 1.
  h = run_soa<F>([ax](const auto& r, const auto& p, std::size_t) { return intersect_plane_uv(r, p, ax); }, s2, 0,
                 make_ray(Vec3f{0, 1, 1}, Vec3f{3, 0, 4}));
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 5.0, kTolPlanar);
  EXPECT_NEAR(h.u, 2.5, kTolPlanar);
  EXPECT_NEAR(h.v, 1.0, kTolPlanar);
  // Parallel, behind, beyond tmax.
  EXPECT_FALSE(run_soa<F>(k, s, 0, make_ray(Vec3f{0, 0, 0}, Vec3f{1, 1, 0})).hit);
  EXPECT_FALSE(run_soa<F>(k, s, 0, zray(0, 0, 0, -1)).hit);
  EXPECT_FALSE(run_soa<F>(k, s, 0, make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 0.f, 4.9f)).hit);
  // Degenerate frames (parallel U, V; zero U; NaN) never hit.
  for (const auto& [u, v] : {std::pair{Vec3f{1, 0, 0}, Vec3f{2, 0, 0}}, std::pair{Vec3f{0, 0, 0}, Vec3f{0, 1, 0}},
                             std::pair{Vec3f{kNaNF, 0, 0}, Vec3f{0, 1, 0}}}) {
    int a = 0;
    const auto d = make_plane_uv(Vec3f{0, 0, 5}, u, v, a);
    EXPECT_FALSE((run_soa<F>([a](const auto& r, const auto& p, std::size_t) { return intersect_plane_uv(r, p, a); },
                             TriLectureSoA::from({d}, {a}), 0, zray(0.1f, 0.1f))
                      .hit));
  }
  // [u,v] of a point alone.
  F u, v;
  plane_uv_of_point(s.template broadcast<F>(0), 2, Vec3<F>{F(3), F(6), F(5)}, u, v);
  EXPECT_NEAR(double(lane(u, 0)), 1.0, kTolPlanar);
  EXPECT_NEAR(double(lane(v, 0)), 1.0, kTolPlanar);
}

TYPED_TEST(Planar, Parallelogram) {
  using F = TypeParam;
  // R0 = (0, 0, 5), U = (2, 0, 0), V = (1, 2, 0) (sheared): P = R0 + u U + v V.
  int ax = -1;
  const auto q = make_parallelogram(Vec3f{0, 0, 5}, Vec3f{2, 0, 0}, Vec3f{1, 2, 0}, ax);
  EXPECT_EQ(ax, 2);
  const auto s = TriLectureSoA::from({q}, {ax});
  auto k = [](const auto& r, const auto& p, std::size_t) { return intersect_parallelogram(r, p, 2); };
  struct Case { float x, y; bool hit; double u, v; };
  for (const Case c : {Case{1.0f, 1.0f, true, 0.25, 0.5}, Case{2.5f, 1.0f, true, 1.0, 0.5},   // on the edge u = 1
                       Case{2.8f, 1.8f, true, 0.95, 0.9},                                     // outside the triangle half
                       Case{0.0f, 0.0f, true, 0.0, 0.0},                                      // corner R0
                       Case{3.0f, 1.0f, false, 0, 0}, Case{0.2f, 1.8f, false, 0, 0},
                       Case{1.0f, -0.1f, false, 0, 0}, Case{2.0f, 2.1f, false, 0, 0}}) {
    const HitF h = run_soa<F>(k, s, 0, zray(c.x, c.y));
    EXPECT_EQ(h.hit, c.hit) << c.x << " " << c.y;
    if (c.hit) {
      EXPECT_NEAR(h.t, 5.0, kTolPlanar);
      EXPECT_NEAR(h.u, c.u, kTolPlanar);
      EXPECT_NEAR(h.v, c.v, kTolPlanar);
    }
  }
  // The same data through TriLectureSoA::build (R0, R0 + U, R0 + V).
  const auto s2 = TriLectureSoA::build(std::vector<std::array<Vec3f, 3>>{{Vec3f{0, 0, 5}, Vec3f{2, 0, 5}, Vec3f{1, 2, 5}}});
  EXPECT_TRUE(run_soa<F>([&](const auto& r, const auto& p, std::size_t j) { return intersect_parallelogram(r, p, s2.axis_of(j)); },
                         s2, 0, zray(2.8f, 1.8f))
                  .hit);
  EXPECT_FALSE(run_soa<F>(k, s, 0, make_ray(Vec3f{1, 1, 0}, Vec3f{1, 0, 0})).hit);  // parallel
  // Collinear corners: never.
  int a2 = 0;
  const auto d = make_parallelogram(Vec3f{0, 0, 5}, Vec3f{1, 1, 0}, Vec3f{2, 2, 0}, a2);
  EXPECT_FALSE(run_soa<F>(k, TriLectureSoA::from({d}, {a2}), 0, zray(0.f, 0.f)).hit);
}

TYPED_TEST(Planar, TriangleCramerAndWoop) {
  using F = TypeParam;
  const Vec3f a{0, 0, 5}, b{2, 0, 5}, c{0, 2, 5};
  const auto cs = one(make_triangle(a, b, c));
  const auto ws = one(make_tri_verts(a, b, c));
  auto kc = [](const auto& r, const auto& q, std::size_t) { return intersect_triangle_cramer(r, q); };
  auto kw = [](const auto& r, const auto& q, std::size_t) { return intersect_triangle_woop(make_woop_ray(r), r, q); };
  auto run = [&](int m, const Ray<float>& r) { return m == 0 ? run_soa<F>(kc, cs, 0, r) : run_soa<F>(kw, ws, 0, r); };
  for (int m = 0; m < 2; ++m) {
    HitF h = run(m, zray(0.5f, 0.25f));
    EXPECT_TRUE(h.hit) << m;
    EXPECT_NEAR(h.t, 5.0, kTolPlanar);
    EXPECT_NEAR(h.u, 0.25, kTolPlanar);
    EXPECT_NEAR(h.v, 0.125, kTolPlanar);
    h = run(m, zray(0.5f, 0.25f, 8, -1));  // from behind
    EXPECT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 3.0, kTolPlanar);
    EXPECT_NEAR(h.u, 0.25, kTolPlanar);
    // Oblique, x-dominant direction (Woop's kz = x): from (-5, 0.5, 0.25) to (0.5, 0.5, 5)... through P = (0.5, 0.5, 5).
    h = run(m, make_ray(Vec3f{-5.5f, 0.5f, 2.f}, Vec3f{6.f, 0.f, 3.f}));
    EXPECT_TRUE(h.hit) << m;
    EXPECT_NEAR(h.t, std::sqrt(45.0), 1e-5);
    EXPECT_NEAR(h.u, 0.25, kTolPlanar);
    EXPECT_NEAR(h.v, 0.25, kTolPlanar);
    // Exactly on edges and a vertex (inclusive; Woop takes its double fallback here).
    EXPECT_TRUE(run(m, zray(1.f, 0.f)).hit) << m;
    EXPECT_TRUE(run(m, zray(1.f, 1.f)).hit) << m;
    EXPECT_TRUE(run(m, zray(0.f, 0.f)).hit) << m;
    // Outside each edge, parallel, behind, beyond tmax.
    EXPECT_FALSE(run(m, zray(-0.1f, 0.5f)).hit);
    EXPECT_FALSE(run(m, zray(0.5f, -0.1f)).hit);
    EXPECT_FALSE(run(m, zray(1.1f, 1.1f)).hit);
    EXPECT_FALSE(run(m, make_ray(Vec3f{0.5f, 0.25f, 0}, Vec3f{1, 0, 0})).hit);
    EXPECT_FALSE(run(m, make_ray(Vec3f{0.5f, 0.25f, 5}, Vec3f{1, 0, 0})).hit);  // in the plane
    EXPECT_FALSE(run(m, zray(0.5f, 0.25f, 0, -1)).hit);
    EXPECT_FALSE(run(m, make_ray(Vec3f{0.5f, 0.25f, 0}, Vec3f{0, 0, 1}, 0.f, 4.f)).hit);
  }
  // Degenerate triangles (repeated vertex, collinear, NaN vertex) never hit.
  for (const auto& t : {std::array<Vec3f, 3>{a, a, c}, std::array<Vec3f, 3>{a, Vec3f{1, 0, 5}, b},
                        std::array<Vec3f, 3>{a, b, Vec3f{kNaNF, 0, 5}}}) {
    EXPECT_FALSE(run_soa<F>(kc, one(make_triangle(t[0], t[1], t[2])), 0, zray(0.f, 0.f)).hit);
    EXPECT_FALSE(run_soa<F>(kw, one(make_tri_verts(t[0], t[1], t[2])), 0, zray(0.f, 0.f)).hit);
  }
  // Normal of the Woop data.
  const Vec3<F> n = triangle_normal(ws.template broadcast<F>(0));
  EXPECT_EQ(double(lane(n.z, 0)), 4.0);
}

// A concave "U" in z = 5: the notch 1 < x < 2, 1 < y < 3 is outside.
std::vector<Vec3f> u_shape(float z = 5.f) {
  return {Vec3f{0, 0, z}, Vec3f{3, 0, z}, Vec3f{3, 3, z}, Vec3f{2, 3, z}, Vec3f{2, 1, z}, Vec3f{1, 1, z}, Vec3f{1, 3, z}, Vec3f{0, 3, z}};
}

TYPED_TEST(Planar, Polygon) {
  using F = TypeParam;
  // Polygon 0: the U; 1: a triangle in the plane x = 3 (dropped axis x); 2..6 degenerate.
  const std::vector<std::vector<Vec3f>> polys = {
      u_shape(),
      {Vec3f{3, 0, 0}, Vec3f{3, 4, 0}, Vec3f{3, 0, 4}},
      {Vec3f{0, 0, 1}, Vec3f{1, 0, 1}},                                   // < 3 vertices
      {Vec3f{0, 0, 1}, Vec3f{1, 1, 1}, Vec3f{2, 2, 1}, Vec3f{3, 3, 1}},   // collinear
      {Vec3f{0, 0, 1}, Vec3f{1, 0, 1}, Vec3f{0, 0, 1}, Vec3f{1, 0, 1}},   // zero area
      {Vec3f{0, 0, 1}, Vec3f{kNaNF, 0, 1}, Vec3f{0, 1, 1}},               // NaN vertex
      {Vec3f{0, 0, 1}, Vec3f{1, 0, 1}, Vec3f{0, kInfF, 1}}};              // inf vertex
  const auto s = PolygonSoA::build(polys);
  EXPECT_EQ(s.degenerate, 5u);
  EXPECT_STREQ(polygon_info(polys[2]).why, "fewer than 3 vertices");
  EXPECT_STREQ(polygon_info(polys[5]).why, "non-finite vertex");
  auto k = [](const auto& r, const auto& p, std::size_t) { return intersect_polygon(r, p); };
  const std::size_t j0 = slot_of(s, 0), j1 = slot_of(s, 1);
  struct Case { float x, y; bool hit; };
  for (const Case c : {Case{0.5f, 0.5f, true}, Case{2.5f, 2.5f, true}, Case{0.5f, 2.5f, true}, Case{1.5f, 0.5f, true},
                       Case{1.5f, 2.f, false}, Case{1.5f, 1.5f, false}, Case{4.f, 1.f, false}, Case{-1.f, 1.f, false},
                       Case{0.5f, 3.5f, false}, Case{2.5f, -0.5f, false}}) {
    const HitF h = run_soa<F>(k, s, j0, zray(c.x, c.y));
    EXPECT_EQ(h.hit, c.hit) << c.x << " " << c.y;
    if (c.hit) {
      EXPECT_NEAR(h.t, 5.0, kTolPlanar);
    }
  }
  // From behind and obliquely: from (0.5, 0.5, 10) towards (2.5, 2.5, 5): t = |(2, 2, -5)|.
  HitF h = run_soa<F>(k, s, j0, make_ray(Vec3f{0.5f, 0.5f, 10}, Vec3f{2, 2, -5}));
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, std::sqrt(33.0), 1e-5);
  // The x = 3 triangle: ray along +x.
  h = run_soa<F>(k, s, j1, make_ray(Vec3f{0, 1, 1}, Vec3f{1, 0, 0}));
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 3.0, kTolPlanar);
  EXPECT_FALSE(run_soa<F>(k, s, j1, make_ray(Vec3f{0, 3, 3}, Vec3f{1, 0, 0})).hit);
  // Parallel, beyond tmax.
  EXPECT_FALSE(run_soa<F>(k, s, j0, make_ray(Vec3f{0.5f, 0.5f, 0}, Vec3f{1, 0, 0})).hit);
  EXPECT_FALSE(run_soa<F>(k, s, j0, make_ray(Vec3f{0.5f, 0.5f, 0}, Vec3f{0, 0, 1}, 0.f, 4.f)).hit);
  // Degenerate polygons never hit, through any point of their (would-be) plane.
  for (std::size_t id = 2; id < polys.size(); ++id) {
    const std::size_t j = slot_of(s, id);
    for (const Ray<float>& r : {zray(0.1f, 0.f), zray(0.5f, 0.5f), make_ray(Vec3f{0.2f, 0.1f, 0}, Vec3f{0.01f, 0.02f, 1})})
      EXPECT_FALSE(run_soa<F>(k, s, j, r).hit) << id;
  }
  EXPECT_NEAR(double(lane(polygon_normal(s.template broadcast<F>(j0)).z, 0)), 1.0, 1e-6);
}

TYPED_TEST(Planar, ParallelPlanes) {
  using F = TypeParam;
  // z = 5, 7, 3 (offsets d with n = (0, 0, 2): 2z + d = 0).
  const auto s = one<ParallelPlanes4>(make_parallel_planes<4>(Vec3f{0, 0, 2}, std::vector<float>{-10, -14, -6}));
  auto k = [](const auto& r, const auto& p, std::size_t) { return intersect_parallel_planes(r, p); };
  HitF h = run_soa<F>(k, s, 0, zray(1, 2));
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 3.0, kTolPlanar);
  h = run_soa<F>(k, s, 0, make_ray(Vec3f{1, 2, 0}, Vec3f{0, 0, 1}, 4.f, 100.f));
  EXPECT_NEAR(h.t, 5.0, kTolPlanar);
  h = run_soa<F>(k, s, 0, zray(0, 0, 10, -1));
  EXPECT_NEAR(h.t, 3.0, kTolPlanar);
  h = run_soa<F>(k, s, 0, make_ray(Vec3f{0, 0, 0}, Vec3f{0, 3, 4}));  // t = z / 0.8
  EXPECT_NEAR(h.t, 3.75, kTolPlanar);
  EXPECT_FALSE(run_soa<F>(k, s, 0, make_ray(Vec3f{0, 0, 4}, Vec3f{1, 0, 0})).hit);   // parallel
  EXPECT_FALSE(run_soa<F>(k, s, 0, zray(0, 0, 0, -1)).hit);                          // all behind
  EXPECT_FALSE(run_soa<F>(k, s, 0, make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 7.5f, 9.f)).hit);
  // Every t_i.
  F t[4];
  const auto m = parallel_planes_all(Ray<F>::broadcast(zray(0, 0)), s.template broadcast<F>(0), t);
  EXPECT_TRUE(lane_mask<F>(m, 0));
  EXPECT_NEAR(double(lane(t[0], 0)), 5.0, kTolPlanar);
  EXPECT_NEAR(double(lane(t[1], 0)), 7.0, kTolPlanar);
  EXPECT_NEAR(double(lane(t[2], 0)), 3.0, kTolPlanar);
  EXPECT_TRUE(std::isnan(double(lane(t[3], 0))));  // unused slot
  // Zero normal: never; too many offsets: an error.
  EXPECT_FALSE(run_soa<F>(k, one<ParallelPlanes4>(make_parallel_planes<4>(Vec3f{0, 0, 0}, std::vector<float>{-5})), 0, zray(0, 0)).hit);
  EXPECT_THROW((make_parallel_planes<4>(Vec3f{0, 0, 1}, std::vector<float>{1, 2, 3, 4, 5})), std::invalid_argument);
}

TYPED_TEST(Planar, Polyhedron) {
  using F = TypeParam;
  // Octahedron |x| + |y| + |z| <= 1.
  std::vector<HalfspaceIn> hs;
  for (int s = 0; s < 8; ++s) {
    const Vec3f n{s & 1 ? -1.f : 1.f, s & 2 ? -1.f : 1.f, s & 4 ? -1.f : 1.f};
    hs.push_back({n, Vec3f{n.x, 0, 0}});
  }
  const auto s = one<Halfspaces8>(make_halfspaces<8>(hs));
  auto k = [](const auto& r, const auto& p, std::size_t) { return intersect_polyhedron(r, p); };
  HitF h = run_soa<F>(k, s, 0, zray(0, 0, -5));
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 4.0, kTolPlanar);
  h = run_soa<F>(k, s, 0, zray(0.5f, 0, -5));
  EXPECT_NEAR(h.t, 4.5, kTolPlanar);
  h = run_soa<F>(k, s, 0, make_ray(Vec3f{0.1f, 0.2f, 0}, Vec3f{0, 1, 0}));  // inside: the exit face
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 0.7, kTolPlanar);
  EXPECT_FALSE(run_soa<F>(k, s, 0, make_ray(Vec3f{0.1f, 0.2f, 0}, Vec3f{0, 1, 0}, 0.f, 0.5f)).hit);  // exit beyond tmax
  EXPECT_FALSE(run_soa<F>(k, s, 0, zray(2, 0, -5)).hit);
  EXPECT_FALSE(run_soa<F>(k, s, 0, zray(0.6f, 0.6f, -5)).hit);
  EXPECT_FALSE(run_soa<F>(k, s, 0, zray(0, 0, -5, -1)).hit);
  EXPECT_FALSE(run_soa<F>(k, s, 0, make_ray(Vec3f{0, 0, -5}, Vec3f{0, 0, 1}, 0.f, 3.5f)).hit);
  // Roots: entry and exit of the line.
  const auto roots = polyhedron_roots(Ray<F>::broadcast(zray(0, 0, -5)), s.template broadcast<F>(0));
  EXPECT_TRUE(lane_mask<F>(roots.valid[0], 0));
  EXPECT_NEAR(double(lane(roots.t[0], 0)), 4.0, kTolPlanar);
  EXPECT_NEAR(double(lane(roots.t[1], 0)), 6.0, kTolPlanar);
  const auto none = polyhedron_roots(Ray<F>::broadcast(zray(2, 0, -5)), s.template broadcast<F>(0));
  EXPECT_FALSE(lane_mask<F>(none.valid[0], 0));
  // Normal at (0.25, 0.25, -0.5): the face (1, 1, -1) / sqrt 3.
  const Vec3<F> n = polyhedron_normal(s.template broadcast<F>(0), Vec3<F>{F(0.25f), F(0.25f), F(-0.5f)});
  EXPECT_NEAR(double(lane(n.z, 0)), -1.0 / std::sqrt(3.0), 1e-6);
  // Slabs: the unit cube [-1, 1]^3 as three axis slabs; an oriented slab pair.
  const auto sb = one<Slabs3>(make_box_slabs(Vec3f{-1, -1, -1}, Vec3f{1, 1, 1}));
  auto ks = [](const auto& r, const auto& p, std::size_t) { return intersect_slabs(r, p); };
  h = run_soa<F>(ks, sb, 0, zray(0.5f, 0.5f, -5));
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 4.0, kTolPlanar);
  EXPECT_FALSE(run_soa<F>(ks, sb, 0, zray(1.5f, 0.5f, -5)).hit);
  const auto sr = slabs_roots(Ray<F>::broadcast(zray(0.5f, 0.5f, -5)), sb.template broadcast<F>(0));
  EXPECT_NEAR(double(lane(sr.t[1], 0)), 6.0, kTolPlanar);
  // Degenerate inputs: zero normal, inverted box, NaN bounds: never; too many halfspaces: an error.
  EXPECT_FALSE(run_soa<F>(k, one<Halfspaces8>(make_halfspaces<8>({{Vec3f{0, 0, 0}, Vec3f{0, 0, 0}}})), 0, zray(0, 0, -5)).hit);
  EXPECT_FALSE(run_soa<F>(k, one<Halfspaces8>(make_box_halfspaces(Vec3f{1, -1, -1}, Vec3f{-1, 1, 1})), 0, zray(0, 0, -5)).hit);
  EXPECT_FALSE(run_soa<F>(ks, one<Slabs3>(make_box_slabs(Vec3f{kNaNF, -1, -1}, Vec3f{1, 1, 1})), 0, zray(0, 0, -5)).hit);
  EXPECT_FALSE(run_soa<F>(ks, one<Slabs3>(make_slabs<3>({Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, Vec3f{0, 0, 1}}, {-1, -1, -1}, {1, 1, 1})), 0,
                          zray(0, 0, -5))
                   .hit);
  EXPECT_THROW(make_halfspaces<2>(hs), std::invalid_argument);
}

// NaN, inf and zero-direction rays, and empty intervals: a miss with t = +inf in every kernel.
TYPED_TEST(Planar, BadRaysMiss) {
  using F = TypeParam;
  const std::vector<Ray<float>> bad = {
      make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 0}),     make_ray(Vec3f{kNaNF, 0, 0}, Vec3f{0, 0, 1}),
      make_ray(Vec3f{0, 0, 0}, Vec3f{0, kNaNF, 1}), make_ray(Vec3f{kInfF, 0, 0}, Vec3f{0, 0, 1}),
      make_ray(Vec3f{0.5f, 0.5f, 0}, Vec3f{0, 0, 1}, 5.f, 1.f), make_ray(Vec3f{0.5f, 0.5f, 0}, Vec3f{0, 0, 1}, kNaNF, 1.f)};
  int ax = 0;
  const auto lec = TriLectureSoA::from({make_parallelogram(Vec3f{-1, -1, 5}, Vec3f{3, 0, 0}, Vec3f{0, 3, 0}, ax)}, {2});
  const auto tri = one(make_triangle(Vec3f{-1, -1, 5}, Vec3f{2, -1, 5}, Vec3f{-1, 2, 5}));
  const auto tv = one(make_tri_verts(Vec3f{-1, -1, 5}, Vec3f{2, -1, 5}, Vec3f{-1, 2, 5}));
  const auto poly = PolygonSoA::build(std::vector<std::vector<Vec3f>>{u_shape()});
  const auto pp = one<ParallelPlanes4>(make_parallel_planes<4>(Vec3f{0, 0, 1}, std::vector<float>{-5, -6}));
  const auto ph = one<Halfspaces8>(make_box_halfspaces(Vec3f{-1, -1, -1}, Vec3f{1, 1, 1}));
  const auto sl = one<Slabs3>(make_box_slabs(Vec3f{-1, -1, -1}, Vec3f{1, 1, 1}));
  for (const auto& r : bad) {
    EXPECT_FALSE(run_soa<F>([](const auto& rr, const auto& q, std::size_t) { return intersect_plane_uv(rr, q, 2); }, lec, 0, r).hit);
    EXPECT_FALSE(run_soa<F>([](const auto& rr, const auto& q, std::size_t) { return intersect_parallelogram(rr, q, 2); }, lec, 0, r).hit);
    EXPECT_FALSE(run_soa<F>([](const auto& rr, const auto& q, std::size_t) { return intersect_triangle_cramer(rr, q); }, tri, 0, r).hit);
    EXPECT_FALSE(run_soa<F>([](const auto& rr, const auto& q, std::size_t) { return intersect_triangle_woop(rr, q); }, tv, 0, r).hit);
    EXPECT_FALSE(run_soa<F>([](const auto& rr, const auto& q, std::size_t) { return intersect_polygon(rr, q); }, poly, 0, r).hit);
    EXPECT_FALSE(run_soa<F>([](const auto& rr, const auto& q, std::size_t) { return intersect_parallel_planes(rr, q); }, pp, 0, r).hit);
    EXPECT_FALSE(run_soa<F>([](const auto& rr, const auto& q, std::size_t) { return intersect_polyhedron(rr, q); }, ph, 0, r).hit);
    EXPECT_FALSE(run_soa<F>([](const auto& rr, const auto& q, std::size_t) { return intersect_slabs(rr, q); }, sl, 0, r).hit);
  }
}

}  // namespace
}  // namespace rb::test
