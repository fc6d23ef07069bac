// load_scene: one name for files and embedded generators; shared loader helpers.
#include "scene/csg_scene.hpp"
#include "scene/loaders.hpp"
#include "scene/parse_util.hpp"
#include "scene/sources.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <memory>

namespace rb::scene {

namespace detail {

std::string read_file(const std::string& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw SceneError(fmt::format("{}: cannot open file", path));
  std::string data;
  if (std::fseek(f.get(), 0, SEEK_END) == 0) {
    const long n = std::ftell(f.get());
    if (n > 0) data.reserve(std::size_t(n));
    std::fseek(f.get(), 0, SEEK_SET);
  }
  char buf[1 << 16];
  std::size_t got;
  while ((got = std::fread(buf, 1, sizeof buf, f.get())) > 0) data.append(buf, got);
  if (std::ferror(f.get())) throw SceneError(fmt::format("{}: read error", path));
  return data;
}

namespace {
struct P2 { double x, y; };
double orient(P2 a, P2 b, P2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }
}  // namespace

void triangulate(const std::uint32_t* idx, std::size_t n, const std::vector<Vec3d>& verts, std::uint32_t mat,
                 std::vector<TriangleIn>& out) {
  if (n < 3) return;
  auto fan = [&](const std::uint32_t* ids, std::size_t m) {
    for (std::size_t i = 1; i + 1 < m; ++i) out.push_back({{ids[0], ids[i], ids[i + 1]}, mat});
  };
  if (n == 3 || n > kMaxEarClip) return fan(idx, n);
  // Project on the plane of the Newell normal (drop its dominant axis), oriented so the polygon
  // is counter-clockwise.
  Vec3d pts[kMaxEarClip];
  for (std::size_t i = 0; i < n; ++i) pts[i] = verts[idx[i]];
  const Vec3d nn = newell_normal(pts, n);
  const int drop = dominant_axis(nn);
  const double sgn = nn[drop] < 0 ? -1.0 : 1.0;
  if (!(nn[drop] != 0.0) || !std::isfinite(nn[drop])) return fan(idx, n);
  const int a = (drop + 1) % 3, b = (drop + 2) % 3;
  P2 q[kMaxEarClip];
  for (std::size_t i = 0; i < n; ++i) q[i] = {double(pts[i][a]), sgn * double(pts[i][b])};
  bool convex = true;
  for (std::size_t i = 0; i < n && convex; ++i)
    if (orient(q[i], q[(i + 1) % n], q[(i + 2) % n]) < 0) convex = false;
  if (convex) return fan(idx, n);
  // Ear clipping, O(n^3) worst case with n <= kMaxEarClip.
  std::uint32_t rem[kMaxEarClip];
  std::size_t m = n;
  for (std::size_t i = 0; i < n; ++i) rem[i] = std::uint32_t(i);
  while (m > 3) {
    bool clipped = false;
    for (std::size_t i = 0; i < m && !clipped; ++i) {
      const std::size_t i0 = (i + m - 1) % m, i2 = (i + 1) % m;
      const P2 A = q[rem[i0]], B = q[rem[i]], C = q[rem[i2]];
      if (orient(A, B, C) <= 0) continue;
      bool empty = true;
      for (std::size_t j = 0; j < m && empty; ++j) {
        if (j == i0 || j == i || j == i2) continue;
        const P2 P = q[rem[j]];
        if ((P.x == A.x && P.y == A.y) || (P.x == B.x && P.y == B.y) || (P.x == C.x && P.y == C.y)) continue;
        if (orient(A, B, P) >= 0 && orient(B, C, P) >= 0 && orient(C, A, P) >= 0) empty = false;
      }
      if (!empty) continue;
      out.push_back({{idx[rem[i0]], idx[rem[i]], idx[rem[i2]]}, mat});
      std::copy(rem + i + 1, rem + m, rem + i);
      --m;
      clipped = true;
    }
    if (!clipped) break;  // self-intersecting or degenerate: fan the rest
  }
  std::uint32_t ids[kMaxEarClip];
  for (std::size_t i = 0; i < m; ++i) ids[i] = idx[rem[i]];
  fan(ids, m);
}

}  // namespace detail

namespace {
std::string lower_ext(const std::string& s) {
  const auto dot = s.find_last_of('.');
  const auto slash = s.find_last_of("/\\");
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string e = s.substr(dot + 1);
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}
}  // namespace

namespace {
Scene load_unchecked(const std::string& source) {
  if (source.rfind("spd:", 0) == 0) {
    std::string rest = source.substr(4);
    const auto colon = rest.find(':');
    const std::string name = rest.substr(0, colon);
    int size = 0;
    if (colon == std::string::npos) {
      size = spd_default_size(name);
    } else {
      const std::string s = rest.substr(colon + 1);
      const auto r = std::from_chars(s.data(), s.data() + s.size(), size);
      if (r.ec != std::errc() || r.ptr != s.data() + s.size() || size < 1)
        throw SceneError(fmt::format("{}: expected spd:NAME[:SIZE] with SIZE a positive integer, got size {}", source,
                                     detail::quote(s)));
    }
    return generate_spd(name, size);
  }
  if (source.rfind("lecture:", 0) == 0) return lecture_scene(source.substr(8));
  if (source.rfind("csg:", 0) == 0) return csg_scene(source.substr(4));
  if (source.rfind("precision:", 0) == 0) return precision_scene(source.substr(10));
  if (source == "heightfield") return height_field(kHeightFieldNx, kHeightFieldNy);
  if (source.rfind("heightfield:", 0) == 0) {
    const std::string s = source.substr(12);
    int nx = 0, ny = 0;
    const char* const end = s.data() + s.size();
    const auto a = std::from_chars(s.data(), end, nx);
    const bool ok = a.ec == std::errc() && a.ptr != end && *a.ptr == 'x' && [&] {
      const auto b = std::from_chars(a.ptr + 1, end, ny);
      return b.ec == std::errc() && b.ptr == end;
    }();
    if (!ok) throw SceneError(fmt::format("{}: expected heightfield:NXxNY with NX and NY whole numbers of quads, got {}", source, detail::quote(s)));
    return height_field(nx, ny);
  }
  const std::string ext = lower_ext(source);
  if (ext == "obj") return load_obj(source);
  if (ext == "ply") return load_ply(source);
  if (ext == "nff") return load_nff(source);
  if (ext == "json") return load_json_scene(source);
  throw SceneError(fmt::format("{}: unknown scene source: expected a .obj, .ply or .nff file, a .json scene, spd:NAME[:SIZE], lecture:NAME, csg:NAME, precision:NAME or heightfield[:NXxNY]",
                               source));
}
}  // namespace

Scene load_scene(const std::string& source) {
  Scene s = load_unchecked(source);
  check_numbers(s, source);
  return s;
}

}  // namespace rb::scene
