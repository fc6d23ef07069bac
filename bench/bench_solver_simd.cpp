// SIMD benchmarks of the solver family: rays in lanes and primitives in lanes.
#include "bench/register.hpp"
#include "bench/specs_solver.hpp"

namespace rb::bench {
void register_solver_simd() {
  for_each_spec_solver([]<class Spec>() {
    register_one<Spec, Variant::rays_in_lanes>();
    register_one<Spec, Variant::prims_in_lanes>();
  });
}
}  // namespace rb::bench
