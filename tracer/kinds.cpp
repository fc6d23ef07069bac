#include "tracer/kinds.hpp"

#include "core/spawn.hpp"

#include <cmath>
#include <limits>

namespace rb::kinds {

Bounds frame_box(const Bounds& b, const Vec3d& origin, float lo[3], float hi[3]) {
  const float inf = std::numeric_limits<float>::infinity();
  if (b.empty()) {
    for (int k = 0; k < 3; ++k) lo[k] = inf, hi[k] = -inf;
    return {};
  }
  const Vec3d l = b.lo - origin, h = b.hi - origin;
  for (int k = 0; k < 3; ++k) {
    // Rounded outward, then 2 float steps more: a primitive made from the same double values and
    // rounded to nearest float per coordinate (a sphere's centre) stays inside. (Rounding to
    // nearest is at most one step inward, so 3 steps from the nearest float cover both.)
    lo[k] = spawn::step_floats(float(l[k]), -3);
    hi[k] = spawn::step_floats(float(h[k]), 3);
  }
  Bounds f;
  f.grow(Vec3d{lo[0], lo[1], lo[2]});
  f.grow(Vec3d{hi[0], hi[1], hi[2]});
  return f;
}

const char* kind_name(Kind k) {
  const char* n = "?";
  AllKinds::each([&]<class K>() {
    if (K::id == k) n = K::name;
  });
  return n;
}

bool parse_kind(const std::string& name, Kind& k) {
  bool found = false;
  AllKinds::each([&]<class K>() {
    if (name == K::name) k = K::id, found = true;
  });
  return found;
}

std::array<std::size_t, kKinds> kind_counts(const Scene& s) {
  std::array<std::size_t, kKinds> c{};
  AllKinds::each([&]<class K>() { c[std::size_t(K::id)] = K::count(s); });
  return c;
}

}  // namespace rb::kinds
