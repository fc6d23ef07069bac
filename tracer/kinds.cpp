#include "tracer/kinds.hpp"

#include "core/spawn.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace rb::kinds {

namespace {
// `n` floats up (n > 0) or down (n < 0) from a finite v, through the ordered integer key of the bit
// pattern (-x has key -key(x); +0 and -0 share key 0), so one step from 0 is the smallest subnormal
// and steps past the largest float stop at infinity. Branch-free: the sign of a coordinate near the
// origin is as good as random, and the three steps per side this replaces cost a mispredicted
// branch each. Infinities and NaN stay as they are.
inline float step_floats(float v, int n) {
  if (!(std::fabs(v) <= std::numeric_limits<float>::max())) return v;
  constexpr std::int32_t kInfKey = 0x7F800000;
  const std::int32_t b = std::bit_cast<std::int32_t>(v);
  std::int32_t key = b >= 0 ? b : std::numeric_limits<std::int32_t>::min() - b;
  key = std::clamp(key + n, -kInfKey, kInfKey);
  return std::bit_cast<float>(key >= 0 ? key : std::numeric_limits<std::int32_t>::min() - key);
}
}  // namespace

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
    lo[k] = step_floats(float(l[k]), -3);
    hi[k] = step_floats(float(h[k]), 3);
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
