// One instruction's throughput: eight independent chains of it in registers (no loads, no stores),
// so that its issue rate, not its latency, bounds the loop on a CPU that overlaps up to eight. Used
// in an AVX2 translation unit (bench/bench_instructions.cpp, 8 lanes) and an AVX-512 one
// (bench/simd16_instructions.cpp, 16 lanes); always inlined, so neither emits a copy the linker
// could share with the other.
#pragma once

namespace rb::bench {

// The instructions whose cost per lane differs between 8 and 16 lanes on some CPUs (division and
// square root on a divider of half the register's width) and the fused multiply-add, the cost of
// everything else in the model.
enum class Instr { fma, div, sqrt };
inline constexpr Instr kInstrs[] = {Instr::fma, Instr::div, Instr::sqrt};
inline const char* instr_name(Instr k) { return k == Instr::fma ? "fma" : k == Instr::div ? "div" : "sqrt"; }

// `steps` rounds of `op` on eight chains started at `seed`, with `b` its second operand; the sum of
// the chains (the caller keeps one lane of it, for DoNotOptimize). V: a register type with +.
template <class V, class Op>
[[gnu::always_inline]] inline V instruction_chains(long steps, V seed, V b, Op op) {
  V a0 = seed, a1 = seed + b, a2 = a1 + b, a3 = a2 + b, a4 = a3 + b, a5 = a4 + b, a6 = a5 + b, a7 = a6 + b;
  for (long k = 0; k < steps; ++k) {
    a0 = op(a0, b), a1 = op(a1, b), a2 = op(a2, b), a3 = op(a3, b);
    a4 = op(a4, b), a5 = op(a5, b), a6 = op(a6, b), a7 = op(a7, b);
  }
  return ((a0 + a1) + (a2 + a3)) + ((a4 + a5) + (a6 + a7));
}

}  // namespace rb::bench
