// The true scalar baseline. This file is compiled with -fno-tree-vectorize and
// -fno-tree-slp-vectorize (bench/CMakeLists.txt): GCC -O3 otherwise vectorises a "scalar" SoA
// loop to within 10% of explicit SIMD (docs/DESIGN.md section 6). The kernels are always_inline, so
// their code is generated here, with these flags.
#include "bench/register.hpp"
#include "bench/specs.hpp"

namespace rb::bench {
void register_basic_scalar() {
  for_each_spec([]<class Spec>() { register_one<Spec, Variant::scalar>(); });
}
}  // namespace rb::bench
