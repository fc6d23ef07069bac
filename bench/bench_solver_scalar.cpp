// True scalar benchmarks of the solver family (compiled with auto-vectorisation off: bench/CMakeLists.txt).
#include "bench/register.hpp"
#include "bench/specs_solver.hpp"

namespace rb::bench {
void register_solver_scalar() {
  for_each_spec_solver([]<class Spec>() { register_one<Spec, Variant::scalar>(); });
}
}  // namespace rb::bench
