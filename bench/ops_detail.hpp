// Building blocks of the ops table, shared by every kernel family's rows (bench/ops_*.cpp).
// A family lists its rows as Entry values (kernel, method, case, the slide's count or nullopt,
// and the note explaining every difference), then measures them with add_spec_rows (a bench
// spec's hit and miss rays) or add_extra_rows (a function of the hit: point, normal, [u,v]).
#pragma once

#include "bench/harness.hpp"
#include "bench/ops_table.hpp"

#include <array>
#include <optional>
#include <span>

namespace rb::opstable {

using bench::Rng;

// What each (kernel, method, case) row says. `lecture` empty: the slides give no count.
struct Entry {
  const char* kernel;
  const char* method;
  const char* kase;
  std::optional<Lecture> lecture;
  const char* note;
};

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
  auto fn = [&soa](const auto& r, const auto& p) { (void)Spec::run(r, p, soa, 0); };
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

}  // namespace rb::opstable
