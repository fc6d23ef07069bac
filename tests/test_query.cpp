// `raybench query`: every primitive type answers, results agree with hand-worked values, t is in
// the caller's direction units, and malformed lines get an error naming the line.
#include "apps/query.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace rb::app {
namespace {
using nlohmann::json;

std::vector<json> run(const std::string& in, bool dbl = false) {
  std::istringstream is(in);
  std::ostringstream os;
  (void)run_query(is, os, dbl);
  std::vector<json> out;
  std::istringstream rs(os.str());
  std::string line;
  while (std::getline(rs, line)) out.push_back(json::parse(line));
  return out;
}

const std::string kRay = R"("ray": {"origin": [0.1, 0.2, -10], "direction": [0, 0, 1]})";

TEST(Query, EveryTypeAnswersWithEveryMethod) {
  const std::vector<std::pair<std::string, double>> cases = {
      {R"({"type":"sphere","center":[0,0,0],"radius":1})", -1.0},
      {R"({"type":"triangle","v0":[-1,-1,0],"v1":[2,-1,0],"v2":[-1,2,0]})", 0.0},
      {R"({"type":"plane","point":[0,0,0],"normal":[0,0,1],"u":[1,0,0],"v":[0,1,0]})", 0.0},
      {R"({"type":"parallelogram","origin":[-1,-1,0],"u":[2,0,0],"v":[0,2,0]})", 0.0},
      {R"({"type":"polygon","vertices":[[-1,-1,0],[1,-1,0],[1,1,0],[0,0.5,0],[-1,1,0]]})", 0.0},
      {R"({"type":"box","min":[-1,-1,-1],"max":[1,1,1]})", -1.0},
      {R"({"type":"cylinder","base":[0,0,-1],"axis":[0,0,1],"radius":1,"height":2,"caps":true})", -1.0},
      {R"({"type":"cone","apex":[0,0,-1],"axis":[0,0,1],"radius":1,"height":2,"caps":true})", -1.0},
      {R"({"type":"torus","center":[0,0,0],"axis":[0,1,0],"major":2,"minor":0.5})", -0.5},
      {R"({"type":"quadric","coefficients":[1,1,1,0,0,0,0,0,0,-1]})", -1.0},
  };
  for (const auto& [prim, z] : cases) {
    const auto out = run(R"({"primitive": )" + prim + ", " + kRay + "}\n");
    ASSERT_EQ(out.size(), 1u);
    ASSERT_FALSE(out[0].contains("error")) << out[0].dump();
    ASSERT_FALSE(out[0]["results"].empty());
    for (const auto& r : out[0]["results"]) {
      SCOPED_TRACE(prim + " " + r.dump());
      if (out[0]["primitive"] == "cone" || out[0]["primitive"] == "torus") {
        // the ray at (0.1, 0.2) enters the cone's side / the torus tube's top: just a hit in front
        EXPECT_TRUE(r["hit"].get<bool>());
        continue;
      }
      ASSERT_TRUE(r["hit"].get<bool>());
      const double expect_t = z + 10 + (out[0]["primitive"] == "sphere" || out[0]["primitive"] == "quadric"
                                             ? 1.0 - std::sqrt(1.0 - 0.05)
                                             : 0.0);
      EXPECT_NEAR(r["t"].get<double>(), expect_t, 1e-5);
      EXPECT_NEAR(r["point"][2].get<double>(), z + (expect_t - (z + 10)), 1e-5);
    }
  }
}

TEST(Query, TIsInTheCallersDirectionUnits) {
  const auto out = run(R"({"primitive": {"type":"sphere","center":[0,0,10],"radius":1}, "ray": {"origin":[0,0,0],"direction":[0,0,4]}, "method":"geometric"})"
                       "\n");
  ASSERT_EQ(out[0]["results"].size(), 1u);
  EXPECT_NEAR(out[0]["results"][0]["t"].get<double>(), 9.0 / 4.0, 1e-6);
  EXPECT_NEAR(out[0]["results"][0]["normal"][2].get<double>(), -1.0, 1e-6);
}

TEST(Query, FarTorusRayReturnsTheEntry) {
  // |d|^2 - 1 of the float-rounded direction must not move the bounding-sphere clip past the entry.
  const std::string line =
      R"({"primitive":{"type":"torus","center":[0.5,-0.25,0.125],"axis":[0,0,1],"major":1,"minor":0.25},)"
      R"("ray":{"origin":[-375.5374450683594,128.5894012451172,-482.1832580566406],)"
      R"("direction":[375.24676513671875,-129.3311004638672,482.7933654785156]}, "method":"robust"})";
  for (const bool dbl : {false, true}) {
    const auto out = run(line + "\n", dbl);
    ASSERT_EQ(out.size(), 1u);
    ASSERT_EQ(out[0]["results"].size(), 1u) << out[0].dump();
    const auto& r = out[0]["results"][0];
    ASSERT_TRUE(r["hit"].get<bool>()) << r.dump();
    // t is in the caller's direction units: |direction| = 624.67...; distance 624.3249.
    const double len = std::sqrt(375.24676513671875 * 375.24676513671875 + 129.3311004638672 * 129.3311004638672 +
                                 482.7933654785156 * 482.7933654785156);
    EXPECT_NEAR(r["t"].get<double>() * len, 624.3249, 2e-3) << (dbl ? "double" : "float");
  }
}

TEST(Query, MissesAndBadRays) {
  const auto out = run(R"({"primitive": {"type":"box","min":[-1,-1,-1],"max":[1,1,1]}, "ray": {"origin":[5,0,-10],"direction":[0,0,1]}})"
                       "\n"
                       R"({"primitive": {"type":"box","min":[-1,-1,-1],"max":[1,1,1]}, "ray": {"origin":[0,0,-10],"direction":[0,0,0]}})"
                       "\n",
                       true);
  ASSERT_EQ(out.size(), 2u);
  for (const auto& o : out)
    for (const auto& r : o["results"]) {
      EXPECT_FALSE(r["hit"].get<bool>());
      EXPECT_FALSE(r.contains("t"));
    }
  EXPECT_FALSE(out[1]["valid_ray"].get<bool>());
}

TEST(Query, MalformedLinesNameTheLineAndTheProblem) {
  const auto out = run("{not json\n"
                       R"({"primitive": {"type":"blob"}, )" + kRay + "}\n" +
                       R"({"primitive": {"type":"sphere","center":[0,0],"radius":1}, )" + kRay + "}\n" +
                       R"({"primitive": {"type":"sphere","center":[0,0,0],"radius":1}, )" + kRay + R"(, "method":"woop"})" + "\n" +
                       R"({"primitive": {"type":"torus","center":[0,0,0],"axis":[0,0,1],"major":1,"minor":2}, )" + kRay + "}\n" +
                       R"({"primitive": {"type":"sphere","center":[0,0,0],"radius":1}, )" + kRay + "}\n");
  ASSERT_EQ(out.size(), 6u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(out[i]["line"].get<int>(), i + 1);
    ASSERT_TRUE(out[i].contains("error")) << out[i].dump();
  }
  EXPECT_NE(out[0]["error"].get<std::string>().find("malformed JSON"), std::string::npos);
  EXPECT_NE(out[1]["error"].get<std::string>().find("unknown primitive type \"blob\""), std::string::npos);
  EXPECT_NE(out[2]["error"].get<std::string>().find("\"center\" must be an array of three numbers"), std::string::npos);
  EXPECT_NE(out[3]["error"].get<std::string>().find("does not apply to a sphere"), std::string::npos);
  EXPECT_NE(out[4]["error"].get<std::string>().find("r = "), std::string::npos);
  EXPECT_FALSE(out[5].contains("error"));  // the lines after a bad one still run
}

// The subcommand convention: a failed line is also one line on stderr naming it, and the status is 1.
TEST(Query, FailedLinesAreNamedOnStderrAndSetTheStatus) {
  std::istringstream in(std::string("not json\n") + R"({"primitive": {"type":"sphere","center":[0,0,5],"radius":1}, )" +
                        R"("ray": {"origin":[0,0,0],"direction":[0,0,1]}})" + "\n");
  std::ostringstream out, err;
  EXPECT_EQ(run_query(in, out, err, false), 1);
  EXPECT_EQ(err.str().rfind("raybench query: stdin line 1: malformed JSON", 0), 0u) << err.str();
  EXPECT_EQ(err.str().find("line 2"), std::string::npos) << err.str();
  std::istringstream good(R"({"primitive": {"type":"sphere","center":[0,0,5],"radius":1}, "ray": {"origin":[0,0,0],"direction":[0,0,1]}})");
  std::ostringstream out2, err2;
  EXPECT_EQ(run_query(good, out2, err2, false), 0);
  EXPECT_TRUE(err2.str().empty());
}


// ---- reproducers of the release probe, through the query ------------------------------------------
// (The kernels on the same rays, compiled with contraction on, are in test_release_robustness.cpp.)

// One query line, float or double; the results array.
json query(const std::string& line, bool dbl) {
  const auto out = run(line + "\n", dbl);
  EXPECT_EQ(out.size(), 1u);
  if (out.empty()) return json::array();
  EXPECT_FALSE(out[0].contains("error")) << out[0].dump();
  return out[0]["results"];
}

bool finite_json(const json& r) {
  for (const char* k : {"t", "point", "normal"}) {
    if (!r.contains(k)) continue;
    if (r[k].is_array()) {
      for (const auto& v : r[k])
        if (!v.is_number() || !std::isfinite(v.get<double>())) return false;
    } else if (!r[k].is_number() || !std::isfinite(r[k].get<double>())) {
      return false;
    }
  }
  return true;
}

// A hit exactly on the apex of a capped cone (finite normal), and a ray through the apex into it
// (entry at the apex: t = 8 in the direction's units, 18 in unit ones).
TEST(Query, ConeApexReproducers) {
  const std::string cone = R"({"type":"cone","apex":[0,0,0],"axis":[0,0,1],"radius":1,"height":1,"caps":true})";
  for (bool dbl : {false, true}) {
    SCOPED_TRACE(dbl ? "double" : "float");
    auto r1 = query(R"({"primitive":)" + cone + R"(,"ray":{"origin":[0,0,-5],"direction":[0,0,1]}})", dbl);
    ASSERT_EQ(r1.size(), 1u);
    EXPECT_TRUE(r1[0]["hit"].get<bool>());
    EXPECT_NEAR(r1[0]["t"].get<double>(), 5.0, 1e-5);
    EXPECT_TRUE(finite_json(r1[0])) << r1[0].dump();
    auto r2 = query(R"({"primitive":)" + cone + R"(,"ray":{"origin":[2,8,-16],"direction":[-0.25,-1,2]}})", dbl);
    ASSERT_EQ(r2.size(), 1u);
    EXPECT_TRUE(r2[0]["hit"].get<bool>()) << r2[0].dump();
    EXPECT_NEAR(r2[0]["t"].get<double>(), 8.0, 1e-3);
    EXPECT_TRUE(finite_json(r2[0])) << r2[0].dump();
  }
}

// Origin inside the unit box: t is the exit (at x = 1), not 0, with both box methods.
TEST(Query, BoxFromInsideReturnsTheExit) {
  for (bool dbl : {false, true}) {
    const auto res = query(R"({"primitive":{"type":"box","min":[-1,-1,-1],"max":[1,1,1]},"ray":{"origin":[0.25,0,0],"direction":[2,0,0]}})", dbl);
    ASSERT_EQ(res.size(), 2u);  // slab, halfspaces
    for (const auto& r : res) {
      SCOPED_TRACE(r.dump());
      EXPECT_TRUE(r["hit"].get<bool>());
      EXPECT_NEAR(r["t"].get<double>(), 0.375, 1e-6);  // (1 - 0.25) / |direction| = 2
      EXPECT_NEAR(r["normal"][0].get<double>(), 1.0, 1e-6);
    }
  }
}

}  // namespace
}  // namespace rb::app
