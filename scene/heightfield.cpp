// A generated mesh the size of a large scan: a wavy height field (scene/sources.hpp).
#include "scene/sources.hpp"

#include <fmt/format.h>

#include <cmath>

namespace rb::scene {

Scene height_field(int nx, int ny) {
  if (nx < 1 || ny < 1 || nx > kMaxHeightFieldSide || ny > kMaxHeightFieldSide)
    throw SceneError(fmt::format("heightfield:{}x{}: each side must be 1 .. {} quads", nx, ny, kMaxHeightFieldSide));
  Scene s;
  s.name = fmt::format("height field {}x{}", nx, ny);
  const auto ux = std::uint32_t(nx), uy = std::uint32_t(ny);
  s.verts.reserve(std::size_t(ux + 1) * std::size_t(uy + 1));
  for (std::uint32_t y = 0; y <= uy; ++y)
    for (std::uint32_t x = 0; x <= ux; ++x) {
      const double u = 2.0 * x / ux - 1, v = 2.0 * y / uy - 1;
      s.verts.push_back(Vec3d{u, 0.15 * std::sin(7 * u) * std::cos(5 * v) + 0.05 * std::sin(31 * u * v), v});
    }
  auto id = [&](std::uint32_t x, std::uint32_t y) { return y * (ux + 1) + x; };
  s.triangles.reserve(2 * std::size_t(ux) * std::size_t(uy));
  for (std::uint32_t y = 0; y < uy; ++y)
    for (std::uint32_t x = 0; x < ux; ++x) {
      s.triangles.push_back({{id(x, y), id(x + 1, y), id(x + 1, y + 1)}, 0});
      s.triangles.push_back({{id(x, y), id(x + 1, y + 1), id(x, y + 1)}, 0});
    }
  return s;
}

}  // namespace rb::scene
