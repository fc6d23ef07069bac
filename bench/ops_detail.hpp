// Building blocks of the ops table, shared by every kernel family's rows (bench/ops_*.cpp).
// A family lists its rows as Entry values (kernel, method, case, the slide's count or nullopt,
// and the note explaining every difference), then measures them with add_spec_rows (a bench
// spec's hit and miss rays) or add_extra_rows (a function of the hit: point, normal, [u,v]).
#pragma once

#include "bench/harness.hpp"
#include "bench/ops_table.hpp"

#include <array>
#include <limits>
#include <memory>
#include <optional>
#include <span>

namespace rb::opstable {

using bench::Rng;

// What each (kernel, method, case) row says. `lecture` empty: the slides give no count.
// `sums`: the counts written in the note (3+-, 9*, 1/, 1 sqrt, 1 cmp, 2 min/max, 1 select) are the
// parts of the whole float row and add up to it (tests/test_ops.cpp checks the sum).
struct Entry {
  const char* kernel;
  const char* method;
  const char* kase;
  std::optional<Lecture> lecture;
  const char* note;
  bool sums = false;
};
inline constexpr bool kNoteSums = true;

// A bench spec's kernel at a Counted number type. Not inlined: the ops rows, the transcendental
// tally and the benchmarks' ops-per-test all call this one copy per (spec, number type) instead of
// each expanding the whole kernel again.
template <class Spec, class F, class P>
[[gnu::noinline]] Hit<F> counted_run(const Ray<F>& r, const P& p, const typename Spec::Soa& s, std::size_t j) {
  return Spec::run(r, p, s, j);
}
template <class Spec>
struct CountedKernel {
  template <class F, class P>
  static Hit<F> run(const Ray<F>& r, const P& p, const typename Spec::Soa& s, std::size_t j) {
    return counted_run<Spec>(r, p, s, j);
  }
};

// Operations per test of one benchmark (bench::ops_per_test): its loop, its data, Counted numbers.
template <class Spec>
double counted_ops_per_test(bench::Case c, bench::Variant v) {
  using bench::Variant;
  if (bench::is_simd16(v)) return std::numeric_limits<double>::quiet_NaN();  // bench::simd16_op_mix
  const auto d = std::make_unique<bench::BenchData<Spec>>(bench::make_bench_data<Spec>(c));
  const ops::Scope s;
  if (v == Variant::scalar) (void)bench::run_rays_in_lanes<Spec, cfloat, CountedKernel<Spec>>(*d);
  else if (v == Variant::rays_in_lanes) (void)bench::run_rays_in_lanes<Spec, cf8, CountedKernel<Spec>>(*d);
  else (void)bench::run_prims_in_lanes<Spec, cf8, CountedKernel<Spec>>(*d);
  const double lanes = v == Variant::scalar ? 1.0 : 8.0;
  // tests counted over the padded arrays, as the timed loops run them
  const double tests = double(d->rays.size()) * double(d->prims.size());
  return bench::ops_per_lane_test(s.elapsed(), lanes, tests);
}

// (kernel, method) -> its ops-per-test function; each family adds its bench specs.
struct OpsPerTest {
  const char* kernel;
  const char* method;
  double (*fn)(bench::Case, bench::Variant);
};
template <class Spec>
OpsPerTest ops_per_test_entry() {
  return {Spec::kernel, Spec::method, &counted_ops_per_test<Spec>};
}
void add_basic_ops_per_test(std::vector<OpsPerTest>& t);    // ops_table.cpp
void add_planar_ops_per_test(std::vector<OpsPerTest>& t);   // ops_planar.cpp
void add_quadric_ops_per_test(std::vector<OpsPerTest>& t);  // ops_quadric.cpp
void add_solver_ops_per_test(std::vector<OpsPerTest>& t);   // ops_solver.cpp

inline const Entry* find_entry(std::span<const Entry> entries, const std::string& k, const std::string& m, const std::string& c) {
  for (const auto& e : entries)
    if (k == e.kernel && m == e.method && c == e.kase) return &e;
  return nullptr;
}

// Counts of fn(ray<F>, prim<F>) for F = cfloat on the given ray, and F = cf8 on a packet of 8
// rays: lane 0 the given ray and lanes 1..7 `other` (no lane can exit early on its own), and
// all eight the given ray (`uniform`: the packet exits early when every lane agrees).
template <template <class> class P, class Fn>
std::array<OpCounts, 3> count3(Fn fn, const P<float>& prim, const Ray<float>& ray, const Ray<float>& other) {
  std::array<OpCounts, 3> out;
  {
    const auto p = prim_cast<cfloat>(prim);
    const auto r = Ray<cfloat>::broadcast(ray);
    const ops::Scope s;
    fn(r, p);
    out[0] = s.elapsed();
  }
  for (int u = 0; u < 2; ++u) {
    RaySoA rays;
    for (int k = 0; k < 8; ++k) rays.push(k == 0 || u == 1 ? ray : other);
    const auto p = prim_cast<cf8>(prim);
    const auto r = rays.packet<cf8>(0);
    const ops::Scope s;
    fn(r, p);
    out[1 + u] = s.elapsed();
  }
  return out;
}

inline void add_rows(std::span<const Entry> entries, std::vector<Row>& rows, const char* kernel, const char* method, const char* kase,
              const std::array<OpCounts, 3>& c) {
  const Entry* e = find_entry(entries, kernel, method, kase);
  Row r;
  r.kernel = kernel; r.method = method; r.kase = kase;
  r.lecture = e ? e->lecture : std::nullopt;
  r.note = e ? e->note : "";
  r.note_sums = e && e->sums;
  r.number = "float";
  r.measured = c[0];
  rows.push_back(r);
  r.number = "simd8";
  r.measured = c[1];
  r.uniform = c[2];
  rows.push_back(r);
}

// The miss ray of the ops table: the spec's own (the lecture's negative case) or its class-1 ray.
template <class Spec>
Ray<float> ops_miss_ray(Rng& g) {
  if constexpr (requires { Spec::ops_miss_ray(g); }) return Spec::ops_miss_ray(g);
  else return Spec::ray(1, g);
}

// Rows of a bench spec: its class-0 primitive, its class-0 ray (hit) and class-1 ray (miss).
template <class Spec>
void add_spec_rows(std::span<const Entry> entries, std::vector<Row>& rows) {
  Rng g(bench::kBenchSeed);
  const auto soa = Spec::build({Spec::make(0, 0, g)});
  const Ray<float> hit = Spec::ray(0, g), miss = ops_miss_ray<Spec>(g);
  const auto prim = soa.template broadcast<float>(0);
  auto fn = [&soa](const auto& r, const auto& p) { (void)counted_run<Spec>(r, p, soa, 0); };
  for (const char* kase : {"hit", "miss"}) {
    if (!find_entry(entries, Spec::kernel, Spec::method, kase)) continue;
    const bool h = kase[0] == 'h';
    add_rows(entries, rows, Spec::kernel, Spec::method, kase, count3(fn, prim, h ? hit : miss, h ? miss : hit));
  }
}

// Rows of a function of the hit (point, normal) on the spec's hit ray.
template <class Spec, class Fn>
void add_extra_rows(std::span<const Entry> entries, std::vector<Row>& rows, const char* kernel, const char* method, Fn fn) {
  Rng g(bench::kBenchSeed);
  const auto soa = Spec::build({Spec::make(0, 0, g)});
  const Ray<float> hit = Spec::ray(0, g);
  add_rows(entries, rows, kernel, method, "hit", count3(fn, soa.template broadcast<float>(0), hit, hit));
}


// The families' row builders; build() calls them in this order.
void add_basic_rows(std::vector<Row>& rows);    // ops_table.cpp: plane, triangle, sphere, box
void add_planar_rows(std::vector<Row>& rows);   // ops_planar.cpp
void add_quadric_rows(std::vector<Row>& rows);  // ops_quadric.cpp
void add_solver_rows(std::vector<Row>& rows);   // ops_solver.cpp
void add_csg_rows(std::vector<Row>& rows);      // ops_csg.cpp

}  // namespace rb::opstable
