// The kernel benchmarks in 16 AVX-512 lanes, in the same binary as the 8-lane AVX2 ones.
//
// The timed loops run in translation units compiled for AVX-512 (bench/simd16_loops.cpp for the
// kernels, bench/simd16_node.cpp for the BVH's node test; target rb_simd16); everything else (data,
// registration, Google Benchmark) stays in the AVX2 code and calls them once per pass. Those
// translation units define nothing else that another one shares: an inline function compiled there with AVX-512 instructions could otherwise be the copy
// the linker keeps, and an AVX2-only CPU would fault on it (tools/check_simd16.py checks the
// object at every build). Which width runs is chosen at run time: isa_choice.
#pragma once

#include "bench/harness.hpp"
#include "bench/instruction_chains.hpp"

#include <cstddef>
#include <string>

namespace rb::bvh {
struct WNode;
}

namespace rb::bench {

// The Spec's loop with 16 lanes: rays in lanes (16 rays x 1 primitive) or primitives in lanes
// (1 ray x 16 primitives). Defined for every spec in rb_simd16 (built when the compiler can
// target AVX-512: RB_HAVE_SIMD16).
template <class Spec>
Acc run_simd16(const BenchData<Spec>& d, Variant v);
// The same loop in Counted<f16> numbers: its operations land in this thread's counters (ops::Scope).
template <class Spec>
void run_simd16_counted(const BenchData<Spec>& d, Variant v);
// A 16-lane row's operations per test, per lane: all of them, as the 8-lane rows count them (more
// than the 8-lane row's where an early exit waits for every lane), the instructions they take (an
// FMA is one) and the divisions and square roots among those. Counted once per spec, case and
// mapping (bench/bench_simd16.cpp, with the 16-lane rows).
struct OpMix {
  double ops = 0, instructions = 0, div = 0, sqrt = 0;
};
template <class Spec>
OpMix simd16_op_mix(Case c, Variant v);

// The BVH's 8-wide node test in 16 lanes (bvh/slab16.hpp; rb_simd16, bench/simd16_node.cpp): every
// ray against every node, the number of child boxes hit. simd16_node_test: one node test, its hit
// bits and the 8 entry distances (for the tests' comparison with bvh::slab8).
template <bool Robust>
unsigned simd16_node_pass(const bvh::WNode* nodes, std::size_t n_nodes, const Ray<float>* rays, std::size_t n_rays, float tmax);
unsigned simd16_node_test(const bvh::WNode& node, const Ray<float>& ray, float tmax, bool robust, float (&tn)[8]);

// One instruction's chains in 16 lanes (bench/instruction_chains.hpp; rb_simd16,
// bench/simd16_instructions.cpp): `steps` rounds of eight, the first lane of their sum.
float simd16_instruction_pass(Instr k, long steps, float seed);

// The ISA the kernel benchmarks run: "auto" (AVX-512 where the CPU and the build have it, else
// AVX2), "avx2" or "avx512". `simd16`: the 16-lane rows are registered; `name`: "avx2" or
// "avx512"; `why`: what decided it, for the results. Throws std::invalid_argument for an unknown
// name or for "avx512" on a CPU or build without it.
struct IsaChoice {
  bool simd16 = false;
  std::string name = "avx2";
  std::string why;
};
IsaChoice isa_choice(const std::string& asked);
bool simd16_built();  // this binary holds the 16-lane loops
bool simd16_cpu();    // this CPU runs them (AVX-512 F, CD, DQ, BW and VL, and the OS saves their registers)

}  // namespace rb::bench
