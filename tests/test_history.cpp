// The results history (apps/history.hpp): the SQLite schema round trip, runs kept by the binary
// with --history and RAYBENCH_HISTORY, `raybench history` listing runs and following a metric (with
// its chart), and the git revision recorded when the binary was built, not when it runs.
#include "apps/build_info.hpp"
#include "apps/results/history.hpp"
#include "apps/results/machine.hpp"
#include "cli_test_util.hpp"

#include <gtest/gtest.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <regex>

namespace {

using namespace rbtest;
using nlohmann::json;

TEST(History, StoresRunsAndFollowsAMetric) {
  Scratch s("history-unit");
  const std::string db = s / "sub/h.sqlite";  // the folder is made
  json m = rb::app::machine().json();
  {
    rb::app::History h(db);
    rb::app::Figure f;
    f.section = "bench";
    f.name = "k/m/scalar/hit";
    f.metric = "tests_per_s";
    f.unit = "Mtests/s";
    f.scale = 1e-6;
    f.samples = {1e8, 1.1e8, 0.9e8};
    f.value = 1e8;
    rb::app::Figure g = f;
    g.name = "k/m/scalar/miss";
    g.value = 2e8;
    g.samples = {};
    EXPECT_EQ(h.store("bench", "raybench bench", m, {f, g}), 1);
    f.value = 1.2e8;
    m["git_revision"] = "0123456789ab";
    m["git_dirty"] = true;
    EXPECT_EQ(h.store("bench", "raybench bench -r 3", m, {f}), 2);
  }
  const rb::app::History h(db, false);  // read back, read-only
  const auto runs = h.runs();
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0].kind, "bench");
  EXPECT_EQ(runs[0].figures, 2);
  EXPECT_EQ(runs[1].git_revision, "0123456789ab");
  EXPECT_TRUE(runs[1].git_dirty);
  EXPECT_EQ(runs[1].cpu, m["cpu"].get<std::string>());
  EXPECT_EQ(runs[1].build_flags, m["build_flags"].get<std::string>());
  EXPECT_EQ(runs[1].pgo, m["pgo"].get<std::string>());
  EXPECT_EQ(runs[1].isa, m["host_simd"].get<std::string>());
  EXPECT_FALSE(runs[1].time.empty());
  EXPECT_EQ(h.runs("miss$").size(), 1u);  // the filter is a regex on section/name
  const auto pts = h.series("tests_per_s", "scalar/hit");
  ASSERT_EQ(pts.size(), 2u);
  EXPECT_DOUBLE_EQ(pts[0].value, 1e8);
  EXPECT_DOUBLE_EQ(pts[1].value, 1.2e8);
  EXPECT_EQ(pts[0].n, 3);
  EXPECT_NEAR(pts[0].cv, 0.1, 1e-12);
  EXPECT_TRUE(h.series("nosuch").empty());
  // Not a history: one line naming the file.
  std::ofstream(s / "text.sqlite") << "this is not a database, just text that is long enough to have a header";
  try {
    rb::app::History bad(s / "text.sqlite", false);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(has(e.what(), "text.sqlite: not a raybench history")) << e.what();
  }
  EXPECT_THROW(rb::app::History(s / "missing.sqlite", false), std::runtime_error);
}

TEST(History, HistoryPathPrecedence) {
  ::unsetenv(rb::app::kHistoryEnv);
  EXPECT_EQ(rb::app::history_path("", ""), "");
  EXPECT_EQ(rb::app::history_path("", rb::app::kReportHistory), "results/history.sqlite");
  ::setenv(rb::app::kHistoryEnv, "env.sqlite", 1);
  EXPECT_EQ(rb::app::history_path("", rb::app::kReportHistory), "env.sqlite");
  EXPECT_EQ(rb::app::history_path("opt.sqlite", rb::app::kReportHistory), "opt.sqlite");
  ::unsetenv(rb::app::kHistoryEnv);
}

TEST(History, BinaryKeepsRunsAndPlotsAMetric) {
  Scratch s("history-bin");
  std::ofstream(s / "oct.obj") << "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
                                  "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";
  const std::string bench = "bench --filter '^box/slab/(scalar|prims_in_lanes)/hit$' -r 2 --min-time 0.001";
  Outcome r = run_in(s.dir, bench + " --history h.sqlite");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.err, "kept as run 1")) << r.err;
  ASSERT_EQ(run_in(s.dir, bench, "RAYBENCH_HISTORY=h.sqlite").status, 0);  // the environment variable
  ASSERT_EQ(run_in(s.dir, "trace oct.obj --count 64 -r 2 --warmup 0", "RAYBENCH_HISTORY=h.sqlite").status, 0);
  ASSERT_EQ(run_in(s.dir, "render oct.obj --width 8 -r 1 --warmup 0 -o o.png --history h.sqlite").status, 0);
  ASSERT_EQ(run_in(s.dir, "accuracy --filter '^box/flat' --rays 16 --no-timing --history h.sqlite").status, 0);
  ASSERT_EQ(run_in(s.dir, "bench --list --history h.sqlite").status, 0);  // a listing is not a run

  r = run_in(s.dir, "history --history h.sqlite");
  EXPECT_EQ(r.status, 0) << r.err;
  for (const char* kind : {"bench", "trace", "render", "accuracy"}) EXPECT_TRUE(has(r.out, kind)) << r.out;
  EXPECT_TRUE(has(r.out, "5 run(s)")) << r.out;
  EXPECT_LE(widest(r.out), 80u) << r.out;
  r = run_in(s.dir, "history --history h.sqlite --json -");
  const json runs = r.json()["runs"];
  ASSERT_EQ(runs.size(), 5u);
  EXPECT_EQ(runs[0]["git_revision"], rb::app::build_info().git_revision);
  EXPECT_EQ(runs[0]["git_dirty"], rb::app::build_info().git_dirty);
  EXPECT_TRUE(has(runs[2]["command"].get<std::string>(), "trace oct.obj")) << runs[2];

  r = run_in(s.dir, "history --history h.sqlite --metric tests_per_s --filter 'slab/scalar' --plot p.png");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "tests_per_s (Mtests/s, higher is better): bench/box/slab/scalar/hit")) << r.out;
  EXPECT_EQ(slurp(s / "p.png").substr(1, 3), "PNG");
  r = run_in(s.dir, "history --history h.sqlite --metric tests_per_s --json -");
  const json series = r.json();
  EXPECT_EQ(series["series"].size(), 2u);  // two benchmarks, each in two runs
  EXPECT_EQ(series["runs"].size(), 2u);

  // Two runs of the history compared by id: the two bench runs (1 and 2), figures and repetitions as
  // stored; a bench run against the trace run is refused (other kinds); ids must be ids.
  r = run_in(s.dir, "compare --history h.sqlite 1 2 --json -");
  EXPECT_EQ(r.status, 0) << r.err;
  const json cmp = r.json();
  EXPECT_EQ(cmp["kind"], "bench");
  EXPECT_EQ(cmp["rows"].size(), 2u);
  EXPECT_EQ(cmp["rows"][0]["a_samples"].size(), 2u);
  EXPECT_TRUE(has(cmp["a"]["source"].get<std::string>(), "h.sqlite run 1")) << cmp["a"];
  EXPECT_EQ(run_in(s.dir, "compare --history h.sqlite 1 3").status, 1);
  r = run_in(s.dir, "compare --history h.sqlite 1 x");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(has(r.err, "run ids")) << r.err;
  r = run_in(s.dir, "compare --history h.sqlite 1 99");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(has(r.err, "no run 99")) << r.err;

  r = run_in(s.dir, "history --history h.sqlite --metric nosuch");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(has(r.err, "stored metrics:")) << r.err;
  r = run_in(s.dir, "history --history h.sqlite --filter 'nosuch'");
  EXPECT_EQ(r.status, 2);
  r = run_in(s.dir, "history --history missing.sqlite");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(has(r.err, std::strerror(ENOENT))) << r.err;
}

// The revision is written into the binary when it is built: with no git on PATH at run time the
// binary still names it (it never asks the source tree when it runs).
TEST(History, RevisionIsRecordedAtBuildTime) {
  Scratch s("revision");
  const Outcome r = run_in(s.dir, "machine --json", "PATH=/nonexistent");
  ASSERT_EQ(r.status, 0) << r.err;
  const json m = r.json();
  EXPECT_EQ(m["git_revision"], rb::app::build_info().git_revision);
  if (rb::app::build_info().git_revision != "unknown") {
    EXPECT_TRUE(std::regex_match(m["git_revision"].get<std::string>(), std::regex("[0-9a-f]{7,40}"))) << m;
  }
  EXPECT_EQ(m["git"], rb::app::build_info().git());
  EXPECT_TRUE(m["git_dirty"].is_boolean());
}

}  // namespace
