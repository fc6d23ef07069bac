#include "tracer/ray_order.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rb::tracer {

namespace {

// The bits of v (below 2^bits) spread to every third position.
std::uint64_t spread3(std::uint64_t v) {
  std::uint64_t r = 0;
  for (int b = 0; b < 21; ++b) r |= ((v >> b) & 1u) << (3 * b);
  return r;
}

// A lookup of spread3 for values below 2^9 (a key takes six of them).
struct Spread {
  std::array<std::uint32_t, 512> t{};
  Spread() {
    for (std::uint32_t v = 0; v < 512; ++v) t[v] = std::uint32_t(spread3(v));
  }
};
const Spread kSpread;

// The cell of x in [lo, lo + cells / scale), clamped (a coordinate far outside, or NaN, converts to
// no integer out of range).
std::uint32_t cell(float x, float lo, float scale, std::uint32_t cells) {
  const float c = (x - lo) * scale;
  if (!(c > 0.0f)) return 0;  // below, and NaN
  return c < float(cells) ? std::uint32_t(c) : cells - 1;
}

// A key and its ray's index in one 64-bit word: the key in the top 36 bits, the index (below 2^28,
// the most rays a run takes) in the rest, so the radix sort moves 8 bytes per ray.
constexpr int kIndexBits = 28, kDigitBits = 12, kPasses = 3, kBins = 1 << kDigitBits;  // 36 key bits

}  // namespace

// Keys (36 bits). octant_first: octant (3 bits) | origin Morton code, 8 bits per axis (24) |
// direction Morton code, 3 bits per axis (9). origin_first: origin Morton code, 7 bits per axis
// (21) | direction Morton code, 5 bits per axis (15). An origin's cell in [lo, hi] (clamped), a
// direction component's in [-1, 1].
namespace {
struct KeyBits {
  int origin, direction;  // per axis
};
constexpr KeyBits key_bits(RayKey::Layout layout) {
  return layout == RayKey::Layout::origin_first ? KeyBits{7, 5} : KeyBits{8, 3};
}
}  // namespace

RayKey::RayKey(const Vec3f& lo, const Vec3f& hi, Layout layout) : lo_(lo), layout_(layout) {
  const float cells = float(1u << key_bits(layout).origin);
  auto scale = [&](float a, float b) { return b > a && std::isfinite(b - a) ? cells / (b - a) : 0.0f; };
  scale_ = {scale(lo.x, hi.x), scale(lo.y, hi.y), scale(lo.z, hi.z)};
}

std::uint64_t RayKey::operator()(const Vec3f& o, const Vec3f& d) const {
  const KeyBits bits = key_bits(layout_);
  const std::uint32_t oc = 1u << bits.origin, dc = 1u << bits.direction;
  const float ds = float(dc) * 0.5f;
  const std::uint64_t om = kSpread.t[cell(o.x, lo_.x, scale_.x, oc)] | kSpread.t[cell(o.y, lo_.y, scale_.y, oc)] << 1 |
                           kSpread.t[cell(o.z, lo_.z, scale_.z, oc)] << 2;
  const std::uint64_t dm = kSpread.t[cell(d.x, -1.0f, ds, dc)] | kSpread.t[cell(d.y, -1.0f, ds, dc)] << 1 |
                           kSpread.t[cell(d.z, -1.0f, ds, dc)] << 2;
  const std::uint64_t key = om << (3 * bits.direction) | dm;
  if (layout_ == Layout::origin_first) return key;
  const std::uint64_t oct = std::uint64_t(d.x < 0) | std::uint64_t(d.y < 0) << 1 | std::uint64_t(d.z < 0) << 2;
  return oct << (3 * (bits.origin + bits.direction)) | key;
}

std::string RayKey::describe(Layout layout) {
  const KeyBits bits = key_bits(layout);
  const std::string codes = "the origin's Morton code (2^" + std::to_string(bits.origin) +
                            " cells per axis of the scene's box), then the direction's (2^" + std::to_string(bits.direction) +
                            " per axis)";
  return layout == Layout::origin_first ? codes : "direction octant, then " + codes;
}

void RayOrder::sort(const RaySoA& in, const Vec3f& lo, const Vec3f& hi, ThreadScope& ts, RayKey::Layout layout) {
  const std::size_t n = in.count;
  if (n >= (std::size_t(1) << kIndexBits)) throw std::length_error("RayOrder: more than 2^28 rays");
  keys_.resize(n);
  tmp_keys_.resize(n);
  order_.resize(n);
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  const RayKey key(lo, hi, layout);
  ts.parallel_for(chunks, 1, [&](std::size_t c) {
    for (std::size_t i = c * kChunk, e = std::min(n, i + kChunk); i < e; ++i)
      keys_[i] = key({in.ox[i], in.oy[i], in.oz[i]}, {in.dx[i], in.dy[i], in.dz[i]}) << kIndexBits | std::uint64_t(i);
  });
  // LSD radix sort of the key bits, stable: per pass, each block's histogram, the blocks' offsets in
  // block order (bin-major: every bin's total first, then each block's running offsets, all
  // sequential), then each block scatters its words in order.
  const std::size_t block = std::max<std::size_t>(kChunk, (n + 7) / 8), blocks = (n + block - 1) / block;
  std::vector<std::array<std::uint32_t, kBins>> hist(blocks);
  std::vector<std::uint32_t> next(kBins);
  for (int pass = 0; pass < kPasses; ++pass) {
    const int shift = kIndexBits + pass * kDigitBits;
    ts.parallel_for(blocks, 1, [&](std::size_t c) {
      auto& h = hist[c];
      h.fill(0);
      for (std::size_t i = c * block, e = std::min(n, i + block); i < e; ++i) ++h[(keys_[i] >> shift) & (kBins - 1)];
    });
    std::fill(next.begin(), next.end(), 0u);
    for (const auto& h : hist)
      for (int b = 0; b < kBins; ++b) next[std::size_t(b)] += h[std::size_t(b)];
    if (std::find(next.begin(), next.end(), std::uint32_t(n)) != next.end()) continue;  // one digit for every key: nothing moves
    std::uint32_t sum = 0;
    for (auto& x : next) {
      const std::uint32_t k = x;
      x = sum;
      sum += k;
    }
    for (auto& h : hist)
      for (int b = 0; b < kBins; ++b) {
        const std::uint32_t k = h[std::size_t(b)];
        h[std::size_t(b)] = next[std::size_t(b)];
        next[std::size_t(b)] += k;
      }
    ts.parallel_for(blocks, 1, [&](std::size_t c) {
      auto& h = hist[c];
      for (std::size_t i = c * block, e = std::min(n, i + block); i < e; ++i) tmp_keys_[h[(keys_[i] >> shift) & (kBins - 1)]++] = keys_[i];
    });
    keys_.swap(tmp_keys_);
  }
  // The rays in their new order, padded as RaySoA keeps them; the reads run ahead by a prefetch
  // distance (each ray's 11 fields are 11 scattered loads).
  const std::size_t padded = in.size();
  for (auto* a : {&sorted_.ox, &sorted_.oy, &sorted_.oz, &sorted_.dx, &sorted_.dy, &sorted_.dz, &sorted_.rx, &sorted_.ry, &sorted_.rz,
                  &sorted_.tmin, &sorted_.tmax})
    a->resize(padded);
  sorted_.count = n;
  constexpr std::uint64_t kIndexMask = (std::uint64_t(1) << kIndexBits) - 1;
  constexpr std::size_t kAhead = 8;
  const float* src[11] = {in.ox.data(), in.oy.data(), in.oz.data(), in.dx.data(), in.dy.data(), in.dz.data(),
                          in.rx.data(), in.ry.data(), in.rz.data(), in.tmin.data(), in.tmax.data()};
  float* dst[11] = {sorted_.ox.data(), sorted_.oy.data(), sorted_.oz.data(), sorted_.dx.data(), sorted_.dy.data(), sorted_.dz.data(),
                    sorted_.rx.data(), sorted_.ry.data(), sorted_.rz.data(), sorted_.tmin.data(), sorted_.tmax.data()};
  const std::size_t all = (padded + kChunk - 1) / kChunk;
  ts.parallel_for(all, 1, [&](std::size_t c) {
    for (std::size_t i = c * kChunk, e = std::min(padded, i + kChunk); i < e; ++i) {
      if (i + kAhead < n)
        for (const float* a : src) __builtin_prefetch(a + (keys_[i + kAhead] & kIndexMask));
      const std::size_t j = i < n ? std::size_t(keys_[i] & kIndexMask) : i;  // the padding stays where it is
      if (i < n) order_[i] = std::uint32_t(j);
      for (int k = 0; k < 11; ++k) dst[k][i] = src[k][j];
    }
  });
}

}  // namespace rb::tracer
