// CSG in 1D ray space: interval-list algebra on hand cases, CSG trees against point membership
// along seeded rays, normals of subtracted surfaces, transformed CSG against CSG of transformed
// leaves, SIMD packets against scalar (the JSON format's errors and CSG queries: test_csg_json.cpp).
#include "core/counted.hpp"
#include "kernels/csg_ray.hpp"
#include "apps/query.hpp"
#include "scene/csg_scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>
#include <regex>

using namespace rb;

namespace {

Spans<float> list(std::initializer_list<float> ts, float tag = 1) {
  Spans<float> s;
  s.n = 0;
  for (float t : ts) {
    s.t[s.n] = t;
    s.tag[s.n] = tag;
    ++s.n;
  }
  return s;
}
std::vector<float> ts(const Spans<float>& s) { return {s.t, s.t + s.n}; }

// Both merges; they must agree; returns the boundaries.
std::vector<float> op(SetOp o, const Spans<float>& a, const Spans<float>& b) {
  Spans<float> x, y;
  merge_linear(o, a, b, x);
  merge_lanes(o, a, b, y);
  EXPECT_EQ(ts(x), ts(y));
  for (int k = 0; k < x.n; ++k) EXPECT_EQ(x.tag[k], y.tag[k]) << k;
  return ts(x);
}
using V = std::vector<float>;
constexpr SetOp U = SetOp::kUnion, I = SetOp::kIntersection, D = SetOp::kDifference;

}  // namespace

// Random lists of small integers (many shared boundaries): both merges against point membership
// at the midpoints between boundaries; the result is sorted and regular (no zero-length pieces).
TEST(CsgIntervals, RandomListsAgreeWithPointMembership) {
  std::mt19937 g(7);
  std::uniform_int_distribution<int> cnt(0, 3), val(0, 12);
  auto random_list = [&]() {
    std::vector<float> v;
    const int n = 2 * cnt(g);
    for (int k = 0; k < n; ++k) v.push_back(float(val(g)));
    std::sort(v.begin(), v.end());
    // Drop zero-length intervals and merge touching ones: a canonical operand.
    std::vector<float> c;
    for (std::size_t k = 0; k < v.size(); k += 2) {
      if (v[k] == v[k + 1]) continue;
      if (!c.empty() && c.back() >= v[k]) c.back() = std::max(c.back(), v[k + 1]);
      else { c.push_back(v[k]); c.push_back(v[k + 1]); }
    }
    return c;
  };
  auto inside = [](const std::vector<float>& v, double x) {
    for (std::size_t k = 0; k + 1 < v.size(); k += 2)
      if (double(v[k]) <= x && x <= double(v[k + 1])) return true;
    return false;
  };
  auto as_spans = [](const std::vector<float>& v) {
    Spans<float> s;
    s.n = 0;
    for (float t : v) { s.t[s.n] = t; s.tag[s.n] = 1; ++s.n; }
    return s;
  };
  for (int it = 0; it < 2000; ++it) {
    const auto a = random_list(), b = random_list();
    for (const SetOp o : {U, I, D}) {
      const auto r = op(o, as_spans(a), as_spans(b));
      ASSERT_EQ(r.size() % 2, 0u);
      for (std::size_t k = 1; k < r.size(); ++k) ASSERT_LT(r[k - 1], r[k]) << "sorted, no zero-length piece";
      std::vector<float> xs(a);
      xs.insert(xs.end(), b.begin(), b.end());
      std::sort(xs.begin(), xs.end());
      for (std::size_t k = 0; k + 1 < xs.size(); ++k) {
        if (xs[k] == xs[k + 1]) continue;
        const double x = 0.5 * (double(xs[k]) + double(xs[k + 1]));
        const bool ia = inside(a, x), ib = inside(b, x);
        const bool want = o == U ? (ia || ib) : o == I ? (ia && ib) : (ia && !ib);
        ASSERT_EQ(inside(r, x), want) << "op " << int(o) << " x " << x;
      }
    }
  }
}

TEST(CsgIntervals, Disjoint) {
  const auto a = list({0, 1}), b = list({2, 3});
  EXPECT_EQ(op(U, a, b), (V{0, 1, 2, 3}));
  EXPECT_EQ(op(I, a, b), V{});
  EXPECT_EQ(op(D, a, b), (V{0, 1}));
  EXPECT_EQ(op(D, b, a), (V{2, 3}));
}

TEST(CsgIntervals, Overlapping) {
  const auto a = list({0, 2}), b = list({1, 3});
  EXPECT_EQ(op(U, a, b), (V{0, 3}));
  EXPECT_EQ(op(I, a, b), (V{1, 2}));
  EXPECT_EQ(op(D, a, b), (V{0, 1}));
  EXPECT_EQ(op(D, b, a), (V{2, 3}));
}

TEST(CsgIntervals, NestedOneInsideTheOther) {
  const auto a = list({0, 10}), b = list({3, 4});
  EXPECT_EQ(op(U, a, b), (V{0, 10}));
  EXPECT_EQ(op(I, a, b), (V{3, 4}));
  EXPECT_EQ(op(D, a, b), (V{0, 3, 4, 10}));
  EXPECT_EQ(op(D, b, a), V{});
}

TEST(CsgIntervals, TouchingFuseAndZeroLengthVanishes) {
  const auto a = list({0, 1}), b = list({1, 2});
  EXPECT_EQ(op(U, a, b), (V{0, 2}));  // touching intervals fuse
  EXPECT_EQ(op(I, a, b), V{});        // a single common point is no interval
  EXPECT_EQ(op(D, a, b), (V{0, 1}));
  // A tangent double root (zero-length interval) adds nothing.
  EXPECT_EQ(op(U, list({0, 1}), list({5, 5})), (V{0, 1}));
  EXPECT_EQ(op(D, list({0, 10}), list({5, 5})), (V{0, 10}));
}

TEST(CsgIntervals, CoincidentBoundaries) {
  const auto a = list({0, 2}, 1), b = list({0, 2}, 2);
  EXPECT_EQ(op(U, a, b), (V{0, 2}));
  EXPECT_EQ(op(I, a, b), (V{0, 2}));
  EXPECT_EQ(op(D, a, b), V{});
  // Shared entry: the first list's tag is kept.
  Spans<float> x;
  merge_linear(U, a, list({0, 3}, 2), x);
  ASSERT_EQ(ts(x), (V{0, 3}));
  EXPECT_EQ(x.tag[0], 1);
  EXPECT_EQ(x.tag[1], 2);
  // A minus B with B's exit at A's exit: A's tag there; B's entry flipped.
  merge_linear(D, list({0, 4}, 1), list({2, 4}, 2), x);
  ASSERT_EQ(ts(x), (V{0, 2}));
  EXPECT_EQ(x.tag[1], -2);
}

TEST(CsgIntervals, Empty) {
  const auto a = list({0, 1}), e = list({});
  EXPECT_EQ(op(U, a, e), (V{0, 1}));
  EXPECT_EQ(op(U, e, a), (V{0, 1}));
  EXPECT_EQ(op(I, a, e), V{});
  EXPECT_EQ(op(D, a, e), (V{0, 1}));
  EXPECT_EQ(op(D, e, a), V{});
  EXPECT_EQ(op(U, e, e), V{});
}

TEST(CsgIntervals, SeveralIntervalsAndDifferenceTags) {
  const auto a = list({0, 2, 4, 6, 8, 10}, 1), b = list({1, 5, 7, 9}, 2);
  EXPECT_EQ(op(U, a, b), (V{0, 6, 7, 10}));
  EXPECT_EQ(op(I, a, b), (V{1, 2, 4, 5, 8, 9}));
  EXPECT_EQ(op(D, a, b), (V{0, 1, 5, 6, 9, 10}));
  Spans<float> x;
  merge_linear(D, a, b, x);
  EXPECT_EQ(x.tag[1], -2);  // B's entry bounds the result: flipped
  EXPECT_EQ(x.tag[2], -2);
  EXPECT_EQ(x.tag[3], 1);
}

TEST(CsgIntervals, ClosestHitStopsEarly) {
  const auto a = list({0, 2, 4, 6}), b = list({1, 5});
  Spans<float> x;
  const int k = merge_linear(D, a, b, x, true, 1.5f);
  ASSERT_GE(k, 0);
  EXPECT_EQ(x.t[k], 5.0f);
  EXPECT_EQ(x.n, k + 1);  // nothing merged beyond the answer
}

// ---- CSG trees ------------------------------------------------------------------------------
namespace {

struct RayCase {
  Ray<float> r;
  Vec3d o, d;  // the float ray's origin and unit direction, widened
};

// Rays from a sphere around the tree's box towards random points inside the box (most meet it).
std::vector<RayCase> seeded_rays(const CsgTree& T, int n, unsigned seed) {
  const CsgNode& b = T.nodes[T.root];
  const Vec3d lo{b.lo[0], b.lo[1], b.lo[2]}, hi{b.hi[0], b.hi[1], b.hi[2]};
  const Vec3d c = (lo + hi) * 0.5, e = (hi - lo) * 0.5;
  const double R = 2.0 * std::sqrt(dot(e, e));
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<RayCase> out;
  while (int(out.size()) < n) {
    Vec3d s{u(g), u(g), u(g)};
    if (dot(s, s) > 1 || dot(s, s) < 1e-3) continue;
    const Vec3d o = c + s * (R / std::sqrt(dot(s, s)));
    // One ray in eight starts inside the box (origin inside or near the solid).
    const Vec3d o2 = out.size() % 8 == 7 ? c + Vec3d{e.x * u(g), e.y * u(g), e.z * u(g)} : o;
    const Vec3d target = c + Vec3d{e.x * u(g), e.y * u(g), e.z * u(g)};
    const Ray<float> r = make_ray(o2, target - o2);
    if (!(r.tmin <= r.tmax)) continue;
    out.push_back({r, to_double(r.o), to_double(r.d)});
  }
  return out;
}

double scale_of(const CsgTree& T) {
  const CsgNode& b = T.nodes[T.root];
  return std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]});
}

// Whether every leaf's insideness is the same at p and at p +- delta on each axis: p is away from
// every leaf surface (the tolerance band).
bool away_from_surfaces(const CsgTree& T, Vec3d p, double delta) {
  for (const CsgLeaf& L : T.leaves) {
    const bool in = csg_leaf_contains(L, p);
    for (int k = 0; k < 3; ++k)
      for (double s : {-delta, delta}) {
        Vec3d q = p;
        (k == 0 ? q.x : k == 1 ? q.y : q.z) += s;
        if (csg_leaf_contains(L, q) != in) return false;
      }
  }
  return true;
}

struct Tally {
  long samples = 0, disagreements = 0, hits = 0, flipped_hits = 0, normal_checks = 0, normal_bad = 0, simd_bad = 0, rays = 0;
};

void check_tree(const CsgTree& T, int nrays, unsigned seed, Tally& y) {
  const double S = scale_of(T), delta = 1e-3 * S;
  const auto rays = seeded_rays(T, nrays, seed);
  std::mt19937 g(seed + 1);
  std::uniform_real_distribution<double> u(0, 1);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const RayCase& rc = rays[i];
    ++y.rays;
    Spans<float> L;
    csg_list(T, rc.r, L);
    for (int k = 1; k < L.n; ++k) ASSERT_LE(L.t[k - 1], L.t[k]);
    // Point membership along the ray against the list's parity.
    for (int s = 0; s < 24; ++s) {
      const double t = u(g) * 4.0 * S;
      const Vec3d p = rc.o + rc.d * t;
      if (!away_from_surfaces(T, p, delta)) continue;
      ++y.samples;
      int below = 0;
      for (int k = 0; k < L.n; ++k) below += double(L.t[k]) <= t;
      if ((below % 2 == 1) != csg_contains(T, p)) ++y.disagreements;
    }
    // The closest hit is the list's first boundary at or after tmin.
    float tag = 0;
    const Hit<float> h = csg_hit(T, rc.r, tag);
    float first = kInf<float>, first_tag = 0;
    for (int k = L.n - 1; k >= 0; --k)
      if (L.t[k] >= rc.r.tmin) {
        first = L.t[k];
        first_tag = L.tag[k];
      }
    ASSERT_EQ(h.mask, first < kInf<float>) << "ray " << i;
    if (!h.mask) continue;
    ASSERT_EQ(h.t, first) << "ray " << i;
    ASSERT_EQ(tag, first_tag) << "ray " << i;
    ++y.hits;
    y.flipped_hits += tag < 0;
    // The normal points out of the result: just outside along n, just inside against it.
    const Vec3f n = csg_normal(T, tag, rc.r.at(h.t));
    const Vec3d p = rc.o + rc.d * double(h.t), nd = to_double(n);
    ++y.normal_checks;
    if (csg_contains(T, p + nd * delta) || !csg_contains(T, p - nd * delta)) ++y.normal_bad;
  }
  // Packets of 8 rays against the scalar query.
  for (std::size_t i = 0; i + 8 <= rays.size(); i += 8) {
    alignas(32) float ox[8], oy[8], oz[8], dx[8], dy[8], dz[8], rx[8], ry[8], rz[8], t0[8], t1[8];
    for (int l = 0; l < 8; ++l) {
      const Ray<float>& r = rays[i + std::size_t(l)].r;
      ox[l] = r.o.x; oy[l] = r.o.y; oz[l] = r.o.z; dx[l] = r.d.x; dy[l] = r.d.y; dz[l] = r.d.z;
      rx[l] = r.rd.x; ry[l] = r.rd.y; rz[l] = r.rd.z; t0[l] = r.tmin; t1[l] = r.tmax;
    }
    Ray<f8> p;
    p.o = {f8::load_aligned(ox), f8::load_aligned(oy), f8::load_aligned(oz)};
    p.d = {f8::load_aligned(dx), f8::load_aligned(dy), f8::load_aligned(dz)};
    p.rd = {f8::load_aligned(rx), f8::load_aligned(ry), f8::load_aligned(rz)};
    p.tmin = f8::load_aligned(t0);
    p.tmax = f8::load_aligned(t1);
    f8 tag8;
    const Hit<f8> h8 = csg_hit8(T, p, tag8);
    for (int l = 0; l < 8; ++l) {
      float tag = 0;
      const Hit<float> h = csg_hit(T, rays[i + std::size_t(l)].r, tag);
      const bool m8 = lane_mask<f8>(h8.mask, l);
      if (m8 != h.mask || (h.mask && (std::fabs(lane(h8.t, l) - h.t) > 1e-5f * (1 + h.t) || lane(tag8, l) != tag))) ++y.simd_bad;
    }
  }
}

}  // namespace

class CsgScenes : public ::testing::TestWithParam<std::string> {};

TEST_P(CsgScenes, AgreesWithPointMembershipAndNormalsPointOut) {
  const scene::Scene s = scene::csg_scene(GetParam());
  ASSERT_EQ(s.csgs.size(), 1u);
  Tally y;
  check_tree(*s.csgs[0].tree, 1600, 7, y);
  std::printf("%s: %ld rays, %ld samples, %ld disagreements, %ld hits (%ld on subtracted surfaces), %ld/%ld normals off, %ld SIMD lanes differ\n",
              GetParam().c_str(), y.rays, y.samples, y.disagreements, y.hits, y.flipped_hits, y.normal_bad, y.normal_checks, y.simd_bad);
  // Every sample away from the surfaces (band: 1e-3 of the object's size on each axis) agrees.
  EXPECT_GT(y.samples, 10000);
  EXPECT_EQ(y.disagreements, 0) << "of " << y.samples;
  EXPECT_GT(y.hits, 400);
  // Normals: the offset test may cross another surface at edges; bounded rate.
  EXPECT_LE(double(y.normal_bad), 0.01 * double(y.normal_checks)) << y.normal_bad << " of " << y.normal_checks;
  EXPECT_LE(double(y.simd_bad), 0.002 * double(y.rays)) << y.simd_bad << " of " << y.rays;
  if (GetParam() == "spheres_minus" || GetParam() == "die" || GetParam() == "ellipsoid_minus_cylinder") {
    EXPECT_GT(y.flipped_hits, 20);  // subtracted surfaces were hit, and their normals checked
  }
}
INSTANTIATE_TEST_SUITE_P(Embedded, CsgScenes, ::testing::ValuesIn(scene::csg_scene_names()));

TEST(CsgTree, TransformedCsgEqualsCsgOfTransformedLeaves) {
  // M = translate(1, 2, 3) rotate(y, 90 degrees): x -> -z, z -> x.
  const CsgTree A = scene::csg_from_json_text(R"({"type": "difference",
    "transform": {"translate": [1, 2, 3], "rotate": {"axis": [0, 1, 0], "degrees": 90}},
    "left": {"type": "union", "children": [
       {"type": "box", "min": [-1, -1, -0.5], "max": [1, 1, 0.5]},
       {"type": "sphere", "center": [1, 0, 0], "radius": 0.7}]},
    "right": {"type": "cylinder", "base": [0, -2, 0], "axis": [1, 1, 0], "radius": 0.3, "height": 4}})",
                                              "A");
  const CsgTree B = scene::csg_from_json_text(R"({"type": "difference",
    "left": {"type": "union", "children": [
       {"type": "box", "min": [0.5, 1, 2], "max": [1.5, 3, 4]},
       {"type": "sphere", "center": [1, 2, 2], "radius": 0.7}]},
    "right": {"type": "cylinder", "base": [1, 0, 3], "axis": [0, 1, -1], "radius": 0.3, "height": 4}})",
                                              "B");
  const auto rays = seeded_rays(B, 3000, 11);
  int compared = 0, differ = 0;
  for (const auto& rc : rays) {
    float ta = 0, tb = 0;
    const Hit<float> ha = csg_hit(A, rc.r, ta), hb = csg_hit(B, rc.r, tb);
    if (ha.mask != hb.mask) {
      ++differ;
      continue;
    }
    if (!ha.mask) continue;
    ++compared;
    const Vec3f na = csg_normal(A, ta, rc.r.at(ha.t)), nb = csg_normal(B, tb, rc.r.at(hb.t));
    if (std::fabs(ha.t - hb.t) > 1e-4f * (1 + hb.t) || dot(na, nb) < 0.999f) ++differ;
  }
  EXPECT_GT(compared, 1000);
  EXPECT_LE(differ, 3) << "of " << rays.size();  // rays grazing an edge may differ by rounding
}

TEST(CsgTree, LensIsTwoSphereIntersection) {
  const scene::Scene s = scene::csg_scene("lens");
  const CsgTree& T = *s.csgs[0].tree;
  // Along the axis: enters the right sphere's far side ... the lens spans z in [-0.4, 0.4].
  float tag = 0;
  const Hit<float> h = csg_hit(T, make_ray(Vec3f{0, 0, 5}, Vec3f{0, 0, -1}), tag);
  ASSERT_TRUE(h.mask);
  EXPECT_NEAR(h.t, 4.6f, 1e-5f);
  const Vec3f n = csg_normal(T, tag, Vec3f{0, 0, 0.4f});
  EXPECT_NEAR(n.z, 1.0f, 1e-6f);  // the left sphere (centre z = -1.6) bounds the lens at +z
  Spans<float> L;
  csg_list(T, make_ray(Vec3f{0, 0, 5}, Vec3f{0, 0, -1}), L);
  ASSERT_EQ(L.n, 2);
  EXPECT_NEAR(L.t[1], 5.4f, 1e-5f);
}

TEST(CsgJson, SceneLoadsWithEverything) {
  const scene::Scene s = scene::parse_json_scene(scene::csg_scene_json("die"), "die.json");
  EXPECT_EQ(s.csgs.size(), 1u);
  EXPECT_EQ(s.polygons.size(), 1u);
  EXPECT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.materials.size(), 7u);  // the default and six named
  EXPECT_EQ(s.csgs[0].tree->leaves.size(), 23u);  // cube, sphere, 21 pips
  // A pip's wall is black, the face white.
  const CsgTree& T = *s.csgs[0].tree;
  int black = 0, white = 0;
  for (const auto& rc : seeded_rays(T, 400, 3)) {
    const scene::CsgSurface h = scene::csg_surface(T, rc.r);
    if (!h.hit) continue;
    const std::string m = h.material == s.csgs[0].mat ? "white" : "other";
    (m == "white" ? white : black)++;
  }
  EXPECT_GT(white, 50);
  EXPECT_GT(black, 0);
}

// The target: a CSG query of two spheres costs the two leaf lists, the node boxes and a merge of a
// few compares per interval end, no arithmetic.
TEST(CsgOps, TwoSphereQueryIsLeavesBoxesAndAFewComparesPerEnd) {
  for (const char* name : {"spheres_minus", "lens"}) {
    const scene::Scene sc = scene::csg_scene(name);
    const CsgTree& T = *sc.csgs[0].tree;
    const Ray<float> r = make_ray(Vec3f{0.05f, 0.02f, 6}, Vec3f{0, 0, -1});
    const Ray<cfloat> c = Ray<cfloat>::broadcast(r);
    OpCounts whole, leaves, box;
    {
      const ops::Scope s;
      cfloat tag;
      ASSERT_TRUE(csg_closest(T, c, tag).mask) << name;
      whole = s.elapsed();
    }
    {
      const ops::Scope s;
      Spans<cfloat> out;
      csg_leaf_spans(T.leaves[0], 0, c, out);
      csg_leaf_spans(T.leaves[1], 1, c, out);
      leaves = s.elapsed();
    }
    {
      const ops::Scope s;
      (void)rb::detail::csg_box_test(T.nodes[T.root], c, c.tmin, c.tmax);
      box = s.elapsed();
    }
    OpCounts boxes;
    for (int k = 0; k < 3; ++k) boxes += box;
    const OpCounts merge = whole - leaves - boxes;
    EXPECT_EQ(merge.add + merge.mul + merge.div + merge.sqrt + merge.fma + merge.minmax, 0u) << name << ": " << merge.str();
    EXPECT_LE(merge.cmp, 4u * 4u) << name << ": " << merge.str();  // at most 4 compares per interval end
    EXPECT_GE(merge.cmp, 4u) << name;                               // the merge did run
  }
}

// The leaves no embedded scene uses: a capped cone and a convex polyhedron (an octahedron), each
// transformed, in a union minus an intersection, against point membership.
TEST(CsgTree, ConeAndPolyhedronLeavesAgreeWithPointMembership) {
  const CsgTree T = scene::csg_from_json_text(R"({"type": "difference",
    "transform": {"rotate": {"axis": [1, 2, 0], "degrees": 25}, "scale": [1, 0.8, 1.1]},
    "left": {"type": "union", "children": [
      {"type": "cone", "apex": [0, 1.5, 0], "axis": [0, -1, 0], "radius": 1, "height": 2},
      {"type": "polyhedron", "transform": {"translate": [1, 0, 0]}, "planes": [
        {"normal": [1, 1, 1], "point": [1, 0, 0]}, {"normal": [-1, 1, 1], "point": [-1, 0, 0]},
        {"normal": [1, -1, 1], "point": [1, 0, 0]}, {"normal": [1, 1, -1], "point": [1, 0, 0]},
        {"normal": [-1, -1, 1], "point": [-1, 0, 0]}, {"normal": [-1, 1, -1], "point": [-1, 0, 0]},
        {"normal": [1, -1, -1], "point": [1, 0, 0]}, {"normal": [-1, -1, -1], "point": [-1, 0, 0]}]}]},
    "right": {"type": "intersection",
      "left": {"type": "sphere", "center": [0.5, 0, 0.6], "radius": 0.7},
      "right": {"type": "ellipsoid", "center": [0.5, 0, 0.9], "radii": [1, 0.5, 0.8]}}})",
                                              "tree");
  Tally y;
  check_tree(T, 1600, 5, y);
  std::printf("cone+polyhedron: %ld samples, %ld disagreements, %ld hits (%ld subtracted), %ld/%ld normals off, %ld SIMD differ\n",
              y.samples, y.disagreements, y.hits, y.flipped_hits, y.normal_bad, y.normal_checks, y.simd_bad);
  EXPECT_GT(y.samples, 10000);
  EXPECT_EQ(y.disagreements, 0);
  EXPECT_GT(y.hits, 400);
  EXPECT_GT(y.flipped_hits, 10);
  EXPECT_LE(double(y.normal_bad), 0.01 * double(y.normal_checks));
  EXPECT_LE(double(y.simd_bad), 0.002 * double(y.rays));
}

// Invalid rays (NaN, zero direction) are a defined miss; a segment that ends before the surface
// misses; one that starts inside the solid reports the exit.
TEST(CsgTree, InvalidRaysAndSegments) {
  const scene::Scene sc = scene::csg_scene("spheres_minus");
  const CsgTree& T = *sc.csgs[0].tree;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  float tag = 1;
  for (const Ray<float>& r : {make_ray(Vec3f{nan, 0, 5}, Vec3f{0, 0, -1}), make_ray(Vec3f{0, 0, 5}, Vec3f{0, 0, 0})}) {
    const Hit<float> h = csg_hit(T, r, tag);
    EXPECT_FALSE(h.mask);
    EXPECT_EQ(h.t, kInf<float>);
    EXPECT_EQ(tag, 0.0f);
    Spans<float> L;
    csg_list(T, r, L);  // defined (whatever the line of the invalid ray meets), never NaN
    for (int k = 0; k < L.n; ++k) EXPECT_FALSE(std::isnan(L.t[k]));
  }
  // Along +z from z = -5: sphere A (radius 1.2 at the origin) is entered at t = 3.8; the bite B
  // (centre (0.7, 0.5, 0.8), radius 0.9) covers z in [0.8 - sqrt(0.07), 0.8 + sqrt(0.07)].
  EXPECT_FALSE(csg_hit(T, make_ray(Vec3f{0, 0, -5}, Vec3f{0, 0, 1}, 0.0f, 3.7f), tag).mask);
  const Hit<float> in = csg_hit(T, make_ray(Vec3f{0, 0, -5}, Vec3f{0, 0, 1}, 4.0f), tag);
  ASSERT_TRUE(in.mask);
  const double z = 0.8 - std::sqrt(0.07);
  EXPECT_NEAR(in.t, 5.0 + z, 1e-5);  // the exit from inside, on B's surface
  EXPECT_LT(tag, 0.0f);              // a subtracted surface
  const Vec3f n = csg_normal(T, tag, Vec3f{0, 0, float(z)});
  EXPECT_NEAR(n.x, 0.7 / 0.9, 1e-5);  // into B: out of the result
  EXPECT_NEAR(n.y, 0.5 / 0.9, 1e-5);
  EXPECT_NEAR(n.z, (0.8 - z) / 0.9, 1e-5);
}
