// The 16-lane rows of the kernel benchmarks (16 rays x 1 primitive, 1 ray x 16 primitives), compiled
// for AVX2 like the rest: the 16-lane loops themselves are in bench/simd16_loops.cpp.
#include "bench/register.hpp"
#include "bench/specs_all.hpp"

namespace rb::bench {

#ifdef RB_HAVE_SIMD16
void register_simd16() {
  for_every_spec([]<class Spec>() {
    register_one<Spec, Variant::rays_in_lanes16>();
    if constexpr (max_prim_lanes<Spec>() >= 16) register_one<Spec, Variant::prims_in_lanes16>();
  });
}
#else
void register_simd16() {}
#endif

}  // namespace rb::bench
