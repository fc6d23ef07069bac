// PrimSoA<P>: one structure-of-arrays batch for a primitive kind P.
//
// A primitive kind is a struct template P<F> whose members are numbers of type F (directly or in
// Vec3<F>) and which lists them once, in `auto fields()` returning std::tie(...). The batch then
// holds exactly those fields, one aligned float array each, padded to 8 lanes with a filler that
// never hits. The same kernel text runs on both SIMD mappings:
//   rays in lanes:       kernel(rays.packet<F>(i), prims.broadcast<F>(j))
//   primitives in lanes: kernel(rays.broadcast<F>(i), prims.load<F>(j))
#pragma once

#include "soa/aligned.hpp"

#include <array>
#include <tuple>

namespace rb {

// S is the storage type: float (every kernel batch), or double where a scene's coordinates need it
// (tracer/plan.hpp: a planet's centre relative to a camera on its surface); a double batch loads
// into the 4-lane double number type.
template <template <class> class P, class S = float>
struct PrimSoA {
  static constexpr std::size_t kFields = std::tuple_size_v<decltype(std::declval<P<S>&>().fields())>;
  std::array<avec<S>, kFields> f;
  std::size_t count = 0;

  std::size_t size() const { return f[0].size(); }  // padded

  // `filler` is a primitive that no ray hits (each kind provides P<S>::never()).
  void push(const P<S>& p) {
    for (auto& a : f) a.resize(count);
    put(p);
    ++count;
    const P<S> pad = P<S>::never();
    while (f[0].size() % kPadLanes) put(pad);
  }
  // Makes the current padding permanent (the next push starts a new aligned lane group);
  // `count` then includes the filler slots.
  void seal() { count = size(); }
  void reserve(std::size_t n) {
    for (auto& a : f) a.reserve(round_up(n, kPadLanes));
  }
  std::size_t bytes() const { return kFields * size() * sizeof(S); }

  P<S> get(std::size_t i) const { return load<S>(i); }
  template <class F>
  RB_INLINE P<F> load(std::size_t i) const {
    P<F> p;
    load_fields<F>(p.fields(), i, std::make_index_sequence<kFields>{});
    return p;
  }
  template <class F>
  RB_INLINE P<F> broadcast(std::size_t i) const {
    P<F> p;
    broadcast_fields<F>(p.fields(), i, std::make_index_sequence<kFields>{});
    return p;
  }

 private:
  void put(P<S> p) {
    auto t = p.fields();
    put_fields(t, std::make_index_sequence<kFields>{});
  }
  template <class Tup, std::size_t... I>
  void put_fields(Tup& t, std::index_sequence<I...>) { (f[I].push_back(std::get<I>(t)), ...); }
  template <class F, class Tup, std::size_t... I>
  RB_INLINE void load_fields(Tup t, std::size_t i, std::index_sequence<I...>) const {
    ((std::get<I>(t) = rb::load<F>(&f[I][i])), ...);
  }
  template <class F, class Tup, std::size_t... I>
  RB_INLINE void broadcast_fields(Tup t, std::size_t i, std::index_sequence<I...>) const {
    ((std::get<I>(t) = F(f[I][i])), ...);
  }
};

namespace detail {
// Field-by-field conversion between two instantiations of one primitive kind.
template <class F, class Src, class Dst>
RB_INLINE void cast_fields(Src& p, Dst& q) {
  auto src = p.fields();
  auto dst = q.fields();
  [&]<std::size_t... I>(std::index_sequence<I...>) RB_INLINE_LAMBDA {
    ((std::get<I>(dst) = F(std::get<I>(src))), ...);
  }(std::make_index_sequence<std::tuple_size_v<decltype(src)>>{});
}
}  // namespace detail

// One primitive in every lane of another number type (broadcast of each field).
template <class F, template <class> class P>
RB_INLINE P<F> prim_cast(P<float> p) {
  P<F> q;
  detail::cast_fields<F>(p, q);
  return q;
}

// The same for kinds with a compile-time size (ParallelPlanesK<F, K>, HalfspacesK<F, K>, ...).
template <class F, template <class, int> class P, int K>
RB_INLINE P<F, K> prim_cast(P<float, K> p) {
  P<F, K> q;
  detail::cast_fields<F>(p, q);
  return q;
}

}  // namespace rb
