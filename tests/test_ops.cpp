// Golden operation counts of the first kernels (Counted<float>, Counted<simd8>), and the rules
// of the ops table: every difference from a slide has a note; the JSON has the documented keys.
#include "bench/bench_name.hpp"
#include "bench/ops_table.hpp"
#include "kernel_test_util.hpp"
#include "bench/specs_planar.hpp"
#include "bench/specs_quadric.hpp"
#include "bench/specs_solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <regex>
#include <tuple>

namespace rb {
namespace {

using test::find_row;
using test::gold;
using test::Golden;
using test::ops_rows;

// Benchmark names in their parts, and back; names of another shape are not kernel benchmarks.
TEST(BenchName, PartsAndBack) {
  const auto b = bench::BenchName::parse("sphere/geometric/rays_in_lanes16/half");
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->kernel, "sphere");
  EXPECT_EQ(b->method, "geometric");
  EXPECT_EQ(b->variant, "rays_in_lanes16");
  EXPECT_EQ(b->kase, "half");
  EXPECT_EQ(b->kernel_method(), "sphere/geometric");
  EXPECT_EQ(b->str(), "sphere/geometric/rays_in_lanes16/half");
  for (const char* other : {"wide_node_slab/fast/l1", "a/b/c/d/e", "", "sphere", "a/b/c/d/", "a//c/d"})
    EXPECT_FALSE(bench::BenchName::parse(other).has_value()) << other;
}

TEST(OpsTable, GoldenScalarCounts) {
  // The lecture's plane: negative 2+- 3*, positive 5+- 6* 1/ (+ comparisons and the final select).
  EXPECT_EQ(gold(find_row("plane", "lecture", "miss", "float").measured), Golden(2, 3, 0, 0, 1, 0, 0, 0));
  EXPECT_EQ(gold(find_row("plane", "lecture", "hit", "float").measured), Golden(5, 6, 1, 0, 3, 0, 1, 0));
  EXPECT_EQ(gold(find_row("plane", "point", "hit", "float").measured), Golden(3, 3, 0, 0, 0, 0, 0, 0));
  // Sphere, geometric: negative 11+- 12* 1 cmp (the lecture's 9+- 7* with a = p1.p1 and the
  // squares times a, since a float unit direction is not of length 1); positive additionally
  // 2+- 2* 1/ 1 sqrt.
  EXPECT_EQ(gold(find_row("sphere", "geometric", "miss", "float").measured), Golden(11, 12, 0, 0, 1, 0, 0, 0));
  EXPECT_EQ(gold(find_row("sphere", "geometric", "hit", "float").measured), Golden(13, 14, 1, 1, 4, 0, 2, 0));
  EXPECT_EQ(gold(find_row("sphere", "algebraic", "miss", "float").measured), Golden(11, 13, 0, 0, 1, 0, 0, 0));
  EXPECT_EQ(gold(find_row("sphere", "algebraic", "hit", "float").measured), Golden(13, 14, 2, 1, 4, 0, 2, 0));
  EXPECT_EQ(gold(find_row("triangle", "lecture", "hit", "float").measured), Golden(12, 12, 3, 0, 6, 0, 1, 0));
  EXPECT_EQ(gold(find_row("triangle", "moller_trumbore", "hit", "float").measured), Golden(18, 27, 1, 0, 7, 0, 1, 0));
  EXPECT_EQ(gold(find_row("triangle", "moller_trumbore", "miss", "float").measured), Golden(10, 13, 1, 0, 3, 0, 0, 0));
  // Box: entry and exit 10 min/max, then the first crossing in [tmin, tmax] (exit from inside).
  EXPECT_EQ(gold(find_row("box", "slab", "hit", "float").measured), Golden(6, 6, 0, 0, 4, 10, 2, 0));
  EXPECT_EQ(gold(find_row("box", "slab", "miss", "float").measured), Golden(6, 6, 0, 0, 4, 10, 2, 0));
}

TEST(OpsTable, SimdRunsTheWholeKernelWhenLanesDisagree) {
  // A missing lane in a packet with hitting lanes pays the full hit path.
  EXPECT_EQ(gold(find_row("sphere", "geometric", "miss", "simd8").measured), gold(find_row("sphere", "geometric", "hit", "float").measured));
  EXPECT_EQ(gold(find_row("plane", "lecture", "miss", "simd8").measured), gold(find_row("plane", "lecture", "hit", "float").measured));
  // A packet whose lanes all miss exits early exactly like the scalar code.
  EXPECT_EQ(gold(*find_row("sphere", "geometric", "miss", "simd8").uniform), gold(find_row("sphere", "geometric", "miss", "float").measured));
}

TEST(OpsTable, EveryDifferenceFromTheSlideHasANote) {
  for (const auto& r : ops_rows()) {
    if (!r.lecture) continue;
    if (!opstable::diff(r).zero()) {
      EXPECT_FALSE(r.note.empty()) << r.kernel << "/" << r.method << "/" << r.kase;
    }
  }
}

// The counts a note writes (3+-, 9*, 1/, 1 sqrt, 1 cmp, 2 min/max, 1 select), summed per kind; an
// FMA is one + and one *, as in the table. "1/pi" or "x^2 + y" are not counts: a count is a number
// right before its unit, and "/" counts only when no name or number follows it.
struct Stated {
  long add = 0, mul = 0, div = 0, sqrt = 0, cmp = 0, minmax = 0, select = 0;
  bool operator==(const Stated&) const = default;
};
std::ostream& operator<<(std::ostream& o, const Stated& s) {
  return o << s.add << "+- " << s.mul << "* " << s.div << "/ " << s.sqrt << " sqrt " << s.cmp << " cmp " << s.minmax << " min/max "
           << s.select << " select";
}
Stated stated_sum(const std::string& note) {
  static const std::regex term(R"((^|[^\w^.])(\d+) ?(\+-|\*|/(?![\w(])|sqrt\b|cmp\b|min/max\b|select\b))");
  Stated s;
  for (auto it = std::sregex_iterator(note.begin(), note.end(), term); it != std::sregex_iterator(); ++it) {
    const long n = std::stol((*it)[2]);
    const std::string u = (*it)[3];
    (u == "+-" ? s.add : u == "*" ? s.mul : u == "/" ? s.div : u == "sqrt" ? s.sqrt : u == "cmp" ? s.cmp : u == "min/max" ? s.minmax : s.select) += n;
  }
  return s;
}
Stated measured_sum(const OpCounts& m) {
  return {long(m.add + m.fma), long(m.mul + m.fma), long(m.div), long(m.sqrt), long(m.cmp), long(m.minmax), long(m.select)};
}

TEST(OpsTable, StatedSumParserReadsCountsOnly) {
  EXPECT_EQ(stated_sum("f 3+-; a 2+- 3*, 1/pi and 1/2pi 2*; x^2 + y^2 1 sqrt (N.E)/sin 1/; 2 clamps = 4 min/max; 1 cmp 1 select"),
            (Stated{5, 5, 1, 1, 1, 4, 1}));
}

// Where a note lists the parts of its row (kNoteSums), the parts add up to the measured float row.
TEST(OpsTable, NotesThatStateTheirPartsAddUpToTheMeasuredRow) {
  int checked = 0;
  for (const auto& r : ops_rows()) {
    if (!r.note_sums || r.number != "float") continue;
    ++checked;
    EXPECT_EQ(stated_sum(r.note), measured_sum(r.measured)) << r.kernel << "/" << r.method << "/" << r.kase << ": " << r.note;
  }
  EXPECT_GE(checked, 5);
}

// Every benchmarked spec has its ops per test in rb_ops (a family that forgets to add its specs to
// the table would report NaN in every benchmark). The miss case: cheap, every lane exits early.
TEST(OpsTable, EveryBenchmarkedSpecHasItsOpsPerTest) {
  int n = 0;
  auto check = [&n]<class Spec>() {
    ++n;
    const double x = bench::ops_per_test(Spec::kernel, Spec::method, bench::Case::miss, bench::Variant::scalar);
    EXPECT_TRUE(std::isfinite(x) && x > 0) << Spec::kernel << "/" << Spec::method << ": " << x;
  };
  bench::for_each_spec(check);
  bench::for_each_spec_planar(check);
  bench::for_each_spec_quadric(check);
  bench::for_each_spec_solver(check);
  EXPECT_GE(n, 30);
  EXPECT_TRUE(std::isnan(bench::ops_per_test("no_such", "kernel", bench::Case::hit, bench::Variant::scalar)));
}

TEST(OpsTable, JsonHasTheDocumentedKeys) {
  const auto j = opstable::to_json(ops_rows());
  ASSERT_TRUE(j.is_array());
  ASSERT_FALSE(j.empty());
  for (const auto& r : j) {
    for (const char* k : {"kernel", "method", "case", "number", "lecture", "measured", "note"}) EXPECT_TRUE(r.contains(k)) << k;
    EXPECT_TRUE(r["case"] == "hit" || r["case"] == "miss");
    EXPECT_TRUE(r["number"] == "float" || r["number"] == "simd8");
    for (const char* k : {"add", "mul", "div", "cmp", "sqrt", "minmax", "select", "fma"}) EXPECT_TRUE(r["measured"].contains(k)) << k;
    if (!r["lecture"].is_null()) {
      for (const char* k : {"add", "mul", "div", "cmp", "sqrt"}) EXPECT_TRUE(r["lecture"].contains(k)) << k;
    }
  }
}

}  // namespace
}  // namespace rb
