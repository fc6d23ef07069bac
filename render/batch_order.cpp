#include "render/batch_order.hpp"

#include <algorithm>

namespace rb::render {

namespace {
// A ray's bucket: its direction octant, then its group.
std::size_t bucket_of(const Ray<float>& r, std::size_t groups, std::uint32_t group) {
  return std::size_t((r.d.x < 0) | (r.d.y < 0) << 1 | (r.d.z < 0) << 2) * groups + group;
}
// Each ray's bucket (direction octant, then group) and where each bucket begins in the octant order:
// false when every ray is in one bucket (then no order is needed). The counts are four histograms
// taken in turn: a ray does not wait on the previous ray's increment of the same count.
bool octant_buckets(const std::vector<Ray<float>>& rays, const std::uint32_t* group, std::size_t groups,
                    std::vector<std::uint32_t>& bucket, std::vector<std::size_t>& start) {
  const std::size_t n = rays.size(), nb = 8 * groups;
  bucket.resize(n);
  start.assign(4 * nb, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t b = bucket_of(rays[i], groups, group ? group[i] : 0);
    bucket[i] = std::uint32_t(b);
    ++start[(i & 3) * nb + b];
  }
  bool one = false;
  for (std::size_t b = 0, at = 0; b < nb; ++b) {
    const std::size_t c = start[b] + start[nb + b] + start[2 * nb + b] + start[3 * nb + b];
    one = one || c == n;
    start[b] = at;
    at += c;
  }
  return !one;
}
}  // namespace

void fill(RaySoA& soa, const std::vector<Ray<float>>& rays, const std::uint32_t* order) {
  soa.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) soa.set(i, rays[order ? order[i] : i]);
}

void octant_pack(const std::vector<Ray<float>>& rays, RaySoA& soa, std::vector<std::uint32_t>& order,
                 std::vector<std::uint32_t>& bucket, std::vector<std::size_t>& start, const std::uint32_t* group,
                 std::size_t groups) {
  order.clear();
  if (!octant_buckets(rays, group, groups, bucket, start)) return fill(soa, rays);
  soa.resize(rays.size());
  order.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const std::size_t slot = start[bucket[i]]++;
    order[slot] = std::uint32_t(i);
    soa.set(slot, rays[i]);
  }
}

void key_order(const std::vector<Ray<float>>& rays, const tracer::RayKey& key, std::vector<std::uint64_t>& keys,
               std::vector<std::uint32_t>& order) {
  constexpr int kIndexBits = 28;  // the index below the 36-bit key: every word differs
  order.clear();
  if (rays.size() >= (std::size_t(1) << kIndexBits)) {  // too many for the key's index: octants only
    std::vector<std::uint32_t> bucket;
    std::vector<std::size_t> start;
    if (!octant_buckets(rays, nullptr, 1, bucket, start)) return;
    order.resize(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) order[start[bucket[i]]++] = std::uint32_t(i);
    return;
  }
  keys.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) keys[i] = key(rays[i].o, rays[i].d) << kIndexBits | std::uint64_t(i);
  std::sort(keys.begin(), keys.end());
  order.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) order[i] = std::uint32_t(keys[i] & ((std::uint64_t(1) << kIndexBits) - 1));
}

}  // namespace rb::render
