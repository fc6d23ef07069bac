// SIMD benchmarks of the quadric family: rays in lanes and primitives in lanes.
#include "bench/register.hpp"
#include "bench/specs_quadric.hpp"

namespace rb::bench {
void register_quadric_simd() {
  for_each_spec_quadric([]<class Spec>() {
    register_one<Spec, Variant::rays_in_lanes>();
    register_one<Spec, Variant::prims_in_lanes>();
  });
}
}  // namespace rb::bench
