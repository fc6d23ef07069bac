// All the roots of a closed solid along a ray, as ordered entry/exit intervals (for CSG in 1D
// ray space, seed 000). Up to N roots per lane, ascending; unused slots hold +inf and a clear
// mask. Interval k is [t[2k], t[2k+1]]: the ray is inside the solid between them.
#pragma once

#include "core/num.hpp"

namespace rb {

template <class F, int N>
struct Roots {
  F t[N];
  mask_t<F> valid[N];
  static RB_INLINE Roots none() {
    Roots r;
    for (int k = 0; k < N; ++k) { r.t[k] = F(kInf<F>); r.valid[k] = mask_false<F>(); }
    return r;
  }
};

}  // namespace rb
