// SPD "rings": objects of six pentagonal rings (30 cylinders + 30 spheres) joining the edge
// midpoints of a dodecahedron, stacked into a pyramid seen from its apex, with a wall behind
// for shadows; three lights.
// Spheres = cylinders = 5 * size * (size+1) * (2 size+1) (4,200 each at size 7) + 1 wall.
#include "scene/spd.hpp"

#include <cmath>
#include <fmt/format.h>

namespace rb::scene::spd {

namespace {

constexpr double kSpreadOut = 1.0;  // > 1 spreads successive layers apart

// The 30 ring vertices: one pentagon in the XY plane, and five copies tilted by the dihedral
// angle of the dodecahedron about X and turned about Z.
std::array<Vec3d, 30> dodec(double minor_radius) {
  std::array<Vec3d, 30> v{};
  const double scale = 1.0 / (1.0 + minor_radius);  // fits in a sphere of radius 1
  for (int k = 0; k < 5; ++k)
    v[std::size_t(k)] = {scale * std::cos(double(k) * 2.0 * kPi / 5.0), scale * std::sin(double(k) * 2.0 * kPi / 5.0), 0.0};
  const Mat4 xm = rotate_x(2.0 * std::acos(std::cos(kPi / 3.0) / std::sin(kPi / 5.0)));
  for (int p = 1; p < 6; ++p) {
    const Mat4 zm = rotate_z(kPi * (2.0 * double(p - 1) + 1.0) / 5.0);
    for (int k = 0; k < 5; ++k) v[std::size_t(5 * p + k)] = xform_point(xform_point(v[std::size_t(k)], xm), zm);
  }
  return v;
}

}  // namespace

Scene rings(int size) {
  const double sf = double(size);
  check_size("rings", size, 2.0 * 5.0 * sf * (sf + 1.0) * (2.0 * sf + 1.0) + 1.0);
  Builder b(fmt::format("rings({})", size));
  const double radius = 0.07412;  // cylinder and sphere radius
  const double spread = 1.0 / std::sin(kPi / 8.0);
  double y_diff, xz_diff;
  if (kSpreadOut <= spread)
    y_diff = spread / kSpreadOut, xz_diff = 1.0;
  else
    y_diff = 1.0, xz_diff = kSpreadOut / spread;

  b.background({0.078, 0.361, 0.753});
  const Vec3d from{-1.0, -spread, 0.5};
  b.view(from, {from.x, from.y + 1.0, from.z}, {0, 0, 1}, 45.0, 1.0, 512, 512);
  b.light({3.0, -spread, 3.0});
  b.light({-4.0, -spread, 1.0});
  b.light({2.0, -spread, -4.0});

  b.surface({1, 1, 1}, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);  // white wall, spans the 45 degree view + 1%
  const double wy = y_diff * (sf + 1.0);
  const double wx = 1.01 * (wy - from.y) * std::tan(kPi / 8.0), wz = wx;
  const Vec3d wall[4] = {{wx + from.x, wy, wz + from.z},
                         {-wx + from.x, wy, wz + from.z},
                         {-wx + from.x, wy, -wz + from.z},
                         {wx + from.x, wy, -wz + from.z}};
  b.polygon(wall);

  const Vec3d ring_color[6] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}, {1, 1, 0}};
  const auto d = dodec(radius);
  const std::size_t n = std::size_t(5.0 * sf * (sf + 1.0) * (2.0 * sf + 1.0));
  b.scene().spheres.reserve(n);
  b.scene().cones.reserve(n);
  for (int depth = 0; depth < size; ++depth) {
    Vec3d off{0, y_diff * double(depth + 1), 0};
    for (int oz = 0; oz <= depth; ++oz) {
      off.z = xz_diff * double(2 * oz - depth);
      for (int ox = 0; ox <= depth; ++ox) {
        off.x = xz_diff * double(2 * ox - depth);
        for (int e = 0; e < 30; ++e) {
          int prev;
          if (e % 5 == 0) {
            prev = e + 4;
            b.surface(ring_color[e / 5], 0.0, 0.5, 0.2, 0.3, 37.0, 0.0, 0.0);  // a new ring
          } else {
            prev = e - 1;
          }
          const Vec3d base = d[std::size_t(e)] + off, apex = d[std::size_t(prev)] + off;
          b.cone(base, radius, apex, radius);
          b.sphere(base, radius);
        }
      }
    }
  }
  return b.take();
}

}  // namespace rb::scene::spd
