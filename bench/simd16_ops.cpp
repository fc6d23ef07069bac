// The kernel benchmarks' 16-lane loops in Counted<f16> numbers (bench/simd16.hpp): the 16-lane rows'
// operations per test. An AVX-512 translation unit under the rules of bench/simd16_loops.cpp (it
// defines only functions of its own: tools/check_simd16.py), in a library of its own (rb_simd16_ops)
// that only the benchmarks link.
#include "bench/simd16.hpp"
#include "bench/specs_all.hpp"

#ifndef RB_SIMD16
#error "bench/simd16_ops.cpp must be compiled for AVX-512 (F and DQ)"
#endif

namespace rb::bench {

template <class Spec>
void run_simd16_counted(const BenchData<Spec>& d, Variant v) {
  using cf16 = Counted<f16>;
  if constexpr (max_prim_lanes<Spec>() >= 16)
    if (v == Variant::prims_in_lanes16) {
      (void)run_prims_in_lanes<Spec, cf16>(d);
      return;
    }
  (void)run_rays_in_lanes<Spec, cf16>(d);
}

// Instantiates run_simd16_counted for every spec (bench/bench_simd16.cpp, compiled for AVX2, calls
// them): each address escapes to `sink`, so the compiler must emit every instantiation. Never called.
void simd16_counted_instantiate(void (*sink)(const void*)) {
  for_every_spec([&]<class Spec>() { sink(reinterpret_cast<const void*>(&run_simd16_counted<Spec>)); });
}

}  // namespace rb::bench
