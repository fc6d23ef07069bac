// True scalar benchmarks of the planar family (compiled with auto-vectorisation off: bench/CMakeLists.txt).
#include "bench/register.hpp"
#include "bench/specs_planar.hpp"

namespace rb::bench {
void register_planar_scalar() {
  for_each_spec_planar([]<class Spec>() { register_one<Spec, Variant::scalar>(); });
}
}  // namespace rb::bench
