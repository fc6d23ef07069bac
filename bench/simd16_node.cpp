// The BVH's 8-wide node test in 16 AVX-512 lanes (bvh/slab16.hpp): the kernel benchmark's timed
// pass and the tests' entry point. An AVX-512 translation unit under the rules of
// bench/simd16_loops.cpp: it defines only functions of its own (tools/check_simd16.py).
#include "bench/simd16.hpp"
#include "bvh/slab16.hpp"

namespace rb::bench {

template <bool Robust>
unsigned simd16_node_pass(const bvh::WNode* nodes, std::size_t n_nodes, const Ray<float>* rays, std::size_t n_rays, float tmax) {
  unsigned acc = 0;
  for (std::size_t i = 0; i < n_rays; ++i) {
    const bvh::SlabRay16 r = bvh::SlabRay16::make(rays[i]);
    for (std::size_t k = 0; k < n_nodes; ++k) {
      f8 tn;
      acc += unsigned(__builtin_popcount(bvh::slab16<Robust>(nodes[k], r, tmax, tn)));
    }
  }
  return acc;
}
template unsigned simd16_node_pass<false>(const bvh::WNode*, std::size_t, const Ray<float>*, std::size_t, float);
template unsigned simd16_node_pass<true>(const bvh::WNode*, std::size_t, const Ray<float>*, std::size_t, float);

unsigned simd16_node_test(const bvh::WNode& node, const Ray<float>& ray, float tmax, bool robust, float (&tn)[8]) {
  const bvh::SlabRay16 r = bvh::SlabRay16::make(ray);
  f8 t;
  const unsigned bits = robust ? bvh::slab16<true>(node, r, tmax, t) : bvh::slab16<false>(node, r, tmax, t);
  t.store_unaligned(tn);
  return bits;
}

}  // namespace rb::bench
