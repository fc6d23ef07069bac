// The lab's machinery shared by the family files: a case (rays, primitives, reference), the
// runner that executes one kernel over a case in float, double and 8-lane SIMD (and times it),
// and the tally that turns outputs and reference into a Row.
#pragma once

#include "accuracy/lab.hpp"
#include "core/num.hpp"
#include "core/poly.hpp"
#include "core/ray.hpp"
#include "soa/prims.hpp"
#include "soa/rays.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace rb {
template <class F>
struct TriVerts;  // kernels/triangle_woop.hpp
}  // namespace rb

namespace rb::acc {

// Reference verdict of one test.
enum class Cls : std::uint8_t { miss = 0, hit = 1, either = 2 };  // either: exactly on an edge, tangent
struct Ref {
  Cls cls = Cls::miss;
  long double t = 0;   // first surface crossing in [tmin, tmax] (cls hit or either-with-hit)
  bool has_t = false;
  double scale = 1;    // |origin| + object extent (for the scale-normalised error)
  long double t_next = 0;  // the next root after t (has_next): a hit nearer to it is a wrong root
  bool has_next = false;
};

struct Out {
  bool hit = false;
  double t = 0;
};

// A case: rays x primitives. one_to_one: test k is (ray k, primitive k); otherwise every ray
// meets every primitive and test (i, j) is j * rays + i (a closed mesh: must_hit per ray).
template <template <class> class P>
struct Case {
  std::string family, name, what;
  PrimSoA<P> prims;
  RaySoA rays;
  bool one_to_one = true;
  std::vector<Ref> ref;
  std::vector<std::uint8_t> must_hit;  // per ray, closed meshes only: the ray crosses the surface
  std::size_t nrays() const { return rays.count; }
  std::size_t nprims() const { return prims.count; }
  std::size_t tests() const { return one_to_one ? rays.count : rays.count * prims.count; }
};

struct Ctx {
  const Options* o = nullptr;
  std::size_t rays = 0;  // rays per case
  std::mt19937_64 rng;
  std::vector<Row>* rows = nullptr;
  std::size_t cases_total = 1, cases_started = 0;
  std::string last_case;
  // Each case draws from its own stream (seed, family, case name): its rays do not depend on
  // which other cases ran before it (--filter).
  void reseed(const std::string& family, const std::string& name) {
    std::uint64_t h = 1469598103934665603ULL ^ std::uint64_t(o->seed);
    for (char ch : family + "/" + name) h = (h ^ std::uint64_t(static_cast<unsigned char>(ch))) * 1099511628211ULL;
    rng.seed(h);
  }
  // Progress: called when a method starts on a case (a new case counts one step).
  void tick(const std::string& family, const std::string& name) {
    // The BVH rows of a mesh case follow it under the same name: one step.
    if (name != last_case) ++cases_started, last_case = name;
    const double f = double(std::min(cases_started, cases_total) - 1) / double(std::max<std::size_t>(cases_total, 1));
    if (o->progress) o->progress(std::max(f, 0.0), family + "/" + name);
  }
  bool selected(const std::string& family, const std::string& name) const {
    return o->filter.empty() || selects(o->filter, family + "/" + name);
  }
  // The lab's case loop: fn(ci) for every case of `cases` the filter selects, each on its own
  // seeded stream.
  template <class Cases, class F>
  void each_case(const Cases& cases, F&& fn) {
    for (const auto& ci : cases) {
      if (!selected(ci.family, ci.name)) continue;
      reseed(ci.family, ci.name);
      fn(ci);
    }
  }
};

// ---- random helpers ----
inline double urand(std::mt19937_64& g, double a, double b) { return std::uniform_real_distribution<double>(a, b)(g); }
inline double lurand(std::mt19937_64& g, double a, double b) { return std::exp(urand(g, std::log(a), std::log(b))); }  // log-uniform
inline Vec3d unit_rand(std::mt19937_64& g) {
  for (;;) {
    const Vec3d v{urand(g, -1, 1), urand(g, -1, 1), urand(g, -1, 1)};
    const double l = std::sqrt(dot(v, v));
    if (l > 0.1 && l <= 1) return v * (1.0 / l);
  }
}
inline double norm(const Vec3d& v) { return std::sqrt(dot(v, v)); }
inline Vec3d any_perp(const Vec3d& n) {
  const Vec3d a = std::fabs(n.x) < 0.7 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
  const Vec3d p = cross(n, a);
  return p * (1.0 / norm(p));
}

// ---- the runner ----
template <class F>
inline constexpr const char* prec_name = std::is_same_v<F, float> ? "float" : std::is_same_v<F, double> ? "double" : "simd8";

template <class F>
inline double prec_eps() {
  return std::is_same_v<F, double> ? std::numeric_limits<double>::epsilon() : double(std::numeric_limits<float>::epsilon());
}

inline volatile double g_sink = 0;

// Runs kern(ray, prim, IterCount*) -> Hit<F> over every test of the case; writes outs (if given).
template <class F, template <class> class P, class K>
void run_pass(const Case<P>& c, const K& kern, std::vector<Out>* out, IterCount* ic) {
  double sink = 0;
  const std::size_t nr = c.nrays();
  if constexpr (std::is_same_v<F, f8>) {
    constexpr int L = 8;
    auto put = [&](const Hit<F>& h, std::size_t base, std::size_t i0) {
      sink += double(lane(h.t, 0));
      if (!out) return;
      for (int l = 0; l < L && i0 + std::size_t(l) < nr; ++l)
        (*out)[base + std::size_t(l)] = {lane_mask<F>(h.mask, l), double(lane(h.t, l))};
    };
    if (c.one_to_one) {
      for (std::size_t i = 0; i < nr; i += L) put(kern(c.rays.template packet<F>(i), c.prims.template load<F>(i), ic), i, i);
    } else {
      for (std::size_t j = 0; j < c.nprims(); ++j) {
        const P<F> p = c.prims.template broadcast<F>(j);
        for (std::size_t i = 0; i < nr; i += L) put(kern(c.rays.template packet<F>(i), p, ic), j * nr + i, i);
      }
    }
  } else {
    auto put = [&](const Hit<F>& h, std::size_t k) {
      sink += double(h.t);
      if (out) (*out)[k] = {bool(h.mask), double(h.t)};
    };
    if (c.one_to_one) {
      for (std::size_t i = 0; i < nr; ++i) put(kern(c.rays.template broadcast<F>(i), c.prims.template broadcast<F>(i), ic), i);
    } else {
      for (std::size_t j = 0; j < c.nprims(); ++j) {
        const P<F> p = c.prims.template broadcast<F>(j);
        for (std::size_t i = 0; i < nr; ++i) put(kern(c.rays.template broadcast<F>(i), p, ic), j * nr + i);
      }
    }
  }
  g_sink = g_sink + sink;
}

// Best-of time per test in ns: passes until ~3 ms (at least 3 passes, at most 200).
template <class F, template <class> class P, class K>
double time_pass(const Case<P>& c, const K& kern, bool timing) {
  if (!timing || c.tests() == 0) return std::numeric_limits<double>::quiet_NaN();
  using clk = std::chrono::steady_clock;
  double best = 1e300, total = 0;
  for (int rep = 0; rep < 200 && (rep < 3 || total < 3e-3); ++rep) {
    const auto t0 = clk::now();
    run_pass<F>(c, kern, nullptr, nullptr);
    const double s = std::chrono::duration<double>(clk::now() - t0).count();
    best = std::min(best, s);
    total += s;
  }
  return best * 1e9 / double(c.tests());
}

// Turns outputs + reference into the figures of a Row (precision eps for ulps).
Row tally(const std::string& family, const std::string& method, const std::string& precision, const std::string& case_name,
          const std::string& what, std::size_t rays, const std::vector<Ref>& ref, const std::vector<Out>& out, double eps,
          bool one_to_one, const std::vector<std::uint8_t>& must_hit, bool wrong_roots);

// Runs one method (kern works for float, double and f8) in the three precisions on a case and
// appends three rows.
template <template <class> class P, class K>
void measure(Ctx& x, const Case<P>& c, const std::string& method, const K& kern, bool wrong_roots = false,
             bool with_iterations = false) {
  x.tick(c.family, c.name);
  auto one = [&]<class F>(F*) {
    std::vector<Out> out(c.tests());
    IterCount ic;
    run_pass<F>(c, kern, &out, with_iterations ? &ic : nullptr);
    Row r = tally(c.family, method, prec_name<F>, c.name, c.what, c.nrays(), c.ref, out, prec_eps<F>(), c.one_to_one,
                  c.must_hit, wrong_roots);
    if (with_iterations) {
      const double calls = std::is_same_v<F, f8> ? std::ceil(double(c.tests()) / 8.0) : double(c.tests());
      r.iterations = double(ic.n) / calls;
    } else {
      r.iterations = std::numeric_limits<double>::quiet_NaN();
    }
    r.ns_per_test = time_pass<F>(c, kern, x.o->timing);
    x.rows->push_back(r);
  };
  one((float*)nullptr);
  one((double*)nullptr);
  one((f8*)nullptr);
}

// Family entry points (each in its own translation unit).
void run_triangles(Ctx& x);
void run_spheres(Ctx& x);
void run_quadrics(Ctx& x);
void run_torus(Ctx& x);
void run_boxes(Ctx& x);
void run_secondary(Ctx& x);
void run_implicit(Ctx& x);
void run_quartics(Ctx& x);
std::vector<CaseInfo> triangle_cases();
std::vector<CaseInfo> sphere_cases();
std::vector<CaseInfo> quadric_cases();
std::vector<CaseInfo> torus_cases();
std::vector<CaseInfo> box_cases();
std::vector<CaseInfo> secondary_cases();
std::vector<CaseInfo> implicit_cases();
std::vector<CaseInfo> quartic_cases();

// The cases through the whole tracer (library rb_accuracy_tracer: accuracy/bvh_cases.cpp and
// accuracy/scenes.cpp), which a lab run includes when Options::tracer points here.
struct TracerCases {
  // A closed-mesh triangle case traced through an 8-wide BVH of the mesh (family "bvh" rows).
  void (*mesh_rows)(Ctx& x, const Case<TriVerts>& woop, const std::vector<Vec3f>& verts, const std::vector<std::array<int, 3>>& faces);
  std::vector<CaseInfo> (*scene_cases)();  // family "scene"
  void (*run_scenes)(Ctx& x);
};
std::vector<CaseInfo> scene_cases();
void run_scenes(Ctx& x);

}  // namespace rb::acc
