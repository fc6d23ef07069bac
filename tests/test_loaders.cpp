// Scene loaders (OBJ, PLY, NFF), the NFF writer and load_scene dispatch.
#include "scene/loaders.hpp"
#include "scene/sources.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>

namespace fs = std::filesystem;
using namespace rb::scene;
using rb::Vec3f;

namespace {

template <class A, class B>
bool eq(const rb::Vec3<A>& a, const rb::Vec3<B>& b) {
  return double(a.x) == double(b.x) && double(a.y) == double(b.y) && double(a.z) == double(b.z);
}

// Equal scenes: every array and parameter, bit for bit (names excepted).
void expect_equal(const Scene& a, const Scene& b) {
  EXPECT_TRUE(eq(a.camera.from, b.camera.from) && eq(a.camera.at, b.camera.at) && eq(a.camera.up, b.camera.up));
  EXPECT_EQ(a.camera.angle, b.camera.angle);
  EXPECT_EQ(a.camera.hither, b.camera.hither);
  EXPECT_EQ(a.camera.width, b.camera.width);
  EXPECT_EQ(a.camera.height, b.camera.height);
  EXPECT_TRUE(eq(a.background, b.background));
  ASSERT_EQ(a.lights.size(), b.lights.size());
  for (std::size_t i = 0; i < a.lights.size(); ++i)
    EXPECT_TRUE(eq(a.lights[i].pos, b.lights[i].pos) && eq(a.lights[i].color, b.lights[i].color));
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (std::size_t i = 0; i < a.materials.size(); ++i) {
    const auto &m = a.materials[i], &n = b.materials[i];
    EXPECT_TRUE(eq(m.color, n.color) && m.kd == n.kd && m.ks == n.ks && m.shine == n.shine && m.t == n.t && m.ior == n.ior) << i;
  }
  ASSERT_EQ(a.spheres.size(), b.spheres.size());
  for (std::size_t i = 0; i < a.spheres.size(); ++i)
    EXPECT_TRUE(eq(a.spheres[i].c, b.spheres[i].c) && a.spheres[i].r == b.spheres[i].r && a.spheres[i].mat == b.spheres[i].mat) << i;
  ASSERT_EQ(a.cones.size(), b.cones.size());
  for (std::size_t i = 0; i < a.cones.size(); ++i) {
    const auto &c = a.cones[i], &d = b.cones[i];
    EXPECT_TRUE(eq(c.base, d.base) && eq(c.apex, d.apex) && c.base_r == d.base_r && c.apex_r == d.apex_r && c.mat == d.mat) << i;
  }
  ASSERT_EQ(a.polygons.size(), b.polygons.size());
  for (std::size_t i = 0; i < a.polygons.size(); ++i)
    EXPECT_TRUE(a.polygons[i].first == b.polygons[i].first && a.polygons[i].count == b.polygons[i].count && a.polygons[i].mat == b.polygons[i].mat);
  ASSERT_EQ(a.poly_verts.size(), b.poly_verts.size());
  for (std::size_t i = 0; i < a.poly_verts.size(); ++i) EXPECT_TRUE(eq(a.poly_verts[i], b.poly_verts[i]));
  ASSERT_EQ(a.poly_normals.size(), b.poly_normals.size());
  for (std::size_t i = 0; i < a.poly_normals.size(); ++i) EXPECT_TRUE(eq(a.poly_normals[i], b.poly_normals[i]));
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (std::size_t i = 0; i < a.triangles.size(); ++i) EXPECT_TRUE(a.triangles[i].v == b.triangles[i].v && a.triangles[i].mat == b.triangles[i].mat) << i;
  ASSERT_EQ(a.verts.size(), b.verts.size());
  for (std::size_t i = 0; i < a.verts.size(); ++i) EXPECT_TRUE(eq(a.verts[i], b.verts[i]));
  ASSERT_EQ(a.vert_normals.size(), b.vert_normals.size());
  for (std::size_t i = 0; i < a.vert_normals.size(); ++i) EXPECT_TRUE(eq(a.vert_normals[i], b.vert_normals[i]));
}

// Expects parse to throw a SceneError whose message matches `pattern` (a regex).
template <class F>
void expect_error(F&& parse, const std::string& pattern) {
  try {
    parse();
    ADD_FAILURE() << "no error; expected /" << pattern << "/";
  } catch (const SceneError& e) {
    EXPECT_TRUE(std::regex_search(e.what(), std::regex(pattern))) << "message: " << e.what() << "\nexpected /" << pattern << "/";
  }
}

fs::path tmpdir() {
  const fs::path d = fs::temp_directory_path() / ("rb_loaders_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}
std::string write_tmp(const std::string& name, const std::string& data) {
  const fs::path p = tmpdir() / name;
  std::ofstream(p, std::ios::binary).write(data.data(), std::streamsize(data.size()));
  return p.string();
}

// ---- PLY writers for the tests ----
template <class T>
void put(std::string& o, T v, bool be) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof v);
  if (be) std::reverse(b, b + sizeof b);
  o.append(reinterpret_cast<char*>(b), sizeof b);
}
// A unit square (two triangles as one quad face) plus a triangle, with an extra vertex property.
std::string ply_square(const std::string& format) {
  const float v[5][4] = {{0, 0, 0, 7}, {1, 0, 0, 7}, {1, 1, 0, 7}, {0, 1, 0, 7}, {0.5f, 0.5f, 1, 7}};
  std::string o = "ply\nformat " + format + " 1.0\ncomment test\nelement vertex 5\nproperty float x\nproperty float y\n"
                  "property float z\nproperty float confidence\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
  if (format == "ascii") {
    for (auto& r : v) o += fmt::format("{} {} {} {}\n", r[0], r[1], r[2], r[3]);
    o += "4 0 1 2 3\n3 0 1 4\n";
    return o;
  }
  const bool be = format == "binary_big_endian";
  for (auto& r : v)
    for (float x : r) put(o, x, be);
  put<std::uint8_t>(o, 4, be);
  for (int i : {0, 1, 2, 3}) put<std::int32_t>(o, i, be);
  put<std::uint8_t>(o, 3, be);
  for (int i : {0, 1, 4}) put<std::int32_t>(o, i, be);
  return o;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
TEST(Obj, PolygonsNegativeIndicesAndSlashForms) {
  const std::string src =
      "# comment\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\nvn 0 0 1\nvt 0 0\n"
      "o thing\ng group\nusemtl red\ns off\n"
      "f 1 2 3 4\n"            // quad: 2 triangles
      "f -4//1 -3//1 -2//1\n"  // relative: 1 2 3
      "f 1/1/1 3/1/1 4/1/1\n"
      "f 2/1 3/1 4/1\n";
  const Scene s = parse_obj(src, "t.obj");
  ASSERT_EQ(s.verts.size(), 4u);
  ASSERT_EQ(s.triangles.size(), 5u);
  EXPECT_EQ(s.triangles[0].v, (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(s.triangles[1].v, (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_EQ(s.triangles[2].v, (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(s.triangles[3].v, (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_EQ(s.triangles[4].v, (std::array<std::uint32_t, 3>{1, 2, 3}));
  EXPECT_EQ(s.materials.size(), 1u);
}

TEST(Obj, ConcaveFaceIsEarClipped) {
  // An L shape (concave at vertex 4): a fan from vertex 0 would cover the notch.
  const std::string src = "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf 1 2 3 4 5 6\n";
  const Scene s = parse_obj(src, "l.obj");
  ASSERT_EQ(s.triangles.size(), 4u);
  double area = 0;
  for (const auto& t : s.triangles) {
    const rb::Vec3d a = s.verts[t.v[0]], b = s.verts[t.v[1]], c = s.verts[t.v[2]];
    const double z = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    EXPECT_GT(z, 0) << "every ear keeps the counter-clockwise winding";
    area += z / 2;
  }
  EXPECT_DOUBLE_EQ(area, 3.0);
}

TEST(Obj, Errors) {
  expect_error([] { parse_obj("v 0 0\n", "a.obj"); }, "^a\\.obj:1: expected three numbers after 'v'");
  expect_error([] { parse_obj("v 0 0 0\nv 1 1 nan\n", "a.obj"); }, "^a\\.obj:2: .*not finite");
  expect_error([] { parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "b.obj"); }, "^b\\.obj:4: vertex index 4 out of range: 3 vertices");
  expect_error([] { parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", "b.obj"); }, "^b\\.obj:4: vertex index -4 out of range");
  expect_error([] { parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2\n", "c.obj"); }, "^c\\.obj:5: a face needs at least 3 vertices, got 2");
  expect_error([] { parse_obj("v 0 0 0\nf 1 x 1\n", "d.obj"); }, "^d\\.obj:2: expected a vertex index");
  expect_error([] { parse_obj("v 0 0 0\nf 0 1 1\n", "d.obj"); }, "^d\\.obj:2: expected a vertex index \\(non-zero");
  expect_error([] { parse_obj("v 0 0 0\nf 1/a 1 1\n", "d.obj"); }, "^d\\.obj:2: malformed face vertex '1/a'");
  expect_error([] { load_obj("/nonexistent/x.obj"); }, "^/nonexistent/x\\.obj: cannot open");
}

// ---------------------------------------------------------------------------------------------
TEST(Ply, AsciiLittleBigEndianGiveTheSameMesh) {
  const Scene a = parse_ply(ply_square("ascii"), "a.ply");
  const Scene l = parse_ply(ply_square("binary_little_endian"), "l.ply");
  const Scene b = parse_ply(ply_square("binary_big_endian"), "b.ply");
  ASSERT_EQ(a.verts.size(), 5u);
  ASSERT_EQ(a.triangles.size(), 3u);
  expect_equal(a, l);
  expect_equal(a, b);
  EXPECT_EQ(a.triangles[1].v, (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_TRUE(eq(a.verts[4], Vec3f{0.5f, 0.5f, 1}));
}

TEST(Ply, DoubleCoordinatesOtherTypesAndVertexIndex) {
  std::string o = "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty uchar red\nproperty double x\nproperty double y\n"
                  "property double z\nelement face 1\nproperty uchar flags\nproperty list ushort uint vertex_index\nelement edge 1\n"
                  "property int a\nproperty int b\nend_header\n";
  const double v[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0.25}};
  for (auto& r : v) {
    put<std::uint8_t>(o, 255, true);
    for (double x : r) put(o, x, true);
  }
  put<std::uint8_t>(o, 1, true);
  put<std::uint16_t>(o, 3, true);
  for (std::uint32_t i : {2u, 1u, 0u}) put(o, i, true);
  put<std::int32_t>(o, 0, true);
  put<std::int32_t>(o, 1, true);
  const Scene s = parse_ply(o, "d.ply");
  ASSERT_EQ(s.triangles.size(), 1u);
  EXPECT_EQ(s.triangles[0].v, (std::array<std::uint32_t, 3>{2, 1, 0}));
  EXPECT_TRUE(eq(s.verts[2], Vec3f{0, 1, 0.25f}));
}

TEST(Ply, TriangleStrips) {
  // Two strips in one list, -1 restarting: 0 1 2 3 (two triangles, alternating winding) and
  // 4 4 5 6 whose first (zero-area) triangle is dropped.
  std::string src = "ply\nformat ascii 1.0\nelement vertex 7\nproperty float x\nproperty float y\nproperty float z\n"
                    "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
                    "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n"
                    "9 0 1 2 3 -1 4 4 5 6\n";
  const Scene s = parse_ply(src, "s.ply");
  ASSERT_EQ(s.triangles.size(), 3u);
  EXPECT_EQ(s.triangles[0].v, (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(s.triangles[1].v, (std::array<std::uint32_t, 3>{2, 1, 3}));
  EXPECT_EQ(s.triangles[2].v, (std::array<std::uint32_t, 3>{5, 4, 6}));  // 2nd of its strip: reversed
  // The same in binary little endian.
  std::string b = "ply\nformat binary_little_endian 1.0\nelement vertex 7\nproperty float x\nproperty float y\nproperty float z\n"
                  "element tristrips 1\nproperty list int int vertex_indices\nend_header\n";
  const float v[7][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  for (auto& r : v)
    for (float x : r) put(b, x, false);
  put<std::int32_t>(b, 9, false);
  for (int i : {0, 1, 2, 3, -1, 4, 4, 5, 6}) put<std::int32_t>(b, i, false);
  expect_equal(s, parse_ply(b, "s.ply"));
}

TEST(Ply, Errors) {
  const std::string hdr = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  expect_error([] { parse_ply("plx\n", "m.ply"); }, "^m\\.ply:1: expected 'ply'");
  expect_error([] { parse_ply("ply\nformat binary_middle_endian 1.0\nend_header\n", "m.ply"); }, "^m\\.ply:2: expected format ascii");
  expect_error([] { parse_ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "m.ply"); }, "^m\\.ply:4: unexpected end of file in the header");
  expect_error([] { parse_ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n", "m.ply"); }, "^m\\.ply:4: expected a property type");
  expect_error([] { parse_ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n", "m.ply"); },
               "^m\\.ply:3: element 'vertex' needs scalar properties x, y and z");
  expect_error([&] { parse_ply(hdr + "end_header\n0 0 0\n1 0 0\n", "t.ply"); }, "^t\\.ply:9: unexpected end of file in element 'vertex' record #2: expected property 'x'");
  expect_error([&] { parse_ply(hdr + "end_header\n0 0 0\n1 0 0\n0 zero 0\n", "t.ply"); }, "^t\\.ply:10: element 'vertex' record #2: expected a number for property 'y', got 'zero'");
  expect_error([&] { parse_ply(hdr + "end_header\n0 0 0\n1 0 0\n0 inf 0\n", "t.ply"); }, "^t\\.ply:10: vertex #2 .*not finite");
  expect_error([&] { parse_ply(hdr + "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "t.ply"); },
               "^t\\.ply:13: element 'face' #0: vertex index 3 out of range \\(the file has 3 vertices\\)");
  // Huge counts are refused before anything is allocated.
  expect_error([] { parse_ply("ply\nformat binary_little_endian 1.0\nelement vertex 5000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n", "h.ply"); },
               "^h\\.ply:3: more than 2\\^32-2 vertices");
  expect_error([] { parse_ply("ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n", "h.ply"); },
               "^h\\.ply: byte 124: element 'vertex' announces 4000000000 records of 12 bytes but only 0 bytes are left");
  expect_error([] { parse_ply("ply\nformat binary_little_endian 1.0\nelement vertex 400000000\nproperty float x\nproperty float y\nproperty float z\nend_header\nabc", "h.ply"); },
               "^h\\.ply: byte 123: element 'vertex' announces 400000000 records of 12 bytes but only 3 bytes are left");
  // Binary truncation names the byte offset.
  std::string b = ply_square("binary_little_endian");
  b.resize(b.size() - 5);
  expect_error([&] { parse_ply(b, "cut.ply"); }, "^cut\\.ply: byte [0-9]+: unexpected end of data in element 'face' record #1: 12 more bytes expected, 7 left");
  std::string f = ply_square("binary_little_endian");
  f[f.size() - 4] = 9;  // last index 4 -> 9
  expect_error([&] { parse_ply(f, "idx.ply"); }, "^idx\\.ply: byte [0-9]+: element 'face' #1: vertex index 9 out of range");
  expect_error([] { parse_ply("ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n", "o.ply"); },
               "^o\\.ply:3: element 'face' comes before element 'vertex'");
}

// ---------------------------------------------------------------------------------------------
namespace {
const char* kNff =
    "# every entity of NFF.TXT\n"
    "v\nfrom 1 2 3\nat 0 0 0\nup 0 0 1\nangle 45\nhither 0.5\nresolution 320 240\n"
    "b 0.1 0.2 0.3\n"
    "l 1 1 1\nl 2 2 2 0.5 0.5 0.5\n"
    "s 0 0 0 1   # before any f: default material\n"
    "f 1 0 0 0.7 0.3 20 0 1\n"
    "c\n0 0 0 1\n0 0 2 0.5\n"
    "c\n1 0 0 0.25\n1 0 1 0.25\n"
    "c 2 0 0 0.3 2 0 1 0.3\n"  // the SPD programs' one-line form
    "s 3 0 0 0.5\n"
    "p 4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
    "f 0 1 0 0.7 0.3 20 0 1\n"
    "p 3\n0 0 1\n1 0 1\n0 1 1\n"
    "pp 3\n0 0 2 0 0 1\n1 0 2 0 0 1\n0 1 2 0 0.6 0.8\n"
    "pp 4\n0 0 3 0 0 1\n1 0 3 0 0 1\n1 1 3 0 0 1\n0 1 3 0 0 1\n"
    "f 1 0 0 0.7 0.3 20 0 1\n"  // the same as the first `f`: merged
    "s 5 5 5 0.1\n";
}

TEST(Nff, EveryEntity) {
  const Scene s = parse_nff(kNff, "all.nff");
  EXPECT_TRUE(eq(s.camera.from, Vec3f{1, 2, 3}));
  EXPECT_EQ(s.camera.width, 320);
  EXPECT_EQ(s.camera.height, 240);
  EXPECT_EQ(s.camera.hither, 0.5);
  EXPECT_TRUE(eq(s.background, Vec3f{0.1f, 0.2f, 0.3f}));
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_TRUE(eq(s.lights[0].color, Vec3f{1, 1, 1}));
  EXPECT_TRUE(eq(s.lights[1].color, Vec3f{0.5f, 0.5f, 0.5f}));
  ASSERT_EQ(s.materials.size(), 3u);  // default, red, green (the second red merged)
  ASSERT_EQ(s.spheres.size(), 3u);
  EXPECT_EQ(s.spheres[0].mat, 0u);
  EXPECT_EQ(s.spheres[1].mat, 1u);
  EXPECT_EQ(s.spheres[2].mat, 1u);
  ASSERT_EQ(s.cones.size(), 3u);
  EXPECT_TRUE(eq(s.cones[2].apex, Vec3f{2, 0, 1}));
  EXPECT_EQ(s.cones[0].apex_r, 0.5);
  EXPECT_EQ(s.polygons.size(), 2u);  // p 4 and pp 4
  EXPECT_EQ(s.triangles.size(), 2u);  // p 3 and pp 3
  EXPECT_EQ(s.verts.size(), 6u);
  ASSERT_EQ(s.vert_normals.size(), 6u);
  EXPECT_TRUE(eq(s.vert_normals[0], Vec3f{0, 0, 1}));  // geometric normal of the plain `p 3` (area 1/2 -> |n| = 1)
  EXPECT_TRUE(eq(s.vert_normals[5], Vec3f{0, 0.6f, 0.8f}));
  ASSERT_EQ(s.poly_normals.size(), 8u);
  EXPECT_TRUE(eq(s.poly_normals[0], Vec3f{0, 0, 2}));  // Newell normal of the unit square (not normalised)
  EXPECT_EQ(s.primitive_count(), 10u);
}

TEST(Nff, RoundTrip) {
  const Scene a = parse_nff(kNff, "all.nff");
  const std::string path = write_tmp("rt.nff", "");
  save_nff(a, path);
  const Scene b = load_nff(path);
  expect_equal(a, b);
  // And the real SPD files, every one (load -> save -> load).
  for (const char* f : {"balls", "gears", "mount", "rings", "teapot", "tetra", "tree"}) {
    SCOPED_TRACE(f);
    const Scene x = load_nff(std::string(RB_TEST_DATA) + "/spd/" + f + ".nff");
    const Scene y = parse_nff(to_nff(x), "rt");
    expect_equal(x, y);
  }
}

TEST(Nff, SpdCountsMatchHainesTable) {
  struct Row { const char* f; std::size_t s, c, p, t, total; };
  // Haines' totals at the default sizes; teapot at size 6 is 32*2*36 - 8*6 = 2,256 patches + 36 squares.
  const Row rows[] = {{"balls", 7381, 0, 1, 0, 7382},   {"gears", 0, 0, 9345, 0, 9345}, {"mount", 4, 0, 0, 8192, 8196},
                      {"rings", 4200, 4200, 1, 0, 8401}, {"teapot", 0, 0, 36, 2256, 2292}, {"tetra", 0, 0, 0, 4096, 4096},
                      {"tree", 4095, 4095, 1, 0, 8191}};
  for (const Row& r : rows) {
    SCOPED_TRACE(r.f);
    const Scene s = load_scene(std::string(RB_TEST_DATA) + "/spd/" + r.f + ".nff");
    EXPECT_EQ(s.spheres.size(), r.s);
    EXPECT_EQ(s.cones.size(), r.c);
    EXPECT_EQ(s.polygons.size(), r.p);
    EXPECT_EQ(s.triangles.size(), r.t);
    EXPECT_EQ(s.primitive_count(), r.total);
  }
}

TEST(Nff, Errors) {
  expect_error([] { parse_nff("s 0 0 0\n", "e.nff"); }, "^e\\.nff:1: expected sphere 's' x y z radius \\(number 4 of 4\\)");
  expect_error([] { parse_nff("\n# c\ns 0 0 nan 1\n", "e.nff"); }, "^e\\.nff:3: sphere 's' x y z radius: number 3 is not finite");
  expect_error([] { parse_nff("s 0 0 0 1 2\n", "e.nff"); }, "^e\\.nff:1: unexpected '2' after sphere");
  expect_error([] { parse_nff("x 1 2\n", "e.nff"); }, "^e\\.nff:1: unknown NFF entity 'x'");
  expect_error([] { parse_nff("p 4\n0 0 0\n1 0 0\n1 1 0\n", "e.nff"); }, "^e\\.nff:1: 'p' announces 4 vertices but only 18 bytes");
  expect_error([] { parse_nff("p 3\n0 0 0\n1 0 0\n", "e.nff"); }, "^e\\.nff:1: 'p' announces 3 vertices but only");
  expect_error([] { parse_nff("p 3\n0 0 0\n1 0 0\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n\n", "e.nff"); }, "^e\\.nff:[0-9]+: unexpected end of file: expected a vertex line 'x y z'");
  expect_error([] { parse_nff("p 4000000000\n0 0 0\n", "e.nff"); }, "^e\\.nff:1: 'p' announces 4000000000 vertices but only 6 bytes follow");
  expect_error([] { parse_nff("p 2\n0 0 0\n1 1 1\n", "e.nff"); }, "^e\\.nff:1: 'p' needs at least 3 vertices, got 2");
  expect_error([] { parse_nff("pp 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n0.5 1 0 0 0\n", "e.nff"); }, "^e\\.nff:4: expected vertex 'x y z nx ny nz' \\(number 6 of 6\\)");
  expect_error([] { parse_nff("c\n0 0 0 1\n", "e.nff"); }, "^e\\.nff:2: unexpected end of file: expected the cone apex line");
  expect_error([] { parse_nff("c\n0 0 0 1\n0 0 0 1\n", "e.nff"); }, "^e\\.nff:3: cone base and apex coincide");
  expect_error([] { parse_nff("f 1 1 1 1 0 0 0\n", "e.nff"); }, "^e\\.nff:1: expected material 'f' .* \\(number 8 of 8\\)");
  expect_error([] { parse_nff("l 1 2 3 4\n", "e.nff"); }, "^e\\.nff:1: expected light 'l' x y z \\[r g b\\]");
  expect_error([] { parse_nff("v\nfrom 0 0 0\nat 0 0 1\nup 0 1 0\nangle 45\n", "e.nff"); }, "^e\\.nff:5: 'v' block without a 'resolution' line");
  expect_error([] { parse_nff("v\nfrom 0 0 0\nat 0 0 1\nup 0 1 0\nangle 45\nresolution -5 5\n", "e.nff"); }, "^e\\.nff:6: resolution must be between");
}

// ---------------------------------------------------------------------------------------------
TEST(LoadScene, DispatchByExtensionAndPrefix) {
  const std::string p = write_tmp("UPPER.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(load_scene(p).triangles.size(), 1u);
  EXPECT_EQ(load_scene(write_tmp("sq.Ply", ply_square("ascii"))).triangles.size(), 3u);
  EXPECT_EQ(load_scene(std::string(RB_TEST_DATA) + "/spd/balls_s1.nff").spheres.size(), 10u);
  expect_error([] { load_scene("scene.3ds"); }, "^scene\\.3ds: unknown scene source: expected a \\.obj, \\.ply or \\.nff file");
  expect_error([] { load_scene("spd:balls:x"); }, "^spd:balls:x: expected spd:NAME\\[:SIZE\\]");
  expect_error([] { load_scene("spd:balls:0"); }, "^spd:balls:0: expected spd:NAME\\[:SIZE\\]");
  EXPECT_THROW(load_scene("spd:nosuchdb"), SceneError);
  EXPECT_THROW(load_scene("lecture:nosuchscene"), SceneError);
}

// The generated height field: NX x NY quads of two triangles over [-1, 1]^2 sharing their
// vertices, the default the size the report traces; malformed and absurd sizes are refused.
TEST(LoadScene, HeightField) {
  const Scene h = load_scene("heightfield:12x7");
  EXPECT_EQ(h.triangles.size(), 2u * 12 * 7);
  EXPECT_EQ(h.verts.size(), 13u * 8);
  const Bounds b = h.bounds();
  EXPECT_DOUBLE_EQ(b.lo.x, -1.0);
  EXPECT_DOUBLE_EQ(b.hi.z, 1.0);
  EXPECT_LT(b.hi.y - b.lo.y, 0.41);
  for (const auto& t : h.triangles)
    for (auto v : t.v) EXPECT_LT(v, h.verts.size());
  EXPECT_EQ(load_scene("heightfield").triangles.size(), 1001112u);
  for (const char* bad : {"heightfield:", "heightfield:12", "heightfield:12x", "heightfield:x7", "heightfield:12x7x",
                          "heightfield:12 x7"})
    expect_error([&] { load_scene(bad); }, "expected heightfield:NXxNY");
  expect_error([] { load_scene("heightfield:0x7"); }, "^heightfield:0x7: each side must be 1 \\.\\. 2048 quads");
  expect_error([] { load_scene("heightfield:5000x5000"); }, "^heightfield:5000x5000: each side must be 1");
  expect_error([] { load_scene("heightfield:-3x7"); }, "^heightfield:-3x7: each side must be 1");
}

TEST(LoadScene, EmbeddedMeshes) {
  const Scene bunny = load_scene(std::string(RB_SOURCE_DIR) + "/data/meshes/stanford-bunny.obj");
  EXPECT_EQ(bunny.triangles.size(), 69451u);
  EXPECT_EQ(bunny.verts.size(), 35947u);
  const Scene dragon = load_scene(std::string(RB_SOURCE_DIR) + "/data/meshes/dragon_vrip_res3_bin.ply");
  EXPECT_EQ(dragon.triangles.size(), 47794u);
}

// Numbers the tracers can use: a scene whose bounds, camera or lights are not finite, or reach
// beyond kMaxCoordinate (float arithmetic on the extent would overflow), is refused by load_scene
// with the file, the value and the bound named.
TEST(LoadScene, NonFiniteOrHugeNumbersAreRefusedNamingTheBound) {
  const std::string huge = write_tmp("huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1e38 0\nf 1 2 3\n");
  expect_error([&] { (void)load_scene(huge); }, "huge\\.obj: the scene's bounds reach 1e\\+38 .*largest coordinate traced, 1e\\+12");
  const std::string far_sphere = write_tmp("far.nff", "s 0 0 0 1\ns 2e13 0 0 1\n");
  expect_error([&] { (void)load_scene(far_sphere); }, "far\\.nff: the scene's bounds reach 2e\\+13");
  const std::string cam = write_tmp("cam.nff", "v\nfrom 0 0 -1e30\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0\nresolution 8 8\ns 0 0 0 1\n");
  expect_error([&] { (void)load_scene(cam); }, "cam\\.nff: the camera .*beyond the largest coordinate traced, 1e\\+12");
  const std::string light = write_tmp("light.json",
                                      R"({"lights": [{"position": [1e300, 0, 0]}], "objects": [{"type": "sphere", "center": [0,0,0], "radius": 1}]})");
  expect_error([&] { (void)load_scene(light); }, "light\\.json: light 1 at .*beyond the largest coordinate traced");
  // In memory (generators, tests): the same check by name.
  Scene s;
  s.spheres.push_back({{0, 0, 0}, 1, 0});
  s.lights.push_back({{0, std::numeric_limits<double>::quiet_NaN(), 0}, {1, 1, 1}});
  expect_error([&] { check_numbers(s, "mine"); }, "^mine: light 1 is not finite");
  s.lights.clear();
  s.camera.up = {0, std::numeric_limits<double>::infinity(), 0};
  expect_error([&] { check_numbers(s, "mine"); }, "^mine: the camera is not finite");
  // At the bound: accepted.
  const std::string edge = write_tmp("edge.obj", "v 0 0 0\nv 1e12 0 0\nv 0 -1e12 0\nf 1 2 3\n");
  EXPECT_NO_THROW((void)load_scene(edge));
  // A header announcing 10^9 records is refused before anything is allocated, naming the count
  // and the bytes that follow.
  const std::string ply = write_tmp("billion.ply",
                                    "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
                                    "property float z\nend_header\n0123456789ab");
  expect_error([&] { (void)load_scene(ply); }, "billion\\.ply.*1000000000 records of 12 bytes but only 12 bytes are left");
}

// Found by the libFuzzer target fuzz_json: a number beyond double's range made the JSON library
// throw its out_of_range, which escaped the loader's contract (SceneError naming the file).
TEST(LoadScene, JsonNumberBeyondDoubleIsASceneError) {
  expect_error([] { (void)load_scene(std::string(RB_TEST_DATA) + "/fuzz/json-number-overflow.json"); },
               "json-number-overflow\\.json: malformed JSON: .*number overflow");
}
