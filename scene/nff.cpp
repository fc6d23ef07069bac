// Haines' Neutral File Format: reader (every entity of NFF.TXT) and writer. See loaders.hpp
// for what each entity becomes.
#include "scene/loaders.hpp"
#include "core/output_file.hpp"
#include "scene/parse_util.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <fstream>
#include <map>
#include <type_traits>

namespace rb::scene {

namespace {

using namespace detail;

struct NffReader {
  std::string_view text;
  const std::string& name;
  Lines lines;
  LineReader ln{nullptr, nullptr};
  Scene s;
  std::int64_t cur_mat = -1;                                      // material of the next primitive
  std::map<std::array<std::uint32_t, 8>, std::uint32_t> mat_index;  // materials are merged by value
  // Primitives seen with / without vertex normals, to keep the normal arrays parallel.
  bool poly_has_n = false, tri_has_n = false;
  std::vector<std::uint8_t> poly_n_given, tri_n_given;  // per polygon / triangle, only while mixed

  NffReader(std::string_view t, const std::string& n) : text(t), name(n), lines(t) {}

  [[noreturn]] void fail(const std::string& what) { fail_line(name, lines.number, what); }

  // Next line that is not blank or a comment ('#' starts a comment anywhere).
  bool next_content() {
    while (lines.next(ln)) {
      const char* h = static_cast<const char*>(std::memchr(ln.p, '#', std::size_t(ln.e - ln.p)));
      if (h) ln.e = h;
      if (!ln.at_end()) return true;
    }
    return false;
  }
  void expect_line(const char* what) {
    if (!next_content()) fail(fmt::format("unexpected end of file: expected {}", what));
  }
  template <class T>
  void nums(T* out, int n, const char* what) {
    for (int i = 0; i < n; ++i)
      if (!ln.number(out[i])) fail(fmt::format("expected {} (number {} of {}), got {}", what, i + 1, n, quote(ln.rest())));
    if (!ln.at_end()) fail(fmt::format("unexpected {} after {}", quote(ln.rest()), what));
    // Every number must also fit a float: the tracer rounds coordinates to float (relative to a
    // frame of its choice), and a value beyond float range cannot be traced.
    if constexpr (std::is_floating_point_v<T>)
      for (int i = 0; i < n; ++i)
        if (!std::isfinite(out[i]) || !std::isfinite(float(out[i])))
          fail(fmt::format("{}: number {} is not finite (NaN, infinity or beyond float range)", what, i + 1));
  }
  std::uint32_t intern(const Material& m) {
    const std::array<std::uint32_t, 8> key = {std::bit_cast<std::uint32_t>(m.color.x), std::bit_cast<std::uint32_t>(m.color.y),
                                              std::bit_cast<std::uint32_t>(m.color.z), std::bit_cast<std::uint32_t>(m.kd),
                                              std::bit_cast<std::uint32_t>(m.ks),      std::bit_cast<std::uint32_t>(m.shine),
                                              std::bit_cast<std::uint32_t>(m.t),       std::bit_cast<std::uint32_t>(m.ior)};
    const auto [it, fresh] = mat_index.try_emplace(key, std::uint32_t(s.materials.size()));
    if (fresh) s.materials.push_back(m);
    return it->second;
  }
  std::uint32_t mat() {
    if (cur_mat < 0) cur_mat = intern(Material{});
    return std::uint32_t(cur_mat);
  }

  void view() {
    bool got[6] = {};
    static const char* const keys[6] = {"from", "at", "up", "angle", "hither", "resolution"};
    // The six lines follow `v` (NFF.TXT order; any order accepted, hither optional).
    for (;;) {
      const char* save_p = lines.p;
      const std::size_t save_n = lines.number;
      if (!next_content()) break;
      LineReader peek = ln;
      const std::string_view kw = peek.word();
      int k = -1;
      for (int i = 0; i < 6; ++i)
        if (kw == keys[i]) k = i;
      if (k < 0) { lines.p = save_p; lines.number = save_n; break; }
      ln = peek;
      if (got[k]) fail(fmt::format("'{}' given twice in one 'v' block", kw));
      got[k] = true;
      double v[3];
      switch (k) {
        case 0: nums(v, 3, "'from' x y z"); s.camera.from = {v[0], v[1], v[2]}; break;
        case 1: nums(v, 3, "'at' x y z"); s.camera.at = {v[0], v[1], v[2]}; break;
        case 2: nums(v, 3, "'up' x y z"); s.camera.up = {v[0], v[1], v[2]}; break;
        case 3: nums(v, 1, "'angle' degrees"); s.camera.angle = v[0]; break;
        case 4: nums(v, 1, "'hither' distance"); s.camera.hither = v[0]; break;
        case 5: {
          long long r[2];
          nums(r, 2, "'resolution' width height (integers)");
          if (r[0] < 1 || r[1] < 1 || r[0] > 65536 || r[1] > 65536) fail("resolution must be between 1 and 65536");
          s.camera.width = int(r[0]);
          s.camera.height = int(r[1]);
          break;
        }
      }
    }
    for (int i : {0, 1, 2, 3, 5})
      if (!got[i]) fail(fmt::format("'v' block without a '{}' line", keys[i]));
    if (!(s.camera.angle > 0 && s.camera.angle < 180)) fail("'angle' must be between 0 and 180 degrees");
  }

  // `p`/`pp` header: vertex count, capped by the bytes left (a vertex line has >= 6 bytes).
  std::size_t poly_count(const char* what, std::size_t min_line) {
    long long n;
    if (!ln.number(n)) fail(fmt::format("expected the vertex count after '{}', got {}", what, quote(ln.rest())));
    if (!ln.at_end()) fail(fmt::format("unexpected {} after the vertex count of '{}'", quote(ln.rest()), what));
    if (n < 3) fail(fmt::format("'{}' needs at least 3 vertices, got {}", what, n));
    if (std::size_t(n) > lines.remaining_bytes() / min_line)
      fail(fmt::format("'{}' announces {} vertices but only {} bytes follow", what, n, lines.remaining_bytes()));
    return std::size_t(n);
  }

  void polygon(bool with_normals) {
    const char* what = with_normals ? "pp" : "p";
    const std::size_t n = poly_count(what, with_normals ? 12 : 6);
    const std::uint32_t m = mat();
    std::vector<Vec3d> p(n);
    std::vector<Vec3f> nn(with_normals ? n : 0);
    for (std::size_t i = 0; i < n; ++i) {
      expect_line(with_normals ? "a vertex line 'x y z nx ny nz'" : "a vertex line 'x y z'");
      double v[6];
      nums(v, with_normals ? 6 : 3, with_normals ? "vertex 'x y z nx ny nz'" : "vertex 'x y z'");
      p[i] = {v[0], v[1], v[2]};
      if (with_normals) nn[i] = to_float(Vec3d{v[3], v[4], v[5]});
    }
    if (!with_normals) {
      const Vec3f g = to_float(newell_normal(p.data(), n));
      nn.assign(n, g);
    }
    if (n == 3) {
      if (s.verts.size() > 0xFFFFFFF0u) fail("too many triangle vertices");
      add_normals(s.vert_normals, s.verts.size(), tri_has_n, with_normals, s.triangles.size(), tri_n_given, nn);
      const auto b = std::uint32_t(s.verts.size());
      s.verts.insert(s.verts.end(), p.begin(), p.end());
      s.triangles.push_back({{b, b + 1, b + 2}, m});
    } else {
      if (s.poly_verts.size() + n > 0xFFFFFFF0u) fail("too many polygon vertices");
      add_normals(s.poly_normals, s.poly_verts.size(), poly_has_n, with_normals, s.polygons.size(), poly_n_given, nn);
      s.polygons.push_back({std::uint32_t(s.poly_verts.size()), std::uint32_t(n), m});
      s.poly_verts.insert(s.poly_verts.end(), p.begin(), p.end());
    }
  }
  // Keeps `normals` empty while no primitive of this kind has given normals; once one has,
  // back-fills the geometric normals of earlier ones and continues in parallel.
  static void add_normals(std::vector<Vec3f>& normals, std::size_t nverts, bool& has, bool given, std::size_t,
                          std::vector<std::uint8_t>&, const std::vector<Vec3f>& nn) {
    if (!has && !given) return;
    if (!has) {  // first primitive with normals: earlier ones get their geometric normal (filled at the end)
      has = true;
      normals.resize(nverts, Vec3f{0, 0, 0});
    }
    normals.insert(normals.end(), nn.begin(), nn.end());
  }
  // Back-fill pass: vertices whose normals were never given (zeros from resize) get the
  // primitive's geometric normal.
  void finish() {
    if (tri_has_n)
      for (const auto& t : s.triangles) {
        if (!(s.vert_normals[t.v[0]].x == 0 && s.vert_normals[t.v[0]].y == 0 && s.vert_normals[t.v[0]].z == 0)) continue;
        const Vec3d p[3] = {s.verts[t.v[0]], s.verts[t.v[1]], s.verts[t.v[2]]};
        const Vec3f g = to_float(newell_normal(p, 3));
        for (auto i : t.v) s.vert_normals[i] = g;
      }
    if (poly_has_n)
      for (const auto& q : s.polygons) {
        const Vec3f& f = s.poly_normals[q.first];
        if (!(f.x == 0 && f.y == 0 && f.z == 0)) continue;
        const Vec3f g = to_float(newell_normal(&s.poly_verts[q.first], q.count));
        for (std::uint32_t i = 0; i < q.count; ++i) s.poly_normals[q.first + i] = g;
      }
  }

  Scene run() {
    s.name = name;
    while (next_content()) {
      const std::string_view kw = ln.word();
      if (kw == "v") {
        if (!ln.at_end()) fail(fmt::format("unexpected {} after 'v'", quote(ln.rest())));
        view();
      } else if (kw == "b") {
        float c[3];
        nums(c, 3, "background 'b' red green blue");
        s.background = {c[0], c[1], c[2]};
      } else if (kw == "l") {
        double v[6];
        int n = 0;
        while (n < 6 && ln.number(v[n])) ++n;
        if ((n != 3 && n != 6) || !ln.at_end())
          fail(fmt::format("expected light 'l' x y z [r g b] (3 or 6 numbers), got {} numbers then {}", n, quote(ln.rest())));
        for (int i = 0; i < n; ++i)
          if (!std::isfinite(v[i]) || !std::isfinite(float(v[i])))
            fail("light 'l': a number is not finite (NaN, infinity or beyond float range)");
        Light L;
        L.pos = {v[0], v[1], v[2]};
        if (n == 6) L.color = to_float(Vec3d{v[3], v[4], v[5]});
        s.lights.push_back(L);
      } else if (kw == "f") {
        float v[8];
        nums(v, 8, "material 'f' red green blue Kd Ks Shine T index_of_refraction");
        cur_mat = intern({{v[0], v[1], v[2]}, v[3], v[4], v[5], v[6], v[7]});
      } else if (kw == "s") {
        double v[4];
        nums(v, 4, "sphere 's' x y z radius");
        s.spheres.push_back({{v[0], v[1], v[2]}, v[3], mat()});
      } else if (kw == "c") {
        // NFF.TXT puts base and apex on the two following lines; the SPD programs print all
        // eight numbers on the `c` line. Both are accepted.
        double b[4], a[4];
        if (ln.at_end()) {
          expect_line("the cone base line 'x y z radius'");
          nums(b, 4, "cone base 'x y z radius'");
          expect_line("the cone apex line 'x y z radius'");
          nums(a, 4, "cone apex 'x y z radius'");
        } else {
          double v[8];
          nums(v, 8, "cone 'c' base x y z radius apex x y z radius");
          std::copy(v, v + 4, b);
          std::copy(v + 4, v + 8, a);
        }
        if (b[0] == a[0] && b[1] == a[1] && b[2] == a[2]) fail("cone base and apex coincide");
        s.cones.push_back({{b[0], b[1], b[2]}, b[3], {a[0], a[1], a[2]}, a[3], mat()});
      } else if (kw == "p") {
        polygon(false);
      } else if (kw == "pp") {
        polygon(true);
      } else {
        fail(fmt::format("unknown NFF entity {}: expected v, b, l, f, c, s, p or pp", quote(kw)));
      }
    }
    finish();
    return std::move(s);
  }
};

}  // namespace

Scene parse_nff(std::string_view text, const std::string& name) { return NffReader(text, name).run(); }
Scene load_nff(const std::string& path) { return parse_nff(detail::read_file(path), path); }

std::string to_nff(const Scene& s) {
  std::string o;
  // fmt writes the shortest decimal that reads back to the same number (float or double).
  auto v3 = [&](const auto& v) { fmt::format_to(std::back_inserter(o), "{} {} {}", v.x, v.y, v.z); };
  o += "# NFF written by raybench: " + s.name.substr(0, 200) + "\n";
  const Camera& c = s.camera;
  o += "v\nfrom "; v3(c.from);
  o += "\nat "; v3(c.at);
  o += "\nup "; v3(c.up);
  fmt::format_to(std::back_inserter(o), "\nangle {}\nhither {}\nresolution {} {}\n", c.angle, c.hither, c.width, c.height);
  o += "b "; v3(s.background); o += "\n";
  for (const Light& L : s.lights) {
    o += "l "; v3(L.pos);
    if (!(L.color.x == 1 && L.color.y == 1 && L.color.z == 1)) { o += " "; v3(L.color); }
    o += "\n";
  }
  // Every material first (the reader merges equal `f` lines, so these define the indices in
  // order), then each kind in its own order, with an `f` line wherever the material changes.
  auto fline = [&](const Material& M) {
    fmt::format_to(std::back_inserter(o), "f {} {} {} {} {} {} {} {}\n", M.color.x, M.color.y, M.color.z, M.kd, M.ks, M.shine, M.t, M.ior);
  };
  for (const Material& M : s.materials) fline(M);
  std::int64_t cur = s.materials.empty() ? -1 : std::int64_t(s.materials.size() - 1);
  auto use = [&](std::uint32_t m) {
    if (std::int64_t(m) == cur) return;
    fline(m < s.materials.size() ? s.materials[m] : Material{});
    cur = m;
  };
  const bool pn = !s.poly_normals.empty(), tn = !s.vert_normals.empty();
  for (const SphereIn& k : s.spheres) {
    use(k.mat);
    o += "s "; v3(k.c); fmt::format_to(std::back_inserter(o), " {}\n", k.r);
  }
  for (const ConeIn& k : s.cones) {
    use(k.mat);
    o += "c\n"; v3(k.base); fmt::format_to(std::back_inserter(o), " {}\n", k.base_r);
    v3(k.apex); fmt::format_to(std::back_inserter(o), " {}\n", k.apex_r);
  }
  for (const PolygonIn& q : s.polygons) {
    use(q.mat);
    fmt::format_to(std::back_inserter(o), "{} {}\n", pn ? "pp" : "p", q.count);
    for (std::uint32_t j = q.first; j < q.first + q.count; ++j) {
      v3(s.poly_verts[j]);
      if (pn) { o += " "; v3(s.poly_normals[j]); }
      o += "\n";
    }
  }
  for (const TriangleIn& t : s.triangles) {
    use(t.mat);
    o += tn ? "pp 3\n" : "p 3\n";
    for (auto j : t.v) {
      v3(s.verts[j]);
      if (tn) { o += " "; v3(s.vert_normals[j]); }
      o += "\n";
    }
  }
  return o;
}

void save_nff(const Scene& scene, const std::string& path) {
  const std::string text = to_nff(scene);
  try {
    write_output(path, text);  // a file whole or not at all, a device as it is (core/output_file.hpp)
  } catch (const std::runtime_error& e) {
    throw SceneError(e.what());
  }
}

}  // namespace rb::scene
