// PrimGroups<P>: a primitive batch stored in groups of kPadLanes slots, each group one contiguous
// block holding its fields one after another (the group's kPadLanes values of field 0, then of
// field 1, ...): an array of structures of arrays. Made for the BVH's leaves, which are groups:
// one kernel call over a leaf's 8 primitives reads kFields * 8 consecutive values instead of 8
// values from each of kFields arrays, so half the cache lines (a float triangle group: 5 lines
// in a row, against a half-used line from each of 9 arrays) and one memory page where the arrays
// were kFields pages apart. The kernels see the same P<F> as from PrimSoA (load and broadcast).
#pragma once

#include "soa/prims.hpp"

#include <stdexcept>

namespace rb {

template <template <class> class P, class S = float>
struct PrimGroups {
  static constexpr std::size_t kFields = PrimSoA<P, S>::kFields;
  static constexpr std::size_t kGroup = kFields * kPadLanes;  // values per group
  std::size_t count = 0;  // slots (a multiple of kPadLanes)

  std::size_t size() const { return count; }
  std::size_t bytes() const { return count * kFields * sizeof(S); }

  // `slots` slots (a multiple of kPadLanes), not initialised: each must be set before a kernel
  // reads it (the builder writes every slot once, in parallel, with no filling pass before).
  void allocate(std::size_t slots) {
    if (slots % kPadLanes) throw std::invalid_argument("PrimGroups: slots must fill whole groups");
    v_ = uninit_array<S, kSimdAlign>(slots * kFields);
    count = slots;
  }
  void set(std::size_t i, P<S> p) {
    auto t = p.fields();
    S* const v = v_.data();
    [&]<std::size_t... I>(std::index_sequence<I...>) { ((v[at(I, i)] = std::get<I>(t)), ...); }(std::make_index_sequence<kFields>{});
  }

  // Slot i's value of field f; a load from there reads the following slots of the same group.
  RB_INLINE const S* field(std::size_t f, std::size_t i) const { return v_.data() + at(f, i); }

  // Slots i, i + 1, ... in the lanes of F (they must lie in one group: i a multiple of F's lanes).
  template <class F>
  RB_INLINE P<F> load(std::size_t i) const {
    P<F> p;
    auto t = p.fields();
    [&]<std::size_t... I>(std::index_sequence<I...>) RB_INLINE_LAMBDA { ((std::get<I>(t) = rb::load<F>(field(I, i))), ...); }(std::make_index_sequence<kFields>{});
    return p;
  }
  // Slot i in every lane of F.
  template <class F>
  RB_INLINE P<F> broadcast(std::size_t i) const {
    P<F> p;
    auto t = p.fields();
    [&]<std::size_t... I>(std::index_sequence<I...>) RB_INLINE_LAMBDA { ((std::get<I>(t) = F(*field(I, i))), ...); }(std::make_index_sequence<kFields>{});
    return p;
  }

 private:
  uninit_array<S, kSimdAlign> v_;
  static constexpr std::size_t at(std::size_t f, std::size_t i) { return i / kPadLanes * kGroup + f * kPadLanes + i % kPadLanes; }
};

}  // namespace rb
