// Per-instruction throughput at 8 and 16 float lanes (with the 16-lane rows only): the fused
// multiply-add, the division and the square root, eight independent chains in registers
// (bench/instruction_chains.hpp). Counter `instructions_per_s`: SIMD instructions per second, one
// thread. The report's 16-against-8-lane section prices each method's operations with them: on a
// CPU whose divider is half as wide as its registers, a 16-lane division costs two 8-lane ones, and
// a method's divisions and square roots gain nothing from the wider register.
// Named with three parts (instruction/KIND+LANES/reg) so the scalar-vs-SIMD tables leave them out.
#include "bench/instruction_chains.hpp"
#include "bench/register.hpp"
#include "bench/simd16.hpp"

#include <benchmark/benchmark.h>
#include <immintrin.h>

#include <string>

namespace rb::bench {

namespace {
constexpr long kSteps = 1024;  // per pass: 8 x 1024 instructions (about 26 us of 16-lane divisions)

float instruction_pass8(Instr k, long steps, float seed) {
  const __m256 s = _mm256_set1_ps(seed), b = _mm256_set1_ps(1.0f + 1e-7f * seed);
  __m256 r;
  switch (k) {
    case Instr::fma: r = instruction_chains(steps, s, b, [](__m256 a, __m256 c) { return _mm256_fmadd_ps(a, c, c); }); break;
    case Instr::div: r = instruction_chains(steps, s, b, [](__m256 a, __m256 c) { return _mm256_div_ps(a, c); }); break;
    default: r = instruction_chains(steps, s, b, [](__m256 a, __m256) { return _mm256_sqrt_ps(a); }); break;
  }
  return _mm256_cvtss_f32(r);
}

void instruction_rate(benchmark::State& st, Instr k, [[maybe_unused]] int lanes) {
  float seed = 1.5f;
  benchmark::DoNotOptimize(seed);  // not a constant the compiler could fold the chains from
  for (auto _ : st) {
    float r;
#ifdef RB_HAVE_SIMD16
    if (lanes == 16) r = simd16_instruction_pass(k, kSteps, seed);
    else
#endif
      r = instruction_pass8(k, kSteps, seed);
    benchmark::DoNotOptimize(r);
  }
  st.counters["instructions_per_s"] = benchmark::Counter(double(8 * kSteps), benchmark::Counter::kIsIterationInvariantRate);
}
}  // namespace

void register_instructions(bool simd16) {
  if (!simd16) return;  // the rates price the 16-lane rows against the 8-lane ones
  for (const Instr k : kInstrs)
    for (const int lanes : {8, 16}) {
      const std::string name = std::string("instruction/") + instr_name(k) + std::to_string(lanes) + "/reg";
      register_benchmark(name, [k, lanes](benchmark::State& st) { instruction_rate(st, k, lanes); });
    }
}

}  // namespace rb::bench
