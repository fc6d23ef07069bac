// AxisGrouped<P>: a PrimSoA<P> batch whose slots are grouped by a per-primitive axis (0, 1, 2) so
// that the axis is uniform over every aligned lane group: the lecture's triangle and
// parallelogram (dropped axis of the normal) and the polygon (projection axis) branch on it
// once per call, not per lane. Each group of one axis is padded to kPadLanes slots with
// P::never(); `axis` and `id` run parallel to the slots, `id` holding the input index of each slot
// (kPadId for padding) so hits map back to the input.
#pragma once

#include "soa/prims.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace rb {

template <template <class> class P>
struct AxisGrouped {
  static constexpr std::uint32_t kPadId = UINT32_MAX;
  PrimSoA<P> prims;
  std::vector<std::int8_t> axis;  // per slot (padding included)
  std::vector<std::uint32_t> id;  // input index per slot, kPadId for padding
  std::size_t real = 0;           // inputs

  // The input indices of each axis, in input order (axis_of(i) must be 0, 1 or 2).
  template <class AxisOf>
  static std::array<std::vector<std::size_t>, 3> by_axis(std::size_t n, AxisOf&& axis_of) {
    std::array<std::vector<std::size_t>, 3> out;
    for (std::size_t i = 0; i < n; ++i) out[std::size_t(axis_of(i))].push_back(i);
    return out;
  }

  // Appends the inputs idx[0], ..., idx[n - 1] (n <= kPadLanes) as one aligned lane group of
  // axis a; prim(i) gives input i's primitive. The group is padded to kPadLanes slots.
  template <class Prim>
  void push_group(int a, const std::size_t* idx, std::size_t n, Prim&& prim) {
    for (std::size_t k = 0; k < kPadLanes; ++k) {
      if (k < n) prims.push(prim(idx[k]));
      axis.push_back(std::int8_t(a));
      id.push_back(k < n ? std::uint32_t(idx[k]) : kPadId);
    }
    prims.seal();
  }

  // Input order within each axis.
  void assign(const std::vector<P<float>>& p, const std::vector<int>& axes) {
    if (p.size() != axes.size()) throw std::invalid_argument("AxisGrouped::assign: one axis per primitive");
    real = p.size();
    const auto groups = by_axis(p.size(), [&](std::size_t i) { return axes[i]; });
    for (int a = 0; a < 3; ++a) {
      const auto& idx = groups[std::size_t(a)];
      for (std::size_t g = 0; g < idx.size(); g += kPadLanes)
        push_group(a, idx.data() + g, std::min(kPadLanes, idx.size() - g), [&](std::size_t i) { return p[i]; });
    }
  }

  std::size_t size() const { return prims.size(); }
  int axis_of(std::size_t i) const { return axis[i]; }
  template <class F> RB_INLINE P<F> load(std::size_t i) const { return prims.template load<F>(i); }
  template <class F> RB_INLINE P<F> broadcast(std::size_t i) const { return prims.template broadcast<F>(i); }
};

}  // namespace rb
