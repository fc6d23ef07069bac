// The JSON scene format's CSG nodes: each error names the file and the JSON path, and `raybench
// query` answers a CSG tree with its closest hit, normal and interval list.
#include "apps/query.hpp"
#include "scene/csg_scene.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <regex>
#include <sstream>
#include <string>

namespace {

using namespace rb;

// ---- the JSON format's errors ---------------------------------------------------------------
std::string error_of(const std::string& text) {
  try {
    (void)scene::parse_json_scene(text, "scene.json");
  } catch (const scene::SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(CsgJson, ErrorsNameFileAndPath) {
  const std::string head = R"({"objects": [{"type": "sphere", "center": [0,0,0], "radius": 1}, {"type": "box", "min": [0,0,0], "max": [1,1,1]},)";
  EXPECT_EQ(error_of(head + R"({"type": "difference", "left": {"type": "sphere", "center": [0,0,0], "radius": 1},
      "right": {"type": "sphere", "center": [0,0,0], "radius": -2}}]})"),
            "scene.json: objects[2].right.radius: expected a positive number");
  EXPECT_EQ(error_of(head + R"({"type": "union", "children": [{"type": "box", "min": [0,0,0], "max": [1,1,1]}, {"type": "blob"}]}]})"),
            "scene.json: objects[2].children[1].type: unknown type \"'blob'\" (union, intersection, difference, sphere, box, "
            "polyhedron, cylinder, cone, torus, ellipsoid, quadric)");
  EXPECT_EQ(error_of(head + R"({"type": "difference", "left": {"type": "sphere", "center": [0,0], "radius": 1}, "right": {"type": "box", "min": [0,0,0], "max": [1,1,1]}}]})"),
            "scene.json: objects[2].left.center: expected an array of three numbers");
  EXPECT_EQ(error_of(head + R"({"type": "intersection", "left": {"type": "sphere", "center": [0,0,0], "radius": 1}}]})"),
            "scene.json: objects[2].right: missing");
  EXPECT_EQ(error_of(head + R"({"type": "quadric", "coefficients": [1,1,-1,0,0,0,0,0,0,-1]}]})"),
            "scene.json: objects[2]: quadric: not bounded (its quadratic part must be positive definite: an ellipsoid)");
  EXPECT_EQ(error_of(head + R"({"type": "sphere", "center": [0,0,0], "radius": 1, "material": "nope"}]})"),
            "scene.json: objects[2].material: unknown material \"'nope'\"");
  EXPECT_EQ(error_of(head + R"({"type": "box", "min": [0,0,0], "max": [1,1,1], "transform": {"scale": [1, 0, 1]}}]})"),
            "scene.json: objects[2].transform.scale: expected non-zero scale factors");
  EXPECT_EQ(error_of(R"({"objects": [{"type": "polyhedron", "planes": [{"normal": [1,0,0], "point": [0,0,0]}, {"normal": [0,1,0], "point": [0,0,0]},
      {"normal": [0,0,1], "point": [0,0,0]}, {"normal": [-1,0,0], "point": [-1,0,0]}]}]})"),
            "scene.json: objects[0].planes: the halfspaces do not bound a non-empty solid");
  EXPECT_EQ(error_of(R"({"objects": [{"type": "torus", "center": [0,0,0], "axis": [0,0,1], "major": 1, "minor": 2}]})"),
            "scene.json: objects[0].minor: expected a number below \"major\" (a ring torus)");
  EXPECT_EQ(error_of(R"({"objects": 3})"), "scene.json: objects: expected an array");
  EXPECT_EQ(error_of(R"({"objekts": []})"), "scene.json: objekts: unknown key (camera, background, lights, materials, objects); did you mean 'objects'?");
  EXPECT_TRUE(std::regex_search(error_of(R"({"objects": [)"), std::regex("^scene\\.json: malformed JSON at byte 1[34]"))) << error_of(R"({"objects": [)");
  // Too many interval ends: 33 spheres in one union.
  std::string big = R"({"objects": [{"type": "union", "children": [)";
  for (int i = 0; i < 33; ++i) big += std::string(i ? "," : "") + R"({"type": "sphere", "center": [0,0,0], "radius": 1})";
  big += "]}]}";
  EXPECT_EQ(error_of(big), "scene.json: objects[0].children[32]: the CSG tree has more than 64 interval ends (2 per leaf, 4 per torus)");
}


// `raybench query` answers a CSG tree with the closest hit, its normal and the whole interval list.
TEST(CsgJson, QueryAcceptsACsgTree) {
  std::istringstream in(
      R"({"primitive":{"type":"difference","left":{"type":"sphere","center":[0,0,5],"radius":1},"right":{"type":"box","min":[-2,-2,3],"max":[2,2,4.5]}},"ray":{"origin":[0,0,0],"direction":[0,0,2]}})"
      "\n"
      R"({"primitive":{"type":"union","children":[{"type":"sphere","center":[0,0,5],"radius":-1}]},"ray":{"origin":[0,0,0],"direction":[0,0,1]}})"
      "\n");
  std::ostringstream out, err;
  EXPECT_EQ(rb::app::run_query(in, out, err, false), 1);
  std::istringstream lines(out.str());
  std::string a, b;
  std::getline(lines, a);
  std::getline(lines, b);
  const auto ja = nlohmann::json::parse(a), jb = nlohmann::json::parse(b);
  const auto& r = ja["results"][0];
  EXPECT_EQ(r["method"], "csg");
  EXPECT_TRUE(r["hit"].get<bool>());
  EXPECT_NEAR(r["t"].get<double>(), 2.25, 1e-6);  // 4.5 along a direction of length 2
  EXPECT_NEAR(r["normal"][2].get<double>(), -1.0, 1e-6);  // the box's far face, flipped: towards the ray
  ASSERT_EQ(r["intervals"].size(), 1u);
  EXPECT_NEAR(r["intervals"][0][1].get<double>(), 3.0, 1e-6);
  EXPECT_EQ(jb["error"], "primitive.children: expected an array of at least two nodes");
}

}  // namespace
