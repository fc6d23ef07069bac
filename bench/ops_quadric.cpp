// Ops-table rows of the quadric kernel family.
#include "bench/ops_detail.hpp"
#include "bench/specs_quadric.hpp"

namespace rb::opstable {
namespace {
// (kernel, method, case, the slide's count or std::nullopt, note explaining every difference)
const Entry kQuadricEntries[] = {
    // Spheres: the slides count only the geometric method (ops_table.cpp); these are measured.
    {"sphere", "stable", "miss", std::nullopt,
     "f = P0 - C 3+-; a = d.d 2+- 3*, b = f.d (half b) 2+- 3*, c = f.f - R^2 3+- 3*; disc = b^2 - a c 1+- 2*; 1 cmp. "
     "a = d.d is formed (not assumed 1) so the kernel also serves transformed instances; half b drops the factors 2 and "
     "4 of b^2 - 4ac",
     kNoteSums},
    {"sphere", "stable", "hit", std::nullopt,
     "as the miss, then q = -(b + sign(b) sqrt(disc)) 1+- 1 sqrt, t0 = q/a, t1 = c/q 2/, ordered by 2 min/max; "
     "3 cmp + 2 select choose the root >= tmin and test [tmin, tmax] (t = +inf on misses)"},
    {"sphere", "hearn_baker", "miss", std::nullopt,
     "|d| = 1 assumed (Ray contract): f 3+-, b = f.d 2+- 3*, l = f - b d 3+- 3*, disc = R^2 - l.l 3+- 3*; 1 cmp: "
     "two multiplications fewer than the stable form (no a = d.d), and c is deferred to the positive case",
     kNoteSums},
    {"sphere", "hearn_baker", "hit", std::nullopt,
     "c = f.f - R^2 3+- 3*, q 1+- 1 sqrt, t1 = c/q 1/ (t0 = q since a = 1), 2 min/max; 3 cmp 2 select as the stable form"},
    {"sphere", "compensated", "miss", std::nullopt,
     "f = P0 - C as fh + fl (3 two-sums), b = f.d and c = f.f - R^2 as if summed exactly and rounded once (two-products "
     "by FMA, two-sums, the error terms collected), a = d.d likewise, disc = b^2 - a c from the unrounded pairs; 1 cmp. "
     "about five times the stable form's operations: the price of a right answer for grazing rays on a planet in float"},
    {"sphere", "compensated", "hit", std::nullopt, "b and c rounded once 2+-, then the stable roots and the root choice"},
    {"sphere", "uv", "miss", std::nullopt, "the stable sphere's negative case (the [u,v] mapping runs only on hits)"},
    {"sphere", "uv", "hit", std::nullopt,
     "stable hit + N = (P0 + t d - C)/R 6+- 6* + the uv_map row + 2 select (u = v = 0 on missing lanes); "
     "plus 2 arccos, counted apart (ops::trans_current(), not in OpCounts)"},
    {"sphere", "uv_map", "hit", std::nullopt,
     "seed 000's inverse mapping (no count on the slide): N.P, N.E, (PxE).N 6+- 9*, with P x E stored per sphere (not "
     "formed per hit); sin Phi = sqrt(1 - (N.P)^2) 1+- 1* 1 sqrt (no sine call); (N.E)/sin Phi 1/; 1/pi and 1/2pi 2*; "
     "1 - theta 1+-; two clamps 4 min/max; 1 cmp 1 select; and two arccos (separate tally)",
     kNoteSums},
    // General quadric: no count on the slides.
    {"quadric", "matrix", "miss", std::nullopt,
     "seed 000 literally: Q P1 (P1 = [p1; 0]) 12* 8+-, Q P0 (P0 = [P0; 1]) 12* 12+-, a2 = P1.QP1 3* 2+-, "
     "a1/2 = P0.QP1 (Q symmetric: QP1 reused) 3* 3+-, a0 = P0.QP0 3* 3+-, disc 2* 1+-, 1 cmp",
     kNoteSums},
    {"quadric", "matrix", "hit", std::nullopt, "+ the stable roots (1+- 1 sqrt 2/ 2 min/max) and the root choice (3 cmp 2 select)"},
    {"quadric", "coeffs10", "miss", std::nullopt,
     "seed 004's A, B, C expanded term by term, B halved (its outer 2* dropped); 14* more and 3+- fewer than the matrix "
     "form: the slide's products a*x0*x0 etc. are not shared between A, B and C"},
    {"quadric", "coeffs10", "hit", std::nullopt, "+ the stable roots and the root choice, as the matrix method"},
    {"quadric", "normal", "hit", std::nullopt, "gradient / 2 (seed 004) 9* 9+-, normalised 3* 2+- 1 sqrt 1/ 3*"},
    {"quadric_rev", "lecture", "miss", std::nullopt,
     "x^2 + y^2 + a z^2 + b z + c about a centre: 3+- for the centre (none in the lecture's basic position), b/2 stored "
     "per primitive (not halved per ray), a z0 1* shared by B and C; A 4* 2+-, B/2 3* 3+-, C 3* 4+-, disc 2* 1+-, 1 cmp",
     kNoteSums},
    {"quadric_rev", "lecture", "hit", std::nullopt, "+ the stable roots and the root choice"},
    {"cylinder", "lecture", "miss", std::nullopt,
     "seed 000's substituted quadratic (half B) with the axis at (cx, cy): 2+- for the axis offset (0 in basic "
     "position); R^2 replaces the 1 at no cost; A, B, C 4+- 6*, disc 1+- 2*, 1 cmp",
     kNoteSums},
    {"cylinder", "lecture", "hit", std::nullopt,
     "+ stable roots; z of both roots 2+- 2*; each root kept when t in [tmin, tmax] and z in [z0, z1] (8 cmp), 1 select + make_hit"},
    {"cylinder", "capped", "miss", std::nullopt, "the same negative case as the open tube"},
    {"cylinder", "capped", "hit", std::nullopt,
     "+ stable roots; parallel-ray handling (A == 0: inside iff C <= 0) 2 cmp 3 select; slab 1/dz 1/ 2+- 2*, ordered by "
     "the sign of 1/dz 1 cmp 2 select; entry = max, exit = min 2 min/max, entry <= exit 1 cmp; root choice 3 cmp 2 select"},
    {"cylinder", "normal", "hit", std::nullopt, "lateral (x - cx, y - cy, 0) / rho: 3+- 4* 1 sqrt 1/"},
    {"cone", "lecture", "miss", std::nullopt,
     "seed 000's substituted quadratic (half B) with the apex at (cx, cy, cz): 3+- for the apex offset (0 in basic "
     "position); A, B, C 6+- 9*, disc 1+- 2*, 1 cmp; A < 0 1 cmp and disc clamped to 0 there 1 min/max (a ray steeper than "
     "the cone always meets it: a negative disc is rounding near the apex, which made rays through the apex miss)"},
    {"cone", "lecture", "hit", std::nullopt, "+ stable roots, z range and [tmin, tmax] of both roots as the open cylinder"},
    {"cone", "capped", "miss", std::nullopt, "the same negative case as the open cone"},
    {"cone", "capped", "hit", std::nullopt,
     "+ stable roots; slab 1/ 2+- 2* 1 cmp 2 select; A < 0 (two nappes) picks the half-line in the solid's nappe by the signs "
     "of dz and z1 (not by comparing roots and slab, which failed through the apex): 1 cmp 4 select; "
     "entry/exit 2 min/max 1 cmp; root choice 3 cmp 2 select"},
    // Transformation (seed 000 "Implementation": 1 transformation 15+, 18*).
    {"transform", "ray", "hit", Lecture{15, 18, 0, 0, 0},
     "as on the slide: P0' = M^-1 [P0; 1] 9* 9+-, p1' = M^-1 [p1; 0] 9* 6+-; t is not rescaled (same line parameter in both "
     "frames, so the local kernel's t is the world distance) and 1/p1' is not formed"},
    {"transform", "normal", "hit", std::nullopt, "(M^-1)^T n' 9* 6+-, then normalised 3* 2+- 1 sqrt 1/ 3*"},
    {"transformed", "sphere", "miss", std::nullopt, "the transformation (15+- 18*) + the stable sphere's negative case (11+- 11* 1 cmp)",
     kNoteSums},
    {"transformed", "sphere", "hit", std::nullopt, "the transformation + the stable sphere's positive case"},
    {"transformed", "cylinder", "miss", std::nullopt,
     "transformation + the capped cylinder's full path: the bench's class-1 ray meets the infinite cylinder (laid along x) "
     "and is rejected by the caps' slab, after the quadratic"},
    {"transformed", "cylinder", "hit", std::nullopt, "transformation + the capped cylinder's positive case"},
    {"transformed", "cone", "miss", std::nullopt,
     "transformation + the capped cone's full path: the class-1 ray meets the infinite double cone and is rejected by the slab"},
    {"transformed", "cone", "hit", std::nullopt, "transformation + the capped cone's positive case"},
};
}  // namespace

void add_quadric_rows(std::vector<Row>& rows) {
  const std::span<const Entry> e = kQuadricEntries;
  bench::for_each_spec_quadric([&]<class Spec>() { add_spec_rows<Spec>(e, rows); });
  add_extra_rows<bench::SphereUVSpec>(e, rows, "sphere", "uv_map", [](const auto& r, const auto& s) {
    (void)sphere_uv_map(r.d, s.P, s.E, s.PxE);
  });
  add_extra_rows<bench::QuadricMatrixSpec>(e, rows, "quadric", "normal", [](const auto& r, const auto& q) {
    (void)quadric_normal(q, r.o);
  });
  add_extra_rows<bench::CylinderSpec>(e, rows, "cylinder", "normal", [](const auto& r, const auto& c) {
    (void)cylinder_normal(c, r.o);
  });
  add_extra_rows<bench::TransformedSphereSpec>(e, rows, "transform", "ray", [](const auto& r, const auto& x) {
    (void)transform_ray(r, x.inv);
  });
  add_extra_rows<bench::TransformedSphereSpec>(e, rows, "transform", "normal", [](const auto& r, const auto& x) {
    (void)transform_normal(x.inv, r.d);
  });
}

void add_quadric_ops_per_test(std::vector<OpsPerTest>& t) {
  bench::for_each_spec_quadric([&]<class Spec>() { t.push_back(ops_per_test_entry<Spec>()); });
}

}  // namespace rb::opstable
