// SIMD benchmarks of the planar family: rays in lanes and primitives in lanes.
#include "bench/register.hpp"
#include "bench/specs_planar.hpp"

namespace rb::bench {
void register_planar_simd() {
  for_each_spec_planar([]<class Spec>() {
    register_one<Spec, Variant::rays_in_lanes>();
    register_one<Spec, Variant::prims_in_lanes>();
  });
}
}  // namespace rb::bench
