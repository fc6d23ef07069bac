// What users type wrong or leave out, on the built `raybench`: an optional FILE that took the
// scene, misspelt values and scene names and keys (the closest one named), an empty scene, and the
// image size from one side and the camera's aspect ratio.
#include "cli_test_util.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace {

using namespace rbtest;

TEST(CliInput, MisspelledCommandNamesTheClosest) {
  Scratch s("typo");
  Outcome r = run_in(s.dir, "tarce bunny.obj");
  EXPECT_EQ(r.status, 1);
  ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
  EXPECT_TRUE(has(r.err, "did you mean 'trace'")) << r.err;
  r = run_in(s.dir, "trace x.obj --trheads 2");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(has(r.err, "did you mean '--threads'")) << r.err;
  expect_one_error_line(r, "trace", "");
}

TEST(CliInput, EveryParseErrorExitsOneWithOneLine) {
  Scratch s("parse");
  // CLI11's own codes were 105 (validation), 106 (required), 109 (extras), 101 (conversion).
  for (const char* args : {"trace", "trace x.obj --packet 3", "bench -r abc", "trace x.obj --threads -1", "render x.obj --depth 0",
                           "compare a.json", "accuracy --rays 2", "machine extra"}) {
    const Outcome r = run_in(s.dir, args);
    EXPECT_EQ(r.status, 1) << args << ": " << r.err;
    const std::string cmd = std::string(args).substr(0, std::string(args).find(' '));
    expect_one_error_line(r, cmd, "");
  }
  const Outcome none = run_in(s.dir, "");
  EXPECT_EQ(none.status, 1);
  EXPECT_TRUE(has(none.err, "a command is required"));
}

// `--json` and `--dump-json` take an optional FILE: before the scene they took it, and the scene was
// missing. The word goes back to its place; the JSON goes to stdout.
TEST(CliInput, AnOptionalFileBeforeTheSceneLeavesTheScene) {
  Scratch s("optional-file");
  std::ofstream(s / "oct.obj") << kOctahedron;
  for (const char* args : {"trace --json oct.obj --count 64 -r 1 --warmup 0 --no-embree", "info --json oct.obj", "plan --json oct.obj",
                           "info --dump-json csg:lens"}) {
    const Outcome r = run_in(s.dir, args);
    EXPECT_EQ(r.status, 0) << args << ": " << r.err;
    EXPECT_NO_THROW(r.json()) << args << ": " << r.out.substr(0, 200);
  }
  EXPECT_FALSE(fs::exists(s / "oct.obj.json"));
  // Given after the scene, --json FILE still names the file.
  Outcome r = run_in(s.dir, "info oct.obj --json out.json");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(s / "out.json"));
  // Nothing left for the scene: the parser's message, exit 1.
  r = run_in(s.dir, "trace --json");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(has(r.err, "scene is required")) << r.err;
}

TEST(CliInput, MisspeltValuesAndSceneNamesNameTheClosest) {
  Scratch s("values");
  std::ofstream(s / "oct.obj") << kOctahedron;
  const struct {
    const char* args;
    const char* closest;
  } cases[] = {{"trace oct.obj --rays primry", "'primary'"}, {"trace oct.obj --model exakt", "'exact'"},
               {"info spd:bals", "'balls'"},                {"info csg:dei", "'die'"},
               {"info precision:planett", "'planet'"},      {"info lecture:sphers", nullptr}};
  for (const auto& c : cases) {
    const Outcome r = run_in(s.dir, c.args);
    EXPECT_EQ(r.status, 1) << c.args;
    ASSERT_EQ(r.err_lines().size(), 1u) << c.args << ": " << r.err;
    if (c.closest) {
      EXPECT_TRUE(has(r.err, std::string("did you mean ") + c.closest)) << c.args << ": " << r.err;
    }
  }
}

// A misspelt key of a JSON scene is an error naming where it is and the key meant, not a default.
TEST(CliInput, AJsonScenesUnknownKeysAreErrors) {
  Scratch s("keys");
  const std::string head = R"({"objects": [)";
  const struct {
    const char* object;
    const char* where;
  } cases[] = {
      {R"({"type": "box", "min": [0,0,0], "max": [1,1,1], "trnsform": {"translate": [1,0,0]}})", "objects[0].trnsform"},
      {R"({"type": "sphere", "center": [0,0,0], "radius": 1, "colour": [1,0,0]})", "objects[0].colour"},
      {R"({"type": "union", "children": [{"type": "sphere", "center": [0,0,0], "radius": 1, "raduis": 2}, {"type": "box", "min": [0,0,0], "max": [1,1,1]}]})",
       "objects[0].children[0].raduis"},
      {R"({"type": "polygon", "vertices": [[0,0,0],[1,0,0],[0,1,0]], "transform": {"scale": 2}})", "objects[0].transform"},
  };
  for (const auto& c : cases) {
    std::ofstream(s / "scene.json") << head << c.object << "]}";
    const Outcome r = run_in(s.dir, "info scene.json");
    EXPECT_EQ(r.status, 1) << c.object;
    EXPECT_TRUE(has(r.err, std::string("scene.json: ") + c.where + ": unknown key")) << r.err;
  }
  std::ofstream(s / "scene.json") << R"({"camera": {"form": [0,0,5]}, "objects": []})";
  const Outcome r = run_in(s.dir, "info scene.json");
  EXPECT_TRUE(has(r.err, "camera.form: unknown key") && has(r.err, "did you mean 'from'")) << r.err;
}

TEST(CliInput, AnEmptySceneIsDescribedAndExitsTwo) {
  Scratch s("empty-info");
  std::ofstream(s / "empty.obj") << "# no geometry\n";
  const Outcome r = run_in(s.dir, "info empty.obj");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(has(r.out, "primitives")) << r.out;
  EXPECT_TRUE(has(r.err, "raybench info: empty.obj: the scene has no primitives")) << r.err;
}

// One side given: the other from the camera's aspect ratio (a camera of 64 x 40 pixels).
TEST(CliInput, ImageSizeFromOneSideKeepsTheCamerasAspect) {
  Scratch s("aspect");
  std::ofstream(s / "scene.json") << R"({"camera": {"from": [0,0,5], "at": [0,0,0], "width": 64, "height": 40},
    "lights": [{"position": [0,5,5]}], "objects": [{"type": "sphere", "center": [0,0,0], "radius": 1}]})";
  const struct {
    const char* size;
    int w, h;
  } cases[] = {{"--width 16", 16, 10}, {"--height 20", 32, 20}, {"", 64, 40}, {"--width 8 --height 8", 8, 8}};
  for (const auto& c : cases) {
    const Outcome r = run_in(s.dir, std::string("render scene.json -r 1 --warmup 0 --no-counts -o i.png --json ") + c.size);
    ASSERT_EQ(r.status, 0) << c.size << ": " << r.err;
    const auto j = r.json();
    EXPECT_EQ(j["width"].get<int>(), c.w) << c.size;
    EXPECT_EQ(j["height"].get<int>(), c.h) << c.size;
  }
}

TEST(CliInput, OpsAndCsgFilterTheirRows) {
  Scratch s("filters");
  Outcome r = run_in(s.dir, "ops --filter '^sphere/' --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto rows = r.json();
  ASSERT_FALSE(rows.empty());
  for (const auto& row : rows) EXPECT_EQ(row["kernel"].get<std::string>(), "sphere") << row.dump();
  r = run_in(s.dir, "csg --filter 'lens$' --rays 16 -r 1 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  ASSERT_EQ(r.json()["rows"].size(), 1u);
  EXPECT_EQ(r.json()["rows"][0]["scene"], "csg:lens");
  for (const char* args : {"ops --filter nosuchrow", "csg --filter nosuchscene"}) {
    r = run_in(s.dir, args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_TRUE(has(r.err, "selects no")) << r.err;
  }
}

}  // namespace

namespace {

// `report --from DIR` takes its figures, and so the options that chose them, from DIR's record: a
// folder without one, a record that is not one, and options that would change what was measured are
// refused with one line naming the folder or the file (a record of another format, or edited since:
// its digest).
TEST(CliInput, ReportFromTakesOnlyAFolderWithARecord) {
  Scratch s("report-from");
  fs::create_directory(s.dir / "empty");
  Outcome r = run_in(s.dir, "report --from empty --no-charts");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(has(r.err, "empty/measured.json") && has(r.err, "cannot be read")) << r.err;
  fs::create_directory(s.dir / "bad");
  std::ofstream(s / "bad/measured.json") << "{\"measurements\": {\"options\": {\"quick\": true}}}";
  r = run_in(s.dir, "report --from bad --no-charts");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(has(r.err, "bad/measured.json") && has(r.err, "another format")) << r.err;
  // An edited record: its measurements no longer match their digest.
  std::ofstream(s / "bad/measured.json") << "{\"format\": 1, \"digest\": \"0123456789abcdef\", \"measurements\": {\"options\": {}}}";
  r = run_in(s.dir, "report --from bad --no-charts");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(has(r.err, "bad/measured.json") && has(r.err, "digest")) << r.err;
  for (const char* text : {"[1, 2", "{\"measurements\": {\"x\": 1e999}}"}) {  // truncated; a number beyond double
    std::ofstream(s / "bad/measured.json") << text;
    r = run_in(s.dir, "report --from bad --no-charts");
    EXPECT_EQ(r.status, 1) << text;
    EXPECT_TRUE(has(r.err, "bad/measured.json") && has(r.err, "not JSON")) << r.err;
  }
  for (const char* opt : {"--quick", "-r 3", "--filter sphere", "--out x", "--min-time 0.01"}) {
    r = run_in(s.dir, std::string("report --from bad ") + opt);
    EXPECT_EQ(r.status, 1) << opt;
    EXPECT_TRUE(has(r.err, "not taken with --from")) << opt << ": " << r.err;
    EXPECT_EQ(r.err_lines().size(), 1u) << r.err;
  }
}

}  // namespace
