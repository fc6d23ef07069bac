// `raybench trace` on the built binary: the timing protocol as it ran (warm-up until stable, passes
// per repetition, rounds alternating with Embree and their interval), builds timed as the report
// does, Embree's best mode and Embree's tree.
#include "apps/cli.hpp"
#include "cli_test_util.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sched.h>

#include <algorithm>
#include <fstream>
#include <vector>

namespace {

using namespace rbtest;

TEST(Cli, TraceGivesMedianRangeAndCvAfterWarmupBesideEmbree) {
  Scratch s("trace");
  std::ofstream(s / "oct.obj") << kOctahedron;
  const Outcome r = run_in(s.dir, "trace oct.obj --count 256 -r 3 --warmup 2 --threads 0 --json t.json");
  EXPECT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(s / "t.json"));
  EXPECT_EQ(j["warmup"], 2);
  EXPECT_EQ(j["seconds"].size(), 3u);          // the warm-up runs are not timed into the median
  EXPECT_EQ(j["embree_seconds"].size(), 3u);   // Embree's runs, alternating with ours
  EXPECT_LE(j["mrays_per_s_min"].get<double>(), j["mrays_per_s"].get<double>());
  EXPECT_GE(j["mrays_per_s_max"].get<double>(), j["mrays_per_s"].get<double>());
  EXPECT_TRUE(j["cv"].is_number());
  EXPECT_EQ(j["threads"], int(rb::app::hardware_threads()));  // --threads 0: every hardware thread
  EXPECT_TRUE(has(r.err, std::to_string(rb::app::hardware_threads()) + " thread(s) of")) << r.err;
  EXPECT_TRUE(has(r.out, "median of 3, range")) << r.out;
  EXPECT_TRUE(has(r.out, "CV ")) << r.out;
  // At least --warmup untimed runs, more while the times still moved by over 5 %; then each
  // repetition traces the rays as often as makes it last --min-time (0.05 s by default).
  EXPECT_GE(j["warmup_seconds"].size(), 2u);
  EXPECT_TRUE(has(r.out, fmt::format("{} warm-up", j["warmup_seconds"].size()))) << r.out;
  EXPECT_TRUE(has(r.out, fmt::format("{} pass(es) over the rays per repetition", j["passes"].get<int>()))) << r.out;
  EXPECT_GE(j["passes"].get<int>(), 1);
  EXPECT_DOUBLE_EQ(j["min_time"].get<double>(), 0.05);
  EXPECT_LE(widest(r.out), 80u) << r.out;
  // raybench over Embree from the 3 paired rounds: the median of their ratios, and [min, max] with
  // the confidence that range holds (3 rounds cannot give 95 %).
  const auto& v = j["vs_embree"];
  EXPECT_EQ(v["rounds"], 3);
  std::vector<double> q;
  for (int i = 0; i < 3; ++i) q.push_back(j["embree_seconds"][i].get<double>() / j["seconds"][i].get<double>());
  std::sort(q.begin(), q.end());
  EXPECT_DOUBLE_EQ(v["ratio"].get<double>(), q[1]);
  EXPECT_DOUBLE_EQ(v["lo"].get<double>(), q[0]);
  EXPECT_DOUBLE_EQ(v["hi"].get<double>(), q[2]);
  EXPECT_DOUBLE_EQ(v["coverage"].get<double>(), 0.75);
  EXPECT_TRUE(has(r.out, "[range of 3: ")) << r.out;
  // The machine around the rounds: load average before and after, the share of CPU time stolen.
  const auto& m = j["machine_load"];
  EXPECT_TRUE(m["load_average_before"].is_number() && m["load_average_after"].is_number()) << m;
  if (!m["steal_share"].is_null()) {
    EXPECT_GE(m["steal_share"].get<double>(), 0.0);
    EXPECT_LE(m["steal_share"].get<double>(), 1.0);
  }
  EXPECT_TRUE(has(r.out, "machine    load average ")) << r.out;
}

// The lanes a packet's groups walked in and their ISA, in the JSON and the text: 16 (AVX-512) for
// packets of 16 or more of a mesh where this binary and CPU have the 16-lane walk (not in the
// sanitizer build), 8 (AVX2) otherwise, 1 for single rays; --isa avx512 fails clearly where 16
// lanes cannot run; --isa both times the 8-lane walk beside the 16-lane one, with the same hits.
TEST(Cli, TraceNamesTheLanesItsPacketsWalkedIn) {
  Scratch s("trace_isa");
  std::ofstream(s / "oct.obj") << kOctahedron;
  auto trace = [&](const std::string& opts) {
    const Outcome r = run_in(s.dir, "trace oct.obj --count 512 -r 2 --warmup 1 --no-embree --json t.json " + opts);
    return std::pair{r, r.status == 0 ? nlohmann::json::parse(slurp(s / "t.json")) : nlohmann::json()};
  };
  const auto [r16, j16] = trace("--packet 16");
  ASSERT_EQ(r16.status, 0) << r16.err;
  const int lanes = j16["group_lanes"].get<int>();
  ASSERT_TRUE(lanes == 8 || lanes == 16) << j16["group_lanes"];
  const bool can16 = lanes == 16;
  EXPECT_EQ(j16["isa"], can16 ? "avx512" : "avx2");
  EXPECT_TRUE(has(r16.out, can16 ? "in groups of 16 lanes (AVX-512)" : "in groups of 8 lanes (AVX2)")) << r16.out;
  const auto [r1, j1] = trace("--packet 1 --isa avx512");
  if (can16) {
    EXPECT_EQ(r1.status, 0) << r1.err;
    EXPECT_EQ(j1["group_lanes"], 1);
  } else {
    EXPECT_NE(r1.status, 0);
    EXPECT_TRUE(has(r1.err, "--isa avx512: this")) << r1.err;
  }
  const auto [r8, j8] = trace("--packet 64 --isa avx2");
  ASSERT_EQ(r8.status, 0) << r8.err;
  EXPECT_EQ(j8["group_lanes"], 8);
  EXPECT_EQ(j8["hits_fnv1a"], trace("--packet 64").second["hits_fnv1a"]) << "the same hits at either width";
  const auto [rb, jb] = trace("--packet 16 --isa both");
  ASSERT_EQ(rb.status, 0) << rb.err;
  EXPECT_EQ(jb.contains("lanes8"), can16);
  if (can16) {
    EXPECT_EQ(jb["lanes8"]["seconds"].size(), 2u);
    EXPECT_EQ(jb["lanes8"]["mismatches"], 0);
    EXPECT_EQ(jb["lanes8"]["speedup_16_over_8"]["rounds"], 2);
    EXPECT_TRUE(has(rb.out, "16 lanes over 8: ")) << rb.out;
  }
}

// --threads-beside: the rays also traced on another thread count in the same rounds, with the same
// hits, and the speed-up as a paired ratio; the builds ran on the larger count. A ray file and a
// sorted stream are refused by name.
TEST(Cli, TraceTimesAnotherThreadCountInTheSameRounds) {
  Scratch s("trace_threads");
  std::ofstream(s / "oct.obj") << kOctahedron;
  const Outcome r = run_in(s.dir, "trace oct.obj --count 512 -r 3 --warmup 1 --threads 1 --threads-beside 2 --packet 8 --json t.json");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(s / "t.json"));
  ASSERT_TRUE(j.contains("threads_beside")) << j.dump();
  const nlohmann::json& w = j["threads_beside"];
  EXPECT_EQ(w["threads"], 2);
  EXPECT_EQ(w["seconds"].size(), 3u);
  EXPECT_EQ(w["mismatches"], 0);
  EXPECT_EQ(w["speedup"]["rounds"], 3);
  EXPECT_GT(w["speedup"]["ratio"].get<double>(), 0.0);
  EXPECT_EQ(j["threads"], 1);
  EXPECT_EQ(j["build_threads"], 2);
  EXPECT_TRUE(has(r.out, "2 thread(s) over 1: ")) << r.out;
  // With two CPUs to run on, the one-thread engines took turns on them (round r on the r % 2-th),
  // raybench ran once more on the other, and the speed-up is over the harmonic mean of its seconds
  // on both, round by round (the median of the rounds' ratios).
  cpu_set_t mask;
  ASSERT_EQ(sched_getaffinity(0, sizeof mask, &mask), 0);
  if (CPU_COUNT(&mask) >= 2) {
    ASSERT_TRUE(w.contains("one_thread_cpus")) << w.dump();
    EXPECT_EQ(w["one_thread_cpus"].size(), 2u);
    const nlohmann::json& on = w["one_thread_seconds_by_cpu"];
    ASSERT_EQ(on.size(), 2u);
    ASSERT_EQ(on[0].size(), 3u);
    ASSERT_EQ(on[1].size(), 3u);
    EXPECT_EQ(on[0][0], j["seconds"][0]);
    EXPECT_EQ(on[1][1], j["seconds"][1]);
    EXPECT_EQ(on[0][2], j["seconds"][2]);
    std::vector<double> ratio;
    for (std::size_t k = 0; k < 3; ++k) {
      const double one = 2 / (1 / on[0][k].get<double>() + 1 / on[1][k].get<double>());
      ratio.push_back(one / w["seconds"][k].get<double>());
    }
    std::sort(ratio.begin(), ratio.end());
    EXPECT_NEAR(w["speedup"]["ratio"].get<double>(), ratio[1], 1e-9 * ratio[1]);
    EXPECT_TRUE(has(r.out, "averaged over the CPUs it took turns on")) << r.out;
    // Embree's control, measured alike: its fastest mode on each CPU and on two threads.
    if (!j["embree_mrays_per_s"].is_null()) {
      ASSERT_TRUE(w.contains("embree")) << w.dump();
      const nlohmann::json& e = w["embree"];
      const nlohmann::json& eon = e["one_thread_seconds_by_cpu"];
      ASSERT_EQ(eon.size(), 2u);
      ASSERT_EQ(e["seconds"].size(), 3u);
      std::vector<double> er;
      for (std::size_t k = 0; k < 3; ++k)
        er.push_back(2 / (1 / eon[0][k].get<double>() + 1 / eon[1][k].get<double>()) / e["seconds"][k].get<double>());
      std::sort(er.begin(), er.end());
      EXPECT_NEAR(e["speedup"]["ratio"].get<double>(), er[1], 1e-9 * er[1]);
      bool named = false;
      for (const auto& m : j["embree_modes"]) named = named || m["mode"] == e["mode"];
      EXPECT_TRUE(named) << e["mode"] << " is one of the run's Embree modes";
      EXPECT_TRUE(has(r.out, "in the same rounds: ")) << r.out;
    }
  } else {
    EXPECT_FALSE(w.contains("one_thread_cpus")) << "one CPU: nothing to take turns on";
  }
  const Outcome same = run_in(s.dir, "trace oct.obj --count 512 -r 1 --warmup 0 --threads 2 --threads-beside 2 --no-embree --json t.json");
  ASSERT_EQ(same.status, 0) << same.err;
  EXPECT_FALSE(nlohmann::json::parse(slurp(s / "t.json")).contains("threads_beside")) << "the same count is no second engine";
  const Outcome sorted = run_in(s.dir, "trace oct.obj --count 512 -r 1 --threads-beside 2 --order sorted --no-embree");
  EXPECT_NE(sorted.status, 0);
  EXPECT_TRUE(has(sorted.err, "--threads-beside times the given order")) << sorted.err;
}

TEST(Cli, TraceTimesManyBuildsAsTheReportDoes) {
  Scratch s("trace-builds");
  std::ofstream(s / "oct.obj") << kOctahedron;
  const Outcome r = run_in(s.dir, "trace oct.obj --count 256 -r 1 --warmup 0 --builds 3 --json t.json");
  EXPECT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(s / "t.json"));
  EXPECT_EQ(j["builds"], 3);
  for (const char* engine : {"", "embree_"}) {
    const nlohmann::json& runs = j[std::string(engine) + "build_ms_runs"];
    ASSERT_EQ(runs.size(), 3u) << engine;
    std::vector<double> v;
    for (const auto& x : runs) v.push_back(x.get<double>());
    std::sort(v.begin(), v.end());
    EXPECT_DOUBLE_EQ(j[std::string(engine) + "build_ms"].get<double>(), v[1]) << engine;  // the median
  }
  EXPECT_TRUE(has(r.out, "medians of 3 builds")) << r.out;
  EXPECT_LE(widest(r.out), 80u) << r.out;
  // One build (the default): the traced session's own, no runs listed.
  const Outcome one = run_in(s.dir, "trace oct.obj --count 256 -r 1 --warmup 0 --json one.json");
  EXPECT_EQ(one.status, 0) << one.err;
  const nlohmann::json k = nlohmann::json::parse(slurp(s / "one.json"));
  EXPECT_EQ(k["builds"], 1);
  EXPECT_FALSE(k.contains("build_ms_runs"));
  EXPECT_EQ(run_in(s.dir, "trace oct.obj --builds 0").status, 1);
}

TEST(Cli, TraceComparesWithEmbreesBestModeAndEmbreesTree) {
  Scratch s("trace-embree");
  std::ofstream(s / "oct.obj") << kOctahedron;
  const Outcome r = run_in(s.dir, "trace oct.obj --count 256 -r 2 --warmup 0 --packet 16 --builder embree --json t.json");
  EXPECT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(s / "t.json"));
  // Both devices warmed up with the packet size's call, the faster (and any within 10 % of it) timed in
  // the rounds; the yardstick is the fastest timed. The protocol is recorded: warm-up runs until
  // stable (two at least), passes per repetition, outliers.
  ASSERT_EQ(j["embree_modes"].size(), 2u);
  double best = 0;
  for (const auto& m : j["embree_modes"]) {
    EXPECT_TRUE(m["warmup_mrays_per_s"].is_number()) << m;
    if (m["timed"].get<bool>()) best = std::max(best, m["mrays_per_s"].get<double>());
  }
  EXPECT_DOUBLE_EQ(j["embree_mrays_per_s"].get<double>(), best);
  EXPECT_GE(j["warmup_seconds"].size(), 2u);
  EXPECT_GE(j["passes"].get<int>(), 1);
  EXPECT_TRUE(j["outliers"].is_array());
  EXPECT_EQ(j["embree_call"], "rtcIntersect16");
  EXPECT_TRUE(has(j["embree_mode"].get<std::string>(), "rtcIntersect16 ")) << j["embree_mode"];
  EXPECT_TRUE(has(j["embree_mode"].get<std::string>(), " coherent")) << j["embree_mode"];  // primary rays
  EXPECT_TRUE(j["embree_isa"].is_string());
  EXPECT_TRUE(has(j["embree_avx2_config"].get<std::string>(), "isa=avx2"));
  // Embree's builder's tree traced by raybench, the SAH tree beside it with its counters.
  EXPECT_EQ(j["builder"], "embree");
  EXPECT_TRUE(j["sah_tree"]["mrays_per_s"].is_number());
  EXPECT_TRUE(j["sah_tree"]["box_tests_per_ray"].is_number());
  EXPECT_EQ(j["sah_tree"]["mismatches_vs_builder_tree"], 0);
  EXPECT_EQ(j["mismatches"], 0);
  EXPECT_TRUE(has(r.out, "raybench / Embree (rtcIntersect16")) << r.out;
  EXPECT_LE(widest(r.out), 80u) << r.out;
}

// A render's own rays: `render --rays-out` writes them, `trace --rays FILE` traces them alone, each
// section with the render's packet size and query, and meets what the render met; the render's JSON
// gives the same rays traced alone with render / alone (their time over the render's), and with
// --primary-rays the scene's primary rays with render / primary, both from paired rounds (each
// timed render followed by the others).
TEST(Cli, RenderRaysTracedAloneByTrace) {
  Scratch s("trace-rays");
  const Outcome r = run_in(s.dir, "render lecture:nine_red_balls --width 32 -r 2 --warmup 0 --min-time 0 --eye-packet 16 "
                                  "--secondary-packet 8 -o a.png --rays-out a.rays --primary-rays 1000 --json r.json");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json rj = nlohmann::json::parse(slurp(s / "r.json"));
  const auto& alone = rj["alone"];
  ASSERT_TRUE(alone.contains("sections")) << alone;
  EXPECT_EQ(alone["seconds"].size(), 2u);
  EXPECT_TRUE(alone["render_over_alone"]["ratio"].is_number()) << alone;
  EXPECT_GT(alone["render_over_alone"]["ratio"].get<double>(), 0.0);
  EXPECT_EQ(alone["render_over_alone"]["rounds"], 2) << alone;
  EXPECT_TRUE(has(alone["render_over_alone"]["method"].get<std::string>(), "paired rounds")) << alone;
  const auto& primary = rj["primary"];
  ASSERT_TRUE(primary.contains("render_over_primary")) << rj;
  EXPECT_EQ(primary["seconds"].size(), 2u);
  EXPECT_EQ(primary["render_over_primary"]["rounds"], 2) << primary;
  EXPECT_GT(primary["render_over_primary"]["ratio"].get<double>(), 0.0);
  // About 1000 rays: the primary set's image of about that many pixels.
  EXPECT_GT(primary["rays"].get<std::size_t>(), 800u);
  EXPECT_LT(primary["rays"].get<std::size_t>(), 1200u);
  EXPECT_TRUE(has(r.out, "the scene's primary rays")) << r.out;  // a paragraph's first words: never wrapped
  // Without --primary-rays: the rays alone as before, and no primary rays.
  const Outcome plain = run_in(s.dir, "render lecture:nine_red_balls --width 16 -r 2 --warmup 0 --min-time 0 -o b.png --json b.json");
  ASSERT_EQ(plain.status, 0) << plain.err;
  const nlohmann::json bj = nlohmann::json::parse(slurp(s / "b.json"));
  ASSERT_TRUE(bj["alone"].contains("render_over_alone")) << bj["alone"];
  EXPECT_EQ(bj["alone"]["render_over_alone"]["rounds"], 2);
  EXPECT_FALSE(bj.contains("primary")) << bj["primary"];
  EXPECT_TRUE(has(plain.out, "the same rays traced alone")) << plain.out;
  EXPECT_FALSE(has(plain.out, "the scene's primary rays")) << plain.out;
  EXPECT_EQ(rj["rays_file"], "a.rays");
  const Outcome t = run_in(s.dir, "trace lecture:nine_red_balls --rays a.rays -r 2 --min-time 0 --json t.json");
  ASSERT_EQ(t.status, 0) << t.err;
  const nlohmann::json tj = nlohmann::json::parse(slurp(s / "t.json"));
  EXPECT_EQ(tj["model"], "auto");
  EXPECT_FALSE(tj["moved_frame"].get<bool>());
  EXPECT_EQ(tj["rays"], alone["rays"]);
  ASSERT_EQ(tj["sections"].size(), alone["sections"].size());
  const auto& gens = rj["time_split"]["generations"];
  std::uint64_t shadow = 0;
  for (std::size_t i = 0; i < tj["sections"].size(); ++i) {
    const auto& sec = tj["sections"][i];
    EXPECT_EQ(sec["hits"], alone["sections"][i]["hits"]);
    // Spheres: every packet walks in 8 lanes, at either width asked for.
    EXPECT_EQ(sec["lanes"], 8) << sec;
    EXPECT_EQ(alone["sections"][i]["lanes"], 8) << alone["sections"][i];
    const auto& g = gens.at(sec["generation"].get<std::size_t>() - 1);
    if (sec["kind"] == "shadow") {
      EXPECT_EQ(sec["query"], "any") << "nine red balls are opaque";
      EXPECT_EQ(sec["packet"], 8);
      shadow += sec["rays"].get<std::uint64_t>();
      continue;
    }
    EXPECT_EQ(sec["packet"], sec["kind"] == "eye" ? 16 : 8);
    EXPECT_EQ(sec["rays"], g["rays"]);
    EXPECT_EQ(sec["hits"], g["hits"]);
  }
  EXPECT_EQ(shadow, rj["shadow_rays"].get<std::uint64_t>());
  // Errors: a misspelt ray set, a file that is not a ray file.
  std::ofstream(s / "not.rays") << "hello\n";
  const Outcome bad = run_in(s.dir, "trace lecture:nine_red_balls --rays not.rays");
  EXPECT_EQ(bad.status, 1);
  EXPECT_TRUE(has(bad.err, "not.rays: line 1: not a ray file")) << bad.err;
  const Outcome typo = run_in(s.dir, "trace lecture:nine_red_balls --rays primry");
  EXPECT_NE(typo.status, 0);
  EXPECT_TRUE(has(typo.err, "did you mean 'primary'")) << typo.err;
}

// --order sorted: the same answers as the given order (the digest of every ray's hit), the sort
// timed, Embree on both orders with raybench over each.
TEST(Cli, TraceSortedOrderGivesTheSameHitsAndEmbreeOnBothOrders) {
  Scratch s("trace-sorted");
  const std::string base = "trace spd:balls:1 --rays diffuse --count 4096 --packet 8 -r 2 --warmup 1 --min-time 0 --brute 256 ";
  const Outcome g = run_in(s.dir, base + "--json g.json");
  ASSERT_EQ(g.status, 0) << g.err;
  const Outcome r = run_in(s.dir, base + "--order sorted --json o.json");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json gj = nlohmann::json::parse(slurp(s / "g.json")), oj = nlohmann::json::parse(slurp(s / "o.json"));
  EXPECT_EQ(gj["order"], "given");
  EXPECT_EQ(oj["order"], "sorted");
  EXPECT_EQ(oj["hits_fnv1a"], gj["hits_fnv1a"]);
  EXPECT_EQ(oj["brute_mismatches"], 0u);
  EXPECT_GT(oj["sort_ms"].get<double>(), 0.0);
  if (!oj["embree_mrays_per_s"].is_null()) {
    ASSERT_FALSE(oj["embree_sorted"].is_null()) << oj;
    EXPECT_EQ(oj["embree_sorted"]["mismatches"], oj["mismatches"]) << "Embree answers alike in both orders";
    EXPECT_EQ(oj["mismatches"], gj["mismatches"]);
    EXPECT_EQ(oj["embree_sorted"]["seconds"].size(), 2u);
    EXPECT_TRUE(oj["embree_sorted"]["vs_embree_sorted"]["ratio"].is_number());
  }
  const Outcome t = run_in(s.dir, base + "--order sorted");
  EXPECT_TRUE(has(t.out, "order      sorted")) << t.out;
  EXPECT_LE(widest(t.out), 80u) << t.out;
}

}  // namespace
