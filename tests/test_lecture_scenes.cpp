// The lecture's scenes (scene/lecture_scenes.cpp): names, contents, materials (glass: T > 0 and
// ior 1.5; mirror: Ks), the checkerboard floor (Material::checker), and that every object sits
// in front of the camera inside the field of view.
#include "scene/sources.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

using namespace rb;
using namespace rb::scene;

bool is_glass(const Material& m) { return m.t > 0.0f && m.ior == 1.5f; }
bool is_mirror(const Material& m) { return m.ks >= 0.5f && m.t == 0.0f; }

// The floor: one square polygon, horizontal (y = const), large, below every sphere.
void expect_floor(const Scene& s, bool checker) {
  ASSERT_EQ(s.polygons.size(), 1u);
  const PolygonIn& p = s.polygons[0];
  ASSERT_EQ(p.count, 4u);
  const double y = s.poly_verts[p.first].y;
  for (std::uint32_t i = 0; i < 4; ++i) EXPECT_EQ(s.poly_verts[p.first + i].y, y);
  // faces up (counter-clockwise seen from +y)
  const Vec3d a = s.poly_verts[p.first], b = s.poly_verts[p.first + 1], c = s.poly_verts[p.first + 2];
  EXPECT_GT(cross(b - a, c - a).y, 0.0);
  const Material& m = s.materials.at(p.mat);
  if (checker) {
    EXPECT_GT(m.checker, 0.0f);
    // mid-cell along y: the parity never flips on the floor itself
    const double cells = y / double(m.checker);
    EXPECT_NEAR(cells - std::floor(cells), 0.5, 1e-6);
    EXPECT_FALSE(m.color.x == m.color2.x && m.color.y == m.color2.y && m.color.z == m.color2.z);
  } else {
    EXPECT_EQ(m.checker, 0.0f);
  }
  for (const auto& sp : s.spheres) EXPECT_GE(sp.c.y - sp.r, y) << "sphere below the floor";
}

void expect_visible(const Scene& s) {
  const Camera& c = s.camera;
  const Vec3d fwd = normalize(c.at - c.from);
  const double half = c.angle * 3.14159265358979 / 360.0;
  for (const auto& sp : s.spheres) {
    const Vec3d d = sp.c - c.from;
    const double along = dot(d, fwd);
    ASSERT_GT(along, sp.r);
    const double off = std::acos(std::min(1.0, along / length(d)));
    EXPECT_LT(off, half) << "sphere centre outside the view";
  }
}

TEST(LectureScenes, Names) {
  const std::vector<std::string> names = {"checkerboard", "nine_red_balls", "five_glass_balls", "glass_sphere"};
  EXPECT_EQ(lecture_scene_names(), names);
  for (const auto& n : names) {
    const Scene s = lecture_scene(n);
    EXPECT_FALSE(s.lights.empty()) << n;
    EXPECT_EQ(s.cones.size() + s.triangles.size(), 0u) << n;
    for (const auto& sp : s.spheres) EXPECT_LT(sp.mat, s.materials.size());
    for (const auto& p : s.polygons) EXPECT_LT(p.mat, s.materials.size());
    expect_visible(s);
  }
  EXPECT_THROW(lecture_scene("nosuch"), SceneError);
  EXPECT_THROW(lecture_scene(""), SceneError);
}

TEST(LectureScenes, Checkerboard) {
  const Scene s = lecture_scene("checkerboard");
  expect_floor(s, true);
  ASSERT_EQ(s.spheres.size(), 2u);
  int glass = 0, mirror = 0;
  for (const auto& sp : s.spheres) {
    glass += is_glass(s.materials[sp.mat]);
    mirror += is_mirror(s.materials[sp.mat]);
  }
  EXPECT_EQ(glass, 1);
  EXPECT_EQ(mirror, 1);
}

TEST(LectureScenes, NineRedBalls) {
  const Scene s = lecture_scene("nine_red_balls");
  expect_floor(s, false);
  ASSERT_EQ(s.spheres.size(), 9u);
  for (const auto& sp : s.spheres) {
    const Material& m = s.materials[sp.mat];
    EXPECT_GT(m.color.x, 0.9f);
    EXPECT_LT(m.color.y, 0.2f);
    EXPECT_LT(m.color.z, 0.2f);
    EXPECT_GT(m.ks, 0.0f);  // reflects its neighbours (second-order reflection)
    EXPECT_EQ(m.t, 0.0f);
  }
  // no two balls overlap
  for (std::size_t i = 0; i < 9; ++i)
    for (std::size_t j = i + 1; j < 9; ++j)
      EXPECT_GT(length(s.spheres[i].c - s.spheres[j].c), s.spheres[i].r + s.spheres[j].r);
}

TEST(LectureScenes, FiveGlassBalls) {
  const Scene s = lecture_scene("five_glass_balls");
  expect_floor(s, true);
  ASSERT_EQ(s.spheres.size(), 5u);
  for (const auto& sp : s.spheres) EXPECT_TRUE(is_glass(s.materials[sp.mat]));
}

TEST(LectureScenes, GlassSphere) {
  const Scene s = lecture_scene("glass_sphere");
  expect_floor(s, true);
  ASSERT_EQ(s.spheres.size(), 1u);
  EXPECT_TRUE(is_glass(s.materials[s.spheres[0].mat]));
  EXPECT_GT(s.spheres[0].c.y - s.spheres[0].r, s.poly_verts[0].y);  // over the board, not on it
}

}  // namespace
