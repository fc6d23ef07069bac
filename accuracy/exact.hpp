// Exact and high-precision references from float inputs: GMP rationals for the decisions at
// triangle edges and box slab planes, MPFR (512 bits) for the roots of quadrics, a long double
// root isolation for the torus quartic. Every function takes the float inputs as stored.
#pragma once

#include "accuracy/common.hpp"
#include "core/roots_ld.hpp"
#include "core/vec3.hpp"
#include "kernels/transform.hpp"

namespace rb::acc {

// Ray (o, d) against triangle (a, b, c), exact: miss, hit (interior) or either (the ray meets the
// closed triangle only on its boundary, or lies in its plane). t (the exact hit distance, rounded
// to long double) when it meets the closed triangle in [tmin, tmax].
Ref triangle_ref(const Vec3f& o, const Vec3f& d, float tmin, float tmax, const Vec3f& a, const Vec3f& b, const Vec3f& c);
// The sign of d . n for the triangle's normal n = (b - a) x (c - a), exact.
int triangle_facing(const Vec3f& d, const Vec3f& a, const Vec3f& b, const Vec3f& c);

// Sphere |p - c|^2 = r2 (the stored r2): first crossing in [tmin, tmax]; either when tangent.
Ref sphere_ref(const Vec3f& o, const Vec3f& d, float tmin, float tmax, const Vec3f& c, float r2);

// A solid { f(p) <= 0, z0 <= z(p) <= z1 } with f quadratic along the ray: f(t) = A t^2 + 2B t + C
// given by a callback on MPFR; z(t) = oz + t dz. `solid` false: the open surface f = 0 cut to the
// slab. Used for cylinders and cones in their local frame.
enum class Quad { cylinder, cone };
Ref quadric_ref(Quad kind, bool solid, const Vec3f& o, const Vec3f& d, float tmin, float tmax, float cx, float cy, float r2,
                float z0, float z1);

// The same open surface placed by an affine map (kernels/transform.hpp): the float ray taken into
// the quadric's frame by the stored float inverse `inv`, exactly, then as above. `extent`: the
// placed shell's size in world units (for the scaled error).
Ref placed_quadric_ref(Quad kind, const Affine34<float>& inv, const Vec3f& o, const Vec3f& d, float tmin, float tmax, float cx, float cy,
                       float r2, float z0, float z1, double extent);

// Torus T(p) = (|q|^2 - R^2 - r^2)^2 - 4 R^2 (r^2 - (q.w)^2), q = p - c, with the stored (float)
// c, w, R, r. All real roots in [tmin, tmax] (sign changes), ascending, in long double.
std::vector<long double> torus_ref_roots(const Vec3f& o, const Vec3f& d, float tmin, float tmax, const Vec3f& c,
                                         const Vec3f& w, float R, float r);

// Box [lo, hi] (the first surface crossing in [tmin, tmax]: the entry, or the exit from inside),
// exact; either when the ray only touches an edge or corner or runs in a face's plane.
Ref box_ref(const Vec3f& o, const Vec3f& d, float tmin, float tmax, const Vec3f& lo, const Vec3f& hi);

// poly_roots_ld: core/roots_ld.hpp.
using rb::poly_roots_ld;

}  // namespace rb::acc
