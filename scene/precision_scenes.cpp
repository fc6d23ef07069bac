// Scenes that test whether a tracer models enough precision (`precision:NAME`): small objects on a
// planet, a scene far from the origin, small things seen from far away, thin tubes, a scene mixing
// scales. Each is a complete scene (camera, lights, materials) that renders and traces like any
// other; the accuracy lab's whole-scene family (accuracy/scenes.cpp) traces them against an exact
// reference, and `raybench plan precision:NAME` shows what each needs. Coordinates are chosen so
// that they are not floats (6400000.3, radius 1.7): rounding them to float moves them.
//   ball_ground     a ball of radius 2 resting on a square floor, a second smaller ball, one light
//                   to the side (a small scene at the origin: it needs nothing special)
//   ball_ground_far the same moved 6.4e6 along x (x = 6400000.3 ...)
//   kinds_ground    ball_ground with one primitive of each other kind on its floor: a cylinder, a
//                   cone, a closed triangle mesh (an icosphere of 320 triangles) and a torus; its far
//                   and scaled copies test every kind's plan at once
//   planet          the balls on a planet of radius 6.4e6 (the floor is the planet), the camera a
//                   few units above its surface
//   mesh_spheres    a closed triangle mesh (an icosphere of 1,280 triangles), spheres and a floor
//                   polygon near the origin; mesh_spheres_1e3 .. mesh_spheres_1e7 the same moved
//                   that far from the origin
//   far_spheres     64 small spheres (radius 0.01..0.1) seen from 5,000 away through a narrow view
//   thin_torus      a torus whose tube is 100 times thinner than its ring, seen from 500 sizes away
//   far_cylinders   NFF cylinders and cone frusta seen from 1e4 of their radii
//   mixed_scales    a planet of radius 6.4e6 with a mesh, spheres and a cylinder on it, and a moon
//                   of radius 1.7e6 at 3.8e8
//   scanned         what a scanner writes: a closed bumpy mesh of 20,480 triangles, 0.2 across,
//                   its coordinates floats, with 3 % slivers (tiny triangles 1e-8..1e-6 across at
//                   its vertices) and 100 collapsed triangles (a repeated vertex, or three on a line)
//   scanned_double  the same mesh with its coordinates in double (a 17-digit export of it): the
//                   slivers are no longer what the input held once rounded to float
//   scattered       a world of 230 small closed meshes (80 triangles each, 1.2..2.4 across): 200
//                   within 800 of the origin, 30 in a cluster 3.7e4 away (where float's step is a
//                   500th of their triangles), the camera among those: no frame holds both groups
//                   in float
//   cluster_ground  ball_ground's balls and floor 3.7e4 above scattered's 200 near meshes, seen
//                   from 80 away: no frame holds both, and the floor lies where float's step is
//                   2^-8 (its balls must keep their shadows there)
//   pipes           what a CAD export makes of 8 pipes 20 long and 0.05..0.2 in radius: 256 facets
//                   around, each two triangles the pipe's length (10^4 times longer than wide),
//                   and end caps as fans (8,192 triangles)
#include "scene/sources.hpp"
#include "core/suggest.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>

namespace rb::scene {

void add_icosphere(Scene& s, const Vec3d& c, double r, int levels, std::uint32_t mat) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                          {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<std::uint32_t, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                                 {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto m = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]) * 0.5);
      return mid[key] = std::uint32_t(v.size() - 1);
    };
    std::vector<std::array<std::uint32_t, 3>> g;
    for (const auto& q : f) {
      const auto a = m(q[0], q[1]), b = m(q[1], q[2]), cc = m(q[2], q[0]);
      g.push_back({q[0], a, cc}), g.push_back({q[1], b, a}), g.push_back({q[2], cc, b}), g.push_back({a, b, cc});
    }
    f = g;
  }
  const auto base = std::uint32_t(s.verts.size());
  for (const auto& p : v) s.verts.push_back(c + p * (r / std::sqrt(dot(p, p))));
  for (const auto& q : f) s.triangles.push_back({{base + q[0], base + q[1], base + q[2]}, mat});
}

namespace {

constexpr double kPrecisionPlanetR = 6.4e6;

// Uniform doubles in [0, 1) from a seed (xorshift64): the same scene on every platform.
struct Uniform {
  std::uint64_t x;
  double operator()() {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    return double(x >> 11) * 0x1p-53;
  }
};

struct PrecisionBuilder {
  Scene s;
  explicit PrecisionBuilder(std::string name) {
    s.name = std::move(name);
    s.background = {0.078f, 0.361f, 0.753f};
    s.camera.angle = 40;
    s.camera.width = s.camera.height = 512;
    s.camera.up = {0, 1, 0};
  }
  std::uint32_t material(Vec3f color, float kd, float ks = 0, float shine = 0, float checker = 0, Vec3f color2 = {0, 0, 0}) {
    Material m;
    m.color = color, m.kd = kd, m.ks = ks, m.shine = shine, m.checker = checker, m.color2 = color2;
    s.materials.push_back(m);
    return std::uint32_t(s.materials.size() - 1);
  }
  void floor(const Vec3d& c, double half, std::uint32_t mat) {
    const auto first = std::uint32_t(s.poly_verts.size());
    s.poly_verts.insert(s.poly_verts.end(), {c + Vec3d{-half, 0, -half}, c + Vec3d{-half, 0, half}, c + Vec3d{half, 0, half},
                                             c + Vec3d{half, 0, -half}});
    s.polygons.push_back({first, 4, mat});
  }
  void sphere(const Vec3d& c, double r, std::uint32_t mat) { s.spheres.push_back({c, r, mat}); }
  void icosphere(const Vec3d& c, double r, int levels, std::uint32_t mat) { add_icosphere(s, c, r, levels, mat); }
  void view(const Vec3d& from, const Vec3d& at, double angle) {
    s.camera.from = from, s.camera.at = at, s.camera.angle = angle;
  }
};

// The balls: radius 2 resting on the ground at `g` (the ground's top point below the ball), and a
// radius-0.7 ball to the front right; a light up and to the side; a camera 4.1 above the ground.
void put_balls(PrecisionBuilder& b, const Vec3d& g) {
  const auto red = b.material({0.85f, 0.2f, 0.15f}, 0.7f, 0.3f, 40), white = b.material({0.9f, 0.9f, 0.85f}, 0.8f, 0.1f, 20);
  b.sphere(g + Vec3d{0.3, 2.0, -0.1}, 2.0, red);
  b.sphere(g + Vec3d{3.1, 0.7, 1.7}, 0.7, white);
  b.s.lights.push_back({g + Vec3d{17.3, 13.1, 6.7}, {1, 1, 1}});
  b.view(g + Vec3d{0.7, 4.1, 12.3}, g + Vec3d{0.9, 1.3, 0.1}, 40);
}

Scene ball_ground_scene(const Vec3d& at, const std::string& name) {
  PrecisionBuilder b(name);
  b.floor(at, 30.3, b.material({0.8f, 0.8f, 0.8f}, 0.8f, 0, 0, 1.0f, {0.35f, 0.35f, 0.4f}));
  put_balls(b, at);
  return std::move(b.s);
}

Scene kinds_ground_scene() {
  PrecisionBuilder b("precision:kinds_ground");
  const Vec3d at{0, 0.5, 0};
  b.floor(at, 30.3, b.material({0.8f, 0.8f, 0.8f}, 0.8f, 0, 0, 1.0f, {0.35f, 0.35f, 0.4f}));
  put_balls(b, at);
  const auto teal = b.material({0.2f, 0.65f, 0.6f}, 0.7f, 0.3f, 30), gold = b.material({0.9f, 0.7f, 0.2f}, 0.7f, 0.3f, 40);
  b.s.cones.push_back({at + Vec3d{-3.1, 0, -3.3}, 0.6, at + Vec3d{-3.1, 3.1, -3.3}, 0.6, teal});   // a cylinder standing
  b.s.cones.push_back({at + Vec3d{-1.9, 0, 2.3}, 0.7, at + Vec3d{-1.6, 1.7, 2.2}, 0.15, gold});    // a cone frustum, tilted
  b.icosphere(at + Vec3d{4.3, 1.1, -2.9}, 1.1, 2, teal);
  b.s.tori.push_back({at + Vec3d{-0.6, 0.45, 3.7}, {0.05, 1.0, 0.1}, 0.9, 0.3, gold});            // a ring lying on the floor
  return std::move(b.s);
}

Scene planet_scene() {
  PrecisionBuilder b("precision:planet");
  const Vec3d top{0.3, 0, -0.2};  // the ground under the balls: the planet's top point
  b.sphere(top - Vec3d{0, kPrecisionPlanetR, 0}, kPrecisionPlanetR, b.material({0.45f, 0.6f, 0.35f}, 0.8f));
  put_balls(b, top);
  return std::move(b.s);
}

Scene mesh_spheres_scene(double offset, const std::string& name) {
  PrecisionBuilder b(name);
  const Vec3d o{offset, offset * 0.37, -offset * 0.61};
  b.floor(o + Vec3d{0, -1.3, 0}, 12.3, b.material({0.8f, 0.8f, 0.8f}, 0.8f, 0, 0, 1.0f, {0.3f, 0.3f, 0.35f}));
  b.icosphere(o + Vec3d{0.1, 0.05, 0.2}, 1.3, 3, b.material({0.3f, 0.5f, 0.9f}, 0.7f, 0.3f, 30));
  const auto m = b.material({0.9f, 0.7f, 0.2f}, 0.7f, 0.3f, 40);
  b.sphere(o + Vec3d{2.7, -0.6, 0.9}, 0.7, m);
  b.sphere(o + Vec3d{-2.3, -0.9, 1.3}, 0.4, m);
  b.sphere(o + Vec3d{-1.1, -1.1, 2.6}, 0.2, m);
  b.sphere(o + Vec3d{1.3, -1.2, 2.9}, 0.1, m);
  b.s.lights.push_back({o + Vec3d{-9.7, 13.3, 7.1}, {1, 1, 1}});
  b.view(o + Vec3d{0.3, 2.1, 9.7}, o + Vec3d{0.1, -0.3, 0.3}, 45);
  return std::move(b.s);
}

Scene far_spheres_scene() {
  PrecisionBuilder b("precision:far_spheres");
  const auto m = b.material({0.9f, 0.5f, 0.2f}, 0.8f, 0.2f, 30);
  Uniform U{88172645463325252ull};
  for (int i = 0; i < 64; ++i) b.sphere({U() * 2 - 1, U() * 2 - 1, U() * 2 - 1}, 0.01 + 0.09 * U(), m);
  b.s.lights.push_back({{4003.1, 3001.7, 5002.3}, {1, 1, 1}});
  b.view({3001.7, 1700.3, 3900.1}, {0.013, -0.021, 0.007}, 0.04);
  return std::move(b.s);
}

Scene thin_torus_scene() {
  PrecisionBuilder b("precision:thin_torus");
  b.s.tori.push_back({{0.11, -0.07, 0.03}, {0.3, 1.0, 0.2}, 1.0, 0.01, b.material({0.9f, 0.8f, 0.3f}, 0.7f, 0.3f, 50)});
  b.s.tori.push_back({{0.13, -0.05, 0.01}, {1.0, 0.1, -0.3}, 0.61, 0.0061, b.material({0.3f, 0.8f, 0.9f}, 0.7f, 0.3f, 50)});
  b.s.lights.push_back({{300.3, 700.1, 400.7}, {1, 1, 1}});
  b.view({250.1, 150.3, 330.7}, {0.1, -0.06, 0.02}, 0.35);
  return std::move(b.s);
}

Scene far_cylinders_scene() {
  PrecisionBuilder b("precision:far_cylinders");
  const auto m = b.material({0.6f, 0.7f, 0.8f}, 0.8f, 0.2f, 20);
  for (int i = 0; i < 6; ++i) {
    const double a = 1.047 * i;
    const Vec3d base{3.1 * std::cos(a), -1.0, 3.1 * std::sin(a)};
    b.s.cones.push_back({base, 0.51, base + Vec3d{0.1, 2.3, 0.05}, i % 2 ? 0.51 : 0.23, m});
  }
  b.s.lights.push_back({{3100.3, 7000.1, 5000.7}, {1, 1, 1}});
  b.view({2900.1, 1700.3, 3800.7}, {0.1, 0.1, 0.02}, 0.18);
  return std::move(b.s);
}

Scene mixed_scales_scene() {
  PrecisionBuilder b("precision:mixed_scales");
  const Vec3d top{0.3, 0, -0.2};
  b.sphere(top - Vec3d{0, kPrecisionPlanetR, 0}, kPrecisionPlanetR, b.material({0.45f, 0.6f, 0.35f}, 0.8f));
  b.sphere(top + Vec3d{-1.7e8, 2.9e8, -2.1e8}, 1.7e6, b.material({0.8f, 0.8f, 0.75f}, 0.9f));  // a moon, 3.8e8 away
  b.icosphere(top + Vec3d{-2.1, 1.3, -0.7}, 1.3, 2, b.material({0.3f, 0.5f, 0.9f}, 0.7f, 0.3f, 30));
  const auto m = b.material({0.9f, 0.7f, 0.2f}, 0.7f, 0.3f, 40);
  b.sphere(top + Vec3d{1.7, 0.7, 0.9}, 0.7, m);
  b.sphere(top + Vec3d{0.4, 0.05, 2.1}, 0.05, m);
  b.s.cones.push_back({top + Vec3d{3.3, 0, -1.9}, 0.3, top + Vec3d{3.3, 2.7, -1.9}, 0.3, m});
  b.s.lights.push_back({top + Vec3d{17.3, 13.1, 6.7}, {1, 1, 1}});
  b.view(top + Vec3d{0.7, 3.1, 9.3}, top + Vec3d{0.2, 1.1, 0.1}, 50);
  return std::move(b.s);
}

Scene scanned_scene(bool as_floats, const std::string& name) {
  PrecisionBuilder b(name);
  const Vec3d c{0.0513, 0.0271, -0.0187};
  const auto m = b.material({0.8f, 0.75f, 0.65f}, 0.8f, 0.2f, 20);
  b.icosphere(c, 0.1, 5, m);
  // Bumps, as a scan has them: each vertex moved along its radius by a smooth pattern.
  for (Vec3d& v : b.s.verts) {
    const Vec3d d = v - c;
    v = c + d * (1.0 + 0.08 * std::sin(41.0 * d.x) * std::cos(37.0 * d.y) + 0.05 * std::sin(53.0 * d.z));
  }
  Uniform U{0x9E3779B97F4A7C15ull};
  const auto n = std::uint32_t(b.s.verts.size()), tris = std::uint32_t(b.s.triangles.size());
  // Slivers: 3 % of the mesh, tiny triangles at its vertices, 1e-8 to 1e-6 across.
  for (std::uint32_t k = 0; k < tris * 3 / 100; ++k) {
    const std::uint32_t a = std::uint32_t(U() * n) % n;
    const double e = std::pow(10.0, -8.0 + 2.0 * U());
    const Vec3d p = b.s.verts[a];
    b.s.verts.push_back(p + Vec3d{e, 0.3 * e, 0});
    b.s.verts.push_back(p + Vec3d{0.2 * e, e, 0.5 * e});
    const auto v0 = std::uint32_t(b.s.verts.size() - 2);
    b.s.triangles.push_back({{a, v0, v0 + 1}, m});
  }
  // Collapsed triangles: a repeated vertex, or three vertices on one line.
  for (std::uint32_t k = 0; k < 100; ++k) {
    const std::uint32_t a = std::uint32_t(U() * n) % n, c2 = std::uint32_t(U() * n) % n;
    if (k % 2) {
      b.s.triangles.push_back({{a, a, c2}, m});
    } else {
      b.s.verts.push_back((b.s.verts[a] + b.s.verts[c2]) * 0.5);
      b.s.triangles.push_back({{a, std::uint32_t(b.s.verts.size() - 1), c2}, m});
    }
  }
  if (as_floats)
    for (Vec3d& v : b.s.verts) v = to_double(to_float(v));
  b.s.lights.push_back({c + Vec3d{1.7, 2.3, 1.1}, {1, 1, 1}});
  b.view(c + Vec3d{0.13, 0.09, 0.31}, c, 40);
  return std::move(b.s);
}

Scene scattered_scene() {
  PrecisionBuilder b("precision:scattered");
  Uniform U{0x2545F4914F6CDD1Dull};
  const auto stone = b.material({0.7f, 0.68f, 0.62f}, 0.8f, 0.1f, 10), blue = b.material({0.3f, 0.45f, 0.8f}, 0.7f, 0.3f, 40);
  for (int i = 0; i < 200; ++i) {
    const double a = 2 * 3.141592653589793 * U(), r = 800 * std::sqrt(U());
    b.icosphere({r * std::cos(a), 5 * U(), r * std::sin(a)}, 0.6 + 0.6 * U(), 1, stone);
  }
  const Vec3d far{30000.37, 3.1, -21000.53};
  for (int i = 0; i < 30; ++i) b.icosphere(far + Vec3d{80 * U() - 40, 6 * U(), 80 * U() - 40}, 0.6 + 0.6 * U(), 1, blue);
  b.s.lights.push_back({far + Vec3d{30.3, 60.7, 45.1}, {1, 1, 1}});
  b.view(far + Vec3d{0.7, 12.3, 75.1}, far + Vec3d{0.1, 1.3, 0.3}, 50);
  return std::move(b.s);
}

// ball_ground's balls and floor 3.7e4 above a world of 200 small meshes near the origin (those of
// scattered): no frame holds both in float, and the balls' floor lies where float's step is 2^-8.
// The floor's checker cells line up with ball_ground's (even offsets, the floor mid-cell), so the
// two render alike wherever the tracer keeps the far scene's detail.
Scene cluster_ground_scene() {
  PrecisionBuilder b("precision:cluster_ground");
  Uniform U{0x2545F4914F6CDD1Dull};
  const auto stone = b.material({0.7f, 0.68f, 0.62f}, 0.8f, 0.1f, 10);
  for (int i = 0; i < 200; ++i) {
    const double a = 2 * 3.141592653589793 * U(), r = 800 * std::sqrt(U());
    b.icosphere({r * std::cos(a), 5 * U(), r * std::sin(a)}, 0.6 + 0.6 * U(), 1, stone);
  }
  const Vec3d at{20, 37000.5, -10};
  b.floor(at, 30.3, b.material({0.8f, 0.8f, 0.8f}, 0.8f, 0, 0, 1.0f, {0.35f, 0.35f, 0.4f}));
  put_balls(b, at);
  // Seen from 80 away: far enough that world coordinates hold the eye (its rounding shifts the view
  // by under a 16th of a pixel), near enough that a unit is 14 pixels.
  b.view(at + Vec3d{0.7, 60.1, 190.3}, at + Vec3d{0.9, 1.3, 0.1}, 25);
  return std::move(b.s);
}

Scene pipes_scene() {
  PrecisionBuilder b("precision:pipes");
  Uniform U{0x6A09E667F3BCC909ull};
  const auto steel = b.material({0.75f, 0.75f, 0.8f}, 0.6f, 0.4f, 60);
  constexpr int n = 256;
  for (int p = 0; p < 8; ++p) {
    // Axis from a to a + L d, radius r; (e1, e2) spans the plane across it.
    const Vec3d a{10 * U() - 5, 3 * U(), 10 * U() - 5};
    const double az = 6.283185307179586 * U(), el = 0.3 * (U() - 0.5);
    const Vec3d d{std::cos(az) * std::cos(el), std::sin(el), std::sin(az) * std::cos(el)};
    const Vec3d e1 = normalize(cross(d, std::fabs(d.y) < 0.9 ? Vec3d{0, 1, 0} : Vec3d{1, 0, 0})), e2 = cross(d, e1);
    const double r = 0.05 + 0.15 * U(), L = 20;
    const auto base = std::uint32_t(b.s.verts.size());
    for (int end = 0; end < 2; ++end) {
      for (int k = 0; k < n; ++k) {
        const double t = 6.283185307179586 * k / n;
        b.s.verts.push_back(a + d * (L * end) + e1 * (r * std::cos(t)) + e2 * (r * std::sin(t)));
      }
    }
    b.s.verts.push_back(a);
    b.s.verts.push_back(a + d * L);
    const std::uint32_t c0 = base + 2 * n, c1 = c0 + 1;
    for (std::uint32_t k = 0; k < std::uint32_t(n); ++k) {
      const std::uint32_t k1 = (k + 1) % n;
      b.s.triangles.push_back({{base + k, base + k1, base + n + k1}, steel});
      b.s.triangles.push_back({{base + k, base + n + k1, base + n + k}, steel});
      b.s.triangles.push_back({{c0, base + k1, base + k}, steel});
      b.s.triangles.push_back({{c1, base + n + k, base + n + k1}, steel});
    }
  }
  b.s.lights.push_back({{13.1, 17.3, 9.7}, {1, 1, 1}});
  b.view({3.7, 9.1, 24.3}, {0.3, 1.1, 0.2}, 45);
  return std::move(b.s);
}

}  // namespace

std::vector<std::string> precision_scene_names() {
  return {"ball_ground", "ball_ground_far", "kinds_ground", "planet", "mesh_spheres", "mesh_spheres_1e3", "mesh_spheres_1e5", "mesh_spheres_1e7",
          "far_spheres", "thin_torus", "far_cylinders", "mixed_scales", "scanned", "scanned_double", "scattered", "cluster_ground", "pipes"};
}

Scene precision_scene(const std::string& name) {
  // The floor at y = 0.5: mid-cell of the checkerboard (cell 1), so its own height never flips the
  // parity.
  if (name == "ball_ground") return ball_ground_scene({0, 0.5, 0}, "precision:ball_ground");
  if (name == "ball_ground_far") return ball_ground_scene({6400000.3, 0.5, 0}, "precision:ball_ground_far");
  if (name == "kinds_ground") return kinds_ground_scene();
  if (name == "planet") return planet_scene();
  if (name == "mesh_spheres") return mesh_spheres_scene(0, "precision:mesh_spheres");
  for (int e : {3, 5, 7})
    if (name == fmt::format("mesh_spheres_1e{}", e)) return mesh_spheres_scene(std::pow(10.0, e) * 1.0000003, "precision:" + name);
  if (name == "far_spheres") return far_spheres_scene();
  if (name == "thin_torus") return thin_torus_scene();
  if (name == "far_cylinders") return far_cylinders_scene();
  if (name == "mixed_scales") return mixed_scales_scene();
  if (name == "scanned") return scanned_scene(true, "precision:scanned");
  if (name == "scanned_double") return scanned_scene(false, "precision:scanned_double");
  if (name == "scattered") return scattered_scene();
  if (name == "cluster_ground") return cluster_ground_scene();
  if (name == "pipes") return pipes_scene();
  std::string all;
  for (const auto& n : precision_scene_names()) all += (all.empty() ? "" : ", ") + n;
  throw SceneError("precision:" + name + ": unknown scene (" + all + ")" + did_you_mean(name, precision_scene_names()));
}

}  // namespace rb::scene
