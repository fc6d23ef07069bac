#include "render/batch_order.hpp"

#include <algorithm>

namespace rb::render {

void octant_order(const std::vector<Ray<float>>& rays, std::vector<std::uint32_t>& order, std::vector<std::size_t>& count,
                  const std::uint32_t* group, std::size_t groups) {
  count.assign(8 * groups + 1, 0);
  auto bucket = [&](std::size_t i) {
    const Ray<float>& r = rays[i];
    const std::size_t oct = std::size_t((r.d.x < 0) | (r.d.y < 0) << 1 | (r.d.z < 0) << 2);
    return oct * groups + (group ? group[i] : 0);
  };
  for (std::size_t i = 0; i < rays.size(); ++i) ++count[bucket(i) + 1];
  order.clear();
  if (std::count(count.begin() + 1, count.end(), rays.size()) == 1) return;
  for (std::size_t k = 1; k < count.size(); ++k) count[k] += count[k - 1];
  order.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) order[count[bucket(i)]++] = std::uint32_t(i);
}

void key_order(const std::vector<Ray<float>>& rays, const tracer::RayKey& key, std::vector<std::uint64_t>& keys,
               std::vector<std::uint32_t>& order) {
  constexpr int kIndexBits = 28;  // the index below the 36-bit key: every word differs
  order.clear();
  if (rays.size() >= (std::size_t(1) << kIndexBits)) {
    std::vector<std::size_t> count;
    return octant_order(rays, order, count);
  }
  keys.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) keys[i] = key(rays[i].o, rays[i].d) << kIndexBits | std::uint64_t(i);
  std::sort(keys.begin(), keys.end());
  order.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) order[i] = std::uint32_t(keys[i] & ((std::uint64_t(1) << kIndexBits) - 1));
}

}  // namespace rb::render
