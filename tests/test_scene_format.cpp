// The JSON scene format's example file and the export (`raybench info SCENE --dump-json`): the
// example loads with every kind it shows, and an exported scene loads back to the same scene
// (the same camera, lights, materials and numbers, CSG trees that answer every ray alike).
#include "scene/csg_scene.hpp"
#include "scene/sources.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <string>

using namespace rb;

namespace {

const std::string kExample = std::string(RB_SOURCE_DIR) + "/data/scenes/example.json";

bool same(const Vec3f& a, const Vec3f& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
bool same(const Vec3d& a, const Vec3d& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// Every CSG object answers a grid of rays from the camera (and one from the side) alike.
void expect_same_csg(const scene::Scene& a, const scene::Scene& b) {
  ASSERT_EQ(a.csgs.size(), b.csgs.size());
  for (std::size_t i = 0; i < a.csgs.size(); ++i) {
    const CsgTree& ta = *a.csgs[i].tree;
    const CsgTree& tb = *b.csgs[i].tree;
    ASSERT_EQ(ta.nodes.size(), tb.nodes.size()) << a.name << " object " << i;
    ASSERT_EQ(ta.leaves.size(), tb.leaves.size()) << a.name << " object " << i;
    EXPECT_EQ(a.csgs[i].mat, b.csgs[i].mat);
    int hits = 0;
    for (const Vec3f eye : {to_float(a.camera.from), Vec3f{9, 1, 0.5f}})
      for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x) {
          const Vec3f target{-4 + 8 * float(x) / 39, -3 + 6 * float(y) / 39, 0};
          const Ray<float> r = make_ray(eye, target - eye);
          const scene::CsgSurface sa = scene::csg_surface(ta, r), sb = scene::csg_surface(tb, r);
          ASSERT_EQ(sa.hit, sb.hit) << a.name << " object " << i << " ray " << x << "," << y;
          if (!sa.hit) continue;
          ++hits;
          EXPECT_EQ(sa.t, sb.t);
          EXPECT_TRUE(same(sa.normal, sb.normal));
          EXPECT_EQ(sa.material, sb.material);
        }
    EXPECT_GT(hits, 0) << a.name << " object " << i << ": no ray hit it, the comparison said nothing";
  }
}

void expect_same_scene(const scene::Scene& a, const scene::Scene& b) {
  EXPECT_TRUE(same(a.camera.from, b.camera.from));
  EXPECT_TRUE(same(a.camera.at, b.camera.at));
  EXPECT_TRUE(same(a.camera.up, b.camera.up));
  EXPECT_EQ(a.camera.angle, b.camera.angle);
  EXPECT_EQ(a.camera.hither, b.camera.hither);
  EXPECT_EQ(a.camera.width, b.camera.width);
  EXPECT_EQ(a.camera.height, b.camera.height);
  EXPECT_TRUE(same(a.background, b.background));
  ASSERT_EQ(a.lights.size(), b.lights.size());
  for (std::size_t i = 0; i < a.lights.size(); ++i) {
    EXPECT_TRUE(same(a.lights[i].pos, b.lights[i].pos));
    EXPECT_TRUE(same(a.lights[i].color, b.lights[i].color));
  }
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (std::size_t i = 0; i < a.materials.size(); ++i) {
    const auto &m = a.materials[i], &n = b.materials[i];
    EXPECT_TRUE(same(m.color, n.color)) << "material " << i;
    EXPECT_EQ(m.kd, n.kd);
    EXPECT_EQ(m.ks, n.ks);
    EXPECT_EQ(m.shine, n.shine);
    EXPECT_EQ(m.t, n.t);
    EXPECT_EQ(m.ior, n.ior);
  }
  ASSERT_EQ(a.spheres.size(), b.spheres.size());
  for (std::size_t i = 0; i < a.spheres.size(); ++i) {
    EXPECT_TRUE(same(a.spheres[i].c, b.spheres[i].c));
    EXPECT_EQ(a.spheres[i].r, b.spheres[i].r);
    EXPECT_EQ(a.spheres[i].mat, b.spheres[i].mat);
  }
  ASSERT_EQ(a.tori.size(), b.tori.size());
  for (std::size_t i = 0; i < a.tori.size(); ++i) {
    EXPECT_TRUE(same(a.tori[i].c, b.tori[i].c));
    EXPECT_TRUE(same(a.tori[i].axis, b.tori[i].axis));
    EXPECT_EQ(a.tori[i].R, b.tori[i].R);
    EXPECT_EQ(a.tori[i].r, b.tori[i].r);
    EXPECT_EQ(a.tori[i].mat, b.tori[i].mat);
  }
  ASSERT_EQ(a.polygons.size(), b.polygons.size());
  ASSERT_EQ(a.poly_verts.size(), b.poly_verts.size());
  for (std::size_t i = 0; i < a.polygons.size(); ++i) {
    EXPECT_EQ(a.polygons[i].count, b.polygons[i].count);
    EXPECT_EQ(a.polygons[i].mat, b.polygons[i].mat);
  }
  for (std::size_t i = 0; i < a.poly_verts.size(); ++i) EXPECT_TRUE(same(a.poly_verts[i], b.poly_verts[i]));
  EXPECT_EQ(a.primitive_count(), b.primitive_count());
  expect_same_csg(a, b);
}

}  // namespace

TEST(SceneFormat, TheExampleFileLoadsWithEveryKindItShows) {
  const scene::Scene s = scene::load_scene(kExample);
  EXPECT_EQ(s.camera.width, 640);
  EXPECT_EQ(s.camera.height, 400);
  EXPECT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.materials.size(), 7u);  // the default and six named
  EXPECT_EQ(s.polygons.size(), 1u);
  EXPECT_EQ(s.spheres.size(), 1u);
  EXPECT_EQ(s.tori.size(), 1u);
  ASSERT_EQ(s.csgs.size(), 4u);  // the drilled cube, the cut polyhedron, the cone, the cut quadric
  for (const auto& c : s.csgs) EXPECT_FALSE(c.tree->empty());
}

TEST(SceneFormat, EveryEmbeddedCsgSceneExportsAndLoadsBackTheSame) {
  for (const auto& n : scene::csg_scene_names()) {
    const scene::Scene a = scene::csg_scene(n);
    const scene::Scene b = scene::parse_json_scene(scene::scene_json(a), "exported " + n);
    SCOPED_TRACE(n);
    expect_same_scene(a, b);
  }
}

TEST(SceneFormat, TheExampleAndAGeneratedSceneExportAndLoadBackTheSame) {
  for (const std::string& src : {kExample, std::string("spd:balls:1")}) {
    const scene::Scene a = scene::load_scene(src);
    const std::string text = scene::scene_json(a);
    const scene::Scene b = scene::parse_json_scene(text, "exported");
    SCOPED_TRACE(src);
    expect_same_scene(a, b);
    // Exporting the loaded export gives the same text (names, order and numbers are stable).
    EXPECT_EQ(scene::scene_json(b), text);
  }
}

TEST(SceneFormat, WhatTheFormatCannotHoldIsNamed) {
  const scene::Scene mesh = scene::load_scene(std::string(RB_SOURCE_DIR) + "/data/meshes/stanford-bunny.obj");
  try {
    (void)scene::scene_json(mesh);
    FAIL() << "a triangle mesh was exported";
  } catch (const scene::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("69451 triangles"), std::string::npos) << e.what();
  }
  const scene::Scene lecture = scene::lecture_scene(scene::lecture_scene_names().front());
  bool checker = false;
  for (const auto& m : lecture.materials) checker |= m.checker > 0;
  if (checker) {
    EXPECT_THROW((void)scene::scene_json(lecture), scene::SceneError);
  }
}
