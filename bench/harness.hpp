// The L1-resident kernel benchmark: R rays x P primitives, every pair tested, in three forms
// that run the same kernel text:
//   scalar           one ray x one primitive, float (compiled in its own translation unit
//                    with -fno-tree-vectorize -fno-tree-slp-vectorize: a true scalar baseline)
//   rays_in_lanes    K = 8 rays x 1 primitive (primitive broadcast)
//   prims_in_lanes   1 ray (broadcast) x M = 8 primitives
//   rays_in_lanes16, prims_in_lanes16: the same with 16 AVX-512 lanes (bench/simd16.hpp), on a CPU
//                    and build that have them
// and three cases: every pair hits, every pair misses, half the pairs hit (ray class i%2 hits
// primitive class j%2 only, so both SIMD mappings see half their lanes hit).
//
// A bench spec (bench/specs.hpp) says how to make a primitive and a ray of a given class and
// which kernel to run: see SphereGeometricSpec for the shape.
#pragma once

#include "bench/bench_name.hpp"
#include "core/counted.hpp"
#include "soa/prims.hpp"
#include "soa/rays.hpp"

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace rb::bench {

enum class Case { hit, miss, half };
inline const char* case_name(Case c) { return c == Case::hit ? "hit" : c == Case::miss ? "miss" : "half"; }
enum class Variant { scalar, rays_in_lanes, prims_in_lanes, rays_in_lanes16, prims_in_lanes16 };
inline const char* variant_name(Variant v) {
  switch (v) {
    case Variant::scalar: return "scalar";
    case Variant::rays_in_lanes: return "rays_in_lanes";
    case Variant::prims_in_lanes: return "prims_in_lanes";
    case Variant::rays_in_lanes16: return "rays_in_lanes16";
    case Variant::prims_in_lanes16: return "prims_in_lanes16";
  }
  return "?";
}
inline constexpr bool is_simd16(Variant v) { return v == Variant::rays_in_lanes16 || v == Variant::prims_in_lanes16; }

inline constexpr std::size_t kBenchRays = 256;   // 256 rays x 11 floats = 11 KiB
inline constexpr std::size_t kBenchPrims = 64;   // 64 primitives: < 4 KiB for every kind here
inline constexpr std::uint32_t kBenchSeed = 20261122;
// Seed of the timed benchmark data (rays and primitives). `raybench bench --seed` changes it, e.g.
// to train a PGO profile on other data than the measured run; the ops tables keep kBenchSeed.
inline std::uint32_t& bench_data_seed() {
  static std::uint32_t seed = kBenchSeed;
  return seed;
}

using Rng = std::mt19937;
inline float uni(Rng& g, float a, float b) { return std::uniform_real_distribution<float>(a, b)(g); }

// Class of ray i / primitive j for a case: a class-c ray hits exactly the class-c primitives.
inline int ray_class(Case c, std::size_t i) { return c == Case::hit ? 0 : c == Case::miss ? 1 : int(i % 2); }
inline int prim_class(Case c, std::size_t j) { return c == Case::half ? int(j % 2) : 0; }

// Default ray of class c: from z = -50 towards +z with a little jitter, shifted by 10 in x per
// class; bounded primitives of class c sit around (10 c, 0, z > 0) with extent >= 0.5.
inline Ray<float> default_ray(int cls, Rng& g) {
  const Vec3f o{10.f * float(cls) + uni(g, -0.3f, 0.3f), uni(g, -0.3f, 0.3f), -50.f};
  const Vec3f d{uni(g, -0.002f, 0.002f), uni(g, -0.002f, 0.002f), 1.f};
  return make_ray(o, d);
}

template <class Spec>
struct BenchData {
  RaySoA rays;
  typename Spec::Soa prims;
  std::size_t tests() const { return rays.count * Spec::count(prims); }
};

template <class Spec>
BenchData<Spec> make_bench_data(Case c) {
  Rng g(bench_data_seed());
  BenchData<Spec> d;
  std::vector<typename Spec::Input> in;
  for (std::size_t j = 0; j < kBenchPrims; ++j) in.push_back(Spec::make(prim_class(c, j), int(j), g));
  d.prims = Spec::build(in);
  for (std::size_t i = 0; i < kBenchRays; ++i) d.rays.push(Spec::ray(ray_class(c, i), g));
  return d;
}

// What a timed loop keeps of its hits: the number of hits, the sum of their distances and the sum
// of their u + v. Every output of the kernel is used, so that the compiler cannot drop the work of
// one the loop would otherwise ignore (a method's [u,v] mapping): the figures time what the
// operation counts count.
struct Acc {
  double tsum = 0, uvsum = 0;
  std::uint64_t hits = 0;
};

template <class F>
struct Sums {
  F t = F(0), uv = F(0);
};

template <class F>
RB_INLINE void accumulate(const Hit<F>& h, Sums<F>& s, std::uint64_t& hits) {
  s.t = s.t + vselect(h.mask, h.t, F(0));
  s.uv = s.uv + vselect(h.mask, h.u + h.v, F(0));
  hits += std::uint64_t(count_true<F>(h.mask));
}

template <class F>
RB_INLINE Acc finish(const Sums<F>& s, std::uint64_t hits) {
  Acc a;
  for (int k = 0; k < lanes_v<F>; ++k) a.tsum += double(lane(s.t, k)), a.uvsum += double(lane(s.uv, k));
  a.hits = hits;
  return a;
}

// The timed loops. `Kernel::run` is the spec's kernel (the default) or, in rb_ops, its Counted
// copy compiled once per spec and number type (bench/ops_detail.hpp).
// Rays in lanes: every primitive broadcast against packets of K rays.
template <class Spec, class F, class Kernel = Spec>
RB_INLINE Acc run_rays_in_lanes(const BenchData<Spec>& d) {
  Sums<F> s;
  std::uint64_t hits = 0;
  const std::size_t np = d.prims.size(), nr = d.rays.size();
  for (std::size_t j = 0; j < np; ++j) {
    const auto p = d.prims.template broadcast<F>(j);
    for (std::size_t i = 0; i < nr; i += lanes_v<F>) accumulate(Kernel::run(d.rays.template packet<F>(i), p, d.prims, j), s, hits);
  }
  return finish(s, hits);
}

// Primitives in lanes: every ray broadcast against groups of M primitives.
template <class Spec, class F, class Kernel = Spec>
RB_INLINE Acc run_prims_in_lanes(const BenchData<Spec>& d) {
  Sums<F> s;
  std::uint64_t hits = 0;
  const std::size_t np = d.prims.size(), nr = d.rays.size();
  for (std::size_t i = 0; i < nr; ++i) {
    const Ray<F> r = d.rays.template broadcast<F>(i);
    for (std::size_t j = 0; j < np; j += lanes_v<F>) accumulate(Kernel::run(r, d.prims.template load<F>(j), d.prims, j), s, hits);
  }
  return finish(s, hits);
}

// Operations per test of a benchmark (per lane, so masked-off SIMD lanes count as work done):
// the variant's loop run once with Counted numbers on the benchmark's own data. Measured by
// rb_ops (bench/ops_per_test.cpp), where the Counted copies of the kernels are compiled (those at
// 16 lanes: bench/simd16.hpp); the benchmark translation units only look the figure up. NaN for an
// unknown spec or a 16-lane variant.
double ops_per_test(const char* kernel, const char* method, Case c, Variant v);

// The count itself: the operations a loop over `tests` pairs performed in `lanes` lanes, per test.
inline double ops_per_lane_test(const OpCounts& e, double lanes, double tests) {
  return double(e.flops() + e.cmp + e.minmax + e.select) * lanes / tests;
}

}  // namespace rb::bench
