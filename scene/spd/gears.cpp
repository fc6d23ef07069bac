// SPD "gears": size^3 gears in a cubic grid above a reflective square; each gear is a 144-vertex
// concave top and bottom face plus 144 rectangular sides; every fifth gear is transparent.
// Polygons = 1 + size^3 * (2 + 4 * 36) (9,345 at size 4). Five lights.
#include "scene/spd.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <vector>

namespace rb::scene::spd {

namespace {

constexpr int kTeeth = 36;                 // a multiple of 4
constexpr double kOuterEdgeRatio = 0.995;  // slightly less than touching: no coincident surfaces
constexpr double kInnerEdgeRatio = 0.9;
constexpr double kEdgeDiff = 1.0 - kInnerEdgeRatio;
constexpr double kDepthRatio = 0.1;

// The four outline points of one tooth: two on the outer circle, two on the inner one.
void tooth(double gear_angle, double tooth_angle, const Vec3d& c, const Vec3d& outer, const Vec3d& inner,
           Vec3d* pts) {
  const auto at = [&](double a, const Vec3d& p) { return xform_vector(p, rotate_z(a)) + c; };
  pts[0] = at(gear_angle - 0.19 * tooth_angle, outer);
  pts[1] = at(gear_angle + 0.19 * tooth_angle, outer);
  pts[2] = at(gear_angle + 0.3 * tooth_angle, inner);
  pts[3] = at(gear_angle + 0.7 * tooth_angle, inner);
}

void gear(Builder& b, const Vec3d& c, double offset_angle, double outer_r, double inner_r, double thickness) {
  Vec3d outer{outer_r, 0, 0}, inner{inner_r, 0, 0};
  const double tooth_angle = 2.0 * kPi / double(kTeeth);
  std::vector<Vec3d> pts(4 * kTeeth);

  for (int k = 0; k < kTeeth; ++k)  // top face
    tooth(offset_angle + 2.0 * kPi * double(k) / double(kTeeth), tooth_angle, c, outer, inner, &pts[std::size_t(4 * k)]);
  b.polygon(pts);

  for (int i = 0; i < 4 * kTeeth; ++i) {  // sides
    const Vec3d& p = pts[std::size_t(i)];
    const Vec3d& q = pts[std::size_t((i + 1) % (4 * kTeeth))];
    const Vec3d side[4] = {p, {p.x, p.y, p.z - thickness}, {q.x, q.y, q.z - thickness}, q};
    b.polygon(side);
  }

  outer.z = inner.z = -thickness;  // bottom face, wound the other way
  for (int k = 0; k < kTeeth; ++k)
    tooth(offset_angle - 2.0 * kPi * double(k) / double(kTeeth), -tooth_angle, c, outer, inner,
          &pts[std::size_t(4 * k)]);
  b.polygon(pts);
}

double fraction(double a) { return a - double(int(a)); }

}  // namespace

Scene gears(int size) {
  check_size("gears", size, 1.0 + std::pow(double(size), 3) * (2.0 + 4.0 * kTeeth));
  Builder b(fmt::format("gears({})", size));
  b.background({0.078, 0.361, 0.753});
  b.view({-1.1, -2.1, 2.6}, {0, 0, 0}, {0, 0, 1}, 45.0, 1.0, 512, 512);
  b.light({2.0, 4.0, 4.0});
  b.light({-2.0, 4.0, 3.0});
  b.light({2.0, -2.5, 2.5});
  b.light({-1.0, -4.0, 2.0});
  b.light({-1.111, -2.121, 2.626});  // just behind the eye

  b.surface({1.0, 0.85, 0.7}, 0.0, 0.3, 0.6, 0.3, 37.0, 0.0, 0.0);  // off-white, reflective ground
  const Vec3d ground[4] = {{2.0, 2.0, 0.0}, {-2.0, 2.0, 0.0}, {-2.0, -2.0, 0.0}, {2.0, -2.0, 0.0}};
  b.polygon(ground);

  const double sf = double(size);
  const double outer_r = 1.0 / (sf - (sf - 1.0) * kEdgeDiff / 2.0);
  const Vec3d zero{-1.0 + outer_r, -1.0 + outer_r, 1.0};
  const Vec3d offset{outer_r * (2.0 - kEdgeDiff), outer_r * (2.0 - kEdgeDiff), -1.0 / sf};
  const std::size_t n3 = std::size_t(size) * std::size_t(size) * std::size_t(size);
  b.scene().polygons.reserve(1 + n3 * (2 + 4 * kTeeth));
  b.scene().poly_verts.reserve(4 + n3 * (2 * 4 * kTeeth + 4 * 4 * kTeeth));

  for (int iz = 0; iz < size; ++iz) {
    Vec3d c{0, 0, 0};
    c.z = zero.z + double(iz) * offset.z;
    for (int iy = 0; iy < size; ++iy) {
      c.y = zero.y + double(iy) * offset.y;
      for (int ix = 0; ix < size; ++ix) {
        c.x = zero.x + double(ix) * offset.x;
        // pseudo-random gear colour, brightest component scaled to 1
        Vec3d col{0.01 + fraction(double(ix * 3 + iy * 2 + iz + 1) * 5.0 / 7.0),
                  0.01 + fraction(double(iy * 3 + iz * 2 + ix + 1) * 3.0 / 7.0),
                  0.01 + fraction(double(iz * 3 + ix * 2 + iy + 1) * 2.0 / 7.0)};
        const double m = std::max(std::max(col.x, col.y), col.z);
        col = {col.x / m, col.y / m, col.z / m};
        if ((ix * 4 + iy * 2 + iz) % 5 == 0)
          b.surface(col, 0.0, 0.2, 0.0, 0.0, 0.0, 0.8, 1.1);  // transparent
        else
          b.surface(col, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        const double angle = kPi * double((ix + iy + iz) % 2) / double(kTeeth);
        const double thickness = std::min(kDepthRatio, 1.0 / (2.0 * sf));
        gear(b, c, angle, kOuterEdgeRatio * outer_r, (1.0 - kEdgeDiff) * outer_r, thickness);
      }
    }
  }
  return b.take();
}

}  // namespace rb::scene::spd
