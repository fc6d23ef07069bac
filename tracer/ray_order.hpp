// A stream of incoherent rays reordered into coherent groups before tracing, and the answers put
// back in the stream's order: the data-oriented answer to diffuse and random rays (ray sorting,
// as in Garanzha and Loop 2010 or the sorted batches of production renderers).
//
// Two keys, by how the sorted rays are traced (RayKey::Layout):
//  - one by one (origin_first): the Morton code of the ray's origin quantised to 2^7 cells per
//    axis of a box (the scene's: origins outside it are clamped), then the Morton code of its
//    direction quantised to 2^5 cells per axis. A ray one after another finds the nodes near its
//    origin in the cache where the previous rays left them; the direction's octant first would
//    split every region of origins into eight passes over the tree (on the 202k dragon's random
//    rays, one run each, that order traced 7 % slower than the unsorted stream and this one 13 %
//    faster: docs/DESIGN.md, "Sorted streams");
//  - in packets of 8 or 16 (octant_first): the direction octant (3 bits: the traversal takes
//    consecutive rays as one packet only when they share it), then the origin's Morton code,
//    2^8 cells per axis, then the direction's, 2^3 cells per axis.
// Keys are 36 bits, sorted with the ray's index in one 64-bit word by LSD radix in 3 passes of 12
// bits (stable: equal keys keep the stream's order, so the order is a function of the rays alone:
// reproducible). At most 2^28 rays.
#pragma once

#include "soa/rays.hpp"
#include "tracer/parallel.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace rb::tracer {

// The key a ray is sorted by (36 bits, above): a box's quantisation of origins, made once.
class RayKey {
 public:
  enum class Layout { octant_first, origin_first };
  // Origins quantised in [lo, hi] (frame coordinates; an empty or infinite extent puts every origin
  // in cell 0 along that axis).
  RayKey(const Vec3f& lo, const Vec3f& hi, Layout layout = Layout::octant_first);
  std::uint64_t operator()(const Vec3f& o, const Vec3f& d) const;
  // The key in words, for the outputs that name it.
  static std::string describe(Layout layout);
  // The key for rays traced in packets of `packet` (1: one by one).
  static Layout layout_for(int packet) { return packet >= 8 ? Layout::octant_first : Layout::origin_first; }

 private:
  Vec3f lo_, scale_;
  Layout layout_;
};

class RayOrder {
 public:
  // Sorts the real rays of `in` (in.count) into sorted() on `ts`'s threads; `lo`, `hi`: the box the
  // origins are quantised in (frame coordinates); `layout`: the key's (RayKey::layout_for).
  void sort(const RaySoA& in, const Vec3f& lo, const Vec3f& hi, ThreadScope& ts,
            RayKey::Layout layout = RayKey::Layout::octant_first);
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
