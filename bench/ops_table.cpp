#include "bench/ops_table.hpp"

#include "bench/specs.hpp"

#include <fmt/format.h>

namespace rb::opstable {
namespace {

using bench::Case;
using bench::Rng;

// What each (kernel, method, case) row says. `lecture` empty: the slides give no count.
struct Entry {
  const char* kernel;
  const char* method;
  const char* kase;
  std::optional<Lecture> lecture;
  const char* note;
};

// Notes state every difference from the slide and its reason (tests/test_ops.cpp checks that a
// row with a difference has a note).
const Entry kEntries[] = {
    {"plane", "lecture", "miss", Lecture{2, 3, 0, 0, 0},
     "miss = ray parallel to the plane (n.p1 == 0): +1 cmp, the parallel test the slide leaves uncounted"},
    {"plane", "lecture", "hit", Lecture{5, 6, 1, 0, 0},
     "+1 cmp parallel test, +2 cmp t within [tmin, tmax], +1 select (t = +inf on missing lanes); the slide counts arithmetic only"},
    {"plane", "point", "hit", Lecture{3, 3, 0, 0, 0}, "[x,y,z] = P0 + t p1, as on the slide"},
    {"triangle", "lecture", "hit", Lecture{14, 14, 3, 3, 0},
     "-1+- -1*: only the two kept coordinates of [x,y,z] are formed (the third is dead code, removed by the compiler anyway); "
     "-1+- -1*: the 2x2 determinant of the [u,v] system is precomputed per triangle (slide's solve 5+-5*2/, ours 4+-4*2/); "
     "+3 cmp: parallel test and t within [tmin, tmax]; +1 select"},
    {"triangle", "lecture", "miss", std::nullopt,
     "miss = ray outside the triangle: plane, point and [u,v] are all needed before the u, v tests fail; the slide gives no negative case"},
    {"triangle", "moller_trumbore", "hit", std::nullopt,
     "not on the slides; Moller-Trumbore 1997 with three early exits (det, u, v)"},
    {"triangle", "moller_trumbore", "miss", std::nullopt, "miss by u > 1: exits after the u test"},
    {"triangle", "normal_mt", "hit", std::nullopt, "e1 x e2 (the lecture form stores n = U x V: 0 ops)"},
    {"sphere", "geometric", "miss", Lecture{9, 6, 0, 1, 0},
     "+1*: the slide's own formulas need 7* (v.p1 3*, v.v 3*, t0^2 1*); the slide's 6* is one short"},
    {"sphere", "geometric", "hit", Lecture{11, 6, 0, 1, 1},
     "+1* as in the miss case; +3 cmp: choosing the root >= tmin and t within [tmin, tmax]; +2 select (root choice, t = +inf on misses)"},
    {"sphere", "algebraic", "miss", std::nullopt, "seed 002's quadratic: A = d.d, B = 2 d.(e-c), C, disc = B^2 - 4AC"},
    {"sphere", "algebraic", "hit", std::nullopt, "both roots (-B -+ sqrt(disc)) / 2A, nearer one >= tmin"},
    {"sphere", "normal", "hit", std::nullopt, "(P - C) / R with 1/R stored per sphere"},
    {"box", "slab", "hit", std::nullopt,
     "branch-free slabs with 1/d precomputed per ray (the slide divides per axis and exits early per axis)"},
    {"box", "slab", "miss", std::nullopt, "no early exit: the same 12 min/max and 1 cmp as a hit"},
};

const Entry* find_entry(const std::string& k, const std::string& m, const std::string& c) {
  for (const auto& e : kEntries)
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

void add_rows(std::vector<Row>& rows, const char* kernel, const char* method, const char* kase,
              const std::array<OpCounts, 3>& c) {
  const Entry* e = find_entry(kernel, method, kase);
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
void add_spec_rows(std::vector<Row>& rows) {
  Rng g(bench::kBenchSeed);
  const auto soa = Spec::build({Spec::make(0, 0, g)});
  const Ray<float> hit = Spec::ray(0, g), miss = ops_miss_ray<Spec>(g);
  const auto prim = soa.template broadcast<float>(0);
  auto fn = [&soa](const auto& r, const auto& p) { (void)Spec::run(r, p, soa, 0); };
  for (const char* kase : {"hit", "miss"}) {
    if (!find_entry(Spec::kernel, Spec::method, kase)) continue;
    const bool h = kase[0] == 'h';
    add_rows(rows, Spec::kernel, Spec::method, kase, count3(fn, prim, h ? hit : miss, h ? miss : hit));
  }
}

// Rows of a function of the hit (point, normal) on the spec's hit ray.
template <class Spec, class Fn>
void add_extra_rows(std::vector<Row>& rows, const char* kernel, const char* method, Fn fn) {
  Rng g(bench::kBenchSeed);
  const auto soa = Spec::build({Spec::make(0, 0, g)});
  const Ray<float> hit = Spec::ray(0, g);
  add_rows(rows, kernel, method, "hit", count3(fn, soa.template broadcast<float>(0), hit, hit));
}

}  // namespace

std::vector<Row> build() {
  std::vector<Row> rows;
  bench::for_each_spec([&]<class Spec>() { add_spec_rows<Spec>(rows); });
  add_extra_rows<bench::PlaneSpec>(rows, "plane", "point", [](const auto& r, const auto&) {
    using F = std::remove_cvref_t<decltype(r.tmin)>;
    (void)hit_point(r, F(3));
  });
  add_extra_rows<bench::SphereGeometricSpec>(rows, "sphere", "normal", [](const auto& r, const auto& s) {
    (void)sphere_normal(s, r.o);
  });
  add_extra_rows<bench::TriangleMTSpec>(rows, "triangle", "normal_mt", [](const auto&, const auto& q) {
    (void)triangle_normal(q);
  });
  return rows;
}

Diff diff(const Row& r) {
  if (!r.lecture) return {0, 0, 0, 0, 0};
  const auto& m = r.measured;
  const auto& l = *r.lecture;
  return {long(m.add + m.fma) - l.add, long(m.mul + m.fma) - l.mul, long(m.div) - l.div, long(m.cmp) - l.cmp,
          long(m.sqrt) - l.sqrt};
}

namespace {
nlohmann::json counts_json(const OpCounts& c) {
  return {{"add", c.add}, {"mul", c.mul}, {"div", c.div}, {"cmp", c.cmp}, {"sqrt", c.sqrt},
          {"minmax", c.minmax}, {"select", c.select}, {"fma", c.fma}};
}
std::string lecture_str(const std::optional<Lecture>& l) {
  if (!l) return "-";
  std::string s = fmt::format("{}\u00b1 {}*", l->add, l->mul);
  if (l->div) s += fmt::format(" {}/", l->div);
  if (l->sqrt) s += fmt::format(" {}sqrt", l->sqrt);
  if (l->cmp) s += fmt::format(" {}cmp", l->cmp);
  return s;
}
std::string diff_str(const Row& r) {
  if (!r.lecture) return "";
  const Diff d = diff(r);
  if (d.zero()) return "0";
  std::string s;
  auto put = [&](long v, const char* u) { if (v) s += fmt::format("{}{:+d}{}", s.empty() ? "" : " ", v, u); };
  put(d.add, "\u00b1"); put(d.mul, "*"); put(d.div, "/"); put(d.sqrt, "sqrt"); put(d.cmp, "cmp");
  return s;
}
}  // namespace

nlohmann::json to_json(const std::vector<Row>& rows) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& r : rows) {
    nlohmann::json j;
    j["kernel"] = r.kernel;
    j["method"] = r.method;
    j["case"] = r.kase;
    j["number"] = r.number;
    if (r.lecture) {
      j["lecture"] = {{"add", r.lecture->add}, {"mul", r.lecture->mul}, {"div", r.lecture->div},
                      {"cmp", r.lecture->cmp}, {"sqrt", r.lecture->sqrt}};
      const Diff d = diff(r);
      j["diff"] = {{"add", d.add}, {"mul", d.mul}, {"div", d.div}, {"cmp", d.cmp}, {"sqrt", d.sqrt}};
    } else {
      j["lecture"] = nullptr;
    }
    j["measured"] = counts_json(r.measured);
    if (r.uniform) j["measured_uniform_packet"] = counts_json(*r.uniform);
    j["note"] = r.note;
    a.push_back(j);
  }
  return a;
}

std::string to_markdown(const std::vector<Row>& rows) {
  std::string s =
      "| kernel | method | case | lecture | measured float | diff | SIMD per lane (mixed packet) | SIMD, uniform packet | note |\n"
      "|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i + 1 < rows.size(); i += 2) {
    const Row& f = rows[i];
    const Row& v = rows[i + 1];
    s += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", f.kernel, f.method, f.kase, lecture_str(f.lecture),
                     f.measured.str(), diff_str(f), v.measured.str(), v.uniform ? v.uniform->str() : "", f.note);
  }
  return s;
}

std::string to_text(const std::vector<Row>& rows) {
  std::string s = fmt::format("{:<10} {:<16} {:<5} {:<22} {:<44} {:<18} {}\n", "kernel", "method", "case", "lecture",
                              "measured (float)", "diff", "simd8 per lane (mixed packet)");
  for (std::size_t i = 0; i + 1 < rows.size(); i += 2) {
    const Row& f = rows[i];
    const Row& v = rows[i + 1];
    s += fmt::format("{:<10} {:<16} {:<5} {:<22} {:<44} {:<18} {}\n", f.kernel, f.method, f.kase, lecture_str(f.lecture),
                     f.measured.str(), diff_str(f), v.measured.str());
    if (!f.note.empty()) s += fmt::format("{:>12}{}\n", "- ", f.note);
  }
  return s;
}

}  // namespace rb::opstable
