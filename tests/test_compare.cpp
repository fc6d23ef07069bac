// `raybench compare` and its statistics: the Mann-Whitney U test against SciPy's test vectors
// (tests/data/mannwhitney), the row matching, verdicts, summary and --threshold on results of every
// kind, and the binary comparing two runs of its own.
#include "apps/results/compare.hpp"
#include "apps/results/results.hpp"
#include "apps/results/stats.hpp"
#include "cli_test_util.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <cmath>
#include <random>
#include <vector>

namespace {

using namespace rbtest;
using nlohmann::json;

TEST(Stats, MannWhitneyMatchesScipy) {
  const json v = json::parse(slurp(std::string(RB_TEST_DATA) + "/mannwhitney/vectors.json"));
  ASSERT_GE(v["cases"].size(), 40u);
  int exact = 0, asymptotic = 0;
  for (const auto& c : v["cases"]) {
    const auto a = c["a"].get<std::vector<double>>(), b = c["b"].get<std::vector<double>>();
    const rb::stats::UTest t = rb::stats::mann_whitney_u(a, b);
    const double p = c["p"].get<double>();
    EXPECT_DOUBLE_EQ(t.u1, c["u1"].get<double>()) << c["what"];
    // Exact p-values are ratios of integer counts: equal to rounding; the normal approximation's
    // erfc agrees with SciPy's to about 1e-12 relative.
    EXPECT_NEAR(t.p, p, 1e-12 + 1e-9 * p) << c["what"];
    (t.exact ? exact : asymptotic)++;
  }
  EXPECT_GT(exact, 5);
  EXPECT_GT(asymptotic, 5);
}

// The paired-ratio interval: its order statistics and stated coverage, checked on a synthetic
// workload with known noise (a load drift shared by both sides of a round, independent lognormal
// noise per side): over many runs the interval holds the true ratio as often as it says.
// Two samples measured apart: the ratio of their medians and the Mann-Whitney test inverted on
// log values. Exact figures on a small case, then the stated coverage on samples that differ by a
// known factor (lognormal noise, no shared drift: the model the interval is exact for).
TEST(Stats, UnpairedRatioIntervalHasItsStatedCoverage) {
  using rb::stats::unpaired_ratio;
  const auto r2 = unpaired_ratio({2, 4}, {1, 2});  // ratios 1, 2, 2, 4; P(U <= 0) = 1/6: the range only
  EXPECT_DOUBLE_EQ(r2.ratio, 2.0);
  EXPECT_DOUBLE_EQ(r2.lo, 1.0);
  EXPECT_DOUBLE_EQ(r2.hi, 4.0);
  EXPECT_DOUBLE_EQ(r2.coverage, 1 - 2.0 / 6);
  EXPECT_FALSE(r2.paired);
  EXPECT_EQ(r2.n, 2u);
  EXPECT_FALSE(unpaired_ratio({1}, {1, 2}).valid());
  // 7 and 7: P(U <= 8) = 0.0189, P(U <= 9) = 0.0265 > 0.025: k = 9, the 9th smallest and largest of 49.
  const auto r7 = unpaired_ratio({1, 2, 3, 4, 5, 6, 7}, {1, 2, 3, 4, 5, 6, 7});
  EXPECT_DOUBLE_EQ(r7.ratio, 1.0);
  EXPECT_NEAR(r7.coverage, 1 - 2 * 0.0189, 5e-4);
  EXPECT_LT(r7.lo, 1.0);
  EXPECT_GT(r7.hi, 1.0);
  std::mt19937_64 g(777);
  std::normal_distribution<double> noise(0, 0.1);
  const double truth = 1.8;
  int covered = 0;
  const int trials = 4000;
  double stated = 0;
  for (int t = 0; t < trials; ++t) {
    std::vector<double> a, b;
    for (int i = 0; i < 7; ++i) a.push_back(truth * std::exp(noise(g))), b.push_back(std::exp(noise(g)));
    const auto r = unpaired_ratio(a, b);
    stated = r.coverage;
    covered += r.lo <= truth && truth <= r.hi;
  }
  EXPECT_NEAR(double(covered) / trials, stated, 0.012);
  EXPECT_GE(stated, 0.95);
}

TEST(Stats, PairedRatioIntervalHasItsStatedCoverage) {
  using rb::stats::paired_ratio;
  const auto r6 = paired_ratio({6, 5, 4, 3, 2, 1}, {1, 1, 1, 1, 1, 1});
  EXPECT_EQ(r6.n, 6u);
  EXPECT_DOUBLE_EQ(r6.ratio, 3.5);
  EXPECT_DOUBLE_EQ(r6.lo, 1);
  EXPECT_DOUBLE_EQ(r6.hi, 6);
  EXPECT_DOUBLE_EQ(r6.coverage, 1 - 2.0 / 64);
  const auto r9 = paired_ratio({1, 2, 3, 4, 5, 6, 7, 8, 9}, std::vector<double>(9, 2));
  EXPECT_DOUBLE_EQ(r9.lo, 1.0);  // k = 2: P(X <= 1) = 10 / 512
  EXPECT_DOUBLE_EQ(r9.hi, 4.0);
  EXPECT_NEAR(r9.coverage, 1 - 2 * 10.0 / 512, 1e-15);
  const auto r5 = paired_ratio({5, 4, 3, 2, 1}, std::vector<double>(5, 1));  // too few for 95 %
  EXPECT_DOUBLE_EQ(r5.lo, 1);
  EXPECT_DOUBLE_EQ(r5.hi, 5);
  EXPECT_DOUBLE_EQ(r5.coverage, 1 - 2.0 / 32);
  EXPECT_FALSE(paired_ratio({1}, {1}).valid());
  EXPECT_EQ(paired_ratio({1, -1, NAN, 2}, {1, 1, 1, 0}).n, 1u);
  using rb::stats::Verdict;
  EXPECT_EQ(rb::stats::verdict(r6, 1.0), Verdict::met);
  EXPECT_EQ(rb::stats::verdict(r6, 6.5), Verdict::not_met);
  EXPECT_EQ(rb::stats::verdict(r6, 2.0), Verdict::undecided);
  EXPECT_EQ(rb::stats::verdict(paired_ratio({}, {}), 1.0), Verdict::not_measured);

  std::mt19937_64 g(12345);
  std::normal_distribution<double> noise(0, 0.08), drift(0, 0.3);
  const double truth = 1.13;
  for (const std::size_t n : {7u, 15u}) {
    int covered = 0;
    const int trials = 4000;
    double stated = 0;
    for (int t = 0; t < trials; ++t) {
      std::vector<double> a, b;
      for (std::size_t i = 0; i < n; ++i) {
        const double load = std::exp(drift(g));
        a.push_back(truth * load * std::exp(noise(g)));
        b.push_back(load * std::exp(noise(g)));
      }
      const auto r = paired_ratio(a, b);
      stated = r.coverage;
      covered += r.lo <= truth && truth <= r.hi;
    }
    // Binomial spread of the observed coverage over 4000 runs: about 0.2-0.3 %.
    EXPECT_NEAR(double(covered) / trials, stated, 0.012) << n << " rounds";
    EXPECT_GE(stated, 0.95);
  }
}

// The rule of `bench --extra-rounds` (and the report's kernel rounds): after 9 paired rounds, one
// more round at a time, at most 6, while the ratio's interval is wider than +-5 %. On a synthetic
// workload (a shared lognormal load drift, independent per-side noise) the intervals keep about
// their stated coverage although the rule stops on their width; and a stretch of two rounds in which the
// host slows one side (the SIMD form at 0.7 of its speed) widens 9 rounds' intervals beyond 5 %,
// which the extra rounds bring back within it, around the undisturbed ratio.
TEST(Stats, ExtraRoundsKeepCoverage) {
  using rb::stats::paired_ratio;
  std::mt19937_64 g(2026);
  std::normal_distribution<double> drift(0, 0.3);
  const double truth = 1.13, within = 0.05;
  struct Outcome {
    double covered9 = 0, covered = 0, narrow9 = 0, narrow = 0, rounds = 0;
  };
  auto simulate = [&](double noise_sd, double slow, int trials) {
    std::normal_distribution<double> noise(0, noise_sd);
    Outcome o;
    for (int t = 0; t < trials; ++t) {
      std::vector<double> a, b;
      auto round = [&] {
        const double load = std::exp(drift(g));
        const double host = a.size() == 3 || a.size() == 4 ? slow : 1.0;  // rounds 4 and 5
        a.push_back(truth * host * load * std::exp(noise(g)));
        b.push_back(load * std::exp(noise(g)));
      };
      for (int i = 0; i < 9; ++i) round();
      auto r = paired_ratio(a, b);
      o.covered9 += r.lo <= truth && truth <= r.hi;
      o.narrow9 += !rb::stats::too_wide(r, within);
      for (int e = 0; e < 6 && rb::stats::too_wide(r, within); ++e) {
        round();
        r = paired_ratio(a, b);
      }
      o.covered += r.lo <= truth && truth <= r.hi;
      o.narrow += !rb::stats::too_wide(r, within);
      o.rounds += double(a.size());
    }
    for (double* x : {&o.covered9, &o.covered, &o.narrow9, &o.narrow, &o.rounds}) *x /= trials;
    return o;
  };
  // Noise at which most runs take extra rounds (9 rounds' intervals within 5 % in about a quarter).
  const Outcome plain = simulate(0.05, 1.0, 3000);
  EXPECT_GT(plain.rounds, 11.0);
  EXPECT_NEAR(plain.covered9, 0.961, 0.015);
  // 9 rounds state 96.1 %, 15 rounds 96.5 %: stopping on the width costs about a point of that.
  EXPECT_GE(plain.covered, 0.935);
  EXPECT_LE(plain.covered, plain.covered9 + 0.01);
  EXPECT_GT(plain.narrow, plain.narrow9 + 0.2);
  // A slow stretch on one side: no 9-round interval within 5 %, nearly every extended one.
  const Outcome slow = simulate(0.02, 0.7, 3000);
  EXPECT_LT(slow.narrow9, 0.05);
  EXPECT_GT(slow.narrow, 0.95);
  EXPECT_GE(slow.covered, 0.93);
  EXPECT_EQ(rb::stats::half_width(paired_ratio({1, 2}, {1, 1})), 0.5 / 1.5);
  EXPECT_FALSE(rb::stats::too_wide(paired_ratio({1}, {1}), within));  // no interval: nothing to narrow
}

TEST(Stats, MedianCvGeometricMean) {
  EXPECT_DOUBLE_EQ(rb::stats::median({3, 1, 2}), 2);
  EXPECT_DOUBLE_EQ(rb::stats::median({4, 1, 2, 3}), 2.5);
  EXPECT_TRUE(std::isnan(rb::stats::median({})));
  EXPECT_NEAR(rb::stats::cv({9, 10, 11}), 0.1, 1e-12);
  EXPECT_TRUE(std::isnan(rb::stats::cv({5})));
  EXPECT_NEAR(rb::stats::geometric_mean({2, 8, -1, std::nan("")}), 4, 1e-12);  // positive finite values only
  const auto s = rb::stats::summarize({5, 1, 3});
  EXPECT_EQ(s.n, 3u);
  EXPECT_EQ(s.min, 1);
  EXPECT_EQ(s.max, 5);
}

// Tukey's upper fence: quartiles of {10, 10.2, 10.4, 10.6, 10.8, 11, 30} are 10.3 and 10.9 (linear
// interpolation), the fence 10.9 + 1.5 x 0.6 = 11.8: the 30 (index 5) is an outlier, 11 is not.
TEST(Stats, TukeyOutliersAreTheRunsAboveTheUpperFence) {
  EXPECT_EQ(rb::stats::tukey_outliers({10, 10.2, 10.4, 10.6, 10.8, 30, 11}), (std::vector<std::size_t>{5}));
  EXPECT_TRUE(rb::stats::tukey_outliers({10, 10.2, 10.4, 10.6, 10.8, 11, 11.7}).empty());
  EXPECT_TRUE(rb::stats::tukey_outliers({1, 100, 1}).empty());  // too few to judge
}

// A Google Benchmark JSON document: every repetition of each benchmark at the given rates.
json bench_doc(const std::vector<std::pair<std::string, std::vector<double>>>& rows, const std::string& git = "abc") {
  json j = {{"context", {{"raybench_seed", "1"}}}, {"benchmarks", json::array()}, {"machine", {{"cpu", "X"}, {"git", git}}}};
  for (const auto& [name, rates] : rows) {
    for (double r : rates) j["benchmarks"].push_back({{"name", name}, {"run_name", name}, {"run_type", "iteration"}, {"tests_per_s", r}});
    j["benchmarks"].push_back({{"name", name + "_median"}, {"run_name", name}, {"run_type", "aggregate"}, {"aggregate_name", "median"},
                               {"tests_per_s", rb::stats::median(rates)}});
  }
  return j;
}
std::vector<double> around(double v, double spread = 0.01) {
  std::vector<double> r;
  for (int i = 0; i < 9; ++i) r.push_back(v * (1 + spread * (i - 4) / 4.0));
  return r;
}

TEST(Compare, BenchRowsVerdictsAndSummary) {
  const json a = bench_doc({{"k/m/scalar/hit", around(100e6)}, {"k/m/rays_in_lanes/hit", around(800e6)}, {"k/m/scalar/miss", around(50e6)},
                            {"only/in/a/hit", around(1e6)}});
  const json b = bench_doc({{"k/m/scalar/hit", around(120e6)}, {"k/m/rays_in_lanes/hit", around(720e6)},
                            {"k/m/scalar/miss", around(50.1e6)}, {"only/in/b/hit", around(1e6)}});
  rb::app::ResultSet ra = rb::app::figures_of("bench", a), rb_ = rb::app::figures_of("bench", b);
  ra.source = "a.json";
  rb_.source = "b.json";
  rb::app::CompareOptions o;
  const rb::app::Comparison c = rb::app::compare_results(ra, rb_, o);
  ASSERT_EQ(c.rows.size(), 3u);
  std::map<std::string, const rb::app::ComparedRow*> by;
  for (const auto& r : c.rows) by[r.a.name] = &r;
  EXPECT_EQ(by["k/m/scalar/hit"]->verdict, "faster");
  EXPECT_NEAR(by["k/m/scalar/hit"]->ratio, 1.2, 1e-9);
  EXPECT_GT(by["k/m/scalar/hit"]->interval.lo, 1.15);  // 1.2 with a 1 % spread on each side
  EXPECT_LT(by["k/m/scalar/hit"]->interval.hi, 1.25);
  EXPECT_EQ(by["k/m/rays_in_lanes/hit"]->verdict, "slower");
  EXPECT_EQ(by["k/m/scalar/miss"]->verdict, "");  // 0.2 % inside a 2 % spread: noise
  EXPECT_LT(by["k/m/scalar/miss"]->interval.lo, 1);
  EXPECT_GT(by["k/m/scalar/miss"]->interval.hi, 1);
  EXPECT_EQ(c.faster, 1u);
  EXPECT_EQ(c.slower, 1u);
  EXPECT_NEAR(c.geomean_gain, std::cbrt(1.2 * 0.9 * 1.002), 1e-9);
  EXPECT_EQ(c.a.figures.size(), 1u);  // only in A
  EXPECT_EQ(c.b.figures.size(), 1u);
  EXPECT_EQ(c.regressions, 0u);  // no threshold: no regression
  const std::string t = rb::app::compare_text(c);
  EXPECT_LE(widest(t), 80u) << t;
  EXPECT_TRUE(has(t, "1 faster, 1 slower beyond noise")) << t;
  EXPECT_TRUE(has(t, "geometric mean")) << t;
  EXPECT_TRUE(has(t, "Mtests/s")) << t;
  const std::string md = rb::app::compare_markdown(c);
  EXPECT_TRUE(has(md, "| k/m/scalar/hit | 100.0 | 120.0 | 1.200 |")) << md;
  const json j = rb::app::compare_json(c);
  EXPECT_EQ(j["rows"].size(), 3u);
  EXPECT_EQ(j["summary"]["faster"], 1);
  EXPECT_EQ(j["only_in_a"].size(), 1u);

  // --threshold: the 10 % slowdown is a regression at 5 %, not at 15 %.
  o.threshold = 0.05;
  EXPECT_EQ(rb::app::compare_results(ra, rb_, o).regressions, 1u);
  o.threshold = 0.15;
  EXPECT_EQ(rb::app::compare_results(ra, rb_, o).regressions, 0u);
  // --filter and --metric select rows; nothing left is "nothing to do".
  o.threshold = -1;
  o.filter = "scalar/(hit|miss)$";
  EXPECT_EQ(rb::app::compare_results(ra, rb_, o).rows.size(), 2u);
  o.filter = "nosuch";
  EXPECT_THROW(rb::app::compare_results(ra, rb_, o), rb::app::NothingToDo);
}

TEST(Compare, FewRepetitionsAreNotJudgedAndSingleFiguresUseTheNoiseBand) {
  const json a = bench_doc({{"k/m/scalar/hit", {100, 101, 102}}}), b = bench_doc({{"k/m/scalar/hit", {200, 201, 202}}});
  const rb::app::Comparison c = rb::app::compare_results(rb::app::figures_of("bench", a), rb::app::figures_of("bench", b), {});
  // Twice as fast, but 3 against 3 repetitions give only the range of the ratios (90 %).
  EXPECT_NEAR(c.rows[0].interval.coverage, 0.9, 1e-12);
  EXPECT_NEAR(c.rows[0].interval.lo, 200.0 / 102, 1e-12);
  EXPECT_EQ(c.rows[0].verdict, "");
  bool noted = false;
  for (const auto& n : c.notes) noted |= has(n, "too few repetitions for a 95 % interval") && has(n, "90.0 %");
  EXPECT_TRUE(noted);
  // csg figures are single numbers: beyond the 5 % noise band or not.
  const json ca = {{"rows", {{{"scene", "csg:die"}, {"simd8_queries_per_s", 1e6}, {"scalar_queries_per_s", 1e6}}}}};
  const json cb = {{"rows", {{{"scene", "csg:die"}, {"simd8_queries_per_s", 1.03e6}, {"scalar_queries_per_s", 0.8e6}}}}};
  ASSERT_EQ(rb::app::result_kind(ca), "csg");
  const rb::app::Comparison cc = rb::app::compare_results(rb::app::figures_of("csg", ca), rb::app::figures_of("csg", cb), {});
  for (const auto& r : cc.rows) EXPECT_EQ(r.verdict, r.a.metric == "scalar_queries_per_s" ? "slower" : "") << r.a.metric;
}

TEST(Compare, TraceRenderAccuracyKinds) {
  const json ta = {{"scene", "bunny.obj"}, {"ray_set", "primary"}, {"layout", "wide"}, {"packet", 8}, {"threads", 1}, {"rays", 1000000},
                   {"mrays_per_s", 10.0}, {"seconds", {0.1, 0.1, 0.1, 0.1, 0.1}}, {"embree_mrays_per_s", 20.0},
                   {"embree_seconds", {0.05, 0.05, 0.05, 0.05, 0.05}}, {"mismatch_rate", 0.0}, {"build_ms", 10.0}};
  json tb = ta;
  tb["threads"] = 2;
  tb["seconds"] = {0.05, 0.05, 0.05, 0.05, 0.05};
  tb["mrays_per_s"] = 20.0;
  tb["mismatch_rate"] = 0.001;
  ASSERT_EQ(rb::app::result_kind(ta), "trace");
  // Runs of other settings (here the thread count) measure different things: refused, unless forced.
  try {
    rb::app::compare_results(rb::app::figures_of("trace", ta), rb::app::figures_of("trace", tb), {});
    ADD_FAILURE() << "runs with 1 and 2 threads compared without --force";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(has(e.what(), "threads 1 / 2")) << e.what();
    EXPECT_TRUE(has(e.what(), "--force")) << e.what();
  }
  rb::app::CompareOptions forced;
  forced.force = true;
  const rb::app::Comparison t = rb::app::compare_results(rb::app::figures_of("trace", ta), rb::app::figures_of("trace", tb), forced);
  std::map<std::string, const rb::app::ComparedRow*> by;
  for (const auto& r : t.rows) by[r.a.metric] = &r;
  ASSERT_TRUE(by.count("mrays_per_s") && by.count("embree_mrays_per_s") && by.count("mismatch_rate"));
  EXPECT_NEAR(by["mrays_per_s"]->ratio, 2.0, 1e-12);
  EXPECT_EQ(by["mrays_per_s"]->a.samples.size(), 5u);  // per-run Mrays/s from the seconds
  EXPECT_EQ(by["mrays_per_s"]->verdict, "faster");
  EXPECT_EQ(by["mismatch_rate"]->verdict, "worse");  // a seeded figure: any change counts
  ASSERT_FALSE(t.notes.empty());
  EXPECT_TRUE(has(t.notes[0], "FORCED") && has(t.notes[0], "threads")) << t.notes[0];

  // Only the subject's figures are judged: Embree's (the yardstick) and a build measured once are
  // shown, not counted, unless --metric names them.
  json tc = ta;
  tc["seconds"] = {0.2, 0.2, 0.2, 0.2, 0.2};  // raybench half as fast
  tc["mrays_per_s"] = 5.0;
  tc["embree_seconds"] = {0.025, 0.025, 0.025, 0.025, 0.025};  // Embree twice as fast
  tc["embree_mrays_per_s"] = 40.0;
  tc["build_ms"] = 20.0;  // one build, twice as long
  rb::app::CompareOptions o5;
  o5.threshold = 0.05;
  const rb::app::Comparison j = rb::app::compare_results(rb::app::figures_of("trace", ta), rb::app::figures_of("trace", tc), o5);
  EXPECT_EQ(j.timings, 1u);
  EXPECT_EQ(j.slower, 1u);
  EXPECT_EQ(j.faster, 0u);
  EXPECT_NEAR(j.geomean_gain, 0.5, 1e-12);  // raybench's speed alone
  EXPECT_EQ(j.regressions, 1u);             // raybench's speed, not the build time
  for (const auto& r : j.rows) {
    EXPECT_EQ(r.judged, r.a.metric == "mrays_per_s" || !r.a.timing) << r.a.metric;
    EXPECT_EQ(r.regression, r.a.metric == "mrays_per_s") << r.a.metric;
  }
  o5.metric = "build_ms";
  const rb::app::Comparison jb = rb::app::compare_results(rb::app::figures_of("trace", ta), rb::app::figures_of("trace", tc), o5);
  ASSERT_EQ(jb.rows.size(), 1u);
  EXPECT_TRUE(jb.rows[0].judged);
  EXPECT_EQ(jb.regressions, 1u);  // asked for: 10 -> 20 ms is a regression beyond 5 %

  const json ra = {{"scene", "spd:balls"}, {"width", 64}, {"height", 64}, {"depth", 5}, {"threads", 1}, {"eye_rays", 4096},
                   {"total_rays", 10000}, {"mrays_per_s", 5.0}, {"trace_seconds", {0.002, 0.002, 0.002}}};
  json rb2 = ra;
  rb2["total_rays"] = 10001;
  ASSERT_EQ(rb::app::result_kind(ra), "render");
  const rb::app::Comparison r = rb::app::compare_results(rb::app::figures_of("render", ra), rb::app::figures_of("render", rb2), {});
  EXPECT_EQ(r.changed, 1u);  // a ray count that moved: neither better nor worse, but not equal
  // Test counts follow the packet sizes a render chose (by timing trial renders): counts of renders
  // that traced in other packets are not paired as better or worse.
  json ca = ra;
  ca["tests_counted"] = true;
  ca["eye_packet"] = 64;
  ca["secondary_packet"] = 1;
  ca["box_tests"] = 30000;
  json cb = ca;
  cb["secondary_packet"] = 8;
  cb["box_tests"] = 20000;
  const rb::app::Comparison rc = rb::app::compare_results(rb::app::figures_of("render", ca), rb::app::figures_of("render", cb), {});
  EXPECT_EQ(rc.better + rc.worse + rc.changed, 0u);
  cb["secondary_packet"] = 1;
  const rb::app::Comparison same = rb::app::compare_results(rb::app::figures_of("render", ca), rb::app::figures_of("render", cb), {});
  EXPECT_EQ(same.better, 1u);  // the same packets: fewer tests is better
  cb["eye_shadow_packet"] = 8;  // the eye rays' shadow rays in other packets: not paired either
  const rb::app::Comparison shadow = rb::app::compare_results(rb::app::figures_of("render", ca), rb::app::figures_of("render", cb), {});
  EXPECT_EQ(shadow.better + shadow.worse + shadow.changed, 0u);

  const json aa = {{"mode", "quick"}, {"seed", 1}, {"rows", {{{"family", "sphere"}, {"case", "far"}, {"method", "geometric"},
                                                              {"precision", "float"}, {"false_hit_ppm", 0.0}, {"false_miss_ppm", 10.0},
                                                              {"ns_per_test", 5.0}}}}};
  json ab = aa;
  ab["rows"][0]["false_hit_ppm"] = 3.0;
  ab["rows"][0]["false_miss_ppm"] = 5.0;
  ASSERT_EQ(rb::app::result_kind(aa), "accuracy");
  rb::app::CompareOptions o;
  o.threshold = 0.5;
  const rb::app::Comparison a = rb::app::compare_results(rb::app::figures_of("accuracy", aa), rb::app::figures_of("accuracy", ab), o);
  EXPECT_EQ(a.worse, 1u);   // false hits 0 -> 3 ppm
  EXPECT_EQ(a.better, 1u);  // false misses 10 -> 5 ppm
  EXPECT_EQ(a.regressions, 1u);  // a rate that rose from 0 is beyond any threshold

  // Two kinds do not compare.
  EXPECT_THROW(rb::app::compare_results(rb::app::figures_of("trace", ta), rb::app::figures_of("render", ra), {}), std::runtime_error);
}

TEST(Compare, ReportFolders) {
  Scratch s("compare-report");
  for (const char* d : {"a", "b"}) {
    fs::create_directories(s / d);
    const double f = std::string(d) == "a" ? 1.0 : 1.5;
    // Goals: one agrees, one moves to undecided, one flips between met and not met.
    const bool a = std::string(d) == "a";
    const json goals = json::array({{{"section", "S"}, {"goal", "g1"}, {"verdict", "met"}},
                                    {{"section", "S"}, {"goal", "g2"}, {"verdict", a ? "met" : "undecided"}},
                                    {{"section", "S"}, {"goal", "g3"}, {"verdict", a ? "not met" : "met"}}});
    std::ofstream(s / (std::string(d) + "/summary.json")) << json{{"machine", {{"cpu", "X"}}},
                                                                {"render", {{{"scene", "lecture:x"}, {"width", 8}, {"height", 8},
                                                                             {"total_rays", 64}, {"mrays_per_s", 2.0 * f}}}},
                                                                {"goals", goals}}.dump();
    std::ofstream(s / (std::string(d) + "/bench.json")) << bench_doc({{"k/m/scalar/hit", around(100 * f)}}).dump();
    std::ofstream(s / (std::string(d) + "/csg.json")) << json::array({{{"scene", "csg:die"}, {"simd8_queries_per_s", 1e6 * f}}}).dump();
  }
  const rb::app::Comparison c = rb::app::compare_results(rb::app::load_results(s / "a"), rb::app::load_results(s / "b"), {});
  EXPECT_EQ(c.kind, "report");
  std::set<std::string> sections;
  for (const auto& r : c.rows) sections.insert(r.a.section);
  EXPECT_EQ(sections, (std::set<std::string>{"bench", "csg", "render"}));
  EXPECT_EQ(c.faster, 3u);
  ASSERT_EQ(c.goals.size(), 3u);
  EXPECT_EQ(c.goal_flips, 1u);
  EXPECT_EQ(c.goal_moves, 1u);
  EXPECT_TRUE(c.goals[2].flipped);
  EXPECT_TRUE(has(rb::app::compare_text(c), "goal FLIPPED: g3: not met -> met")) << rb::app::compare_text(c);
  EXPECT_EQ(rb::app::compare_json(c)["summary"]["goal_flips"], 1);
  // A report folder against a single result is an error that names both.
  try {
    std::ofstream(s / "x.json") << bench_doc({{"k/m/scalar/hit", around(1)}}).dump();
    rb::app::compare_results(rb::app::load_results(s / "a"), rb::app::load_results(s / "x.json"), {});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(has(e.what(), "one kind")) << e.what();
  }
  EXPECT_THROW(rb::app::load_results(s / "nosuch.json"), std::runtime_error);
  std::ofstream(s / "notjson.json") << "{ nope";
  try {
    rb::app::load_results(s / "notjson.json");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(has(e.what(), "notjson.json: not JSON")) << e.what();
  }
}

// The binary on its own results: two bench runs and two trace runs compare, --threshold guards.
TEST(Compare, BinaryComparesItsOwnRunsAndGuardsWithThreshold) {
  Scratch s("compare-bin");
  const std::string filter = "--filter '^sphere/geometric/(scalar|rays_in_lanes)/hit$' -r 3 --min-time 0.001";
  ASSERT_EQ(run_in(s.dir, "bench " + filter + " --json a.json").status, 0);
  ASSERT_EQ(run_in(s.dir, "bench " + filter + " --json b.json").status, 0);
  Outcome r = run_in(s.dir, "compare a.json b.json");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "2 rows compared")) << r.out;
  EXPECT_LE(widest(r.out), 80u) << r.out;
  r = run_in(s.dir, "compare a.json b.json --markdown");
  EXPECT_TRUE(has(r.out, "| sphere/geometric/scalar/hit |")) << r.out;
  r = run_in(s.dir, "compare a.json b.json --json -");
  EXPECT_EQ(r.json()["rows"].size(), 2u);

  // A synthetic regression built from run A alone (run B's own timings could differ from A's by
  // any factor on a loaded machine): nine repetitions per row around A's first repetition, and B
  // the same at half the rate. 3 against 3 repetitions cannot reach a 95 % interval: the guard needs more.
  json a9 = json::parse(slurp(s / "a.json"));
  std::map<std::string, double> first;
  json more = json::array();
  for (const auto& x : a9["benchmarks"])
    if (x.value("run_type", "") == "iteration" && x.contains("tests_per_s") && x["tests_per_s"].is_number() &&
        first.emplace(x.value("name", ""), x["tests_per_s"].get<double>()).second)
      for (int k = 0; k < 9; ++k) {
        json y = x;
        y["tests_per_s"] = first[x.value("name", "")] * (1 + 0.001 * k);
        more.push_back(y);
      }
  ASSERT_EQ(first.size(), 2u) << a9.dump();
  a9["benchmarks"] = more;
  json b9 = a9;
  for (auto& x : b9["benchmarks"]) x["tests_per_s"] = x["tests_per_s"].get<double>() * 0.5;
  std::ofstream(s / "a9.json") << a9.dump();
  std::ofstream(s / "b9.json") << b9.dump();
  r = run_in(s.dir, "compare a9.json b9.json --threshold 10");
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_TRUE(has(r.err, "2 regression(s)")) << r.err;
  EXPECT_TRUE(has(r.out, "slower!")) << r.out;
  r = run_in(s.dir, "compare b9.json a9.json --threshold 10");  // the other way round: faster, exit 0
  EXPECT_EQ(r.status, 0) << r.err;

  std::ofstream(s / "oct.obj") << "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
                                  "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";
  ASSERT_EQ(run_in(s.dir, "trace oct.obj --count 128 -r 2 --warmup 0 --json t1.json").status, 0);
  ASSERT_EQ(run_in(s.dir, "trace oct.obj --count 128 -r 2 --warmup 0 --json t2.json").status, 0);
  r = run_in(s.dir, "compare t1.json t2.json");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "mrays_per_s") && has(r.out, "embree_mrays_per_s")) << r.out;
  r = run_in(s.dir, "compare a.json t1.json");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err_lines().size(), 1u) << r.err;
}

}  // namespace
