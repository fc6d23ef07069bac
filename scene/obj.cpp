// Wavefront OBJ loader. Only what a triangle scene needs: positions and faces.
//
// Own parser rather than Debian's tinyobjloader 2.0.0rc10, measured on the 69,451-triangle
// bunny in one run (median of 7, 2 shared cores under load, -O2): this parser 41.7 ms,
// tinyobjloader ObjReader::ParseFromFile with triangulation 156 ms (3.7x slower, before any
// conversion into the scene model). tinyobjloader did survive the 3,000 seeded mutations of
// tests/test_loader_fuzz.cpp under ASan + UBSan without a crash, but it loaded 1,905 of them
// (this parser: 1,030) because it reads malformed numbers as 0 and passes NaN/inf through (10
// mutations gave non-finite vertices), and its messages do not name the line. So: own parser,
// std::from_chars numbers, every index checked, "FILE:LINE: expected ..." on every error.
#include "scene/loaders.hpp"
#include "scene/parse_util.hpp"

namespace rb::scene {

Scene parse_obj(std::string_view text, const std::string& name) {
  using namespace detail;
  Scene s;
  s.name = name;
  s.materials.push_back(Material{});
  // A vertex line has at least 6 bytes ("v 0 0 0" minus a space), a face vertex 2: a cheap
  // upper bound keeps reserve() proportional to the file.
  s.verts.reserve(std::min<std::size_t>(text.size() / 32, std::size_t(1) << 24));
  s.triangles.reserve(std::min<std::size_t>(text.size() / 32, std::size_t(1) << 24));
  std::vector<std::uint32_t> face;
  Lines lines(text);
  LineReader ln{nullptr, nullptr};
  while (lines.next(ln)) {
    const std::string_view kw = ln.word();
    if (kw.empty() || kw[0] == '#') continue;
    if (kw == "v") {
      Vec3d p;
      if (!ln.number(p.x) || !ln.number(p.y) || !ln.number(p.z))
        fail_line(name, lines.number, fmt::format("expected three numbers after 'v', got {}", quote(ln.rest())));
      if (!finite3(p) || !finite3(to_float(p)))
        fail_line(name, lines.number, "vertex coordinate is not finite (NaN, infinity or beyond float range)");
      if (s.verts.size() >= 0xFFFFFFFEu) fail_line(name, lines.number, "more than 2^32-2 vertices");
      s.verts.push_back(p);
    } else if (kw == "f") {
      face.clear();
      const long long nv = static_cast<long long>(s.verts.size());
      while (!ln.at_end()) {
        const std::string_view tok = ln.word();
        // v, v/t, v//n, v/t/n: the position index is everything before the first '/'.
        const std::size_t slash = tok.find('/');
        const std::string_view vi = tok.substr(0, slash);
        long long i = 0;
        const auto r = std::from_chars(vi.data(), vi.data() + vi.size(), i);
        if (r.ec != std::errc() || r.ptr != vi.data() + vi.size() || i == 0)
          fail_line(name, lines.number, fmt::format("expected a vertex index (non-zero integer, v, v/t, v//n or v/t/n), got {}",
                                                    quote(tok)));
        if (slash != std::string_view::npos) {  // the rest must be [t][/[n]] integers
          const std::string_view tail = tok.substr(slash + 1);
          for (char c : tail)
            if (!(c == '/' || c == '-' || (c >= '0' && c <= '9')))
              fail_line(name, lines.number, fmt::format("malformed face vertex {}", quote(tok)));
        }
        const long long k = i > 0 ? i - 1 : nv + i;
        if (k < 0 || k >= nv)
          fail_line(name, lines.number, fmt::format("vertex index {} out of range: {} vertices defined so far", i, nv));
        face.push_back(static_cast<std::uint32_t>(k));
      }
      if (face.size() < 3)
        fail_line(name, lines.number, fmt::format("a face needs at least 3 vertices, got {}", face.size()));
      triangulate(face.data(), face.size(), s.verts, 0, s.triangles);
    }
    // vn, vt, vp, g, o, s, usemtl, mtllib, l, p and unknown statements: ignored.
  }
  return s;
}

Scene load_obj(const std::string& path) { return parse_obj(detail::read_file(path), path); }

}  // namespace rb::scene
