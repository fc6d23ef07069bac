// Whether the 16-lane walk (tracer/traverse_mesh16.cpp) is in this binary and runs on this CPU:
// compiled for AVX2, so that it runs on every CPU the binary runs on.
#include "tracer/simd16.hpp"

#include <stdexcept>

namespace rb::tracer {

bool simd16_traversal_built() {
#ifdef RB_HAVE_SIMD16
  return true;
#else
  return false;
#endif
}

bool simd16_cpu() {
  // libgcc sets the AVX-512 features only when the OS saves their registers (XGETBV).
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512dq") &&
         __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl");
}

bool simd16_traversal_runs() {
  static const bool runs = simd16_traversal_built() && simd16_cpu();
  return runs;
}

#ifndef RB_HAVE_SIMD16
void trace_packet_simd16(const bvh::Bvh8&, const MeshLeaves&, const RaySoA&, std::size_t, int, bool, bool, bvh::HitRec*) {
  throw std::logic_error("this build has no 16-lane traversal (compiled without AVX-512 support)");
}
#endif

}  // namespace rb::tracer
