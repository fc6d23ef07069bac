#include "render/batch_order.hpp"

#include <algorithm>

namespace rb::render {

namespace {
// A ray's bucket: its direction octant, then its group.
std::size_t bucket_of(const Ray<float>& r, std::size_t groups, std::uint32_t group) {
  return std::size_t((r.d.x < 0) | (r.d.y < 0) << 1 | (r.d.z < 0) << 2) * groups + group;
}
// Ray i of the batch.
RB_INLINE void set(RaySoA& soa, std::size_t i, const Ray<float>& r) {
  soa.ox[i] = r.o.x, soa.oy[i] = r.o.y, soa.oz[i] = r.o.z;
  soa.dx[i] = r.d.x, soa.dy[i] = r.d.y, soa.dz[i] = r.d.z;
  soa.rx[i] = r.rd.x, soa.ry[i] = r.rd.y, soa.rz[i] = r.rd.z;
  soa.tmin[i] = r.tmin, soa.tmax[i] = r.tmax;
}
}  // namespace

void resize_batch(RaySoA& soa, std::size_t n) {
  const std::size_t padded = round_up(std::max<std::size_t>(n, 1), kPadLanes);
  for (auto* a : {&soa.ox, &soa.oy, &soa.oz, &soa.dx, &soa.dy, &soa.dz, &soa.rx, &soa.ry, &soa.rz, &soa.tmin, &soa.tmax})
    a->resize(padded);
  soa.count = n;
}

void pad_batch(RaySoA& soa) {
  const Ray<float> invalid = make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 0});
  for (std::size_t i = soa.count; i < soa.size(); ++i) set(soa, i, invalid);
}

void fill(RaySoA& soa, const std::vector<Ray<float>>& rays, const std::uint32_t* order) {
  resize_batch(soa, rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) set(soa, i, rays[order ? order[i] : i]);
  pad_batch(soa);
}

namespace {
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

void octant_pack(const std::vector<Ray<float>>& rays, RaySoA& soa, std::vector<std::uint32_t>& order,
                 std::vector<std::uint32_t>& bucket, std::vector<std::size_t>& start, const std::uint32_t* group,
                 std::size_t groups) {
  order.clear();
  if (!octant_buckets(rays, group, groups, bucket, start)) return fill(soa, rays);
  resize_batch(soa, rays.size());
  order.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const std::size_t slot = start[bucket[i]]++;
    order[slot] = std::uint32_t(i);
    set(soa, slot, rays[i]);
  }
  pad_batch(soa);
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
