// A stream of incoherent rays reordered into coherent groups before tracing, and the answers put
// back in the stream's order: the data-oriented answer to diffuse and random rays (ray sorting,
// as in Garanzha and Loop 2010 or the sorted batches of production renderers).
//
// Each ray's key is its direction octant (3 bits: the traversal takes 8 consecutive rays as one
// packet only when they share it), then the Morton code of its origin quantised to 2^8 cells per
// axis of a box (the scene's: origins outside it are clamped), then the Morton code of its
// direction quantised to 2^3 cells per axis. Rays close in the order thus start close and point
// alike. Keys are 36 bits, sorted with the ray's index in one 64-bit word by LSD radix in 3 passes
// of 12 bits (stable: equal keys keep the stream's order, so the order is a function of the rays
// alone: reproducible). At most 2^28 rays.
#pragma once

#include "soa/rays.hpp"
#include "tracer/parallel.hpp"

#include <cstdint>
#include <vector>

namespace rb::tracer {

// The key a ray is sorted by (36 bits, above): a box's quantisation of origins, made once.
class RayKey {
 public:
  // Origins quantised in [lo, hi] (frame coordinates; an empty or infinite extent puts every origin
  // in cell 0 along that axis).
  RayKey(const Vec3f& lo, const Vec3f& hi);
  std::uint64_t operator()(const Vec3f& o, const Vec3f& d) const;

 private:
  Vec3f lo_, scale_;
};

class RayOrder {
 public:
  // Sorts the real rays of `in` (in.count) into sorted() on `ts`'s threads; `lo`, `hi`: the box the
  // origins are quantised in (frame coordinates).
  void sort(const RaySoA& in, const Vec3f& lo, const Vec3f& hi, ThreadScope& ts);
  const RaySoA& sorted() const { return sorted_; }
  // Slot i of sorted() holds ray order()[i] of the stream.
  const std::vector<std::uint32_t>& order() const { return order_; }
  // The hits of sorted() back in the stream's order: out[order[i]] = sorted_hits[i].
  template <class Hit>
  void unsort(const Hit* sorted_hits, Hit* out, ThreadScope& ts) const {
    const std::size_t n = order_.size();
    ts.parallel_for((n + kChunk - 1) / kChunk, 1, [&](std::size_t c) {
      for (std::size_t i = c * kChunk, e = std::min(n, i + kChunk); i < e; ++i) out[order_[i]] = sorted_hits[i];
    });
  }
  static constexpr std::size_t kChunk = 4096;

 private:
  RaySoA sorted_;
  std::vector<std::uint32_t> order_;
  std::vector<std::uint64_t> keys_, tmp_keys_;  // key << 28 | index
};

}  // namespace rb::tracer
