// The SIMD mappings of every bench spec: rays in lanes and primitives in lanes (8 x float).
#include "bench/register.hpp"
#include "bench/specs.hpp"

namespace rb::bench {
void register_basic_simd() {
  for_each_spec([]<class Spec>() {
    register_one<Spec, Variant::rays_in_lanes>();
    register_one<Spec, Variant::prims_in_lanes>();
  });
}
}  // namespace rb::bench
