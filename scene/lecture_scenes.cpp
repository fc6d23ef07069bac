// The lecture's recursive ray tracing scenes (seed 004: CS 4300 lecture 27, Watt's "Adventures
// of the 7 rays" and the slides' images), as small exact scenes:
//   checkerboard      "Reflection and Refraction of Checkerboard": a mirror sphere and a glass
//                     sphere on a red/yellow checkerboard floor
//   nine_red_balls    "Second Order Reflection" / "Nine Red Balls": a 3x3 grid of shiny red
//                     spheres reflecting each other, on a grey floor
//   five_glass_balls  "Five Glass Balls": five glass spheres in a row over the checkerboard
//   glass_sphere      "One Glass Sphere": one glass sphere over the checkerboard
// The slides give images, not numbers: positions, sizes and colours are ours, chosen to
// reproduce the compositions. Conventions (those of NFF / Haines' SPD): y is up here; glass is
// T = 0.9, ior 1.5 (the slides' "glass (typical) 1.5"); a mirror reflects with Ks.
// The scene model has no infinite plane or texture: the floor is one large square polygon
// (40 x 40, centred under the objects) and its checkerboard is the Material checker fields
// (scene/scene.hpp): cells of 1 unit, floor at y = -1.5 (mid-cell, as the checker requires).
#include "scene/sources.hpp"
#include "core/suggest.hpp"

#include <fmt/format.h>

namespace rb::scene {

namespace {

constexpr double kFloorY = -1.5;  // mid-cell for checker size 1
constexpr double kFloorHalf = 20.0;

struct LectureBuilder {
  Scene s;

  explicit LectureBuilder(std::string name) {
    s.name = std::move(name);
    s.background = {0.078f, 0.361f, 0.753f};  // Haines' "UNC sky blue", as the SPD scenes
    s.camera.from = {0.0f, 1.0f, 7.0f};
    s.camera.at = {0.0f, -0.5f, 0.0f};
    s.camera.up = {0.0f, 1.0f, 0.0f};
    s.camera.angle = 45.0f;
    s.camera.hither = 0.001f;
    s.camera.width = s.camera.height = 512;
    s.lights.push_back(Light{{-6.0f, 10.0f, 8.0f}, {1, 1, 1}});
    s.lights.push_back(Light{{8.0f, 6.0f, 6.0f}, {0.5f, 0.5f, 0.5f}});
  }
  std::uint32_t material(const Material& m) {
    s.materials.push_back(m);
    return std::uint32_t(s.materials.size() - 1);
  }
  void floor(std::uint32_t mat) {
    const auto first = std::uint32_t(s.poly_verts.size());
    // counter-clockwise seen from above: normal +y
    s.poly_verts.insert(s.poly_verts.end(), {Vec3d{-kFloorHalf, kFloorY, -kFloorHalf}, Vec3d{-kFloorHalf, kFloorY, kFloorHalf},
                                             Vec3d{kFloorHalf, kFloorY, kFloorHalf}, Vec3d{kFloorHalf, kFloorY, -kFloorHalf}});
    s.polygons.push_back(PolygonIn{first, 4, mat});
  }
  // Positions as the float values the scenes were designed with (0.55f, 1.3f, ...), widened.
  void sphere(Vec3f c, float r, std::uint32_t mat) { s.spheres.push_back(SphereIn{to_double(c), double(r), mat}); }
};

Material checker_floor() {
  Material m;
  m.color = {1.0f, 0.0f, 0.0f};   // red
  m.color2 = {1.0f, 1.0f, 0.0f};  // yellow (Whitted's floor)
  m.checker = 1.0f;
  m.kd = 0.8f, m.ks = 0.0f, m.shine = 100000.0f;
  return m;
}
Material glass() {
  Material m;
  m.color = {1.0f, 1.0f, 1.0f};
  m.kd = 0.05f, m.ks = 0.1f, m.shine = 200.0f, m.t = 0.9f, m.ior = 1.5f;
  return m;
}
Material mirror() {
  Material m;
  m.color = {1.0f, 1.0f, 1.0f};
  m.kd = 0.1f, m.ks = 0.9f, m.shine = 100.0f;
  return m;
}
Material shiny_red() {
  Material m;
  m.color = {1.0f, 0.05f, 0.05f};
  m.kd = 0.6f, m.ks = 0.4f, m.shine = 30.0f;
  return m;
}

Scene checkerboard() {
  LectureBuilder b("lecture:checkerboard");
  b.floor(b.material(checker_floor()));
  b.sphere({-1.2f, -0.5f, -0.8f}, 1.0f, b.material(mirror()));
  b.sphere({1.2f, -0.5f, 0.6f}, 1.0f, b.material(glass()));
  return std::move(b.s);
}

Scene nine_red_balls() {
  LectureBuilder b("lecture:nine_red_balls");
  Material grey;
  grey.color = {0.6f, 0.6f, 0.6f};
  grey.kd = 0.8f, grey.shine = 100000.0f;
  b.floor(b.material(grey));
  const auto red = b.material(shiny_red());
  const float r = 0.55f;
  for (int iz = -1; iz <= 1; ++iz)
    for (int ix = -1; ix <= 1; ++ix) b.sphere({1.3f * float(ix), float(kFloorY) + r, 1.3f * float(iz)}, r, red);
  return std::move(b.s);
}

Scene five_glass_balls() {
  LectureBuilder b("lecture:five_glass_balls");
  b.floor(b.material(checker_floor()));
  const auto g = b.material(glass());
  const float r = 0.5f;
  for (int i = -2; i <= 2; ++i) b.sphere({1.15f * float(i), float(kFloorY) + r + 0.25f, 0.0f}, r, g);
  return std::move(b.s);
}

Scene glass_sphere() {
  LectureBuilder b("lecture:glass_sphere");
  b.floor(b.material(checker_floor()));
  b.sphere({0.0f, 0.0f, 0.0f}, 1.0f, b.material(glass()));  // floats 0.5 above the floor
  return std::move(b.s);
}

struct LectureEntry {
  const char* name;
  Scene (*make)();
};
constexpr LectureEntry kLecture[] = {
    {"checkerboard", checkerboard},
    {"nine_red_balls", nine_red_balls},
    {"five_glass_balls", five_glass_balls},
    {"glass_sphere", glass_sphere},
};

}  // namespace

std::vector<std::string> lecture_scene_names() {
  std::vector<std::string> r;
  for (const auto& e : kLecture) r.emplace_back(e.name);
  return r;
}

Scene lecture_scene(const std::string& name) {
  for (const auto& e : kLecture)
    if (name == e.name) return e.make();
  std::string known;
  for (const auto& e : kLecture) known += std::string(known.empty() ? "" : " ") + e.name;
  throw SceneError(fmt::format("lecture:{}: unknown lecture scene (known: {}){}", name, known, did_you_mean(name, lecture_scene_names())));
}

}  // namespace rb::scene
