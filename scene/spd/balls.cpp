// SPD "balls" (sphereflake): a sphere with nine spheres of a third of its radius around it, each of
// which blooms the same way, to `size` levels; a square floor polygon; three lights.
// Spheres = sum_{n=0..size} 9^n (10, 91, 820, 7381 at sizes 1..4).
#include "scene/spd.hpp"

#include <cmath>
#include <fmt/format.h>

namespace rb::scene::spd {

namespace {

// The nine child directions about +Z: three trios, each trio tilted towards -Z, the three
// copies 120 degrees apart about Z.
std::array<Vec3d, 9> child_directions() {
  const double d = 1.0 / std::sqrt(2.0);
  Vec3d trio[3] = {{d, d, 0.0}, {d, 0.0, -d}, {0.0, d, -d}};
  const Mat4 tilt = rotate_about(unit(Vec3d{1.0, -1.0, 0.0}), std::asin(2.0 / std::sqrt(6.0)));
  for (auto& v : trio) v = xform_vector(v, tilt);
  std::array<Vec3d, 9> set{};
  for (int s = 0; s < 3; ++s) {
    const Mat4 rz = rotate_z(double(s) * 2.0 * kPi / 3.0);
    for (int v = 0; v < 3; ++v) set[std::size_t(s * 3 + v)] = xform_vector(trio[v], rz);
  }
  return set;
}

struct Flake {
  Builder& out;
  std::array<Vec3d, 9> set;
  double ratio;  // child radius / parent radius

  // Output the sphere, then its children, depth first (the reference order).
  void grow(int depth, const Vec3d& c, double r, const Vec3d& dir) {
    out.sphere(c, r);
    if (depth <= 0) return;
    --depth;
    Mat4 mx;
    if (dir.z >= 0.9999)
      mx = Mat4::identity();
    else if (dir.z <= -0.9999)
      mx = rotate_y(kPi);
    else
      mx = rotate_about(unit(cross(Vec3d{0, 0, 1}, dir)), std::acos(dir.z));
    const double scale = r * (1.0 + ratio);
    for (const Vec3d& s : set) {
      const Vec3d v = xform_vector(s, mx);
      const Vec3d child{v.x * scale + c.x, v.y * scale + c.y, v.z * scale + c.z};
      const Vec3d child_dir{(child.x - c.x) / scale, (child.y - c.y) / scale, (child.z - c.z) / scale};
      grow(depth, child, r * ratio, child_dir);
    }
  }
};

}  // namespace

Scene balls(int size) {
  check_size("balls", size, (std::pow(9.0, size + 1) - 1.0) / 8.0 + 1.0);
  Builder b(fmt::format("balls({})", size));
  b.background({0.078, 0.361, 0.753});
  b.view({2.1, 1.3, 1.7}, {0, 0, 0}, {0, 0, 1}, 45.0, 0.01, 512, 512);
  b.light({4, 3, 2});
  b.light({1, -4, 4});
  b.light({-3, 1, 5});

  const double radius = 1.0;
  b.surface({1.0, 0.75, 0.33}, 0.2, 0.8, 0.0, 0.0, 0.0, 0.0, 1.0);  // beige floor
  const Vec3d fl{12.0 * radius, 12.0 * radius, -radius / 2.0};
  const Vec3d floor[4] = {{fl.x, fl.y, fl.z}, {-fl.x, fl.y, fl.z}, {-fl.x, -fl.y, fl.z}, {fl.x, -fl.y, fl.z}};
  b.polygon(floor);

  b.surface({1.0, 0.9, 0.7}, 0.0, 0.5, 0.5, 0.5, 37.0, 0.0, 1.0);  // mirrored spheres
  auto& s = b.scene();
  const double n = (std::pow(9.0, size + 1) - 1.0) / 8.0;
  s.spheres.reserve(std::size_t(n));
  Flake f{b, child_directions(), 1.0 / 3.0};
  f.grow(size, {0, 0, 0}, radius / 2.0, {0, 0, 1});
  return b.take();
}

}  // namespace rb::scene::spd
