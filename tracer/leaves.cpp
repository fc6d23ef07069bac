// The leaf function tables: every kind's kernel in every method and precision it supports, each
// instantiated once here.
#include "tracer/leaves.hpp"

namespace rb::tracer {

namespace {

template <class K, int M, bool F64, bool S64>
LeafFns std_fns() {
  LeafFns f;
  f.single = [](const void* b, std::size_t base, const Ray<float>& r, RayCache& c, bvh::Closest& h) {
    return std_single<K, M, F64, S64>(*static_cast<const StdBatch<K>*>(b), base, r, c, h);
  };
  f.packet[0] = [](const void* b, std::size_t base, bvh::PacketRays& p, PacketCache& c) {
    std_packet<K, M, F64, S64, false>(*static_cast<const StdBatch<K>*>(b), base, p, c);
  };
  f.packet[1] = [](const void* b, std::size_t base, bvh::PacketRays& p, PacketCache& c) {
    std_packet<K, M, F64, S64, true>(*static_cast<const StdBatch<K>*>(b), base, p, c);
  };
  return f;
}

template <class K>
LeafFns custom_fns() {
  using B = typename K::Batch;
  LeafFns f;
  f.single = [](const void* b, std::size_t base, const Ray<float>& r, RayCache& c, bvh::Closest& h) {
    // A kind whose hits carry an aux datum (HitRec::aux) writes it into the ray's cache.
    if constexpr (requires(const B& x, bvh::Closest& y, float& a) { K::single(x, base, r, y, a); })
      return K::single(*static_cast<const B*>(b), base, r, h, c.aux);
    else
      return K::single(*static_cast<const B*>(b), base, r, h);
  };
  f.packet[0] = [](const void* b, std::size_t base, bvh::PacketRays& p, PacketCache&) { K::template packet<false>(*static_cast<const B*>(b), base, p); };
  f.packet[1] = [](const void* b, std::size_t base, bvh::PacketRays& p, PacketCache&) { K::template packet<true>(*static_cast<const B*>(b), base, p); };
  return f;
}

// Method M of kind K in the precision asked (only the precisions the method supports exist).
template <class K, int M>
LeafFns method_fns(bool f64, bool f64_storage) {
  constexpr MethodInfo info = K::methods[M];
  if constexpr (info.f64_storage)
    if (f64_storage) return std_fns<K, M, true, true>();
  if constexpr (info.f64)
    if (f64) return std_fns<K, M, true, false>();
  return std_fns<K, M, false, false>();
}

template <class K, int M = 0>
LeafFns find_method(int method, bool f64, bool f64_storage) {
  if constexpr (M + 1 < int(K::methods.size()))
    if (method != M) return find_method<K, M + 1>(method, f64, f64_storage);
  return method_fns<K, M>(f64, f64_storage);
}

template <class K>
LeafFns leaf_fns(int method, bool f64, bool f64_storage) {
  if constexpr (K::custom) return custom_fns<K>();
  else return find_method<K>(method, f64, f64_storage);
}

// The primitives of kind K stored apart (method M, which stores double): local frames or double.
template <class K, int M>
LeafFns apart_method_fns() {
  if constexpr (!K::methods[M].f64_storage) {
    return std_fns<K, M, false, false>();  // never chosen for primitives apart (the plan's stores64)
  } else {
    LeafFns f;
    f.single = [](const void* b, std::size_t base, const Ray<float>& r, RayCache&, bvh::Closest& h) {
      return apart_single<K, M>(*static_cast<const StdBatch<K>*>(b), base, r, h);
    };
    f.packet[0] = [](const void* b, std::size_t base, bvh::PacketRays& p, PacketCache&) {
      apart_packet<K, M, false>(*static_cast<const StdBatch<K>*>(b), base, p);
    };
    f.packet[1] = [](const void* b, std::size_t base, bvh::PacketRays& p, PacketCache&) {
      apart_packet<K, M, true>(*static_cast<const StdBatch<K>*>(b), base, p);
    };
    return f;
  }
}
template <class K, int M = 0>
LeafFns find_apart(int method) {
  if constexpr (M + 1 < int(K::methods.size()))
    if (method != M) return find_apart<K, M + 1>(method);
  return apart_method_fns<K, M>();
}

}  // namespace

std::array<LeafFns, kKinds> apart_table(const std::array<int, kKinds>& method) {
  std::array<LeafFns, kKinds> t{};
  AllKinds::each([&]<class K>() {
    if constexpr (K::custom) t[std::size_t(K::id)] = custom_fns<K>();  // (custom kinds have no primitives apart)
    else t[std::size_t(K::id)] = find_apart<K>(method[std::size_t(K::id)]);
  });
  return t;
}

std::array<LeafFns, kKinds> leaf_table(const std::array<LeafChoice, kKinds>& c) {
  std::array<LeafFns, kKinds> t{};
  AllKinds::each([&]<class K>() {
    const LeafChoice& k = c[std::size_t(K::id)];
    t[std::size_t(K::id)] = leaf_fns<K>(k.method, k.f64, k.f64_storage);
  });
  return t;
}

}  // namespace rb::tracer
