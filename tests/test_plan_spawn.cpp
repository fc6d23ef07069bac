// Where secondary rays start (tracer/plan.hpp, SceneAccel::spawn_point): each hit's own offset keeps
// a small object's shadow, and the surface it leaves lit, however far from the frame's origin the
// scene lies and whatever the size of what it rests on.
#include "core/spawn.hpp"
#include "scene/sources.hpp"
#include "tracer/accel.hpp"
#include "tracer/plan.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <string>

namespace {

using namespace rb;
using tracer::Model;
using kinds::Kind;

bvh::HitRec trace_one(const tracer::SceneAccel& a, const Ray<float>& r, bool any) {
  RaySoA rays;
  rays.push(r);
  std::vector<bvh::HitRec> h(rays.size());
  tracer::TraceOptions o;
  o.any = any;
  a.trace(rays, 0, rays.size(), h.data(), o);
  return h[0];
}
// Whether the light is blocked from the point a world ray from `from` along `dir` first hits.
bool shadowed(const tracer::SceneAccel& a, const Vec3d& from, const Vec3d& dir, const Vec3d& light, std::uint32_t* hit_prim) {
  const Ray<float> r = a.frame_ray(from, dir);
  const bvh::HitRec h = trace_one(a, r, false);
  *hit_prim = h.prim;
  if (h.prim == bvh::kNoPrim) return false;
  const kinds::Surface sf = a.surface(h, r);
  const Vec3d to = light - sf.p;
  const Vec3f d = to_float(to * (1.0 / std::sqrt(dot(to, to))));
  const Vec3f o = a.spawn_point(sf, d);
  return trace_one(a, make_ray(o, d, 0.0f, float(std::sqrt(dot(to, to)))), true).prim != bvh::kNoPrim;
}

// The shader's spawn points, eight hits at a time (SceneAccel::spawn_point on lanes), are the
// scalar ones bit for bit: error-bound offsets of points near and far from the frame's origin,
// normals on either side of the ray's direction, and the extent-epsilon offset.
TEST(PlanSpawn, EightLanesGiveTheScalarSpawnPoints) {
  const scene::Scene s = scene::precision_scene("cluster_ground");
  const tracer::SceneAccel a = tracer::SceneAccel::build(s, tracer::make_plan(s, Model::automatic));
  ASSERT_EQ(a.plan().spawn, tracer::SpawnScheme::error_bound);
  std::uint32_t state = 7u;
  auto uni = [&] {  // a fixed sequence in [-1, 1)
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) * 0x1p-23f - 1.0f;
  };
  auto unit = [&] { return normalize(Vec3f{uni(), uni(), uni()}); };
  auto same = [](float x, float y) { return std::bit_cast<std::uint32_t>(x) == std::bit_cast<std::uint32_t>(y); };
  int moved = 0;
  for (int round = 0; round < 64; ++round) {
    alignas(kSimdAlign) float v[12][8];
    tracer::SceneAccel::SpawnBase b[8];
    Vec3f dir[8];
    for (int i = 0; i < 8; ++i) {
      const float scale = std::ldexp(1.0f, (round + i) % 40 - 10);  // 2^-10 .. 2^29 from the origin
      b[i].p = Vec3f{uni(), uni(), uni()} * scale;
      b[i].err = Vec3f{std::fabs(uni()), std::fabs(uni()), std::fabs(uni())} * (scale * 0x1p-20f);
      b[i].ng = unit();
      dir[i] = i == 7 ? Vec3f{0, 0, 0} : unit();  // lane 7: a direction along no side
      const Vec3f* f[4] = {&b[i].p, &b[i].err, &b[i].ng, &dir[i]};
      for (int k = 0; k < 12; ++k) v[k][i] = (*f[k / 3])[k % 3];
    }
    auto lanes3 = [&](int k) { return Vec3<f8>{load<f8>(v[k]), load<f8>(v[k + 1]), load<f8>(v[k + 2])}; };
    const Vec3<f8> o8 = a.spawn_point(lanes3(0), lanes3(3), lanes3(6), lanes3(9));
    const Vec3<f8> e8 = spawn::eps_offset(lanes3(0), lanes3(6), f8(1e-3f));
    for (int i = 0; i < 8; ++i) {
      const Vec3f o1 = a.spawn_point(b[i], dir[i]), e1 = spawn::eps_offset(b[i].p, b[i].ng, 1e-3f);
      moved += !(o1.x == b[i].p.x && o1.y == b[i].p.y && o1.z == b[i].p.z);
      EXPECT_TRUE(same(lane(o8.x, i), o1.x) && same(lane(o8.y, i), o1.y) && same(lane(o8.z, i), o1.z)) << "round " << round << " lane " << i;
      EXPECT_TRUE(same(lane(e8.x, i), e1.x) && same(lane(e8.y, i), e1.y) && same(lane(e8.z, i), e1.z)) << "round " << round << " lane " << i;
    }
  }
  EXPECT_GT(moved, 500);  // the offsets did move the points
}

// A ball of radius 2 resting on a planet of radius 6.4e6: secondary rays start off the point they
// leave by an offset scaled to that hit, not to the scene's largest coordinate (which would put
// them tens of units away: no shadow under the ball, a false terminator on its lower half).
TEST(PlanSpawn, ABallOnAPlanetCastsItsShadowAndLightsItsLowerHalf) {
  const scene::Scene s = scene::precision_scene("planet");
  // The scene's own layout (scene/precision_scenes.cpp): the planet's top point, the ball on it.
  const Vec3d top{0.3, 0, -0.2}, ball = top + Vec3d{0.3, 2.0, -0.1}, light = s.lights.at(0).pos;
  const double radius = 2.0;
  for (Model m : {Model::automatic, Model::exact}) {
    const tracer::SceneAccel a = tracer::SceneAccel::build(s, tracer::make_plan(s, m));
    std::uint32_t prim = 0;
    // The ground in the ball's shadow: the line from the light through the ball's centre, where it
    // meets the ground, seen from above.
    const double k = light.y / (light.y - ball.y);
    const Vec3d umbra = light + (ball - light) * k;
    const Vec3d above = umbra + Vec3d{-0.5, 3.0, 0.4};
    EXPECT_TRUE(shadowed(a, above, umbra - above, light, &prim)) << tracer::model_name(m) << ": no shadow under the ball";
    EXPECT_EQ(kinds::index_of(prim), 0u) << "the planet (sphere 0) is what the ray meets";
    // Lit ground away from the ball.
    const Vec3d open = top + Vec3d{-6.0, 0.0, 5.0};
    EXPECT_FALSE(shadowed(a, open + Vec3d{0.3, 3.0, 0.2}, Vec3d{-0.3, -3.0, -0.2}, light, &prim)) << tracer::model_name(m);
    // Lit points of the ball whose normals point down (its lower half, facing the light).
    const Vec3d l = light - ball;
    for (const double down : {-0.05, -0.2, -0.4}) {
      Vec3d n{l.x, down * std::sqrt(dot(l, l)), l.z};
      n = n * (1.0 / std::sqrt(dot(n, n)));
      ASSERT_GT(dot(n, l), 0.0);
      EXPECT_FALSE(shadowed(a, ball + n * (radius + 1.0), n * -1.0, light, &prim))
          << tracer::model_name(m) << ": a false terminator at normal y " << n.y;
      EXPECT_EQ(kinds::index_of(prim), 1u) << "the ball (sphere 1) is what the ray meets";
    }
  }
}

// Balls on a floor 3.7e4 above a world of small meshes near the origin, which world coordinates
// must hold beside them (precision:cluster_ground): where the float step is 2^-8, an offset of 256
// float steps lifted a shadow ray from the floor by one unit, past the ball of radius 0.7. Per
// hit, from its own error, every ball keeps its shadow, whatever the model.
TEST(PlanSpawn, BallsOnAFloorFarFromTheFrameOriginCastTheirShadows) {
  const scene::Scene s = scene::precision_scene("cluster_ground");
  // The scene's own layout (scene/precision_scenes.cpp): the floor at `at`, put_balls' two balls.
  const Vec3d at{20, 37000.5, -10}, light = s.lights.at(0).pos;
  const struct {
    Vec3d c;
    double r;
  } balls[] = {{at + Vec3d{0.3, 2.0, -0.1}, 2.0}, {at + Vec3d{3.1, 0.7, 1.7}, 0.7}};
  for (Model m : {Model::automatic, Model::exact}) {
    const tracer::Plan p = tracer::make_plan(s, m);
    if (m == Model::automatic) {
      ASSERT_EQ(p.frame, tracer::FrameKind::world) << "the scene keeps its balls far from the frame's origin";
    }
    const tracer::SceneAccel a = tracer::SceneAccel::build(s, p);
    for (const auto& b : balls) {
      // The floor where the line from the light through the ball's centre meets it, and nine
      // tenths of the way there from where the ball touches the floor: both in its shadow, and
      // both seen from straight above past the ball (over its radius from its centre's foot).
      const Vec3d umbra = light + (b.c - light) * ((light.y - at.y) / (light.y - b.c.y));
      const Vec3d contact{b.c.x, at.y, b.c.z};
      for (const Vec3d& q : {umbra, contact + (umbra - contact) * 0.9}) {
        std::uint32_t prim = 0;
        EXPECT_TRUE(shadowed(a, q + Vec3d{0, 5.0, 0}, Vec3d{0, -1, 0}, light, &prim))
            << tracer::model_name(m) << ": no shadow of the ball of radius " << b.r;
        EXPECT_EQ(kinds::kind_of(prim), Kind::polygon) << "the floor is what the ray meets";
      }
    }
    // Lit floor beside the balls.
    std::uint32_t prim = 0;
    EXPECT_FALSE(shadowed(a, at + Vec3d{-6.3, 5.0, 6.1}, Vec3d{-0.3, -5.0, -0.2}, light, &prim)) << tracer::model_name(m);
  }
}

}  // namespace
