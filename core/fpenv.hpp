// The floating-point environment every thread that traces runs in: flush-to-zero and
// denormals-are-zero set (as Embree's threads run, so both engines see the same arithmetic), set
// once per thread and restored on the calling thread when the work is done.
#pragma once

#include <xmmintrin.h>

namespace rb {

inline constexpr unsigned kMxcsrFtzDaz = 0x8040u;  // FTZ (bit 15) | DAZ (bit 6)

// Sets FTZ and DAZ on this thread.
inline void set_ftz_daz() { _mm_setcsr(_mm_getcsr() | kMxcsrFtzDaz); }

// FTZ/DAZ on this thread while alive; the previous MXCSR restored afterwards.
class FtzScope {
 public:
  FtzScope() : saved_(_mm_getcsr()) { set_ftz_daz(); }
  ~FtzScope() { _mm_setcsr(saved_); }
  FtzScope(const FtzScope&) = delete;
  FtzScope& operator=(const FtzScope&) = delete;

 private:
  unsigned saved_;
};

}  // namespace rb
