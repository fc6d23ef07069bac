// SPD "tetra": a recursive tetrahedral pyramid (Glassner's / Kay & Kajiya's test scene), one
// light. Triangles = 4^size (4,096 at size 6).
#include "scene/spd.hpp"

#include <cmath>
#include <fmt/format.h>
#include <utility>

namespace rb::scene::spd {

namespace {

// The tetrahedron inscribed in the cube of half-side r about c: the corners whose sign product
// is +1, in x-major order.
void tetra_rec(Builder& b, int depth, const Vec3d& c, double r) {
  if (depth <= 1) {
    Vec3d p[4];
    int n = 0;
    for (int x = -1; x <= 1; x += 2)
      for (int y = -1; y <= 1; y += 2)
        for (int z = -1; z <= 1; z += 2)
          if (x * y * z == 1) p[n++] = {c.x + double(x) * r, c.y + double(y) * r, c.z + double(z) * r};
    // faces 0 1 2, 3 2 1, 2 3 0, 1 0 3 (outward)
    for (int f = 0; f < 4; ++f) {
      int o[3] = {f % 4, (f + 1) % 4, (f + 2) % 4};
      if (f % 2 == 1) std::swap(o[0], o[2]);
      const Vec3d tri[3] = {p[o[0]], p[o[1]], p[o[2]]};
      b.polygon(tri);
    }
    return;
  }
  for (int x = -1; x <= 1; x += 2)
    for (int y = -1; y <= 1; y += 2)
      for (int z = -1; z <= 1; z += 2)
        if (x * y * z == 1)
          tetra_rec(b, depth - 1, {c.x + double(x) * r / 2.0, c.y + double(y) * r / 2.0, c.z + double(z) * r / 2.0},
                    r / 2.0);
}

}  // namespace

Scene tetra(int size) {
  check_size("tetra", size, std::pow(4.0, size));
  Builder b(fmt::format("tetra({})", size));
  b.background({0.078, 0.361, 0.753});
  b.view({1.022846, -3.177154, -2.174512}, {-0.004103, -0.004103, 0.216539}, {-0.816497, -0.816497, 0.816497}, 45.0,
         1.0, 512, 512);
  b.light({2.0, -18.0, -5.0});
  b.surface({1.0, 0.2, 0.2}, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);  // red
  const auto n = std::size_t(std::pow(4.0, size));
  b.scene().triangles.reserve(n);
  b.scene().verts.reserve(3 * n);
  tetra_rec(b, size, {0, 0, 0}, 1.0);
  return b.take();
}

}  // namespace rb::scene::spd
