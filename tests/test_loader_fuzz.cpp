// Robustness of the loaders: thousands of seeded mutations of small valid files (truncations,
// byte flips, digit changes, huge counts, NaN numbers, deleted and repeated lines) through each
// parser. Each must either load or throw SceneError: no crash, hang, leak (ASan + UBSan in the
// debug preset) or other exception. Outcomes are counted and printed.
#include "scene/loaders.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <functional>
#include <random>

using namespace rb::scene;

namespace {

std::string ply_binary(bool be, bool strips) {
  std::string o = std::string("ply\nformat ") + (be ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\n" +
                  (strips ? "element tristrips 1\nproperty list int int vertex_indices\n"
                          : "element face 3\nproperty list uchar int vertex_indices\n") +
                  "end_header\n";
  auto put = [&](const void* p, std::size_t n) {
    std::string b(static_cast<const char*>(p), n);
    if (be) std::reverse(b.begin(), b.end());
    o += b;
  };
  const float v[6][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 1}, {2, 2, 2}};
  for (auto& r : v) {
    for (float x : r) put(&x, 4);
    const std::uint8_t red = 200;
    put(&red, 1);
  }
  if (strips) {
    const std::int32_t idx[] = {9, 0, 1, 2, 3, -1, 4, 4, 5, 0};
    for (std::int32_t i : idx) put(&i, 4);
  } else {
    const std::vector<std::vector<std::int32_t>> faces = {{0, 1, 2, 3}, {0, 1, 4}, {2, 3, 5, 4, 1}};
    for (const auto& f : faces) {
      const std::uint8_t n = std::uint8_t(f.size());
      put(&n, 1);
      for (std::int32_t i : f) put(&i, 4);
    }
  }
  return o;
}

const char* kObj =
    "# seed\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1e-3\nvn 0 0 1\nvt 0.5 0.5\n"
    "f 1 2 3 4\nf -5//1 -4//1 -1//1\nf 1/1/1 3/1/1 5/1/1\nf 2 3 4 5 1\ng x\nf 1 2 3 4 5\n";
const char* kPlyAscii =
    "ply\nformat ascii 1.0\ncomment seed\nelement vertex 5\nproperty float x\nproperty float y\nproperty double z\n"
    "element face 2\nproperty list uchar int vertex_indices\nelement tristrips 1\nproperty list int int vertex_indices\n"
    "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 1\n4 0 1 2 3\n3 0 1 4\n7 0 1 2 -1 2 3 4\n";
const char* kFuzzNff =
    "v\nfrom 1 2 3\nat 0 0 0\nup 0 0 1\nangle 45\nhither 0.5\nresolution 32 24\nb 0.1 0.2 0.3\nl 1 1 1\nl 2 2 2 0.5 0.5 0.5\n"
    "s 0 0 0 1\nf 1 0 0 0.7 0.3 20 0 1\nc\n0 0 0 1\n0 0 2 0.5\ns 3 0 0 0.5\np 4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
    "f 0 1 0 0.7 0.3 20 0 1.5\np 3\n0 0 1\n1 0 1\n0 1 1\npp 3\n0 0 2 0 0 1\n1 0 2 0 0 1\n0 1 2 0 0.6 0.8\n"
    "pp 4\n0 0 3 0 0 1\n1 0 3 0 0 1\n1 1 3 0 0 1\n0 1 3 0 0 1\n";

std::vector<std::string> split_lines(const std::string& s) {
  std::vector<std::string> out;
  std::size_t a = 0;
  while (a < s.size()) {
    const std::size_t b = s.find('\n', a);
    const std::size_t e = b == std::string::npos ? s.size() : b + 1;
    out.push_back(s.substr(a, e - a));
    a = e;
  }
  return out;
}

// One random mutation of `s`.
std::string mutate(std::string s, std::mt19937_64& rng) {
  auto pick = [&](std::size_t n) { return n == 0 ? std::size_t(0) : std::size_t(rng() % n); };
  static const char* const evil[] = {"4000000000", "-1", "nan", "inf", "-inf", "1e39", "99999999999999999999", "0", "-2147483648",
                                     "2147483647", "1e-45", "+", "-", "", "1.5", "65535", "-nan", "0x10", "3 3 3 3 3 3 3 3 3"};
  switch (rng() % 9) {
    case 0: s.resize(pick(s.size() + 1)); break;  // truncate
    case 1: if (!s.empty()) s[pick(s.size())] ^= char(1u << (rng() % 8)); break;  // bit flip
    case 2: if (!s.empty()) s[pick(s.size())] = char(rng()); break;  // random byte
    case 3: {  // change a digit
      std::vector<std::size_t> d;
      for (std::size_t i = 0; i < s.size(); ++i)
        if (s[i] >= '0' && s[i] <= '9') d.push_back(i);
      if (!d.empty()) s[d[pick(d.size())]] = char('0' + rng() % 10);
      break;
    }
    case 4: {  // replace a number (a maximal run of digits) by something hostile
      std::vector<std::size_t> d;
      for (std::size_t i = 0; i < s.size(); ++i)
        if (s[i] >= '0' && s[i] <= '9' && (i == 0 || !(s[i - 1] >= '0' && s[i - 1] <= '9'))) d.push_back(i);
      if (d.empty()) break;
      const std::size_t a = d[pick(d.size())];
      std::size_t b = a;
      while (b < s.size() && ((s[b] >= '0' && s[b] <= '9') || s[b] == '.')) ++b;
      s = s.substr(0, a) + evil[pick(std::size(evil))] + s.substr(b);
      break;
    }
    case 5: case 6: case 7: {  // delete, duplicate or swap lines
      auto L = split_lines(s);
      if (L.empty()) break;
      const std::size_t i = pick(L.size()), j = pick(L.size());
      const int op = int(rng() % 3);
      if (op == 0) L.erase(L.begin() + std::ptrdiff_t(i));
      else if (op == 1) L.insert(L.begin() + std::ptrdiff_t(i), L[j]);
      else std::swap(L[i], L[j]);
      s.clear();
      for (auto& l : L) s += l;
      break;
    }
    case 8: {  // insert random bytes
      const std::size_t at = pick(s.size() + 1);
      std::string ins(1 + pick(8), ' ');
      for (char& c : ins) c = char(rng());
      s.insert(at, ins);
      break;
    }
  }
  return s;
}

struct Outcome {
  int loaded = 0, errors = 0;
  double max_ms = 0;
};

Outcome run(const std::string& label, const std::vector<std::string>& seeds, const std::function<Scene(std::string_view)>& parse,
            int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Outcome o;
  for (int i = 0; i < n; ++i) {
    std::string m = seeds[std::size_t(i) % seeds.size()];
    const int k = 1 + int(rng() % 3);
    for (int j = 0; j < k; ++j) m = mutate(m, rng);
    const auto t0 = std::chrono::steady_clock::now();
    try {
      const Scene s = parse(m);
      ++o.loaded;
      // A loaded scene is consistent: every index in range, every coordinate finite.
      for (const auto& t : s.triangles)
        for (auto v : t.v) EXPECT_LT(v, s.verts.size()) << label << " mutation " << i;
      for (const auto& p : s.polygons) EXPECT_LE(std::size_t(p.first) + p.count, s.poly_verts.size());
      for (const auto& v : s.verts) EXPECT_TRUE(rb::finite3(v)) << label << " mutation " << i;
      EXPECT_TRUE(s.vert_normals.empty() || s.vert_normals.size() == s.verts.size());
      EXPECT_TRUE(s.poly_normals.empty() || s.poly_normals.size() == s.poly_verts.size());
      for (const auto& t : s.triangles) EXPECT_LT(t.mat, s.materials.size());
      for (const auto& t : s.spheres) EXPECT_LT(t.mat, s.materials.size());
    } catch (const SceneError& e) {
      ++o.errors;
      EXPECT_NE(std::strlen(e.what()), 0u);
    } catch (const std::exception& e) {
      ADD_FAILURE() << label << " mutation " << i << ": not a SceneError: " << e.what();
    }
    o.max_ms = std::max(o.max_ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::printf("[fuzz] %-10s %5d mutations: %5d loaded, %5d clean SceneError, slowest %.2f ms\n", label.c_str(), n, o.loaded, o.errors, o.max_ms);
  EXPECT_EQ(o.loaded + o.errors, n);
  EXPECT_LT(o.max_ms, 1000.0) << label << ": a mutation took more than a second (hang?)";
  return o;
}

constexpr int kN = 3000;

}  // namespace

TEST(LoaderFuzz, Obj) {
  run("obj", {kObj}, [](std::string_view s) { return parse_obj(s, "fuzz.obj"); }, kN, 1);
}
TEST(LoaderFuzz, PlyAscii) {
  run("ply-ascii", {kPlyAscii}, [](std::string_view s) { return parse_ply(s, "fuzz.ply"); }, kN, 2);
}
TEST(LoaderFuzz, PlyBinary) {
  run("ply-binary", {ply_binary(false, false), ply_binary(true, false), ply_binary(false, true), ply_binary(true, true)},
      [](std::string_view s) { return parse_ply(s, "fuzz.ply"); }, kN, 3);
}
TEST(LoaderFuzz, Nff) {
  run("nff", {kFuzzNff}, [](std::string_view s) { return parse_nff(s, "fuzz.nff"); }, kN, 4);
}
// The seeds themselves load.
TEST(LoaderFuzz, SeedsAreValid) {
  EXPECT_EQ(parse_obj(kObj, "s.obj").triangles.size(), 10u);
  EXPECT_EQ(parse_ply(kPlyAscii, "s.ply").triangles.size(), 5u);
  EXPECT_EQ(parse_ply(ply_binary(false, false), "s.ply").triangles.size(), 6u);
  EXPECT_EQ(parse_ply(ply_binary(true, true), "s.ply").triangles.size(), 3u);
  EXPECT_EQ(parse_nff(kFuzzNff, "s.nff").primitive_count(), 7u);
}
