// Stanford PLY loader: ascii, binary_little_endian, binary_big_endian. See loaders.hpp.
// The binary path is bulk: one bounds check per element (or per face), fixed-offset memcpy
// for the coordinates, templates chosen once per element on the value type and byte order.
#include "scene/loaders.hpp"
#include "scene/parse_util.hpp"

#include <algorithm>
#include <cstring>

namespace rb::scene {

namespace {

using namespace detail;

enum class Ty : std::uint8_t { i8, u8, i16, u16, i32, u32, f32, f64 };
constexpr std::size_t tsize(Ty t) {
  switch (t) {
    case Ty::i8: case Ty::u8: return 1;
    case Ty::i16: case Ty::u16: return 2;
    case Ty::i32: case Ty::u32: case Ty::f32: return 4;
    case Ty::f64: return 8;
  }
  return 1;
}
bool parse_type(std::string_view s, Ty& t) {
  static const std::pair<const char*, Ty> names[] = {
      {"char", Ty::i8},   {"int8", Ty::i8},    {"uchar", Ty::u8},   {"uint8", Ty::u8},     {"short", Ty::i16},
      {"int16", Ty::i16}, {"ushort", Ty::u16}, {"uint16", Ty::u16}, {"int", Ty::i32},      {"int32", Ty::i32},
      {"uint", Ty::u32},  {"uint32", Ty::u32}, {"float", Ty::f32},  {"float32", Ty::f32}, {"double", Ty::f64},
      {"float64", Ty::f64}};
  for (const auto& [n, ty] : names)
    if (s == n) { t = ty; return true; }
  return false;
}

struct Prop {
  std::string name;
  bool list = false;
  Ty count_t = Ty::u8, t = Ty::f32;
};
struct Elem {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Prop> props;
  std::size_t line = 0;  // header line
  std::size_t min_bytes() const {
    std::size_t n = 0;
    for (const auto& p : props) n += p.list ? tsize(p.count_t) : tsize(p.t);
    return n;
  }
};

template <class T>
T load_as(const unsigned char* p, bool swap) {
  using U = std::conditional_t<sizeof(T) == 1, std::uint8_t,
            std::conditional_t<sizeof(T) == 2, std::uint16_t, std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
  U u;
  std::memcpy(&u, p, sizeof u);
  if (swap) {
    if constexpr (sizeof(U) == 2) u = __builtin_bswap16(u);
    else if constexpr (sizeof(U) == 4) u = __builtin_bswap32(u);
    else if constexpr (sizeof(U) == 8) u = __builtin_bswap64(u);
  }
  T v;
  std::memcpy(&v, &u, sizeof v);
  return v;
}
double load_val(Ty t, const unsigned char* p, bool swap) {
  switch (t) {
    case Ty::i8: return load_as<std::int8_t>(p, swap);
    case Ty::u8: return load_as<std::uint8_t>(p, swap);
    case Ty::i16: return load_as<std::int16_t>(p, swap);
    case Ty::u16: return load_as<std::uint16_t>(p, swap);
    case Ty::i32: return load_as<std::int32_t>(p, swap);
    case Ty::u32: return load_as<std::uint32_t>(p, swap);
    case Ty::f32: return double(load_as<float>(p, swap));
    case Ty::f64: return load_as<double>(p, swap);
  }
  return 0;
}

enum class Role { other, vertex, face, strips };

struct PlyReader {
  std::string_view data;
  const std::string& name;
  enum class Fmt { ascii, le, be } fmt = Fmt::ascii;
  std::vector<Elem> elems;
  std::size_t body = 0;  // offset of the first byte after the header
  Scene s;
  std::vector<std::uint32_t> face;  // scratch

  PlyReader(std::string_view d, const std::string& n) : data(d), name(n) {}

  void header() {
    Lines lines(data);
    LineReader ln{nullptr, nullptr};
    if (!lines.next(ln) || ln.word() != "ply" || !ln.at_end()) fail_line(name, 1, "expected 'ply' (the PLY magic number)");
    bool have_fmt = false;
    for (;;) {
      if (!lines.next(ln)) fail_line(name, lines.number, "unexpected end of file in the header: expected 'end_header'");
      const std::string_view kw = ln.word();
      if (kw == "end_header") {
        if (!ln.at_end()) fail_line(name, lines.number, "unexpected text after 'end_header'");
        if (!have_fmt) fail_line(name, lines.number, "no 'format' line in the header");
        body = std::size_t(lines.p - data.data());
        return;
      } else if (kw == "comment" || kw == "obj_info" || kw.empty()) {
        continue;
      } else if (kw == "format") {
        const std::string_view f = ln.word(), v = ln.word();
        if (f == "ascii") fmt = Fmt::ascii;
        else if (f == "binary_little_endian") fmt = Fmt::le;
        else if (f == "binary_big_endian") fmt = Fmt::be;
        else fail_line(name, lines.number, fmt::format("expected format ascii, binary_little_endian or binary_big_endian, got {}", quote(f)));
        if (v != "1.0" || !ln.at_end()) fail_line(name, lines.number, "expected format version 1.0");
        have_fmt = true;
      } else if (kw == "element") {
        Elem e;
        e.name = std::string(ln.word().substr(0, 64));
        e.line = lines.number;
        if (e.name.empty() || !ln.number(e.count) || !ln.at_end())
          fail_line(name, lines.number, "expected 'element NAME COUNT' with COUNT a non-negative integer");
        elems.push_back(std::move(e));
      } else if (kw == "property") {
        if (elems.empty()) fail_line(name, lines.number, "'property' before any 'element'");
        Prop p;
        std::string_view t = ln.word();
        if (t == "list") {
          p.list = true;
          if (!parse_type(ln.word(), p.count_t)) fail_line(name, lines.number, "expected the list count type (uchar, int, ...)");
          if (p.count_t == Ty::f32 || p.count_t == Ty::f64) fail_line(name, lines.number, "a list count type must be an integer type");
          t = ln.word();
        }
        if (!parse_type(t, p.t)) fail_line(name, lines.number, fmt::format("expected a property type (char uchar short ushort int uint float double), got {}", quote(t)));
        p.name = std::string(ln.word().substr(0, 64));
        if (p.name.empty() || !ln.at_end()) fail_line(name, lines.number, "expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'");
        elems.back().props.push_back(std::move(p));
      } else {
        fail_line(name, lines.number, fmt::format("unknown header keyword {}: expected format, element, property, comment or end_header", quote(kw)));
      }
    }
  }

  Role role_of(const Elem& e, int& xi, int& yi, int& zi, int& li) const {
    xi = yi = zi = li = -1;
    for (std::size_t i = 0; i < e.props.size(); ++i) {
      const Prop& p = e.props[i];
      if (!p.list && p.name == "x") xi = int(i);
      if (!p.list && p.name == "y") yi = int(i);
      if (!p.list && p.name == "z") zi = int(i);
      if (p.list && (p.name == "vertex_indices" || p.name == "vertex_index") && li < 0) li = int(i);
    }
    if (e.name == "vertex") return Role::vertex;
    if (e.name == "face") return Role::face;
    if (e.name == "tristrips") return Role::strips;
    return Role::other;
  }

  // ---- polygons and strips from index lists ----
  bool have_verts = false;
  void add_face(std::size_t rec, std::size_t where, bool ascii) {
    if (face.size() < 3) return;  // points and edges: not surfaces
    triangulate(face.data(), face.size(), s.verts, 0, s.triangles);
    (void)rec; (void)where; (void)ascii;
  }
  void add_strip() {
    for (std::size_t k = 2; k < face.size(); ++k) {
      std::uint32_t a = face[k - 2], b = face[k - 1];
      const std::uint32_t c = face[k];
      if (k % 2) std::swap(a, b);
      if (a == b || b == c || a == c) continue;
      s.triangles.push_back({{a, b, c}, 0});
    }
    face.clear();
  }
  // Validates index `v` of record `rec`; -1 is a strip restart when `strips`.
  [[noreturn]] void bad_index(double v, const Elem& e, std::size_t rec, std::size_t where, bool ascii) {
    const std::string what = fmt::format("element '{}' #{}: vertex index {} out of range (the file has {} vertices{})", e.name, rec, v,
                                         s.verts.size(), e.name == "tristrips" ? "; -1 restarts a strip" : "");
    if (ascii) fail_line(name, where, what);
    fail_byte(name, where, what);
  }
  void index(double v, const Elem& e, bool strips, std::size_t rec, std::size_t where, bool ascii) {
    if (strips && v == -1) { add_strip(); return; }
    if (!(v >= 0 && v < double(s.verts.size())) || v != std::floor(v)) bad_index(v, e, rec, where, ascii);
    face.push_back(std::uint32_t(v));
  }

  // ---- binary ----
  const unsigned char* base() const { return reinterpret_cast<const unsigned char*>(data.data()); }
  void need(std::size_t at, std::size_t n, const Elem& e, std::uint64_t rec) const {
    if (data.size() - at < n)
      fail_byte(name, at, fmt::format("unexpected end of data in element '{}' record #{}: {} more bytes expected, {} left", e.name, rec, n,
                                      data.size() - at));
  }

  template <class V, bool Swap>
  void xyz_fast(std::size_t at, std::size_t n, std::size_t rs, std::size_t ox, std::size_t oy, std::size_t oz) {
    const unsigned char* p = base() + at;
    s.verts.resize(n);
    bool finite = true;
    for (std::size_t i = 0; i < n; ++i, p += rs) {
      const Vec3d v{double(load_as<V>(p + ox, Swap)), double(load_as<V>(p + oy, Swap)), double(load_as<V>(p + oz, Swap))};
      finite &= std::isfinite(float(v.x)) & std::isfinite(float(v.y)) & std::isfinite(float(v.z));
      s.verts[i] = v;
    }
    if (!finite)
      for (std::size_t i = 0; i < n; ++i)
        if (!finite3(to_float(s.verts[i])))
          fail_byte(name, at + i * rs, fmt::format("vertex #{} has a coordinate that is not finite (NaN, infinity or beyond float range)", i));
  }

  template <class I, bool Swap>
  std::size_t faces_fast(std::size_t at, const Elem& e, Ty count_t) {
    const unsigned char* b = base();
    const std::size_t cs = tsize(count_t);
    const double nv = double(s.verts.size());
    s.triangles.reserve(s.triangles.size() + std::size_t(e.count));  // count was capped by the bytes left
    auto idx = [&](std::size_t p, std::uint64_t r) -> std::uint32_t {
      const I v = load_as<I>(b + p, Swap);
      if (!(double(v) >= 0 && double(v) < nv) || double(v) != std::floor(double(v))) bad_index(double(v), e, r, p, false);
      return std::uint32_t(v);
    };
    for (std::uint64_t r = 0; r < e.count; ++r) {
      need(at, cs, e, r);
      const double c = load_val(count_t, b + at, Swap);
      if (c < 0) fail_byte(name, at, fmt::format("element '{}' #{}: negative list count {}", e.name, r, c));
      const std::size_t n = std::size_t(c);
      const std::size_t rec_at = at;
      at += cs;
      need(at, n * sizeof(I), e, r);
      if (n == 3) {  // the common case: straight into the triangle array
        s.triangles.push_back({{idx(at, r), idx(at + sizeof(I), r), idx(at + 2 * sizeof(I), r)}, 0});
        at += 3 * sizeof(I);
        continue;
      }
      face.clear();
      for (std::size_t k = 0; k < n; ++k, at += sizeof(I)) face.push_back(idx(at, r));
      add_face(r, rec_at, false);
    }
    return at;
  }

  template <bool Swap>
  std::size_t binary_faces(std::size_t at, const Elem& e) {
    const Prop& p = e.props[0];
    switch (p.t) {
      case Ty::i8: return faces_fast<std::int8_t, Swap>(at, e, p.count_t);
      case Ty::u8: return faces_fast<std::uint8_t, Swap>(at, e, p.count_t);
      case Ty::i16: return faces_fast<std::int16_t, Swap>(at, e, p.count_t);
      case Ty::u16: return faces_fast<std::uint16_t, Swap>(at, e, p.count_t);
      case Ty::i32: return faces_fast<std::int32_t, Swap>(at, e, p.count_t);
      case Ty::u32: return faces_fast<std::uint32_t, Swap>(at, e, p.count_t);
      case Ty::f32: return faces_fast<float, Swap>(at, e, p.count_t);
      case Ty::f64: return faces_fast<double, Swap>(at, e, p.count_t);
    }
    return at;
  }

  std::size_t binary_elem(std::size_t at, const Elem& e, Role role, int xi, int yi, int zi, int li) {
    const bool swap = fmt == Fmt::be;
    const unsigned char* b = base();
    bool all_scalar = true;
    std::size_t rs = 0;
    for (const auto& p : e.props) {
      all_scalar &= !p.list;
      rs += p.list ? 0 : tsize(p.t);
    }
    if (all_scalar) {
      if (rs != 0 && e.count > (data.size() - at) / rs)
        fail_byte(name, at, fmt::format("element '{}' announces {} records of {} bytes but only {} bytes are left", e.name, e.count, rs,
                                        data.size() - at));
      const std::size_t n = std::size_t(e.count);
      if (role == Role::vertex) {
        std::size_t off[3];
        const int idx[3] = {xi, yi, zi};
        for (int k = 0; k < 3; ++k) {
          off[k] = 0;
          for (int j = 0; j < idx[k]; ++j) off[k] += tsize(e.props[std::size_t(j)].t);
        }
        const Ty tx = e.props[std::size_t(xi)].t;
        const bool same = tx == e.props[std::size_t(yi)].t && tx == e.props[std::size_t(zi)].t;
        if (same && tx == Ty::f32) swap ? xyz_fast<float, true>(at, n, rs, off[0], off[1], off[2]) : xyz_fast<float, false>(at, n, rs, off[0], off[1], off[2]);
        else if (same && tx == Ty::f64) swap ? xyz_fast<double, true>(at, n, rs, off[0], off[1], off[2]) : xyz_fast<double, false>(at, n, rs, off[0], off[1], off[2]);
        else {
          s.verts.resize(n);
          for (std::size_t i = 0; i < n; ++i) {
            const unsigned char* r = b + at + i * rs;
            const Vec3d v{load_val(tx, r + off[0], swap), load_val(e.props[std::size_t(yi)].t, r + off[1], swap),
                          load_val(e.props[std::size_t(zi)].t, r + off[2], swap)};
            s.verts[i] = v;
            if (!finite3(to_float(v))) fail_byte(name, at + i * rs, fmt::format("vertex #{} has a coordinate that is not finite (NaN, infinity or beyond float range)", i));
          }
        }
        have_verts = true;
      }
      return at + n * rs;
    }
    // Elements with lists: a record at a time. Count cap first: every record has >= min_bytes.
    const std::size_t mb = std::max<std::size_t>(1, e.min_bytes());
    if (e.count > (data.size() - at) / mb)
      fail_byte(name, at, fmt::format("element '{}' announces {} records of at least {} bytes but only {} bytes are left", e.name, e.count, mb,
                                      data.size() - at));
    if (role == Role::face && li == 0 && e.props.size() == 1) return swap ? binary_faces<true>(at, e) : binary_faces<false>(at, e);
    if (role == Role::vertex) s.verts.reserve(std::size_t(e.count));
    for (std::uint64_t r = 0; r < e.count; ++r) {
      Vec3d v{0, 0, 0};
      const std::size_t rec_at = at;
      face.clear();
      for (std::size_t j = 0; j < e.props.size(); ++j) {
        const Prop& p = e.props[j];
        if (!p.list) {
          need(at, tsize(p.t), e, r);
          if (role == Role::vertex && (int(j) == xi || int(j) == yi || int(j) == zi)) {
            const double x = load_val(p.t, b + at, swap);
            (int(j) == xi ? v.x : int(j) == yi ? v.y : v.z) = x;
          }
          at += tsize(p.t);
          continue;
        }
        need(at, tsize(p.count_t), e, r);
        const double c = load_val(p.count_t, b + at, swap);
        if (c < 0) fail_byte(name, at, fmt::format("element '{}' #{}: negative list count {}", e.name, r, c));
        at += tsize(p.count_t);
        const std::size_t n = std::size_t(c);
        need(at, n * tsize(p.t), e, r);
        if (int(j) == li && (role == Role::face || role == Role::strips)) {
          for (std::size_t k = 0; k < n; ++k) index(load_val(p.t, b + at + k * tsize(p.t), swap), e, role == Role::strips, r, at + k * tsize(p.t), false);
        }
        at += n * tsize(p.t);
      }
      if (role == Role::vertex) {
        if (!finite3(to_float(v))) fail_byte(name, rec_at, fmt::format("vertex #{} has a coordinate that is not finite (NaN, infinity or beyond float range)", r));
        s.verts.push_back(v);
      } else if (role == Role::face) {
        add_face(r, rec_at, false);
      } else if (role == Role::strips) {
        add_strip();
      }
    }
    if (role == Role::vertex) have_verts = true;
    return at;
  }

  // ---- ascii: whitespace-separated tokens, line numbers kept for messages ----
  std::size_t pos = 0, line = 0;
  std::string_view token() {
    while (pos < data.size() && (is_space(data[pos]) || data[pos] == '\n')) {
      if (data[pos] == '\n') ++line;
      ++pos;
    }
    const std::size_t s0 = pos;
    while (pos < data.size() && !is_space(data[pos]) && data[pos] != '\n') ++pos;
    return data.substr(s0, pos - s0);
  }
  double ascii_num(const Elem& e, std::uint64_t r, const Prop& p, bool integer) {
    const std::string_view t = token();
    if (t.empty())  // end of file: name the last line
      fail_line(name, line - (line > 1 && !data.empty() && data.back() == '\n' ? 1 : 0), fmt::format("unexpected end of file in element '{}' record #{}: expected property '{}'", e.name, r, p.name));
    double v = 0;
    const char* b = t.data() + (t[0] == '+' ? 1 : 0);
    const auto res = std::from_chars(b, t.data() + t.size(), v);
    if (res.ec != std::errc() || res.ptr != t.data() + t.size())
      fail_line(name, line, fmt::format("element '{}' record #{}: expected a number for property '{}', got {}", e.name, r, p.name, quote(t)));
    if (integer && v != std::floor(v))
      fail_line(name, line, fmt::format("element '{}' record #{}: expected an integer for property '{}', got {}", e.name, r, p.name, quote(t)));
    return v;
  }
  void ascii_elem(const Elem& e, Role role, int xi, int yi, int zi, int li) {
    // Each value takes at least two bytes (a digit and a separator).
    const std::size_t mb = std::max<std::size_t>(2, 2 * e.props.size());
    if (e.count > (data.size() - pos) / mb + 1)
      fail_line(name, e.line, fmt::format("element '{}' announces {} records but only {} bytes follow the header", e.name, e.count, data.size() - pos));
    if (role == Role::vertex) s.verts.reserve(std::size_t(e.count));
    for (std::uint64_t r = 0; r < e.count; ++r) {
      Vec3d v{0, 0, 0};
      face.clear();
      for (std::size_t j = 0; j < e.props.size(); ++j) {
        const Prop& p = e.props[j];
        if (!p.list) {
          const double x = ascii_num(e, r, p, p.t != Ty::f32 && p.t != Ty::f64);
          if (role == Role::vertex && (int(j) == xi || int(j) == yi || int(j) == zi)) (int(j) == xi ? v.x : int(j) == yi ? v.y : v.z) = x;
          continue;
        }
        const double c = ascii_num(e, r, p, true);
        if (c < 0 || c > double(data.size() - pos)) fail_line(name, line, fmt::format("element '{}' record #{}: list count {} out of range", e.name, r, c));
        const bool idx = int(j) == li && (role == Role::face || role == Role::strips);
        for (std::size_t k = 0; k < std::size_t(c); ++k) {
          const double x = ascii_num(e, r, p, idx || (p.t != Ty::f32 && p.t != Ty::f64));
          if (idx) index(x, e, role == Role::strips, r, line, true);
        }
      }
      if (role == Role::vertex) {
        if (!finite3(to_float(v))) fail_line(name, line, fmt::format("vertex #{} has a coordinate that is not finite (NaN, infinity or beyond float range)", r));
        s.verts.push_back(v);
      } else if (role == Role::face) {
        add_face(r, line, true);
      } else if (role == Role::strips) {
        add_strip();
      }
    }
    if (role == Role::vertex) have_verts = true;
  }

  Scene run() {
    s.name = name;
    s.materials.push_back(Material{});
    header();
    // Line of the first body byte (for ascii messages).
    line = 1 + std::size_t(std::count(data.begin(), data.begin() + std::ptrdiff_t(body), '\n'));
    pos = body;
    std::size_t at = body;
    bool seen_vertex = false;
    for (const Elem& e : elems) {
      int xi, yi, zi, li;
      const Role role = role_of(e, xi, yi, zi, li);
      if (role == Role::vertex) {
        if (seen_vertex) fail_line(name, e.line, "a second 'vertex' element");
        seen_vertex = true;
        if (xi < 0 || yi < 0 || zi < 0) fail_line(name, e.line, "element 'vertex' needs scalar properties x, y and z");
        if (e.count >= 0xFFFFFFFFull) fail_line(name, e.line, "more than 2^32-2 vertices");
      }
      if ((role == Role::face || role == Role::strips) && e.count > 0) {
        if (li < 0) fail_line(name, e.line, fmt::format("element '{}' needs a list property 'vertex_indices' (or 'vertex_index')", e.name));
        if (!seen_vertex) fail_line(name, e.line, fmt::format("element '{}' comes before element 'vertex' (not supported)", e.name));
      }
      if (fmt == Fmt::ascii) ascii_elem(e, role, xi, yi, zi, li);
      else at = binary_elem(at, e, role, xi, yi, zi, li);
      if (role == Role::strips) add_strip();
    }
    if (!seen_vertex) fail_line(name, 1, "no 'vertex' element in the header");
    return std::move(s);
  }
};

}  // namespace

Scene parse_ply(std::string_view bytes, const std::string& name) { return PlyReader(bytes, name).run(); }
Scene load_ply(const std::string& path) { return parse_ply(detail::read_file(path), path); }

}  // namespace rb::scene
