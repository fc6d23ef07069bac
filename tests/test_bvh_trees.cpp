// The BVH's boxes and layout (conservative widening, frame boxes, the reciprocal and Woop forms,
// leaf groups), unusable boxes, hostile inputs, and adversarial trees against the traversal stack.
#include "bvh/slab.hpp"
#include "scene/sources.hpp"
#include "soa/groups.hpp"
#include "tracer/accel.hpp"
#include "tracer/mesh_leaves.hpp"
#include "tracer/ray_sets.hpp"
#include "bvh_test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <iostream>
#include <map>
#include <random>
#include <stdexcept>

namespace {

using namespace rb;
using namespace rbtest_bvh;

// The conservative boxes: every widened wide-node box contains the box as built, and the bound is
// the plan's.
TEST(Bvh, ConservativeBoxesContainTheBuiltOnes) {
  const scene::Scene s = icosphere(3, {1e3, 0, 0}, 1.0);
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  EXPECT_EQ(a.wide.origin_bound, a.plan().origin_bound);
  EXPECT_GT(a.wide.origin_bound, 0.0f);
  bvh::Bvh8 raw = bvh::collapse8(a.bin);
  ASSERT_EQ(raw.nodes.size(), a.wide.nodes.size());
  std::size_t wider = 0;
  for (std::size_t i = 0; i < raw.nodes.size(); ++i)
    for (int ax = 0; ax < 3; ++ax)
      for (int c = 0; c < 8; ++c) {
        if (raw.nodes[i].child[c] == bvh::kEmpty) continue;
        EXPECT_LE(a.wide.nodes[i].b[2 * ax][c], raw.nodes[i].b[2 * ax][c]);
        EXPECT_GE(a.wide.nodes[i].b[2 * ax + 1][c], raw.nodes[i].b[2 * ax + 1][c]);
        wider += a.wide.nodes[i].b[2 * ax][c] < raw.nodes[i].b[2 * ax][c];
      }
  EXPECT_GT(wider, 0u);
}

// The widening, 8 coordinates at a time, gives bit for bit what its definition gives one coordinate
// at a time (moved out by 4 u (|c| + O) in double, rounded to float, one float further when that
// went inward): on zeros of both signs, subnormals, the largest floats, random magnitudes from
// 2^-140 to 2^40, empty slots and origin bounds from 0 to 1e30.
TEST(Bvh, ConservativeWideningEqualsItsDefinitionOneCoordinateAtATime) {
  auto widened = [](float c, bool up, float bound) {
    const double u = 0x1p-24, m = double(c) + (up ? 1 : -1) * 4 * u * (std::fabs(double(c)) + double(bound));
    float f = float(m);
    if (up ? double(f) < m : double(f) > m) f = std::nextafter(f, up ? INFINITY : -INFINITY);
    return f;
  };
  std::mt19937 g(11);
  std::uniform_real_distribution<float> U(-1, 1);
  std::uniform_int_distribution<int> E(-140, 40), pick(0, 9);
  const float big = std::numeric_limits<float>::max(), sub = std::numeric_limits<float>::denorm_min();
  for (const float bound : {0.f, 1e-30f, 1.f, 3.5f, 1e6f, 1e30f}) {
    bvh::Bvh8 t;
    t.nodes.resize(4000);
    for (auto& n : t.nodes)
      for (int c = 0; c < 8; ++c) {
        n.child[c] = pick(g) == 0 ? bvh::kEmpty : std::uint32_t(c);
        for (int ax = 0; ax < 3; ++ax) {
          float lo = 0, hi = 0;
          switch (pick(g)) {
            case 0: break;
            case 1: lo = -0.f, hi = sub; break;
            case 2: lo = -big, hi = big; break;
            case 3: lo = -sub, hi = -0.f; break;
            default: lo = std::ldexp(U(g), E(g)), hi = lo + std::ldexp(std::fabs(U(g)), E(g));
          }
          if (n.child[c] == bvh::kEmpty) lo = INFINITY, hi = -INFINITY;
          n.b[2 * ax][c] = lo;
          n.b[2 * ax + 1][c] = hi;
        }
      }
    const bvh::Bvh8 before = t;
    bvh::make_conservative(t, bound);
    EXPECT_EQ(t.origin_bound, bound);
    for (std::size_t i = 0; i < t.nodes.size(); ++i)
      for (int row = 0; row < 6; ++row)
        for (int c = 0; c < 8; ++c) {
          const float was = before.nodes[i].b[row][c];
          const float want = before.nodes[i].child[c] == bvh::kEmpty ? was : widened(was, row % 2 == 1, bound);
          ASSERT_EQ(std::bit_cast<std::uint32_t>(t.nodes[i].b[row][c]), std::bit_cast<std::uint32_t>(want))
              << "node " << i << " row " << row << " child " << c << ": " << was << ", origin bound " << bound;
        }
  }
}

// A frame box lies three floats outside the nearest float of each double coordinate, whatever its
// sign and size: across zero (through the subnormals), at the largest float (to infinity), and
// with infinities and NaN left as they are.
TEST(Bvh, FrameBoxesStepThreeFloatsOutward) {
  auto steps = [](float v, int n) {
    for (int i = 0; i < std::abs(n); ++i) v = n > 0 ? std::nextafter(v, INFINITY) : std::nextafter(v, -INFINITY);
    return v;
  };
  const float big = std::numeric_limits<float>::max(), sub = std::numeric_limits<float>::denorm_min();
  const double values[] = {0.0, -0.0, 1.0, -1.0, 0.1, -0.1, 1e-40, -1e-40, double(sub), -double(sub), 2.0 * double(sub), -3.0 * double(sub),
                           1e30, -1e30, double(big), -double(big), 123456.789, -0.0078125};
  for (const double v : values) {
    scene::Bounds b;
    b.grow(Vec3d{v, v, v});
    float lo[3], hi[3];
    kinds::frame_box(b, Vec3d{0, 0, 0}, lo, hi);
    const float f = float(v);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(lo[k], steps(f, -3)) << v;
      EXPECT_EQ(hi[k], steps(f, 3)) << v;
      EXPECT_LE(double(lo[k]), v);
      EXPECT_GE(double(hi[k]), v);
    }
  }
  scene::Bounds inf;
  inf.grow(Vec3d{-INFINITY, 0, 0});
  inf.grow(Vec3d{INFINITY, 0, 0});
  float lo[3], hi[3];
  kinds::frame_box(inf, Vec3d{0, 0, 0}, lo, hi);
  EXPECT_EQ(lo[0], -INFINITY);
  EXPECT_EQ(hi[0], INFINITY);
}

// The 8-lane step (frame boxes) equals the scalar definition on every special value and on random
// bit patterns (the scalar one was checked once against next_up/next_down for all 2^32 floats).
TEST(Bvh, EightLaneFloatStepEqualsTheScalarOne) {
  std::vector<std::uint32_t> bits = {0u, 0x80000000u, 1u, 0x80000001u, 2u, 0x007FFFFFu, 0x807FFFFFu, 0x00800000u, 0x80800000u,
                                     0x7F7FFFFFu, 0xFF7FFFFFu, 0x7F7FFFFEu, 0x7F800000u, 0xFF800000u, 0x7FC00000u, 0xFFC00001u, 0x3F800000u,
                                     0xBF800000u};
  std::mt19937 g(7);
  for (int i = 0; i < 1 << 20; ++i) bits.push_back(std::uint32_t(g()));
  const int steps[8] = {-3, -1, 0, 1, 3, -2, 2, 5};
  for (std::size_t i = 0; i < bits.size(); ++i) {
    const float v = std::bit_cast<float>(bits[i]);
    alignas(32) float out[8];
    _mm256_store_ps(out, spawn::step_floats8(_mm256_set1_ps(v), _mm256_loadu_si256(reinterpret_cast<const __m256i*>(steps))));
    for (int l = 0; l < 8; ++l) {
      const float want = spawn::step_floats(v, steps[l]);
      ASSERT_EQ(std::bit_cast<std::uint32_t>(out[l]), std::bit_cast<std::uint32_t>(want)) << std::hex << bits[i] << " " << steps[l];
    }
  }
}

// Large arrays (huge-page advice from 2 MiB) keep the vector contract: value-initialised,
// aligned for the SIMD loads, and the same contents after growing past the threshold.
TEST(Bvh, LargeArraysAreAlignedAndInitialised) {
  avec<float> a(100);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(a.data()) % kSimdAlign, 0u);
  for (std::size_t i = 0; i < a.size(); ++i) a[i] = float(i);
  a.resize((std::size_t(3) << 20) / sizeof(float), 0.5f);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(a.data()) % kSimdAlign, 0u);
  EXPECT_EQ(a[99], 99.f);
  EXPECT_EQ(a[100], 0.5f);
  EXPECT_EQ(a.back(), 0.5f);
  big_vector<std::uint32_t> z(std::size_t(1) << 20);
  EXPECT_EQ(std::count(z.begin(), z.end(), 0u), std::ptrdiff_t(z.size()));
}

// The slab test's reciprocal from the ray's stored rd equals the divided one: for every direction
// component make_ray stores (random unit directions, axis-aligned ones with signed zeros) and on
// the bit patterns around the smallest component the test keeps (kMinDir) and 2^20 random ones.
TEST(Bvh, SlabReciprocalFromTheRayEqualsTheDividedOne) {
  auto same = [](float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); };
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::vector<Vec3f> dirs{{0.f, 0.f, 1.f}, {-0.f, 0.f, -1.f}, {1.f, -0.f, 0.f}, {0.f, -1.f, -0.f}, {1e-20f, 1.f, 0.f}};
  for (int i = 0; i < 100000; ++i) dirs.push_back({u(rng), u(rng), u(rng) * (i % 3 == 0 ? 1e-12f : 1.f)});
  for (const Vec3f& d : dirs) {
    const Ray<float> r = make_ray(Vec3f{0, 0, 0}, d);
    if (!(r.tmin <= r.tmax)) continue;
    for (int a = 0; a < 3; ++a) ASSERT_TRUE(same(bvh::safe_rcp(r.d[a], r.rd[a]), bvh::safe_rcp(r.d[a]))) << r.d[a];
    const f8 d8(r.d.x), rd8(r.rd.x);
    ASSERT_TRUE(same(bvh::safe_rcp_lanes(d8, rd8).get(3), bvh::safe_rcp(r.d.x))) << r.d.x;
  }
  std::uniform_int_distribution<std::uint32_t> bits;
  const std::uint32_t m = std::bit_cast<std::uint32_t>(bvh::kMinDir);
  for (std::uint32_t k = 0; k < (1u << 20) + 64; ++k) {
    std::uint32_t b = k < 64 ? m - 32 + k : bits(rng);
    if (k < 64 && (k & 1)) b |= 0x80000000u;
    const float d = std::bit_cast<float>(b);
    if (std::isnan(d)) continue;
    ASSERT_TRUE(same(bvh::safe_rcp(d, 1.0f / d), bvh::safe_rcp(d))) << d;
  }
}

// Both forms of the tracer's shear set-up (branch-free for single rays, conditional for packets)
// give make_woop_ray's values: the same axes and the same three quotients, bit for bit, on random
// directions and on ties, signed zeros and extremes.
TEST(Bvh, WoopShearFormsEqualTheKernelsOwn) {
  std::vector<float> special{0.0f, -0.0f, 1.0f, -1.0f, 0.5f, -2.0f, 1e-30f, -1e-30f, 3e38f, -3e38f,
                             std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()};
  std::vector<Vec3f> dirs;
  for (float x : special)
    for (float y : special)
      for (float z : special) dirs.push_back({x, y, z});
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  for (int i = 0; i < 200000; ++i) {
    Vec3f d{u(rng), u(rng), u(rng)};
    if (i % 4 == 1) d.y = (i & 8) ? d.x : -d.x;  // |dx| == |dy|
    if (i % 4 == 2) d.z = (i & 8) ? d.y : -d.y;  // |dy| == |dz|
    if (i % 4 == 3) d.z = d.x = (i & 8) ? d.y : -d.y;
    dirs.push_back(d);
  }
  auto same = [](float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b) || (std::isnan(a) && std::isnan(b)); };
  for (const Vec3f& d : dirs) {
    Ray<float> r;
    r.o = {0, 0, 0};
    r.d = d;
    const WoopRay<float> w = make_woop_ray(r);
    for (const tracer::WoopShear& s : {tracer::woop_shear<false>(d), tracer::woop_shear<true>(d)}) {
      ASSERT_EQ(s.k[0], w.kx) << d.x << " " << d.y << " " << d.z;
      ASSERT_EQ(s.k[1], w.ky) << d.x << " " << d.y << " " << d.z;
      ASSERT_EQ(s.k[2], w.kz) << d.x << " " << d.y << " " << d.z;
      ASSERT_TRUE(same(s.S[0], w.Sx) && same(s.S[1], w.Sy) && same(s.S[2], w.Sz)) << d.x << " " << d.y << " " << d.z;
    }
  }
}

// The leaves' batch layout: each group of 8 slots one block, field after field; the kernels read
// the same primitives from it as from the structure of arrays.
TEST(Bvh, LeafGroupsHoldTheSamePrimitivesAsArrays) {
  PrimGroups<TriVerts> g;
  PrimSoA<TriVerts> s;
  g.allocate(16);
  for (std::size_t i = 0; i < 16; ++i) {
    const float v = float(i);
    const TriVerts<float> t = i == 5 ? TriVerts<float>::never()
                                     : TriVerts<float>{{v, v + 100, v + 200}, {v + 300, v + 400, v + 500}, {v + 600, v + 700, v + 800}};
    g.set(i, t);
    s.push(t);
  }
  EXPECT_EQ(g.bytes(), 16 * 9 * sizeof(float));
  for (std::size_t f = 0; f < 9; ++f)
    for (std::size_t i = 0; i < 16; ++i) {
      EXPECT_EQ(g.field(f, i), g.field(0, i - i % 8) + 8 * f + i % 8);  // one block per group
      const float want = s.f[f][i];
      if (std::isnan(want)) EXPECT_TRUE(std::isnan(*g.field(f, i)));
      else EXPECT_EQ(*g.field(f, i), want);
    }
  auto same = []<class F>(TriVerts<F> a, TriVerts<F> b) {  // equal, NaN equal to NaN
    auto x = a.fields();
    auto y = b.fields();
    bool eq = true;
    [&]<std::size_t... I>(std::index_sequence<I...>) {
      ((eq = eq && all_of<F>((std::get<I>(x) == std::get<I>(y)) | ((std::get<I>(x) != std::get<I>(x)) & (std::get<I>(y) != std::get<I>(y))))), ...);
    }(std::make_index_sequence<9>{});
    return eq;
  };
  EXPECT_TRUE(same(g.load<f8>(8), s.load<f8>(8)));
  EXPECT_TRUE(same(g.load<d4>(12), s.load<d4>(12)));
  EXPECT_TRUE(same(g.broadcast<f8>(3), s.broadcast<f8>(3)));
  EXPECT_THROW(g.allocate(12), std::invalid_argument);
}

// Unusable boxes (NaN, infinite, lo > hi) among usable ones: the builder leaves them out and
// builds the tree it builds over the usable boxes alone (the same nodes and statistics, the
// order naming the same primitives), also when the boxes are scanned in parallel (n above the
// parallel threshold) and the unusable ones are removed after the scan.
TEST(Bvh, UnusableBoxesAreLeftOutOfTheSameTree) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  std::vector<float> lo, hi, ulo, uhi;
  std::vector<std::uint8_t> kind, ukind;
  std::vector<std::uint32_t> usable;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.f, 100.f);
  for (std::uint32_t i = 0; i < 40000; ++i) {
    const float x = u(rng), y = u(rng), z = u(rng), e = 0.01f + u(rng) * 0.01f;
    float l[3] = {x - e, y - e, z - e}, h[3] = {x + e, y + e, z + e};
    const bool bad = i % 7 == 3;
    if (bad) {
      switch (i % 4) {
        case 0: l[1] = nan; break;
        case 1: h[2] = inf; break;
        case 2: std::swap(l[0], h[0]); break;
        default: l[2] = -inf; break;
      }
    }
    lo.insert(lo.end(), l, l + 3);
    hi.insert(hi.end(), h, h + 3);
    kind.push_back(bad ? 1 : 0);  // the usable ones are of one kind
    if (!bad) {
      ulo.insert(ulo.end(), l, l + 3);
      uhi.insert(uhi.end(), h, h + 3);
      ukind.push_back(0);
      usable.push_back(i);
    }
  }
  bvh::BuildOptions serial;
  serial.parallel = false;
  const bvh::Bvh2 want = bvh::build_sah(ulo, uhi, ukind, serial);
  for (const bool parallel : {false, true}) {
    bvh::BuildOptions o;
    o.parallel = parallel;
    const bvh::Bvh2 got = bvh::build_sah(lo, hi, kind, o);
    ASSERT_EQ(got.order.size(), usable.size()) << parallel;
    for (std::size_t j = 0; j < got.order.size(); ++j) ASSERT_EQ(got.order[j], usable[want.order[j]]) << j << " " << parallel;
    EXPECT_EQ(got.nodes.size(), want.nodes.size()) << parallel;
    EXPECT_EQ(got.stats.leaf_hist, want.stats.leaf_hist) << parallel;
    EXPECT_NEAR(got.stats.sah_cost, want.stats.sah_cost, 1e-9 * want.stats.sah_cost) << parallel;
  }
  // Nothing usable: an empty tree.
  const std::vector<float> l1{nan, 0, 0}, h1{1, 1, 1};
  EXPECT_TRUE(bvh::build_sah(l1, h1, {0}).nodes.empty());
}

TEST(Bvh, HostileInputsGiveDefinedResults) {
  // NaN, infinite and zero-direction rays: a miss.
  const scene::Scene s = icosphere(1);
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  RaySoA bad;
  bad.push(Vec3f{nan, 0, 0}, Vec3f{0, 0, 1});
  bad.push(Vec3f{0, 0, -5}, Vec3f{nan, 0, 1});
  bad.push(Vec3f{0, 0, -5}, Vec3f{0, 0, 0});
  bad.push(Vec3f{inf, 0, -5}, Vec3f{0, 0, 1});
  bad.push(Vec3f{0, 0, -5}, Vec3f{0, 0, 1}, 0.0f, nan);
  bad.push(Vec3f{0, 0, -5}, Vec3f{0, 0, 1});  // a good ray in the same packet
  for (int packet : {1, 8, 16, 64, 256}) {
    std::vector<HitRec> h(round_up(bad.size(), 16));
    RaySoA r = bad;
    while (r.size() < 16) r.push(Vec3f{0, 0, -5}, Vec3f{0, 0, 0});
    a.trace(r, 0, r.size(), h.data(), opts(packet));
    for (int i = 0; i < 5; ++i) EXPECT_EQ(h[std::size_t(i)].prim, kNoPrim) << i;
    EXPECT_NE(h[5].prim, kNoPrim);
    EXPECT_NEAR(h[5].t, 4.0f, 0.1f);
  }
  // An empty scene builds and misses.
  {
    const scene::Scene e;
    const tracer::SceneAccel ea = tracer::SceneAccel::build(e);
    EXPECT_TRUE(ea.empty());
    RaySoA r;
    r.push(Vec3f{0, 0, 0}, Vec3f{0, 0, 1});
    std::vector<HitRec> h(r.size());
    for (int packet : {1, 8}) {
      ea.trace(r, 0, r.size(), h.data(), opts(packet));
      EXPECT_EQ(h[0].prim, kNoPrim);
    }
  }
  // One primitive; a degenerate primitive beside it is left out of the tree.
  {
    scene::Scene one;
    one.spheres.push_back({{0, 0, 5}, 1, 0});
    one.spheres.push_back({{0, 0, 9}, -1, 0});
    const tracer::SceneAccel oa = tracer::SceneAccel::build(one);
    EXPECT_EQ(oa.bin.nodes.size(), 1u);
    RaySoA r;
    r.push(Vec3f{0, 0, 0}, Vec3f{0, 0, 1});
    for (int packet : {1, 8}) {
      std::vector<HitRec> h(r.size());
      oa.trace(r, 0, r.size(), h.data(), opts(packet));
      EXPECT_EQ(h[0].prim, kinds::code(kinds::Kind::sphere, 0));
      EXPECT_FLOAT_EQ(h[0].t, 4.0f);
    }
  }
  // All primitives at one point: the builder falls back to median splits, depth stays logarithmic.
  {
    scene::Scene same;
    same.verts = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
    for (int i = 0; i < 20000; ++i) same.triangles.push_back({{0, 1, 2}, 0});
    const tracer::SceneAccel sa = tracer::SceneAccel::build(same);
    EXPECT_LE(sa.bin.stats.depth, 64);
    RaySoA r;
    r.push(Vec3f{0.2f, 0.2f, 0}, Vec3f{0, 0, 1});
    r.push(Vec3f{0.9f, 0.9f, 0}, Vec3f{0, 0, 1});
    std::vector<HitRec> h(r.size());
    sa.trace(r, 0, r.size(), h.data(), opts(8));
    EXPECT_NE(h[0].prim, kNoPrim);
    EXPECT_EQ(h[1].prim, kNoPrim);
  }
  // 10M identical triangles: refused before allocating when above the stated memory bound.
  {
    scene::Scene big;
    big.verts = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
    big.triangles.assign(10'000'000, scene::TriangleIn{{0, 1, 2}, 0});
    bvh::BuildOptions o;
    o.max_bytes = std::size_t(1) << 30;  // 1 GiB
    EXPECT_THROW(tracer::SceneAccel::build(big, o), std::length_error);
  }
}

}  // namespace

// ---- adversarial trees: the traversal stack against the tree's depth ----------------------------
namespace {

// Every packet mode and slab test against the oracle, for the four ray sets (no hit count
// required: some of these scenes send their bounce rays into the void).
void check_against_oracle(const scene::Scene& s, std::size_t count, const std::string& name, const bvh::BuildOptions& opt = {}) {
  const tracer::SceneAccel a = tracer::SceneAccel::build(s, opt);
  ASSERT_FALSE(a.empty()) << name;
  std::cout << "[ depth    ] " << name << ": binary " << a.bin.stats.depth << ", wide " << a.wide.depth << " (bound "
            << bvh::kMaxTreeDepth << ")\n";
  EXPECT_LE(a.wide.depth, bvh::kMaxTreeDepth) << name;
  EXPECT_LE(a.bin.stats.depth, bvh::kMaxTreeDepth) << name;
  for (auto set : {tracer::RaySet::primary, tracer::RaySet::shadow, tracer::RaySet::diffuse, tracer::RaySet::random}) {
    const RaySoA rays = tracer::make_rays(s, a, set, count, 11);
    const bool any = set == tracer::RaySet::shadow;
    const auto ref = brute(a, rays, any);
    for (int packet : {1, 8, 16, 64, 256})
      for (bvh::Slab slab : {bvh::Slab::conservative, bvh::Slab::robust}) {
        std::vector<HitRec> h(rays.size());
        a.trace(rays, 0, rays.size(), h.data(), opts(packet, slab, any));
        expect_same(h, ref, rays.count, any, name + " " + tracer::ray_set_name(set) + " packet " + std::to_string(packet) + " " + bvh::slab_name(slab));
      }
  }
}

}  // namespace

TEST(Bvh, AdversarialTreesStayWithinTheStackBound) {
  // Geometrically shrinking triangles nested at one corner: every SAH split cuts off the largest.
  // (Ratio 0.97: the smallest stays at 5e-6, above float resolution at the rays' distance; far
  // smaller triangles are below what a float ray from there resolves, and the leaf kernel's answer
  // for them is not a reference.)
  {
    scene::Scene s;
    for (int k = 0; k < 400; ++k) {
      const double e = std::pow(0.97, k);
      const auto b = std::uint32_t(s.verts.size());
      s.verts.push_back({0, 0, 1});
      s.verts.push_back({e, 0, 1 + 1e-3 * e});
      s.verts.push_back({0, e, 1 - 1e-3 * e});
      s.triangles.push_back({{b, b + 1, b + 2}, 0});
    }
    check_against_oracle(s, 256, "shrinking triangles");
  }
  // A long chain of nested boxes: spheres that all touch the origin, each 1.2 times the last.
  {
    scene::Scene s;
    for (int k = 0; k < 200; ++k) {
      const double r = 1e-3 * std::pow(1.2, k);
      s.spheres.push_back({{r, 0, 0}, r, 0});
    }
    check_against_oracle(s, 256, "nested boxes");
    // The same with one primitive per leaf and SAH asked for any depth (clamped to kMaxSahDepth):
    // the deepest tree the builder makes of them, traversed with the stack at its bound.
    bvh::BuildOptions deep;
    deep.max_leaf = 1;
    deep.leaf_block = 1;
    deep.max_depth = 100000;
    check_against_oracle(s, 256, "nested boxes, one per leaf", deep);
  }
  // Identical centroids, different sizes: 3000 concentric spheres.
  {
    scene::Scene s;
    for (int k = 0; k < 3000; ++k) s.spheres.push_back({{1, 2, 3}, 1.0 + 1e-3 * k, 0});
    check_against_oracle(s, 256, "concentric spheres");
  }
}

TEST(Bvh, TreeDeeperThanTheTraversalServesIsRefused) {
  // A binary chain of 1000 levels (a leaf and an internal node per level) made by hand: each wide
  // node absorbs 7 of its levels, so the wide tree is deeper than kMaxTreeDepth.
  bvh::Bvh2 b;
  const int levels = 1000;
  b.nodes.resize(2 * std::size_t(levels) + 1);
  for (int i = 0; i < levels; ++i) {
    bvh::BNode& n = b.nodes[2 * std::size_t(i)];
    n = bvh::BNode{{0, 0, 0}, {1, 1, 1}, std::uint32_t(2 * i + 1), 0, 0, 0};
    b.nodes[2 * std::size_t(i) + 1] = bvh::BNode{{0, 0, 0}, {1, 1, 1}, std::uint32_t(i), 1, 0, 0};
  }
  b.nodes[2 * std::size_t(levels)] = bvh::BNode{{0, 0, 0}, {1, 1, 1}, std::uint32_t(levels), 1, 0, 0};
  try {
    (void)bvh::collapse8(b);
    ADD_FAILURE() << "a tree deeper than the traversal's bound was collapsed";
  } catch (const std::length_error& e) {
    EXPECT_NE(std::string(e.what()).find("serves at most " + std::to_string(bvh::kMaxTreeDepth)), std::string::npos) << e.what();
  }
  // The builder never makes such a tree, whatever max_depth asks: it is clamped.
  std::vector<float> lo, hi;
  std::vector<std::uint8_t> kind;
  for (int k = 0; k < 3000; ++k) {
    const float e = std::pow(0.99f, float(k));
    lo.insert(lo.end(), {0, 0, 0});
    hi.insert(hi.end(), {e, e, e});
    kind.push_back(0);
  }
  bvh::BuildOptions o;
  o.max_depth = 100000;
  o.max_leaf = 1;
  o.parallel = false;
  const bvh::Bvh2 deep = bvh::build_sah(lo, hi, kind, o);
  std::cout << "[ depth    ] 3000 shrinking boxes, one per leaf, max_depth 100000: binary " << deep.stats.depth << "\n";
  EXPECT_LE(deep.stats.depth, bvh::kMaxTreeDepth);
  EXPECT_NO_THROW((void)bvh::collapse8(deep));
}
