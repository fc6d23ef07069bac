// The recursive ray tracer (render/): Snell's law and total internal reflection against
// hand-computed directions, shadows (full shadow = ambient only, a transmitting occluder scales
// the light), golden images per feature, and Haines' SPD ray statistics at a reduced resolution.
#include "render/optics.hpp"
#include "render/render.hpp"
#include "scene/loaders.hpp"
#include "scene/sources.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

namespace {

using namespace rb;
using namespace rb::render;

// ---- directions --------------------------------------------------------------------------------

void expect_vec(const Vec3f& a, const Vec3f& b, float tol = 2e-6f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(RenderOptics, ReflectMirrorsAboutTheNormal) {
  const float s = std::sqrt(0.5f);
  expect_vec(reflect<float>({s, -s, 0}, {0, 1, 0}), {s, s, 0});
  expect_vec(reflect<float>({0, 0, 1}, {0, 0, -1}), {0, 0, -1});  // head-on: straight back
}

TEST(RenderOptics, SnellIntoGlassAt45Degrees) {
  // sin t = sin 45 / 1.5 = 0.47140452, cos t = sqrt(1 - 2/9) = 0.88191710
  const float s = std::sqrt(0.5f);
  const auto t = refract({s, -s, 0}, {0, 1, 0}, 1.0f, 1.5f);
  ASSERT_TRUE(t.has_value());
  expect_vec(*t, {0.47140452f, -0.88191710f, 0.0f});
}

TEST(RenderOptics, SnellOutOfGlassAt30Degrees) {
  // sin t = 1.5 sin 30 = 0.75, cos t = sqrt(1 - 0.5625) = 0.66143783
  const auto t = refract({0.5f, -0.8660254f, 0}, {0, 1, 0}, 1.5f, 1.0f);
  ASSERT_TRUE(t.has_value());
  expect_vec(*t, {0.75f, -0.66143783f, 0.0f});
}

TEST(RenderOptics, HeadOnPassesStraight) {
  const auto t = refract({0, 0, -1}, {0, 0, 1}, 1.0f, 1.33f);
  ASSERT_TRUE(t.has_value());
  expect_vec(*t, {0, 0, -1});
}

TEST(RenderOptics, TotalInternalReflectionBeyondTheCriticalAngle) {
  // Critical angle glass -> air: asin(1 / 1.5) = 41.81 degrees.
  const double below = 41.7 * M_PI / 180, above = 41.9 * M_PI / 180;
  const Vec3f d_below{float(std::sin(below)), float(-std::cos(below)), 0}, d_above{float(std::sin(above)), float(-std::cos(above)), 0};
  const auto t = refract(d_below, {0, 1, 0}, 1.5f, 1.0f);
  ASSERT_TRUE(t.has_value());
  EXPECT_GT(t->x, 0.99f);  // nearly grazing just below the critical angle: sin t = 1.5 sin 41.7 = 0.9978
  EXPECT_FALSE(refract(d_above, {0, 1, 0}, 1.5f, 1.0f).has_value());
  const float s = std::sqrt(0.5f);
  EXPECT_FALSE(refract({s, -s, 0}, {0, 1, 0}, 1.5f, 1.0f).has_value());  // 45 degrees
  EXPECT_TRUE(refract({s, -s, 0}, {0, 1, 0}, 1.0f, 1.5f).has_value());   // never into the denser medium
}

// Shading runs eight hits at a time (render.cpp); each lane must give the bits of the scalar
// instantiation, or an image would depend on where its hits fall in the lanes.
TEST(RenderOptics, LanesGiveTheScalarBits) {
  std::uint32_t state = 12345u;
  auto uni = [&] {  // a fixed sequence in [-1, 1)
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) * 0x1p-23f - 1.0f;
  };
  auto unit = [&] { return normalize(Vec3f{uni(), uni(), uni()}); };
  int lit = 0, refracted = 0;
  for (int round = 0; round < 64; ++round) {
    alignas(kSimdAlign) float L[3][8], nl[3][8], v[3][8], kd[8], ks[8], sh[8], base[3][8];
    alignas(kSimdAlign) double d[3][8], n[3][8], eta[8];
    for (int i = 0; i < 8; ++i) {
      const Vec3f a = unit(), b = unit(), c = unit(), e = unit(), f = unit();
      for (int k = 0; k < 3; ++k) L[k][i] = a[k], nl[k][i] = b[k], v[k][i] = c[k], base[k][i] = 0.5f + 0.5f * uni();
      for (int k = 0; k < 3; ++k) d[k][i] = e[k], n[k][i] = f[k];
      kd[i] = 0.5f + 0.5f * uni(), ks[i] = i % 3 == 0 ? 0.0f : 0.5f + 0.5f * uni(), sh[i] = 1.0f + 40.0f * (uni() + 1.0f);
      eta[i] = i % 2 ? 1.0 / 1.5 : 1.5;
    }
    Vec3<f8> local8;
    const f8 ndl8 = local_light<f8>({load<f8>(L[0]), load<f8>(L[1]), load<f8>(L[2])}, {load<f8>(nl[0]), load<f8>(nl[1]), load<f8>(nl[2])},
                                    {load<f8>(v[0]), load<f8>(v[1]), load<f8>(v[2])}, load<f8>(kd), load<f8>(ks), load<f8>(sh),
                                    {load<f8>(base[0]), load<f8>(base[1]), load<f8>(base[2])}, local8);
    const Vec3<f8> r8 = reflect<f8>({load<f8>(L[0]), load<f8>(L[1]), load<f8>(L[2])}, {load<f8>(nl[0]), load<f8>(nl[1]), load<f8>(nl[2])});
    for (int j = 0; j < 8; j += 4) {
      Vec3<d4> t4;
      const d4 k4 = refract_k<d4>({load<d4>(d[0] + j), load<d4>(d[1] + j), load<d4>(d[2] + j)},
                                  {load<d4>(n[0] + j), load<d4>(n[1] + j), load<d4>(n[2] + j)}, load<d4>(eta + j), t4);
      for (int i = 0; i < 4; ++i) {
        Vec3d t1;
        const double k1 = refract_k<double>({d[0][j + i], d[1][j + i], d[2][j + i]}, {n[0][j + i], n[1][j + i], n[2][j + i]}, eta[j + i], t1);
        EXPECT_EQ(std::bit_cast<std::uint64_t>(lane(k4, i)), std::bit_cast<std::uint64_t>(k1));
        if (k1 >= 0.0) {
          ++refracted;
          for (int c = 0; c < 3; ++c) EXPECT_EQ(lane(c == 0 ? t4.x : c == 1 ? t4.y : t4.z, i), t1[c]) << "round " << round;
        }
      }
    }
    for (int i = 0; i < 8; ++i) {
      Vec3f local1;
      const float ndl1 = local_light<float>({L[0][i], L[1][i], L[2][i]}, {nl[0][i], nl[1][i], nl[2][i]}, {v[0][i], v[1][i], v[2][i]},
                                            kd[i], ks[i], sh[i], {base[0][i], base[1][i], base[2][i]}, local1);
      EXPECT_EQ(std::bit_cast<std::uint32_t>(lane(ndl8, i)), std::bit_cast<std::uint32_t>(ndl1)) << "round " << round;
      const Vec3f r1 = reflect<float>({L[0][i], L[1][i], L[2][i]}, {nl[0][i], nl[1][i], nl[2][i]});
      EXPECT_EQ(lane(r8.x, i), r1.x);
      EXPECT_EQ(lane(r8.y, i), r1.y);
      EXPECT_EQ(lane(r8.z, i), r1.z);
      if (!(ndl1 > 0.0f)) continue;
      ++lit;
      EXPECT_EQ(lane(local8.x, i), local1.x) << "round " << round << " lane " << i;
      EXPECT_EQ(lane(local8.y, i), local1.y);
      EXPECT_EQ(lane(local8.z, i), local1.z);
    }
  }
  EXPECT_GT(lit, 100);  // both branches were taken
  EXPECT_GT(refracted, 50);
}

// ---- shadows -----------------------------------------------------------------------------------

// A grey floor (y = 0, normal +y, Kd 0.8), one light straight above the origin, and an eye ray
// (a 1 x 1 image) that hits the floor at the origin from the side. `occluder_t` < 0: no
// occluder; else a sphere at (0, 5, 0) radius 1 with transmittance occluder_t.
scene::Scene shadow_scene(float occluder_t) {
  scene::Scene s;
  s.name = "shadow test";
  s.background = {0, 0, 0};
  s.camera.from = {4, 1, 0};
  s.camera.at = {0, 0, 0};
  s.camera.angle = 10;
  s.lights.push_back({{0, 10, 0}, {1, 1, 1}});
  scene::Material floor;
  floor.color = {0.5f, 0.6f, 0.7f};
  floor.kd = 0.8f;
  s.materials.push_back(floor);
  s.poly_verts = {{-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}};
  s.polygons.push_back({0, 4, 0});
  if (occluder_t >= 0) {
    scene::Material occ;
    occ.kd = 0.5f;
    occ.t = occluder_t;
    occ.ior = 1.0f;
    s.materials.push_back(occ);
    s.spheres.push_back({{0, 5, 0}, 1.0f, 1});
  }
  return s;
}

Vec3f render_pixel(const scene::Scene& s, RenderStats* st = nullptr) {
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  RenderOptions o;
  o.width = o.height = 1;
  o.depth = 1;
  const Renderer r(s, a, o);
  std::vector<float> samples;
  const RenderStats got = render_tiles(r, samples, 1);
  if (st) *st = got;
  const std::vector<float> img = r.resolve(samples);
  return {img[0], img[1], img[2]};
}

TEST(RenderShadow, LitPointGetsAmbientPlusLambert) {
  RenderStats st;
  const Vec3f c = render_pixel(shadow_scene(-1), &st);
  // ambient 0.1 * Kd * colour + Kd * (n . L = 1) * colour * light (one light: intensity 1)
  const float k = 0.1f * 0.8f + 0.8f;
  expect_vec(c, {0.5f * k, 0.6f * k, 0.7f * k}, 1e-5f);
  EXPECT_EQ(st.eye, 1u);
  EXPECT_EQ(st.eye_hit, 1u);
  EXPECT_EQ(st.shadow, 1u);
}

TEST(RenderShadow, FullShadowGivesAmbientOnly) {
  const Vec3f c = render_pixel(shadow_scene(0.0f));
  const float k = 0.1f * 0.8f;
  expect_vec(c, {0.5f * k, 0.6f * k, 0.7f * k}, 1e-6f);
}

TEST(RenderShadow, TransmittingOccluderScalesTheLight) {
  // The shadow ray crosses the sphere's surface twice: the light is scaled by T^2.
  const float T = 0.5f;
  const Vec3f c = render_pixel(shadow_scene(T));
  const float k = 0.1f * 0.8f + 0.8f * T * T;
  expect_vec(c, {0.5f * k, 0.6f * k, 0.7f * k}, 1e-5f);
}

TEST(RenderShadow, NoShadowRayWhenTheNormalFacesAway) {
  scene::Scene s = shadow_scene(-1);
  s.lights[0].pos = {0, -10, 0};  // below the floor
  RenderStats st;
  const Vec3f c = render_pixel(s, &st);
  EXPECT_EQ(st.shadow, 0u);
  const float k = 0.1f * 0.8f;
  expect_vec(c, {0.5f * k, 0.6f * k, 0.7f * k}, 1e-6f);
}

TEST(RenderInput, AbsurdSizesAreRejected) {
  const scene::Scene s = shadow_scene(-1);
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  RenderOptions o;
  o.width = 0;
  EXPECT_THROW(Renderer(s, a, o), std::invalid_argument);
  o.width = 100000;
  EXPECT_THROW(Renderer(s, a, o), std::invalid_argument);
  o.width = 8;
  o.depth = 0;
  EXPECT_THROW(Renderer(s, a, o), std::invalid_argument);
}

// The checker's cells: parity of the cells' sum, odd cells in color2; points far beyond any cell
// count (2^62 cells and more, where every double is even) and NaN count as even, with no
// overflowing conversion.
TEST(RenderInput, CheckerCellsNearAndFar) {
  scene::Material m;
  m.checker = 2;
  m.color = {1, 0, 0};
  m.color2 = {0, 0, 1};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const struct { Vec3d p; bool odd; } cases[] = {
      {{0.5, 0.5, 0.5}, false}, {{2.5, 0.5, 0.5}, true}, {{-0.5, 0.5, 0.5}, true}, {{-2.5, 3.0, 0.5}, true},
      {{0x1p70, 0.5, 0.5}, false}, {{0x1p70, 2.5, 0.5}, true}, {{-1e300, 0.5, -1.0}, true}, {{nan, 0.5, 0.5}, false},
      {{nan, 2.5, 0.5}, true}, {{std::numeric_limits<double>::infinity(), 0.5, 0.5}, false}};
  for (const auto& c : cases)
    expect_vec(surface_color(m, c.p), c.odd ? m.color2 : m.color, 0);
}

TEST(RenderInput, EmptySceneIsBackground) {
  scene::Scene s;
  s.background = {0.25f, 0.5f, 0.75f};
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  RenderOptions o;
  o.width = o.height = 4;
  const Renderer r(s, a, o);
  std::vector<float> samples;
  const RenderStats st = render_tiles(r, samples, 1);
  EXPECT_EQ(st.eye, 16u);
  EXPECT_EQ(st.eye_hit, 0u);
  for (std::size_t i = 0; i < samples.size(); i += 3) expect_vec({samples[i], samples[i + 1], samples[i + 2]}, s.background, 0);
}

TEST(RenderDepth, DepthLimitStopsTheRayTree) {
  const scene::Scene s = scene::lecture_scene("glass_sphere");
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  auto run = [&](int depth) {
    RenderOptions o;
    o.width = o.height = 24;
    o.depth = depth;
    const Renderer r(s, a, o);
    std::vector<float> samples;
    return render_tiles(r, samples, 1);
  };
  const RenderStats d1 = run(1), d2 = run(2), d5 = run(5);
  EXPECT_EQ(d1.reflect + d1.refract, 0u);
  EXPECT_GT(d2.refract, 0u);
  // Depth 2: one reflection and one refraction ray at most per eye hit on the glass.
  EXPECT_LE(d2.reflect, d2.eye_hit);
  EXPECT_LE(d2.refract, d2.eye_hit);
  EXPECT_GT(d5.refract, d2.refract);  // rays inside the sphere refract out again
  EXPECT_EQ(d1.eye, d5.eye);
  EXPECT_EQ(d1.eye_hit, d5.eye_hit);
}

// Eye rays traced one by one, in packets of 8 or 16, or as 64-ray blocks with the frustum test:
// the same closest hits, so the same image bit for bit. The gears are polygons and the torus box a
// CSG solid (a scalar query for single rays, an 8-lane one for packets); the gears' faces share
// edges (faces at one distance).
TEST(RenderPackets, EyePacketSizesGiveTheSameImage) {
  for (const char* name : {"lecture:nine_red_balls", "spd:tetra:3", "spd:gears:1", "csg:torus_box"}) {
    const scene::Scene s = scene::load_scene(name);
    const tracer::SceneAccel a = tracer::SceneAccel::build(s);
    std::vector<float> first;
    for (int packet : {1, 8, 16, 64}) {
      RenderOptions o;
      o.width = 40;  // tiles of 16: the last column of tiles is 8 wide, so 64-ray packets span rows
      o.height = 36;
      o.eye_packet = packet;
      const Renderer r(s, a, o);
      std::vector<float> samples;
      render_tiles(r, samples, 1);
      if (packet == 1) first = samples;
      else EXPECT_EQ(samples, first) << name << ", eye packet " << packet;
    }
  }
}

// Reflection, refraction and shadow rays one by one or in octant-ordered packets of 8 (the eye
// rays' shadow rays also of 16, and in a size apart from the other rays'): the hits go
// back to the batch's order before shading, so every sample sums its terms in the same order and
// the image is the same bit for bit (glass scenes: refraction, total internal reflection and
// shadow rays through transmitting occluders; a triangle mesh, whose packets of 16 walk in 16 lanes
// where the build and the CPU have them).
TEST(RenderPackets, SecondaryPacketSizesGiveTheSameImage) {
  for (const char* name : {"lecture:five_glass_balls", "lecture:nine_red_balls", "spd:balls:1", "spd:tetra:3"}) {
    const scene::Scene s = scene::load_scene(name);
    const tracer::SceneAccel a = tracer::SceneAccel::build(s);
    // one by one; packets of 8; the eye rays' shadow rays in packets (of 8, of 16), the others one
    // by one; and the reverse
    constexpr int kModes = 5;
    const int secondary[kModes] = {1, 8, 1, 1, 8}, eye_shadow[kModes] = {0, 0, 8, 16, 1};
    std::vector<float> samples[kModes];
    RenderStats st[kModes];
    for (int k = 0; k < kModes; ++k) {
      RenderOptions o;
      o.width = 40;
      o.height = 36;
      o.secondary_packet = secondary[k];
      o.eye_shadow_packet = eye_shadow[k];
      const Renderer r(s, a, o);
      st[k] = render_tiles(r, samples[k], 1);
    }
    EXPECT_GT(st[0].shadow, 0u) << name;
    for (int k = 1; k < kModes; ++k) {
      EXPECT_EQ(samples[k], samples[0]) << name << " " << k;
      EXPECT_EQ(st[k].shadow, st[0].shadow) << name;
      EXPECT_EQ(st[k].reflect + st[k].refract, st[0].reflect + st[0].refract) << name;
    }
  }
}

// ---- golden images -----------------------------------------------------------------------------
// tests/data/render/*.png were rendered once by `raybench render SCENE --width 48 -o FILE`
// (release build) and checked by eye; the test renders the same scene with the same options and
// compares. Tolerance: builds differ in FMA contraction, which moves a ray that grazes an edge or
// a shadow boundary to the other side, so at most 1 % of the pixels may differ by more than
// 4/255 in a channel, and the mean absolute difference must stay below 0.5/255.

struct Golden {
  const char* file;
  const char* scene;
};

void compare_golden(const Golden& g) {
  const std::string path = std::string(RB_TEST_DATA) + "/render/" + g.file;
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load(path.c_str(), &w, &h, &n, 3);
  ASSERT_NE(px, nullptr) << path;
  const std::vector<unsigned char> ref(px, px + std::size_t(w) * std::size_t(h) * 3);
  stbi_image_free(px);
  const scene::Scene s = scene::load_scene(g.scene);
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  RenderOptions o;
  o.width = w;
  o.height = h;
  const Renderer r(s, a, o);
  std::vector<float> samples;
  render_tiles(r, samples, 2);
  const std::vector<std::uint8_t> got = to_rgb8(r.resolve(samples));
  ASSERT_EQ(got.size(), ref.size());
  std::size_t bad = 0;
  double sum = 0;
  for (std::size_t p = 0; p < got.size() / 3; ++p) {
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
      const int d = std::abs(int(got[3 * p + std::size_t(c)]) - int(ref[3 * p + std::size_t(c)]));
      worst = std::max(worst, d);
      sum += d;
    }
    bad += worst > 4;
  }
  EXPECT_LE(double(bad), 0.01 * double(got.size() / 3)) << g.file;
  EXPECT_LT(sum / double(got.size()), 0.5) << g.file;
}

TEST(RenderGolden, Shadows) { compare_golden({"shadows.png", RB_TEST_DATA "/render/shadows.nff"}); }
TEST(RenderGolden, Reflection) { compare_golden({"reflection.png", "lecture:nine_red_balls"}); }
TEST(RenderGolden, Refraction) { compare_golden({"refraction.png", "lecture:glass_sphere"}); }
TEST(RenderGolden, Checkerboard) { compare_golden({"checkerboard.png", "lecture:checkerboard"}); }

// The goldens are not trivially flat: a test that compares two flat images cannot fail.
TEST(RenderGolden, ImagesHaveStructure) {
  for (const char* f : {"shadows.png", "reflection.png", "refraction.png", "checkerboard.png"}) {
    // Built by appending: GCC 12 at -O3 warns (-Warray-bounds, a false positive) on the inlined
    // temporary of std::string(...) + "..." + f.
    std::string path = RB_TEST_DATA "/render/";
    path += f;
    int w = 0, h = 0, n = 0;
    unsigned char* px = stbi_load(path.c_str(), &w, &h, &n, 3);
    ASSERT_NE(px, nullptr) << path;
    int lo = 255, hi = 0;
    for (int i = 0; i < w * h * 3; ++i) lo = std::min(lo, int(px[i])), hi = std::max(hi, int(px[i]));
    stbi_image_free(px);
    EXPECT_GT(hi - lo, 100) << f;
  }
}

// ---- Haines' SPD statistics ----------------------------------------------------------------------
// Haines' figures are for 513 x 513 corner rays. At R x R pixels ((R+1)^2 corner rays) every
// count scales with the number of eye rays (the image samples the same view more coarsely), so
// the counts are scaled by 513^2 / (R+1)^2 before the 10 % comparison.

struct SpdRow {
  const char* scene;
  double eye_hit, reflect, refract, shadow;
};

void expect_spd(const SpdRow& row, int res) {
  const scene::Scene s = scene::load_scene(std::string("spd:") + row.scene);
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  const Renderer r(s, a, spd_options(s, res, res, 5));
  std::vector<float> samples;
  const RenderStats st = render_tiles(r, samples, 2);
  EXPECT_EQ(st.eye, std::uint64_t(res + 1) * std::uint64_t(res + 1));
  const double k = 513.0 * 513.0 / double(st.eye);
  auto near = [&](const char* what, double got, double ref) {
    if (ref == 0) EXPECT_EQ(got, 0.0) << row.scene << " " << what;
    else EXPECT_NEAR(got * k / ref, 1.0, 0.10) << row.scene << " " << what << ": " << got * k << " vs " << ref;
  };
  std::uint64_t by_kind = 0;
  for (const auto n : st.cost.kind_prims) by_kind += n;
  EXPECT_EQ(by_kind, st.cost.prims) << "primitive tests by kind add up to the total";
  EXPECT_GT(st.cost.boxes, st.eye);
  near("eye hits", double(st.eye_hit), row.eye_hit);
  near("reflection rays", double(st.reflect), row.reflect);
  near("refraction rays", double(st.refract), row.refract);
  near("shadow rays", double(st.shadow), row.shadow);
}

// 96 x 96 pixels (97^2 = 9,409 eye rays, 3.6 % of Haines'): small enough for the sanitizer build,
// large enough that the smallest figure (tetra, 49,788 eye hits: about 1,780 here) is not
// dominated by sampling (at 48 x 48 tetra's shadow count came out 10.4 % low).
constexpr int kSpdRes = 96;
TEST(RenderSpd, BallsWithinTenPercentOfHaines) { expect_spd({"balls", 263169, 175095, 0, 954368}, kSpdRes); }
TEST(RenderSpd, TeapotWithinTenPercentOfHaines) { expect_spd({"teapot", 161120, 225248, 0, 407656}, kSpdRes); }
TEST(RenderSpd, TetraWithinTenPercentOfHaines) { expect_spd({"tetra", 49788, 0, 0, 46112}, kSpdRes); }
TEST(RenderSpd, TreeWithinTenPercentOfHaines) { expect_spd({"tree", 169836, 0, 0, 1097419}, kSpdRes); }

}  // namespace
