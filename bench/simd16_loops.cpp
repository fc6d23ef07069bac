// The kernel benchmarks' timed loops in 16 AVX-512 lanes (bench/simd16.hpp). Compiled with AVX-512
// flags (bench/CMakeLists.txt, target rb_simd16): it defines run_simd16 for every spec and nothing
// that another translation unit also defines (tools/check_simd16.py).
#include "bench/simd16.hpp"
#include "bench/specs_all.hpp"

#ifndef RB_SIMD16
#error "bench/simd16_loops.cpp must be compiled for AVX-512 (F and DQ)"
#endif

namespace rb::bench {

template <class Spec>
Acc run_simd16(const BenchData<Spec>& d, Variant v) {
  if constexpr (max_prim_lanes<Spec>() >= 16)
    if (v == Variant::prims_in_lanes16) return run_prims_in_lanes<Spec, f16>(d);
  return run_rays_in_lanes<Spec, f16>(d);
}

// Instantiates run_simd16 for every spec (the registration, compiled for AVX2, calls them): each
// address escapes to `sink`, so the compiler must emit every instantiation. Never called.
void simd16_instantiate(void (*sink)(const void*)) {
  for_every_spec([&]<class Spec>() { sink(reinterpret_cast<const void*>(&run_simd16<Spec>)); });
}

}  // namespace rb::bench
