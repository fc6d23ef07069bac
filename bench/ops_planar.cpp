// Ops-table rows of the planar kernel family.
#include "bench/ops_detail.hpp"
#include "bench/specs_planar.hpp"

namespace rb::opstable {
namespace {
// (kernel, method, case, the slide's count or std::nullopt, note explaining every difference)
// Where a row's slide count differs from the measurement, the note names each difference.
const Entry kPlanarEntries[] = {
    {"plane", "uv", "hit", Lecture{13, 14, 3, 0, 0},
     "slide total = plane positive case 5+-6*1/ + point [x,y,z] 3+-3* + [u,v] solve 5+-5*2/; "
     "-1+- -1*: only the two kept coordinates of [x,y,z] are formed (the dropped axis is not needed); "
     "-1+- -1*: the 2x2 determinant is precomputed per plane (see plane/uv_solve); "
     "+1 cmp parallel test, +2 cmp t within [tmin, tmax]; +1 select (t = +inf on missing lanes)"},
    {"plane", "uv", "miss", Lecture{2, 3, 0, 0, 0},
     "miss = ray parallel to the plane (the slide's negative case): +1 cmp, the parallel test the slide leaves uncounted"},
    {"plane", "uv_solve", "hit", Lecture{5, 5, 2, 0, 0},
     "[u,v] from [x,y,z] alone. The slide eliminates: det 1+-2*, v numerator 1+-2*, back-substitution for u 1+-1*, "
     "plus 2+- for P - PI0 = 5+-5*2/. Here det is precomputed per plane (-1+- -2*) and u is solved by Cramer's rule like v "
     "(1+-2* instead of 1+-1*: +1*): net -1+- -1*. The two coordinates are those that drop the normal's dominant axis, not always x, y"},
    {"parallelogram", "lecture", "hit", Lecture{13, 14, 3, 4, 0},
     "-1+- -1*: only the two kept coordinates of [x,y,z] are formed; -1+- -1*: the 2x2 determinant of the [u,v] system is "
     "precomputed per parallelogram (slide's solve 5+-5*2/, ours 4+-4*2/); +3 cmp: parallel test and t within [tmin, tmax] "
     "(the slide counts the 4 u,v tests only); +1 select"},
    {"parallelogram", "lecture", "miss", std::nullopt,
     "miss = ray through the plane outside the parallelogram: plane, point and [u,v] are all computed before the u, v tests "
     "fail (the slide gives no negative case; a parallel ray exits after 2+-3* 1 cmp as plane/uv/miss)"},
    {"triangle", "cramer", "hit", std::nullopt,
     "seeds 002/004: [a-b a-c d][beta gamma t] = a-e by Cramer's rule; the minors (a-c) x d and (a-b) x (a-e) are shared "
     "by the four 3x3 determinants (M, t, gamma, beta); three divisions by M; early exits after t, gamma; no parallel test "
     "(M == 0 gives t = +-inf or NaN, rejected by the range test)"},
    {"triangle", "cramer", "miss", std::nullopt,
     "miss = ray through the plane outside the triangle: t and gamma pass, beta fails (exit at the end; the whole arithmetic)"},
    {"triangle", "woop", "hit", std::nullopt,
     "Woop-Benthin-Wald 2013 per test, the per-ray shear/permutation excluded (row woop_precompute); uniform permutation "
     "(no selects; a packet of mixed permutations adds 18 selects); 3 cmp zero test of U,V,W (double fallback not taken), "
     "6 cmp sign test, 1 cmp det, T 2+-3* with Az,Bz,Cz 3*, one 1/ and 3* for t, u, v"},
    {"triangle", "woop", "miss", std::nullopt,
     "miss = ray outside the triangle: exits after the sign and det tests (vertices 9+-, shear 6+- 6*, U V W 3+- 6*, det 2+-; 3 + 6 + 1 cmp)"},
    {"triangle", "woop_precompute", "hit", std::nullopt,
     "per ray, once: kz = argmax |d| (3 cmp), kx, ky (mask logic), d[kz] < 0 (1 cmp), 6 selects, Sx, Sy, Sz (3/)"},
    {"polygon", "plane", "hit", Lecture{8, 9, 1, 0, 0},
     "plane part only (t and the point): -1+- -1*: only the two kept coordinates of [x,y,z] are formed (the crossing test "
     "works in the projected plane); +1 cmp parallel test, +2 cmp t within [tmin, tmax]"},
    {"polygon", "crossing", "hit", std::nullopt,
     "the spec's polygon 0: a 12-vertex concave star. Plane part 7+-8*1/ 3 cmp, then the crossing test: first vertex 2+- 1 cmp, "
     "per edge 4+- 2* 2 cmp (12 edges: 48+- 24* 24 cmp), mask logic free; 1 select"},
    {"polygon", "crossing", "miss", std::nullopt,
     "miss = ray through the plane outside the polygon: the same whole crossing test as a hit (no early exit per edge)"},
    {"parallel_planes", "lecture", "hit", Lecture{8, 6, 4, 0, 0},
     "4 planes: slide 5+-6*1/ + 3 x (1+-1/); +1 cmp parallel test; nearest hit in range: per plane +2 cmp, +1 select, "
     "+1 min; +1 select (t = +inf on missing lanes)"},
    {"parallel_planes", "lecture", "miss", std::nullopt,
     "miss = ray parallel to the planes: n . p1 (2+- 3*) and the parallel test, then exit (the slide gives no negative case)"},
    {"polyhedron", "halfspaces", "hit", std::nullopt,
     "octahedron (8 halfspaces), the slide's t_in/t_out algorithm: per plane n.p1 2+-3*, n.P0 + D 3+-3*, 1/, "
     "enter/leave 2 cmp 2 select 2 min/max, parallel-outside 2 cmp, t_in <= t_out 1 cmp (early exit check); t_in and t_out "
     "start from the whole line, then the first crossing in [tmin, tmax] (t_out from inside, as every closed primitive): "
     "3 cmp 1 select + make_hit"},
    {"polyhedron", "halfspaces", "miss", std::nullopt,
     "miss = ray beside the octahedron (x + 10): early exit (t_in > t_out) after 5 of the 8 planes"},
    {"polyhedron", "slabs", "hit", std::nullopt,
     "oriented box as 3 slabs (parallel plane pairs): per slab the parallel-planes cost 5+-6*1/ + 1+-1/, 4 min/max, 1 cmp "
     "early exit; an axis-aligned box this way costs 12+- 12* 6/ more than box/slab (6+- 6*: 1/d stored per ray, "
     "the 0/1 normals implicit); the first crossing in [tmin, tmax] as the halfspaces: 3 cmp 1 select + make_hit"},
    {"polyhedron", "slabs", "miss", std::nullopt,
     "miss = ray beside the box (x + 10): early exit after the second slab empties [t_in, t_out] (it starts as the whole "
     "line, not [tmin, tmax], so that the exit from inside is known: one slab later than the clamped form)"},
};

// count3 (ops_detail.hpp) for batches whose primitive view is not a plain P<float>: the batch's
// own broadcast<F>(0) gives the primitive for F = cfloat and cf8. `prep` is per-ray work done
// before the counting scope (Woop's precompute).
template <class Soa, class Prep, class Fn>
std::array<OpCounts, 3> count3_soa(const Soa& soa, Prep prep, Fn fn, const Ray<float>& ray, const Ray<float>& other) {
  std::array<OpCounts, 3> out;
  {
    const auto p = soa.template broadcast<cfloat>(0);
    const auto r = Ray<cfloat>::broadcast(ray);
    const auto pre = prep(r);
    const ops::Scope s;
    fn(pre, r, p);
    out[0] = s.elapsed();
  }
  for (int u = 0; u < 2; ++u) {
    RaySoA rays;
    for (int k = 0; k < 8; ++k) rays.push(k == 0 || u == 1 ? ray : other);
    const auto p = soa.template broadcast<cf8>(0);
    const auto r = rays.packet<cf8>(0);
    const auto pre = prep(r);
    const ops::Scope s;
    fn(pre, r, p);
    out[1 + u] = s.elapsed();
  }
  return out;
}

const auto kNoPrep = [](const auto& r) { return r.tmin; };

// Rows of a spec through count3_soa: class-0 primitive, class-0 ray (hit), miss ray.
template <class Spec, class Prep, class Fn>
void add_soa_rows(std::span<const Entry> e, std::vector<Row>& rows, const char* method, Prep prep, Fn fn) {
  Rng g(bench::kBenchSeed);
  const auto soa = Spec::build({Spec::make(0, 0, g)});
  const Ray<float> hit = Spec::ray(0, g), miss = ops_miss_ray<Spec>(g);
  for (const char* kase : {"hit", "miss"}) {
    if (!find_entry(e, Spec::kernel, method, kase)) continue;
    const bool h = kase[0] == 'h';
    add_rows(e, rows, Spec::kernel, method, kase, count3_soa(soa, prep, [&](const auto& pre, const auto& r, const auto& p) {
               fn(pre, r, p, soa);
             }, h ? hit : miss, h ? miss : hit));
  }
}

}  // namespace

void add_planar_rows(std::vector<Row>& rows) {
  const std::span<const Entry> e = kPlanarEntries;
  using namespace bench;
  add_spec_rows<PlaneUVSpec>(e, rows);
  // [u,v] of the hit point alone (the point, 3+- 3*, is formed before the counting scope).
  add_soa_rows<PlaneUVSpec>(
      e, rows, "uv_solve",
      [](const auto& r) {
        using F = std::remove_cvref_t<decltype(r.tmin)>;
        return hit_point(r, F(3));
      },
      [](const auto& pt, const auto& r, const auto& q, const auto& soa) {
        using F = std::remove_cvref_t<decltype(r.tmin)>;
        F u, v;
        plane_uv_of_point(q, soa.axis_of(0), pt, u, v);
      });
  add_spec_rows<ParallelogramSpec>(e, rows);
  add_spec_rows<TriangleCramerSpec>(e, rows);
  // Woop: the test alone (the per-ray precompute before the counting scope), then the precompute.
  add_soa_rows<TriangleWoopSpec>(e, rows, "woop", [](const auto& r) { return make_woop_ray(r); },
                                 [](const auto& w, const auto& r, const auto& q, const auto&) { (void)intersect_triangle_woop(w, r, q); });
  add_soa_rows<TriangleWoopSpec>(e, rows, "woop_precompute", kNoPrep,
                                 [](const auto&, const auto& r, const auto&, const auto&) { (void)make_woop_ray(r); });
  add_soa_rows<PolygonSpec>(e, rows, "plane", kNoPrep, [](const auto&, const auto& r, const auto& p, const auto&) {
    using F = std::remove_cvref_t<decltype(r.tmin)>;
    mask_t<F> m;
    F t, pa, pb;
    (void)polygon_plane_point(r, p, m, t, pa, pb);
  });
  add_soa_rows<PolygonSpec>(e, rows, "crossing", kNoPrep,
                            [](const auto&, const auto& r, const auto& p, const auto&) { (void)intersect_polygon(r, p); });
  // (PrimSoA of alias templates: count3 cannot deduce P, so through the batch's broadcast.)
  auto run = [](const auto&, const auto& r, const auto& p, const auto&) { (void)intersect_parallel_planes(r, p); };
  add_soa_rows<ParallelPlanesSpec>(e, rows, "lecture", kNoPrep, run);
  add_soa_rows<PolyhedronSpec>(e, rows, "halfspaces", kNoPrep,
                               [](const auto&, const auto& r, const auto& p, const auto&) { (void)intersect_polyhedron(r, p); });
  add_soa_rows<SlabsSpec>(e, rows, "slabs", kNoPrep,
                          [](const auto&, const auto& r, const auto& p, const auto&) { (void)intersect_slabs(r, p); });
}

void add_planar_ops_per_test(std::vector<OpsPerTest>& t) {
  bench::for_each_spec_planar([&]<class Spec>() { t.push_back(ops_per_test_entry<Spec>()); });
}

}  // namespace rb::opstable
