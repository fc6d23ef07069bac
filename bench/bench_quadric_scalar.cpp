// True scalar benchmarks of the quadric family (compiled with auto-vectorisation off: bench/CMakeLists.txt).
#include "bench/register.hpp"
#include "bench/specs_quadric.hpp"

namespace rb::bench {
void register_quadric_scalar() {
  for_each_spec_quadric([]<class Spec>() { register_one<Spec, Variant::scalar>(); });
}
}  // namespace rb::bench
