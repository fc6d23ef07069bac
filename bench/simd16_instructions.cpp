// One instruction's throughput in 16 AVX-512 lanes (bench/instruction_chains.hpp; registered by
// bench/bench_instructions.cpp). An AVX-512 translation unit under the rules of
// bench/simd16_loops.cpp: it defines only functions of its own (tools/check_simd16.py).
#include "bench/instruction_chains.hpp"
#include "bench/simd16.hpp"

#include <immintrin.h>

#ifndef RB_SIMD16
#error "bench/simd16_instructions.cpp must be compiled for AVX-512 (F and DQ)"
#endif

namespace rb::bench {

float simd16_instruction_pass(Instr k, long steps, float seed) {
  const __m512 s = _mm512_set1_ps(seed), b = _mm512_set1_ps(1.0f + 1e-7f * seed);
  __m512 r;
  switch (k) {
    case Instr::fma: r = instruction_chains(steps, s, b, [](__m512 a, __m512 c) { return _mm512_fmadd_ps(a, c, c); }); break;
    case Instr::div: r = instruction_chains(steps, s, b, [](__m512 a, __m512 c) { return _mm512_div_ps(a, c); }); break;
    default: r = instruction_chains(steps, s, b, [](__m512 a, __m512) { return _mm512_sqrt_ps(a); }); break;
  }
  return _mm512_cvtss_f32(r);
}

}  // namespace rb::bench
