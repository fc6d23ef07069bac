// The quadratic A t^2 + 2 B t + C = 0 shared by every quadric kernel (sphere, general quadric,
// quadric of revolution, cylinder, cone), solved in the numerically stable form
//   disc = B^2 - A C,  q = -(B + sign(B) sqrt(disc)),  t0 = q / A,  t1 = C / q
// (the half-B form of q = -1/2 (b + sign(b) sqrt(b^2 - 4ac)) with b = 2B: the factor 2 cancels,
// which saves the lecture's 2* and 4* and changes no rounding). t1 = C / q never subtracts two
// nearly equal numbers, so the near root of a far-away or nearly-tangent quadric keeps its
// relative accuracy, where (-B + sqrt(disc)) / A cancels.
//
// The linear case A ~ 0 (a ray parallel to an asymptotic direction: the axis of a paraboloid, a
// generator of a cone, the rulings of a cylinder) is handled by the same formulas, explicitly:
//   A == 0:        q = -2B, t1 = C / q = -C / (2B) is exactly the root of the linear equation,
//                  t0 = q / A = +-inf lies outside every [tmin, tmax] (tmax is finite);
//   A tiny:        t0 = q / A is the huge far root and t1 keeps full accuracy (the naive form
//                  divides a cancelled difference by A: 0/0 at the limit);
//   A == B == 0:   the ray runs along a line where the quadric's value is the constant C: both
//                  roots are NaN (0/0) and every range test fails: a defined miss.
// One NaN (t1 = 0/0 when C == q == 0: a double root at t = 0, t0 = 0 / A = 0) is dropped by the
// argument order of vmin/vmax (minps semantics return the second argument when the first is NaN).
// The roots come back as a raw two-slot Roots (core/roots.hpp), valid where the caller's mask is.
#pragma once

#include "core/roots.hpp"

namespace rb {

// Caller has already formed disc = B^2 - A C, exited early where disc < 0 on every lane, and
// passes m = (disc >= 0). lo <= hi; NaN only when A == B == 0.
//   1 sqrt, 1+-, 2/, 2 min/max
template <class F>
RB_INLINE Roots<F, 2> stable_roots(const F& A, const F& B, const F& C, const F& disc, const mask_t<F>& m) {
  const F q = -(B + vcopysign(vsqrt(disc), B));  // 1 sqrt 1+-
  const F t0 = q / A;                            // 1/   (+-inf when A == 0: the linear case)
  const F t1 = C / q;                            // 1/   (NaN only when C == q == 0)
  return Roots<F, 2>::span(m, vmin(t1, t0), vmax(t1, t0));  // 2 min/max, NaN t1 dropped
}

// The nearer root in [tmin, tmax] (the far one when the near one is before tmin): first_hit in
// core/roots.hpp (3 cmp 2 select with make_hit).

}  // namespace rb
