#include "bench/ops_table.hpp"

#include "bench/ops_detail.hpp"
#include "bench/specs.hpp"
#include "core/text.hpp"

#include <fmt/format.h>

namespace rb::opstable {
namespace {

// Notes state every difference from the slide and its reason (tests/test_ops.cpp checks that a
// row with a difference has a note).
const Entry kBasicEntries[] = {
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
     "+1*: the slide's own formulas need 7* (v.p1 3*, v.v 3*, t0^2 1*); the slide's 6* is one short; "
     "+2+- +5*: a = p1.p1 (2+- 3*) where the slide assumes |p1| = 1, the squares kept times a (a v.v, a R^2: 2*): a "
     "float-rounded unit direction is 1 +- 1e-7 long, and t0^2 then misclassified half the rays at distance/R = 1e4, even in double"},
    {"sphere", "geometric", "hit", Lecture{11, 6, 0, 1, 1},
     "+2+- +7* +1/: as in the miss case, then 1/a, t0/a and sqrt(a tD^2)/a (1/ 2*); +3 cmp: choosing the root >= tmin and t "
     "within [tmin, tmax]; +2 select (root choice, t = +inf on misses)"},
    {"sphere", "algebraic", "miss", std::nullopt, "seed 002's quadratic: A = d.d, B = 2 d.(e-c), C, disc = B^2 - 4AC"},
    {"sphere", "algebraic", "hit", std::nullopt, "both roots (-B -+ sqrt(disc)) / 2A, nearer one >= tmin"},
    {"sphere", "normal", "hit", std::nullopt, "(P - C) / R with 1/R stored per sphere"},
    {"box", "slab", "hit", std::nullopt,
     "branch-free slabs with 1/d precomputed per ray (the slide divides per axis and exits early per axis); entry and exit "
     "10 min/max; the first surface crossing in [tmin, tmax] (the exit from inside, as the sphere): 4 cmp 1 select + make_hit"},
    {"box", "slab", "miss", std::nullopt, "no early exit: the same 10 min/max, 4 cmp and 2 select as a hit"},
};

}  // namespace

void add_basic_rows(std::vector<Row>& rows) {
  const std::span<const Entry> e = kBasicEntries;
  add_spec_rows<bench::PlaneSpec>(e, rows);
  add_spec_rows<bench::TriangleLectureSpec>(e, rows);
  add_spec_rows<bench::TriangleMTSpec>(e, rows);
  add_spec_rows<bench::SphereGeometricSpec>(e, rows);
  add_spec_rows<bench::SphereAlgebraicSpec>(e, rows);
  add_spec_rows<bench::BoxSpec>(e, rows);
  add_extra_rows<bench::PlaneSpec>(e, rows, "plane", "point", [](const auto& r, const auto&) {
    using F = std::remove_cvref_t<decltype(r.tmin)>;
    (void)hit_point(r, F(3));
  });
  add_extra_rows<bench::SphereGeometricSpec>(e, rows, "sphere", "normal", [](const auto& r, const auto& s) {
    (void)sphere_normal(s, r.o);
  });
  add_extra_rows<bench::TriangleMTSpec>(e, rows, "triangle", "normal_mt", [](const auto&, const auto& q) {
    (void)triangle_normal(q);
  });
}

void add_basic_ops_per_test(std::vector<OpsPerTest>& t) {
  bench::for_each_spec([&]<class Spec>() { t.push_back(ops_per_test_entry<Spec>()); });
}

std::vector<Row> build() {
  std::vector<Row> rows;
  add_basic_rows(rows);
  add_planar_rows(rows);
  add_quadric_rows(rows);
  add_solver_rows(rows);
  add_csg_rows(rows);
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
    if (r.iterations) j["iterations"] = {{"mean", r.iterations->first}, {"max", r.iterations->second}};
    a.push_back(j);
  }
  return a;
}

std::vector<Row> from_json(const nlohmann::json& rows) {
  auto counts = [](const nlohmann::json& j) {
    OpCounts c;
    c.add = j.at("add"), c.mul = j.at("mul"), c.div = j.at("div"), c.cmp = j.at("cmp"), c.sqrt = j.at("sqrt");
    c.minmax = j.at("minmax"), c.select = j.at("select"), c.fma = j.at("fma");
    return c;
  };
  std::vector<Row> out;
  for (const auto& j : rows) {
    Row r;
    r.kernel = j.at("kernel"), r.method = j.at("method"), r.kase = j.at("case"), r.number = j.at("number");
    if (!j.at("lecture").is_null()) {
      const auto& l = j["lecture"];
      r.lecture = Lecture{l.at("add"), l.at("mul"), l.at("div"), l.at("cmp"), l.at("sqrt")};
    }
    r.measured = counts(j.at("measured"));
    if (j.contains("measured_uniform_packet")) r.uniform = counts(j["measured_uniform_packet"]);
    r.note = j.at("note");
    if (j.contains("iterations")) r.iterations = std::make_pair(j["iterations"].at("mean").get<double>(), j["iterations"].at("max").get<double>());
    out.push_back(std::move(r));
  }
  return out;
}

std::string to_markdown(const std::vector<Row>& rows) {
  std::string s =
      "| kernel | method | case | lecture | measured float | diff | SIMD per lane (mixed packet) | SIMD, uniform packet | note |\n"
      "|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i + 1 < rows.size(); i += 2) {
    const Row& f = rows[i];
    const Row& v = rows[i + 1];
    s += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", f.kernel, f.method, f.kase, lecture_str(f.lecture),
                     f.measured.str(), diff_str(f), v.measured.str(), v.uniform ? v.uniform->str() : "",
                     f.iterations ? fmt::format("iterations per ray: mean {:.2f}, max {:.0f}. {}", f.iterations->first,
                                                f.iterations->second, f.note)
                                  : f.note);
  }
  return s;
}


// The terminal table, within 80 columns: per kernel, method and case the Counted<float> count,
// then (indented) the lecture's count with the difference and the SIMD per-lane count where it
// differs from the scalar one; with `notes`, the reason for every difference.
std::string to_text(const std::vector<Row>& rows, bool notes) {
  std::string s = fmt::format("{:<28} {:<4} {}\n", "kernel/method", "case", "Counted<float> operations per test");
  s += "      then the lecture's count (measured - lecture) and, where it differs, the\n"
       "      simd8 count per lane in a packet whose other lanes take the other case\n"
       "      (\u00b1 add/sub, * mul, / div, cmp compares, sel selects; FMA = 1\u00b1 1*)\n";
  for (std::size_t i = 0; i + 1 < rows.size(); i += 2) {
    const Row& f = rows[i];
    const Row& v = rows[i + 1];
    const std::string km = f.kernel + "/" + f.method;
    s += fmt::format("{:<28} {:<4} {}\n", km, f.kase, f.measured.str());
    std::string more;
    if (f.lecture) {
      const std::string d = diff_str(f);
      more = "lecture " + lecture_str(f.lecture) + (d == "0" ? " (equal)" : " (" + d + ")");
    }
    if (v.measured.str() != f.measured.str()) more += (more.empty() ? "" : "; ") + std::string("simd8 ") + v.measured.str();
    if (f.iterations) more += (more.empty() ? "" : "; ") + fmt::format("iterations per ray: mean {:.2f}, max {:.0f}", f.iterations->first, f.iterations->second);
    if (!more.empty()) s += wrap_words("      " + more, 80, "      ");
    if (notes && !f.note.empty()) s += wrap_words("      note: " + f.note, 80, "        ");
  }
  if (!notes) s += "\nThe reason for every difference: raybench ops --notes\n";
  return s;
}

}  // namespace rb::opstable
