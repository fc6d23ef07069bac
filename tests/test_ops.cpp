// Golden operation counts of the first kernels (Counted<float>, Counted<simd8>), and the rules
// of the ops table: every difference from a slide has a note; the JSON has the documented keys.
#include "bench/ops_table.hpp"
#include "kernel_test_util.hpp"

#include <gtest/gtest.h>

#include <map>

namespace rb {
namespace {

using test::find_row;
using test::gold;
using test::Golden;
using test::ops_rows;

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
