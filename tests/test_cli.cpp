// The command line's conventions (README "Command-line conventions"), each checked on the built
// `raybench` as a user runs it, and the helpers behind them (apps/cli.hpp, apps/progress.hpp).
#include "apps/build_info.hpp"
#include "apps/cli.hpp"
#include "apps/progress.hpp"
#include "cli_test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <regex>
#include <set>
#include <sstream>

namespace {

using namespace rbtest;
using rb::app::ProgressBar;

const char* const kCommands[] = {"report", "ops", "bench", "info", "query", "trace", "render", "accuracy", "csg", "compare", "history", "machine"};

// ---- helpers ----------------------------------------------------------------------------------

TEST(CliHelpers, ClosestNameFindsTyposOnly) {
  const std::vector<std::string> names(std::begin(kCommands), std::end(kCommands));
  EXPECT_EQ(rb::closest_name("tarce", names), "trace");
  EXPECT_EQ(rb::closest_name("rendr", names), "render");
  EXPECT_EQ(rb::closest_name("acuracy", names), "accuracy");
  EXPECT_EQ(rb::closest_name("hisotry", names), "history");
  EXPECT_EQ(rb::closest_name("xyzzy", names), "");
  EXPECT_EQ(rb::edit_distance("trace", "tarce"), 1u);  // an adjacent swap is one edit
  EXPECT_EQ(rb::edit_distance("", "abc"), 3u);
}

TEST(CliHelpers, ErrorLineNamesTheInputOnce) {
  EXPECT_EQ(rb::app::error_line("trace", "a.obj", "No such file or directory"), "raybench trace: a.obj: No such file or directory");
  EXPECT_EQ(rb::app::error_line("info", "a.obj", "a.obj: line 3: bad vertex"), "raybench info: a.obj: line 3: bad vertex");
  EXPECT_EQ(rb::app::error_line("x", "", "two\nlines"), "raybench x: two; lines");
  EXPECT_EQ(rb::app::error_line("", "", "bad"), "raybench: bad");
}

TEST(CliHelpers, OutputChecksGiveTheSystemsReason) {
  Scratch s("outputs");
  std::ofstream(s / "file") << "x";
  EXPECT_EQ(rb::app::check_output_file(s / "new.json"), "");
  EXPECT_FALSE(fs::exists(s / "new.json"));  // the check creates nothing
  EXPECT_EQ(rb::app::check_output_file(s / "file"), "");
  EXPECT_EQ(slurp(s / "file"), "x");  // an existing file is not truncated by the check
  EXPECT_EQ(rb::app::check_output_file(s / "file/x.json"), std::strerror(ENOTDIR));
  EXPECT_EQ(rb::app::check_output_file(s.dir.string()), std::strerror(EISDIR));
  EXPECT_EQ(rb::app::check_output_file("-"), "");
  EXPECT_EQ(rb::app::check_output_dir(s / "a/b/c"), "");
  EXPECT_TRUE(fs::is_directory(s / "a/b/c"));
  EXPECT_EQ(rb::app::check_output_dir(s / "file/sub"), std::strerror(ENOTDIR));
  EXPECT_EQ(rb::app::check_input_file(s / "missing.obj"), std::strerror(ENOENT));
  EXPECT_EQ(rb::app::check_input_file(s.dir.string()), std::strerror(EISDIR));
  EXPECT_EQ(rb::app::check_input_file(s / "file"), "");
}

TEST(CliHelpers, ThreadsZeroMeansAllAndTooManyWarns) {
  std::string w;
  EXPECT_EQ(rb::app::resolve_threads(0, &w), int(rb::app::hardware_threads()));
  EXPECT_EQ(w, "");
  EXPECT_EQ(rb::app::resolve_threads(1, &w), 1);
  EXPECT_EQ(w, "");
  const int more = int(rb::app::hardware_threads()) + 1;
  EXPECT_EQ(rb::app::resolve_threads(more, &w), more);
  EXPECT_TRUE(has(w, "warning")) << w;
}

TEST(CliHelpers, BusyAndNoiseWarnings) {
  EXPECT_EQ(rb::app::busy_warning(0.9, 1), "");
  EXPECT_EQ(rb::app::busy_warning(-1, 1), "");  // unknown load
  EXPECT_TRUE(has(rb::app::busy_warning(2.5, 1), "busy"));
  EXPECT_EQ(rb::app::busy_warning(2.5, 2), "");  // our own two threads
  EXPECT_EQ(rb::app::noise_warning(0.049, "x"), "");
  EXPECT_EQ(rb::app::noise_warning(std::nan(""), "x"), "");
  EXPECT_TRUE(has(rb::app::noise_warning(0.08, "x"), "8.0 %"));
}

TEST(CliHelpers, FilterIsAnExtendedRegex) {
  const std::regex re = rb::app::filter_regex("^torus/(tangent|far)");
  EXPECT_TRUE(rb::app::filter_matches(re, "torus/tangent"));
  EXPECT_FALSE(rb::app::filter_matches(re, "sphere/torus/tangent"));
  EXPECT_THROW(rb::app::filter_regex("["), std::invalid_argument);
}

TEST(CliHelpers, WrapKeepsEightyColumnsAndIndentation) {
  const std::string long_text(30, 'a');
  const std::string w = rb::wrap_words("  key  " + long_text + " " + long_text + " " + long_text, 80, "       ");
  EXPECT_LE(widest(w), 80u);
  EXPECT_EQ(w.rfind("  key  aaa", 0), 0u);  // leading and inner spaces of the first line kept
  EXPECT_TRUE(has(w, "\n       aaa"));
  EXPECT_LE(widest(rb::fit_columns(std::string(200, 'x') + "\n" + long_text + " " + long_text + " " + long_text, 4)), 200u);
}

TEST(CliHelpers, ProgressBarShowsElapsedAndTheRest) {
  const std::string l = ProgressBar::line("raybench trace", 0.25, 30, "bunny");
  EXPECT_TRUE(has(l, "25 %")) << l;
  EXPECT_TRUE(has(l, "30 s")) << l;
  EXPECT_TRUE(has(l, "~1 min 30 s left")) << l;  // 30 s for a quarter: 90 s to go
  EXPECT_LE(widest(ProgressBar::line(std::string(100, 'l'), 0.5, 10, std::string(100, 'w'))), 79u);
  EXPECT_EQ(ProgressBar::remaining(0.01, 30), "");  // too early to tell
  EXPECT_EQ(rb::app::format_duration(3725), "1 h 02 min");
  // In a log: one line per tenth, none for a run shorter than two seconds.
  std::ostringstream log;
  {
    ProgressBar b("job", ProgressBar::Mode::lines, &log);
    b.update_at(0.5, "a", 1.0);
    EXPECT_EQ(log.str(), "");
    b.update_at(0.55, "b", 2.4);
    b.update_at(0.58, "c", 2.6);  // the same tenth: no new line
    b.update_at(0.71, "d", 3.0);
    b.done();
  }
  const std::string t = log.str();
  EXPECT_EQ(std::count(t.begin(), t.end(), '\n'), 2) << t;
  EXPECT_TRUE(has(t, "job:  50 % after 2 s, ~2 s left  b")) << t;
  std::ostringstream tty;
  {
    ProgressBar b("job", ProgressBar::Mode::terminal, &tty);
    b.update_at(0.5, "", 4);
    b.done();
  }
  EXPECT_TRUE(has(tty.str(), "\r")) << "redrawn in place";
}

// ---- the binary -------------------------------------------------------------------------------

TEST(Cli, VersionNamesRevisionAndFlags) {
  Scratch s("version");
  const Outcome r = run_in(s.dir, "--version");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "raybench " + rb::app::build_info().version)) << r.out;
  EXPECT_TRUE(has(r.out, "git revision")) << r.out;
  EXPECT_TRUE(has(r.out, "build flags")) << r.out;
  EXPECT_TRUE(has(r.out, "-ffp-contract=")) << r.out;
  EXPECT_LE(widest(r.out), 80u) << r.out;
}

TEST(Cli, InputErrorsExitOneWithTheSystemsReason) {
  Scratch s("input");
  std::ofstream(s / "bad.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 x\n";
  fs::create_directories(s / "folder.obj");
  struct Case { std::string args, command, input, reason; };
  for (const Case& c : std::vector<Case>{{"info missing.obj", "info", "missing.obj", std::strerror(ENOENT)},
                                         {"trace missing.obj", "trace", "missing.obj", std::strerror(ENOENT)},
                                         {"render folder.obj", "render", "folder.obj", std::strerror(EISDIR)},
                                         {"compare missing.json other.json", "compare", "missing.json", std::strerror(ENOENT)},
                                         {"info bad.obj", "info", "bad.obj", "bad.obj:3:"},
                                         {"info spd:nosuch", "info", "spd:nosuch", ""}}) {
    const Outcome r = run_in(s.dir, c.args);
    EXPECT_EQ(r.status, 1) << c.args << ": " << r.err;
    expect_one_error_line(r, c.command, c.input);
    EXPECT_TRUE(has(r.err, c.reason)) << c.args << ": " << r.err;
  }
}

// Absurd sizes are refused before anything is allocated, with the bound in the one error line;
// a scene with a vertex at 1e38 (its camera framing and rays would overflow) is refused by every
// command with the bound named.
TEST(Cli, AbsurdSizesAndHugeScenesAreRefusedNamingTheBound) {
  Scratch s("absurd");
  std::ofstream(s / "huge.obj") << "v 0 0 0\nv 1 0 0\nv 0 1e38 0\nf 1 2 3\n";
  struct Case { std::string args, command, input, bound; };
  for (const Case& c : std::vector<Case>{{"render spd:balls:1 --width 100000 --height 100000", "render", "", "16384"},
                                         {"trace spd:balls:1 --count 4e9", "trace", "", "268435456"},
                                         {"trace spd:balls:1 --count -1", "trace", "", "268435456"},
                                         {"trace spd:balls:1 --threads 100000", "trace", "", "256"},
                                         {"info huge.obj", "info", "huge.obj", "1e+12"},
                                         {"trace huge.obj --no-embree -r 1", "trace", "huge.obj", "1e+12"},
                                         {"render huge.obj --width 8 -r 1 -o x.png", "render", "huge.obj", "1e+12"}}) {
    const Outcome r = run_in(s.dir, c.args);
    EXPECT_EQ(r.status, 1) << c.args << ": " << r.err;
    expect_one_error_line(r, c.command, c.input);
    EXPECT_TRUE(has(r.err, c.bound)) << c.args << ": " << r.err;
  }
  // In scientific notation within the bound: accepted as the integer.
  const Outcome ok = run_in(s.dir, "trace spd:balls:1 --count 1e3 --no-embree -r 1 --warmup 0 --brute 0 --json");
  EXPECT_EQ(ok.status, 0) << ok.err;
  if (ok.status == 0) {
    EXPECT_LE(ok.json().at("rays").get<std::size_t>(), 2048u);
  }
}

TEST(Cli, NothingToDoExitsTwo) {
  Scratch s("nothing");
  std::ofstream(s / "empty.obj") << "# no geometry\n";
  for (const char* args : {"trace empty.obj", "render empty.obj -o e.png", "bench --filter nosuchkernel", "bench --list --filter nosuch",
                           "accuracy --filter nosuchcase", "report --filter nosuchkernel -o rep"}) {
    const Outcome r = run_in(s.dir, args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    const std::string cmd = std::string(args).substr(0, std::string(args).find(' '));
    expect_one_error_line(r, cmd, "");
  }
  EXPECT_FALSE(fs::exists(s / "e.png"));
  EXPECT_FALSE(fs::exists(s / "rep/index.md"));  // the report found nothing to do before its work
}

TEST(Cli, OutputsAreCheckedBeforeTheWork) {
  Scratch s("outputs-bin");
  std::ofstream(s / "file") << "x";
  std::ofstream(s / "oct.obj") << kOctahedron;
  for (const char* args : {"trace oct.obj --json file/t.json", "render oct.obj -o file/i.png", "render oct.obj -o .",
                           "accuracy --json file/a.json", "bench --json file/b.json", "ops --json file/o.json", "csg --json file/c.json",
                           "report -o file/rep", "trace oct.obj --history file/h.sqlite", "machine --json file/m.json",
                           "history --plot file/p.png"}) {
    const Outcome r = run_in(s.dir, args);
    EXPECT_EQ(r.status, 1) << args << ": " << r.err;
    expect_one_error_line(r, std::string(args).substr(0, std::string(args).find(' ')), "");
    EXPECT_TRUE(has(r.err, std::strerror(ENOTDIR)) || has(r.err, std::strerror(EISDIR))) << args << ": " << r.err;
    // Before the work: no progress, no header of the run, no result on stdout.
    EXPECT_FALSE(has(r.err, "thread(s) of")) << args << ": " << r.err;
    EXPECT_EQ(r.out, "") << args;
  }
}

TEST(Cli, JsonOnEveryCommand) {
  Scratch s("json");
  std::ofstream(s / "oct.obj") << kOctahedron;
  const std::string query_line = R"({"primitive":{"type":"sphere","center":[0,0,5],"radius":1},"ray":{"origin":[0,0,0],"direction":[0,0,1]}})";
  for (const char* args : {"ops --json", "info oct.obj --json -", "machine --json", "csg --rays 16 -r 1 --json -",
                           "accuracy --filter '^sphere/far_small_1e1$' --rays 16 --no-timing --json -",
                           "bench --filter '^sphere/geometric/scalar/hit$' -r 1 --min-time 0.001 --json -",
                           "trace oct.obj --count 64 -r 1 --warmup 0 --json -", "render oct.obj --width 8 -r 1 --warmup 0 -o i.png --json -",
                           "query --json"}) {
    const Outcome r = run_in(s.dir, args, "", query_line + "\n");
    EXPECT_EQ(r.status, 0) << args << ": " << r.err;
    if (std::string(args).rfind("query", 0) == 0) {
      EXPECT_NO_THROW(nlohmann::json::parse(r.out.substr(0, r.out.find('\n')))) << r.out;
      continue;
    }
    nlohmann::json j;
    ASSERT_NO_THROW(j = r.json()) << args << ": " << r.out.substr(0, 200);
    // Every result carries the same machine and build block.
    if (std::string(args).rfind("ops", 0) != 0 && std::string(args).rfind("info", 0) != 0) {
      const nlohmann::json& m = std::string(args).rfind("machine", 0) == 0 ? j : j["machine"];
      EXPECT_TRUE(m.contains("cpu") && m.contains("git_revision") && m.contains("git_dirty") && m.contains("build_flags") &&
                  m.contains("host_simd") && m.contains("cores") && m.contains("pgo"))
          << args;
    }
  }
  // --json FILE: the JSON in the file, the table still on the terminal.
  const Outcome r = run_in(s.dir, "info oct.obj --json info.json");
  EXPECT_EQ(r.status, 0);
  EXPECT_TRUE(has(r.out, "primitives")) << r.out;
  EXPECT_NO_THROW(nlohmann::json::parse(slurp(s / "info.json")));
}

// A kind whose few coarse primitives the plan stores apart (in local frames): info lists both of its
// batches.
TEST(Cli, InfoListsThePrimitivesStoredApartInABatchOfTheirOwn) {
  Scratch s("info-apart");
  const Outcome r = run_in(s.dir, "info precision:scattered --json info.json");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(s / "info.json"));
  const auto& b = j["kinds"][0]["batches"];
  ASSERT_EQ(b.size(), 2u) << b;
  EXPECT_EQ(b[0]["batch"], "PrimSoA<triangle> in float");
  EXPECT_EQ(b[1]["batch"], "PrimSoA<triangle> in float, local frames: 2400 apart");
  EXPECT_GT(b[1]["bytes"].get<std::size_t>(), 0u);
  EXPECT_LT(b[1]["bytes"].get<std::size_t>(), b[0]["bytes"].get<std::size_t>());
  EXPECT_TRUE(has(r.out, "local frames: 2400 apart")) << r.out;
  EXPECT_LE(widest(r.out), 80u) << r.out;
}

TEST(Cli, DashOOnlyForTheMainOutputAndFilterIsARegex) {
  Scratch s("help");
  for (const char* c : kCommands) {
    const Outcome r = run_in(s.dir, std::string(c) + " --help");
    EXPECT_EQ(r.status, 0) << c;
    const bool main_output = std::string(c) == "report" || std::string(c) == "render";
    EXPECT_EQ(has(r.out, "-o,--out"), main_output) << c;
    if (has(r.out, "\n  --filter")) {
      EXPECT_TRUE(has(r.out, "regex")) << c << ": --filter must say it is a regex";
    }
  }
  // A regex in accuracy and bench alike (the lab used a substring before).
  Outcome r = run_in(s.dir, "accuracy --list --filter '^torus/(tangent|thin_tube)$'");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "tangent") && has(r.out, "thin_tube")) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n') >= 2, true);
  EXPECT_FALSE(has(r.out, "camera_5x")) << r.out;
  r = run_in(s.dir, "bench --list --filter '^sphere/geometric/(scalar|rays_in_lanes)/hit$'");
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, "sphere/geometric/scalar/hit\nsphere/geometric/rays_in_lanes/hit\n");
  r = run_in(s.dir, "accuracy --filter '(' --list");
  EXPECT_EQ(r.status, 1);
  expect_one_error_line(r, "accuracy", "");
  EXPECT_TRUE(has(r.err, "invalid regular expression")) << r.err;
}

TEST(Cli, RenderWithoutOutputWritesSceneNameAndHainesOnlyUnderSpd) {
  Scratch s("render");
  Outcome r = run_in(s.dir, "render spd:balls:1 --width 16 -r 1 --warmup 0");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(s / "spd_balls_1.png"));
  EXPECT_TRUE(has(r.err, "spd_balls_1.png in the current folder")) << r.err;
  EXPECT_FALSE(has(r.out, "Haines")) << r.out;
  r = run_in(s.dir, "render spd:balls:1 --width 16 -r 1 --warmup 0 --spd -o spd.png");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "Haines")) << r.out;
  EXPECT_LE(widest(r.out), 80u) << r.out;
}

// Box and primitive tests are counted only when asked (--counts, or --spd), in one more render that
// is not timed; the image is the same, as it is under other tile sides and orders. Every render says where its
// time went, per generation.
TEST(Cli, RenderCountsOnlyWhenAskedAndSplitsItsTime) {
  Scratch s("render-counts");
  const std::string base = "render lecture:five_glass_balls --width 32 -r 2 --warmup 0 --min-time 0 --eye-packet 8 --secondary-packet 8 ";
  Outcome r = run_in(s.dir, base + "-o a.png --json -");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json plain = r.json();
  EXPECT_FALSE(plain["tests_counted"].get<bool>());
  EXPECT_EQ(plain["box_tests"], 0u);
  r = run_in(s.dir, base + "--counts -o b.png --json -");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json counted = r.json();
  EXPECT_TRUE(counted["tests_counted"].get<bool>());
  EXPECT_GT(counted["box_tests"].get<std::uint64_t>(), counted["total_rays"].get<std::uint64_t>());
  EXPECT_EQ(counted["trace_seconds"].size(), 2u) << "the counted render is not timed";
  EXPECT_EQ(counted["image_fnv1a"], plain["image_fnv1a"]);
  EXPECT_EQ(counted["total_rays"], plain["total_rays"]);
  // Other tile sides: the same image and rays (each sample's rays do not depend on its tile).
  for (const char* tile : {"5", "64"}) {
    r = run_in(s.dir, base + "--tile " + tile + " -o c.png --json -");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.json()["tile"].get<int>(), std::atoi(tile));
    EXPECT_EQ(r.json()["image_fnv1a"], plain["image_fnv1a"]) << "tile " << tile;
    EXPECT_EQ(r.json()["total_rays"], plain["total_rays"]) << "tile " << tile;
  }
  // Packets of 8 in the ray sort's order: the same image and rays (the hits go back to the batch's
  // order before shading).
  EXPECT_EQ(plain["secondary_order"], "octant");
  r = run_in(s.dir, base + "--secondary-order sfc -o d.png --json -");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.json()["secondary_order"], "sfc");
  EXPECT_EQ(r.json()["image_fnv1a"], plain["image_fnv1a"]) << "--secondary-order sfc";
  EXPECT_EQ(r.json()["total_rays"], plain["total_rays"]) << "--secondary-order sfc";
  r = run_in(s.dir, "render spd:balls:1 --width 16 -r 1 --warmup 0 --spd -o spd.png --json -");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.json()["tests_counted"].get<bool>()) << "--spd counts";
  r = run_in(s.dir, "render spd:balls:1 --width 16 -r 1 --warmup 0 --spd --no-counts -o spd.png --json -");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(r.json()["tests_counted"].get<bool>());
  // The split: generations add up to the rays by kind; the parts to the thread time.
  const nlohmann::json& ts = plain["time_split"];
  std::uint64_t rays = 0, shadow = 0;
  for (const auto& g : ts["generations"]) {
    rays += g["rays"].get<std::uint64_t>();
    shadow += g["shadow_rays"].get<std::uint64_t>();
    EXPECT_LE(g["hits"].get<std::uint64_t>(), g["rays"].get<std::uint64_t>());
  }
  EXPECT_GE(ts["generations"].size(), 2u) << "the glass balls reflect and refract";
  EXPECT_EQ(rays, plain["eye_rays"].get<std::uint64_t>() + plain["reflect_rays"].get<std::uint64_t>() + plain["refract_rays"].get<std::uint64_t>());
  EXPECT_EQ(shadow, plain["shadow_rays"].get<std::uint64_t>());
  EXPECT_EQ(ts["generations"][0]["hits"], plain["eye_hit_rays"]);
  for (const auto& g : ts["generations"])
    for (const char* k : {"coherent_groups", "shadow_coherent_groups"}) {
      EXPECT_GE(g[k].get<double>(), 0.0) << k;
      EXPECT_LE(g[k].get<double>(), 1.0) << k;
    }
  // 32 pixels wide: every 8-ray group of eye rays lies within one row and on one side of the centre
  // column, and this camera has no roll (a ray's x sign follows its column, its y and z signs its
  // row), so every group shares an octant.
  EXPECT_EQ(ts["generations"][0]["coherent_groups"].get<double>(), 1.0);
  double parts = 0;
  for (const char* k : {"generate_ms", "pack_ms", "traverse_eye_ms", "traverse_secondary_ms", "traverse_shadow_ms", "shade_ms", "shadow_light_ms"}) {
    EXPECT_GE(ts[k].get<double>(), 0.0) << k;
    parts += ts[k].get<double>();
  }
  EXPECT_NEAR(parts, ts["thread_ms"].get<double>(), 1e-9 * parts + 1e-12);
  EXPECT_GT(ts["traverse_eye_ms"].get<double>(), 0.0);
  EXPECT_LE(ts["thread_ms"].get<double>(), 1.05 * ts["render_ms"].get<double>()) << "one thread: the parts are within the render";
  r = run_in(s.dir, base + "-o c.png");
  EXPECT_TRUE(has(r.out, "time split of the last timed render")) << r.out;
  EXPECT_LE(widest(r.out), 80u) << r.out;
}

TEST(Cli, BenchPrintsATable) {
  Scratch s("bench");
  const Outcome r = run_in(s.dir, "bench --filter '^sphere/geometric/(scalar|rays_in_lanes)/hit$' -r 3 --min-time 0.001 --json b.json");
  EXPECT_EQ(r.status, 0) << r.err;
  for (const char* col : {"Mtests/s", "CV %", "ops/test", "vs scalar", "sphere/geometric/scalar/hit", "sphere/geometric/rays_in_lanes/hit"})
    EXPECT_TRUE(has(r.out, col)) << col << "\n" << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(rays_in_lanes/hit +[0-9.]+ +[0-9.]+ +[0-9.]+ +[0-9.]+x)"))) << r.out;
  EXPECT_LE(widest(r.out), 80u) << r.out;
  // Rounds: each benchmark once per round, its repetitions numbered by round, Google Benchmark's
  // aggregates over them, and the SIMD form's speedup round by round with its interval.
  const nlohmann::json j = nlohmann::json::parse(slurp(s / "b.json"));
  // The first round finds each benchmark's iterations, the later rounds run as many (under the
  // benchmark's own name, without Google Benchmark's "/iterations:N").
  std::map<std::string, std::vector<int>> rounds;
  std::map<std::string, std::set<std::int64_t>> iterations;
  std::size_t medians = 0;
  for (const auto& b : j["benchmarks"]) {
    if (b["run_type"] == "iteration") {
      rounds[b["run_name"].get<std::string>()].push_back(b["repetition_index"].get<int>());
      iterations[b["name"].get<std::string>()].insert(b["iterations"].get<std::int64_t>());
    }
    medians += b.value("aggregate_name", "") == "median";
  }
  ASSERT_EQ(rounds.size(), 2u) << j.dump(1);
  for (const auto& [name, v] : rounds) EXPECT_EQ(v, (std::vector<int>{0, 1, 2})) << name;
  ASSERT_EQ(iterations.size(), 2u) << j.dump(1);
  for (const auto& [name, v] : iterations) EXPECT_EQ(v.size(), 1u) << name << ": other iterations in another round";
  EXPECT_EQ(medians, 2u);
  const auto& sp = j["raybench_simd_vs_scalar"]["sphere/geometric/rays_in_lanes/hit"];
  EXPECT_EQ(sp["rounds"], 3);
  EXPECT_LE(sp["lo"].get<double>(), sp["ratio"].get<double>());
  EXPECT_GE(sp["hi"].get<double>(), sp["ratio"].get<double>());
  EXPECT_GT(sp["ratio"].get<double>(), 0.0);
  // The machine around the rounds.
  EXPECT_TRUE(j["machine_load"]["load_average_before"].is_number() && j["machine_load"]["load_average_after"].is_number()) << j;
  EXPECT_TRUE(has(r.out, "load average")) << r.out;
}

// --extra-rounds: after the rounds, the forms of a case whose ratio's interval is wider than
// --within run again, a round at a time, paired with each other; none when every interval is narrow.
TEST(Cli, BenchGivesWideCasesExtraRounds) {
  Scratch s("bench_extra");
  const char* filter = "--filter '^sphere/geometric/(scalar|rays_in_lanes)/(hit|miss)$' -r 3 --min-time 0.001 --extra-rounds 2";
  const Outcome r = run_in(s.dir, std::string("bench ") + filter + " --within 0.001 --json b.json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "Extra rounds: 2 of at most 2 (4, 4 benchmarks in turn")) << r.out;
  EXPECT_TRUE(has(r.err, "4 benchmarks x 3 rounds, then 8 runs in 2 extra rounds")) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(s / "b.json"));
  EXPECT_EQ(j["context"]["raybench_rounds"], 3);
  const auto& e = j["raybench_extra_rounds"];
  EXPECT_DOUBLE_EQ(e["within"].get<double>(), 0.00001);
  ASSERT_EQ(e["rounds"].size(), 2u) << e;
  EXPECT_EQ(e["rounds"][0]["round"], 3);
  EXPECT_EQ(e["rounds"][1]["benchmarks"], 4);
  std::map<std::string, std::vector<int>> rounds;
  for (const auto& b : j["benchmarks"])
    if (b["run_type"] == "iteration") {
      rounds[b["run_name"].get<std::string>()].push_back(b["repetition_index"].get<int>());
      EXPECT_EQ(b["repetitions"], 5) << b;
    }
  ASSERT_EQ(rounds.size(), 4u);
  for (const auto& [name, v] : rounds) EXPECT_EQ(v, (std::vector<int>{0, 1, 2, 3, 4})) << name;
  EXPECT_EQ(j["raybench_simd_vs_scalar"]["sphere/geometric/rays_in_lanes/hit"]["rounds"], 5);
  // Every interval within 100 %: no extra round.
  const Outcome n = run_in(s.dir, std::string("bench ") + filter + " --within 100 --json n.json");
  ASSERT_EQ(n.status, 0) << n.err;
  EXPECT_TRUE(has(n.out, "Extra rounds: none needed")) << n.out;
  const nlohmann::json k = nlohmann::json::parse(slurp(s / "n.json"));
  EXPECT_TRUE(k["raybench_extra_rounds"]["rounds"].empty());
  EXPECT_EQ(k["raybench_simd_vs_scalar"]["sphere/geometric/rays_in_lanes/hit"]["rounds"], 3);
}

TEST(Cli, RenderGivesMedianRangeAndCvAndTooManyThreadsWarn) {
  Scratch s("render-time");
  const int more = int(rb::app::hardware_threads()) + 2;
  const Outcome r = run_in(s.dir, "render spd:balls:1 --width 16 -r 3 --warmup 1 --threads " + std::to_string(more) + " --json r.json");
  EXPECT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(s / "r.json"));
  EXPECT_EQ(j["warmup"], 1);
  EXPECT_EQ(j["trace_seconds"].size(), 3u);
  EXPECT_LE(j["trace_ms_min"].get<double>(), j["trace_ms"].get<double>());
  EXPECT_TRUE(has(r.out, "median of 3 repetitions of at least 0.1 s")) << r.out;
  EXPECT_TRUE(has(r.out, "after 1 warm-up and 3 trial renders")) << r.out;
  // Each repetition lasted --min-time (0.1 s by default): this tiny image is rendered many times, up to
  // the cap of 1000 renders per repetition (which a fast machine reaches within 0.1 s).
  ASSERT_EQ(j["passes"].size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const int passes = j["passes"][i].get<int>();
    EXPECT_GT(passes, 1) << j["passes"];
    EXPECT_LE(passes, 1000) << j["passes"];
    if (passes < 1000) {
      EXPECT_GE(passes * j["trace_seconds"][i].get<double>(), 0.1) << j["passes"];
    }
  }
  EXPECT_TRUE(has(r.err, "warning: " + std::to_string(more) + " threads asked for")) << r.err;
  // The machine around the renders, as trace and bench record it.
  EXPECT_TRUE(j["machine_load"]["load_average_before"].is_number() && j["machine_load"]["load_average_after"].is_number()) << j;
  EXPECT_TRUE(has(r.out, "load average")) << r.out;
}

// Packet sizes by default: trial renders try eye packets of 64, 16 and 8 and the other rays one by
// one and in packets of 8, in turn, and the timed renders use the size with the least trace time
// for each; given sizes are used as given, without trials.
TEST(Cli, RenderChoosesTheFastestPacketSizesInTrialRenders) {
  Scratch s("render-packets");
  Outcome r = run_in(s.dir, "render spd:balls:1 --width 16 -r 1 --warmup 0 -o b.png --json -");
  ASSERT_EQ(r.status, 0) << r.err;
  nlohmann::json j = r.json();
  EXPECT_EQ(j["trial_renders"], 3);
  const auto& trials = j["packet_choice"]["trials"];
  ASSERT_EQ(trials.size(), 3u);
  std::map<int, double> eye, other, eye_shadow;
  auto keep_least = [](std::map<int, double>& m, int size, double ms) { m[size] = m.count(size) ? std::min(m[size], ms) : ms; };
  for (const auto& t : trials) {
    keep_least(eye, t["eye_packet"], t["eye_trace_ms"].get<double>());
    keep_least(other, t["secondary_packet"], t["secondary_trace_ms"].get<double>());
    keep_least(eye_shadow, t["eye_shadow_packet"], t["eye_shadow_trace_ms"].get<double>());
  }
  EXPECT_EQ(eye.size(), 3u);
  EXPECT_EQ(other.size(), 2u);
  EXPECT_EQ(eye_shadow.size(), 3u);  // 1, 8 and 16
  auto least = [](const std::map<int, double>& m) {
    return std::min_element(m.begin(), m.end(), [](const auto& a, const auto& b) { return a.second < b.second; })->first;
  };
  EXPECT_EQ(j["eye_packet"].get<int>(), least(eye));
  EXPECT_EQ(j["secondary_packet"].get<int>(), least(other));
  EXPECT_EQ(j["eye_shadow_packet"].get<int>(), least(eye_shadow));  // chosen apart from the other rays'
  EXPECT_GT(eye_shadow.at(1) + eye_shadow.at(8) + eye_shadow.at(16), 0.0);  // the eye rays' shadow rays were traced and timed
  EXPECT_GT(other.at(1) + other.at(8), 0.0);

  r = run_in(s.dir, "render spd:balls:1 --width 16 -r 1 --warmup 0 --eye-packet 8 --secondary-packet 8 -o b.png --json -");
  ASSERT_EQ(r.status, 0) << r.err;
  j = r.json();
  EXPECT_EQ(j["trial_renders"], 0);
  EXPECT_EQ(j["eye_packet"], 8);
  EXPECT_EQ(j["secondary_packet"], 8);
  EXPECT_EQ(j["eye_shadow_packet"], 8);  // as --secondary-packet
  EXPECT_EQ(j["packet_choice"]["eye"], "given");
  EXPECT_TRUE(j["packet_choice"]["trials"].empty());
  // The eye rays' shadow rays given apart from the other rays.
  r = run_in(s.dir, "render spd:balls:1 --width 16 -r 1 --warmup 0 --eye-packet 8 --secondary-packet 1 --eye-shadow-packet 16 -o b.png --json -");
  ASSERT_EQ(r.status, 0) << r.err;
  j = r.json();
  EXPECT_EQ(j["trial_renders"], 0);
  EXPECT_EQ(j["secondary_packet"], 1);
  EXPECT_EQ(j["eye_shadow_packet"], 16);
  EXPECT_EQ(j["packet_choice"]["eye_shadow"], "given");
  const Outcome wrong = run_in(s.dir, "render spd:balls:1 --eye-packet 32 -o b.png");
  EXPECT_EQ(wrong.status, 1);
  EXPECT_TRUE(has(wrong.err, "'32' is not a packet size here; choose auto, 1, 8, 16, 64")) << wrong.err;
  const Outcome wrong2 = run_in(s.dir, "render spd:balls:1 --secondary-packet 16 -o b.png");
  EXPECT_EQ(wrong2.status, 1);
  EXPECT_TRUE(has(wrong2.err, "choose auto, 1, 8")) << wrong2.err;
}

TEST(Cli, HelpAndTablesFitEightyColumns) {
  Scratch s("width");
  std::ofstream(s / "oct.obj") << kOctahedron;
  std::vector<std::string> runs = {"--help", "ops", "ops --notes", "info spd:teapot", "machine", "csg --rays 16 -r 1",
                                   "accuracy --filter '^(box|triangle)/' --rays 16 --no-timing", "accuracy --list",
                                   "trace oct.obj --count 64 -r 2 --warmup 0", "render spd:balls:1 --width 8 -r 1 --warmup 0 -o b.png",
                                   "plan precision:scattered", "plan csg:die"};
  for (const char* c : kCommands) runs.push_back(std::string(c) + " --help");
  for (const auto& args : runs) {
    const Outcome r = run_in(s.dir, args);
    EXPECT_EQ(r.status, 0) << args << ": " << r.err;
    EXPECT_LE(widest(r.out), 80u) << args << "\n" << r.out;
  }
  // Units in the column headers.
  const Outcome acc = run_in(s.dir, "accuracy --filter '^box/' --rays 16 --no-timing");
  EXPECT_TRUE(has(acc.out, "ppm") && has(acc.out, "p99 ulp")) << acc.out;
}

}  // namespace
