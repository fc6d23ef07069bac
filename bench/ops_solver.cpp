// Ops-table rows of the solver kernel family. The slides give no counts for these methods: the
// rows are measured counts with a note saying what they contain. Iterative solvers also report
// loop trips per ray (mean, max) over the bench spec's 256 rays x 8 primitives, scalar float;
// transcendental calls (sin, cos, acos, cbrt: not in OpCounts) are appended to the note.
#include "bench/ops_detail.hpp"
#include "bench/specs_solver.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace rb::opstable {
namespace {

#define RB_SIMD_NOTE                                                                                             \
  " SIMD: a packet iterates until its slowest lane converges (finished lanes are masked), so the per-lane count " \
  "is the packet maximum and the speedup over scalar is bounded by mean/max iterations across the packet."

// (kernel, method, case, the slide's count or std::nullopt, note explaining every difference)
const Entry kSolverEntries[] = {
    {"torus", "ferrari", "hit", std::nullopt,
     "closed form: bounding sphere, quartic at the ray origin, depressed quartic, Schwarze resolvent cubic "
     "(Cardano or trigonometric largest root), two quadratics, 4-root sort; no iterations, every lane does the same work"},
    {"torus", "ferrari", "miss", std::nullopt, "miss = outside the bounding sphere |q| <= R + r: 1 sqrt-free test"},
    {"torus", "robust", "hit", std::nullopt,
     "origin moved to the bounding-sphere entry, quartic in s, roots isolated between the roots of its derivatives "
     "(quadratic closed form, then safeguarded Newton on the cubic and the quartic), 2 Newton polish steps on T_ab "
     "at the point." RB_SIMD_NOTE},
    {"torus", "robust", "miss", std::nullopt, "miss = outside the bounding sphere (same test as ferrari)"},
    {"algebraic", "isolation_d4", "hit", std::nullopt,
     "degree 4 (the torus as 35 coefficients): A*(s) by nested Horner on polynomials in s at the bounding-sphere "
     "entry, then derivative isolation + safeguarded Newton on [0, t1 - t0]." RB_SIMD_NOTE},
    {"algebraic", "isolation_d4", "miss", std::nullopt, "miss = outside the bounding sphere"},
    {"algebraic", "isolation_d6", "hit", std::nullopt,
     "degree 6 (product of three spheres, 84 coefficients): expansion O(terms x degree), isolation recursion "
     "through degrees 2..6." RB_SIMD_NOTE},
    {"algebraic", "isolation_d6", "miss", std::nullopt, "miss = outside the bounding sphere"},
    {"implicit", "sphere_tracing", "hit", std::nullopt,
     "slide's surface (c - cos ax) cos z + (y + a sin ax) sin z + cos a(x+z), a = 1, c = 0.5, step |F|/L with a "
     "global Lipschitz bound L on the ball; per step 1 evaluation (3 cos + 2 sin: cos ax, cos z, cos a(x+z), sin ax, "
     "sin z)." RB_SIMD_NOTE},
    {"implicit", "sphere_tracing", "miss", std::nullopt, "miss = outside the bounding sphere"},
    {"implicit", "illinois", "hit", std::nullopt,
     "fixed step h = radius/8 until F changes sign, then Illinois regula falsi to 1e-4 radius; per step 1 "
     "evaluation. The SIMD lane and the scalar form may differ by whole Illinois steps (one evaluation and the secant, "
     "one division each), in either direction: xsimd's sin and cos round differently from the C library's, so the secant "
     "iterates reach the tolerance after a different number of steps. That is rounding, not a SIMD cost or saving." RB_SIMD_NOTE},
    {"implicit", "illinois", "miss", std::nullopt, "miss = outside the bounding sphere"},
    {"revolution", "polynomial", "hit", std::nullopt,
     "seed 000's ray in the rz plane a r^2 + b z^2 + c z + d = 0, cubic profile -> K*(s) of degree 6 on [0, 1] "
     "(derivative isolation + Newton), t = (z(s) - z0) / z1, nearest in range." RB_SIMD_NOTE},
    {"revolution", "polynomial", "miss", std::nullopt, "miss = outside the bounding sphere of the profile"},
    {"revolution", "bezier", "hit", std::nullopt,
     "cubic Bezier profile, converted to power basis at construction: same kernel as polynomial." RB_SIMD_NOTE},
    {"revolution", "bezier", "miss", std::nullopt, "miss = outside the bounding sphere of the profile"},
    {"torus", "normal", "hit", std::nullopt, "grad T_ab = 4 G q + 8 R^2 z w, normalised"},
    {"torus", "uv", "hit", std::nullopt, "the two angles: 2 atan2, 1 sqrt"},
};

// Iterations per ray (mean, max) for the class-c rays against the class-0 primitives.
template <class Spec>
std::pair<double, double> iteration_stats(int cls) {
  bench::Rng g(bench::kBenchSeed);
  std::vector<typename Spec::Input> in;
  for (int k = 0; k < 8; ++k) in.push_back(Spec::make(0, k, g));
  const auto soa = Spec::build(in);
  double sum = 0, mx = 0;
  int n = 0;
  for (int i = 0; i < 256; ++i) {
    const Ray<float> r = Spec::ray(cls, g);
    for (std::size_t j = 0; j < Spec::count(soa); ++j) {
      IterCount ic;
      (void)Spec::run_ic(r, soa.template broadcast<float>(j), &ic);
      sum += ic.n;
      mx = std::max(mx, double(ic.n));
      ++n;
    }
  }
  return {sum / n, mx};
}

// Transcendental calls of one scalar run on the spec's hit ray.
template <class Spec>
std::uint64_t trans_calls() {
  bench::Rng g(bench::kBenchSeed);
  const auto soa = Spec::build({Spec::make(0, 0, g)});
  const Ray<float> r = Spec::ray(0, g);
  const std::uint64_t before = ops::trans_current();
  (void)counted_run<Spec>(Ray<cfloat>::broadcast(r), soa.template broadcast<cfloat>(0), soa, 0);
  return ops::trans_current() - before;
}

template <class Spec>
void add_solver_spec(std::span<const Entry> e, std::vector<Row>& rows) {
  const std::size_t first = rows.size();
  add_spec_rows<Spec>(e, rows);
  const std::uint64_t tr = trans_calls<Spec>();
  for (std::size_t i = first; i < rows.size(); ++i) {
    if constexpr (requires { &Spec::template run_ic<float>; })
      rows[i].iterations = iteration_stats<Spec>(rows[i].kase == "hit" ? 0 : 1);
    if (tr && rows[i].kase == "hit") rows[i].note += fmt::format(" Transcendental calls (hit, float): {}.", tr);
  }
}

}  // namespace

void add_solver_rows(std::vector<Row>& rows) {
  const std::span<const Entry> e = kSolverEntries;
  add_solver_spec<bench::TorusFerrariSpec>(e, rows);
  add_solver_spec<bench::TorusRobustSpec>(e, rows);
  add_solver_spec<bench::AlgebraicD4Spec>(e, rows);
  add_solver_spec<bench::AlgebraicD6Spec>(e, rows);
  add_solver_spec<bench::ImplicitSphereTraceSpec>(e, rows);
  add_solver_spec<bench::ImplicitIllinoisSpec>(e, rows);
  add_solver_spec<bench::RevolutionPolySpec>(e, rows);
  add_solver_spec<bench::RevolutionBezierSpec>(e, rows);
  add_extra_rows<bench::TorusRobustSpec>(e, rows, "torus", "normal", [](const auto& r, const auto& t) {
    (void)torus_normal(t, r.o);
  });
  add_extra_rows<bench::TorusRobustSpec>(e, rows, "torus", "uv", [](const auto& r, const auto& t) {
    using F = std::remove_cvref_t<decltype(r.tmin)>;
    F u, v;
    torus_uv(t, r.o, u, v);
  });
}

void add_solver_ops_per_test(std::vector<OpsPerTest>& t) {
  bench::for_each_spec_solver([&]<class Spec>() { t.push_back(ops_per_test_entry<Spec>()); });
}

}  // namespace rb::opstable
