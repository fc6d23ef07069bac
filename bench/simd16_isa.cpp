// Which SIMD width the kernel benchmarks run (bench/simd16.hpp): compiled for AVX2, so that it runs
// on every CPU the binary runs on.
#include "bench/simd16.hpp"
#include "tracer/simd16.hpp"

#include <stdexcept>

namespace rb::bench {

bool simd16_built() {
#ifdef RB_HAVE_SIMD16
  return true;
#else
  return false;
#endif
}

bool simd16_cpu() { return tracer::simd16_cpu(); }  // the tracer's 16-lane walk asks the same

IsaChoice isa_choice(const std::string& asked) {
  IsaChoice c;
  const bool built = simd16_built(), cpu = simd16_cpu();
  const std::string missing = !built ? "this build has no AVX-512 code (compiled without AVX-512 support: the debug preset, or a "
                                       "compiler that cannot target it)"
                                     : "this CPU lacks AVX-512 F, CD, DQ, BW or VL";
  if (asked == "avx2") {
    c.why = "asked for (--isa avx2)";
  } else if (asked == "avx512") {
    if (!built || !cpu) throw std::invalid_argument("--isa avx512: " + missing);
    c.simd16 = true;
    c.why = "asked for (--isa avx512)";
  } else if (asked == "auto") {
    c.simd16 = built && cpu;
    c.why = c.simd16 ? "auto: the CPU and the build have AVX-512" : "auto: " + missing;
  } else {
    throw std::invalid_argument("--isa '" + asked + "': auto, avx2 or avx512");
  }
  c.name = c.simd16 ? "avx512" : "avx2";
  return c;
}

}  // namespace rb::bench
