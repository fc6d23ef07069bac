// Shared helpers of the SPD generators (matrices in the SPD library's conventions, the NFF-like
// scene builder, the size guard) and the public entry points spd_names / spd_default_size /
// generate_spd.
#include "scene/spd.hpp"
#include "core/suggest.hpp"

#include <cmath>
#include <fmt/format.h>

namespace rb::scene::spd {

Mat4 Mat4::identity() {
  Mat4 r{};
  for (int i = 0; i < 4; ++i) r.m[i][i] = 1.0;
  return r;
}

Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 r{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j] + a.m[i][3] * b.m[3][j];
  return r;
}

// Rotations about a coordinate axis, row-vector form: rotate_z(a) maps (1,0,0) to (cos a, sin a, 0).
Mat4 rotate_x(double a) {
  Mat4 r{};
  const double c = std::cos(a), s = std::sin(a);
  r.m[0][0] = 1.0;
  r.m[1][1] = c, r.m[1][2] = s;
  r.m[2][1] = -s, r.m[2][2] = c;
  r.m[3][3] = 1.0;
  return r;
}
Mat4 rotate_y(double a) {
  Mat4 r{};
  const double c = std::cos(a), s = std::sin(a);
  r.m[1][1] = 1.0;
  r.m[0][0] = c, r.m[0][2] = -s;
  r.m[2][0] = s, r.m[2][2] = c;
  r.m[3][3] = 1.0;
  return r;
}
Mat4 rotate_z(double a) {
  Mat4 r{};
  const double c = std::cos(a), s = std::sin(a);
  r.m[2][2] = 1.0;
  r.m[0][0] = c, r.m[0][1] = s;
  r.m[1][0] = -s, r.m[1][1] = c;
  r.m[3][3] = 1.0;
  return r;
}

// Rodrigues' rotation, written for row vectors (the transpose of the usual column-vector form).
Mat4 rotate_about(const Vec3d& n, double a) {
  const double c = std::cos(a), s = std::sin(a), k = 1.0 - c;
  Mat4 r{};
  r.m[0][0] = n.x * n.x + (1.0 - n.x * n.x) * c;
  r.m[0][1] = n.x * n.y * k + n.z * s;
  r.m[0][2] = n.x * n.z * k - n.y * s;
  r.m[1][0] = n.x * n.y * k - n.z * s;
  r.m[1][1] = n.y * n.y + (1.0 - n.y * n.y) * c;
  r.m[1][2] = n.y * n.z * k + n.x * s;
  r.m[2][0] = n.x * n.z * k + n.y * s;
  r.m[2][1] = n.y * n.z * k - n.x * s;
  r.m[2][2] = n.z * n.z + (1.0 - n.z * n.z) * c;
  r.m[3][3] = 1.0;
  return r;
}

Vec3d xform_vector(const Vec3d& v, const Mat4& m) {
  return {v.x * m.m[0][0] + v.y * m.m[1][0] + v.z * m.m[2][0], v.x * m.m[0][1] + v.y * m.m[1][1] + v.z * m.m[2][1],
          v.x * m.m[0][2] + v.y * m.m[1][2] + v.z * m.m[2][2]};
}

Vec3d xform_point(const Vec3d& v, const Mat4& m) {
  return {v.x * m.m[0][0] + v.y * m.m[1][0] + v.z * m.m[2][0] + m.m[3][0],
          v.x * m.m[0][1] + v.y * m.m[1][1] + v.z * m.m[2][1] + m.m[3][1],
          v.x * m.m[0][2] + v.y * m.m[1][2] + v.z * m.m[2][2] + m.m[3][2]};
}

std::array<double, 4> xform4(const std::array<double, 4>& v, const Mat4& m) {
  std::array<double, 4> r{};
  for (int j = 0; j < 4; ++j) r[j] = v[0] * m.m[0][j] + v[1] * m.m[1][j] + v[2] * m.m[2][j] + v[3] * m.m[3][j];
  return r;
}

Vec3d unit(const Vec3d& v) {
  const double d = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  if (d > 0.0) return {v.x / d, v.y / d, v.z / d};
  return v;
}

void check_size(const std::string& db, int size, double count) {
  if (size < 1) throw SceneError(fmt::format("spd:{}: size factor {} is not >= 1", db, size));
  if (!(count <= kMaxPrimitives))
    throw SceneError(fmt::format("spd:{}:{}: {:.3g} primitives exceed the limit of {:.3g}", db, size, count,
                                 kMaxPrimitives));
}

// ---- Builder ---------------------------------------------------------------------------------

Builder::Builder(std::string name) { s_.name = std::move(name); }

void Builder::background(const Vec3d& c) { s_.background = to_float(c); }

void Builder::view(const Vec3d& from, const Vec3d& at, const Vec3d& up, double angle, double hither, int resx,
                   int resy) {
  s_.camera.from = from;
  s_.camera.at = at;
  s_.camera.up = up;
  s_.camera.angle = angle;
  s_.camera.hither = hither;
  s_.camera.width = resx;
  s_.camera.height = resy;
}

void Builder::light(const Vec3d& p) { s_.lights.push_back(Light{p, Vec3f{1, 1, 1}}); }

void Builder::surface(const Vec3d& color, double /*ka*/, double kd, double ks, double /*ks_spec*/, double ang,
                      double kt, double ior) {
  // libpr1.c lib_output_color: the highlight half-angle becomes a Phong exponent.
  const double a = kPi * ang / 180.0;
  double phong;
  if (a <= 0.0)
    phong = 100000.0;
  else if (a >= kPi / 2.0)
    phong = 1.0;
  else
    phong = std::log(0.5) / std::log(std::cos(a));
  Material m;
  m.color = to_float(color);
  m.kd = float(kd), m.ks = float(ks), m.shine = float(phong), m.t = float(kt), m.ior = float(ior);
  for (std::size_t i = 0; i < s_.materials.size(); ++i) {
    const Material& o = s_.materials[i];
    if (o.color.x == m.color.x && o.color.y == m.color.y && o.color.z == m.color.z && o.kd == m.kd && o.ks == m.ks &&
        o.shine == m.shine && o.t == m.t && o.ior == m.ior && o.checker == 0.0f && m.checker == 0.0f) {
      mat_ = std::uint32_t(i);
      return;
    }
  }
  mat_ = std::uint32_t(s_.materials.size());
  s_.materials.push_back(m);
}

void Builder::sphere(const Vec3d& c, double r) {
  if (s_.materials.empty()) s_.materials.emplace_back();
  s_.spheres.push_back(SphereIn{c, r, mat_});
}

void Builder::cone(const Vec3d& b, double br, const Vec3d& a, double ar) {
  if (s_.materials.empty()) s_.materials.emplace_back();
  s_.cones.push_back(ConeIn{b, br, a, ar, mat_});
}

namespace {
Vec3f unit_newell_normal(const Vec3d* v, std::size_t n) { return to_float(unit(newell_normal(v, n))); }
}  // namespace

void Builder::fill_vert_normals() {
  for (std::size_t t = s_.vert_normals.size() / 3; t < s_.triangles.size(); ++t) {
    const auto& tri = s_.triangles[t];
    const Vec3d p[3] = {s_.verts[tri.v[0]], s_.verts[tri.v[1]], s_.verts[tri.v[2]]};
    const Vec3f n = unit_newell_normal(p, 3);
    s_.vert_normals.insert(s_.vert_normals.end(), {n, n, n});
  }
}

void Builder::fill_poly_normals() {
  for (const auto& poly : s_.polygons) {
    if (poly.first < s_.poly_normals.size()) continue;
    const Vec3f n = unit_newell_normal(&s_.poly_verts[poly.first], poly.count);
    s_.poly_normals.insert(s_.poly_normals.end(), poly.count, n);
  }
}

void Builder::polygon(std::span<const Vec3d> v) {
  if (s_.materials.empty()) s_.materials.emplace_back();
  if (v.size() == 3) {
    const auto i = std::uint32_t(s_.verts.size());
    for (const auto& p : v) s_.verts.push_back(p);
    s_.triangles.push_back(TriangleIn{{i, i + 1, i + 2}, mat_});
    if (!s_.vert_normals.empty()) fill_vert_normals();
  } else {
    const auto first = std::uint32_t(s_.poly_verts.size());
    for (const auto& p : v) s_.poly_verts.push_back(p);
    s_.polygons.push_back(PolygonIn{first, std::uint32_t(v.size()), mat_});
    if (!s_.poly_normals.empty()) fill_poly_normals();
  }
}

void Builder::patch(std::span<const Vec3d> v, std::span<const Vec3d> n) {
  if (s_.materials.empty()) s_.materials.emplace_back();
  if (v.size() == 3) {
    fill_vert_normals();  // backfill the plain triangles before this one
    const auto i = std::uint32_t(s_.verts.size());
    for (const auto& p : v) s_.verts.push_back(p);
    for (const auto& q : n) s_.vert_normals.push_back(to_float(q));
    s_.triangles.push_back(TriangleIn{{i, i + 1, i + 2}, mat_});
  } else {
    fill_poly_normals();
    const auto first = std::uint32_t(s_.poly_verts.size());
    for (const auto& p : v) s_.poly_verts.push_back(p);
    for (const auto& q : n) s_.poly_normals.push_back(to_float(q));
    s_.polygons.push_back(PolygonIn{first, std::uint32_t(v.size()), mat_});
  }
}

}  // namespace rb::scene::spd

// ---- public entry points (scene/sources.hpp) -------------------------------------------------

namespace rb::scene {

namespace {
struct SpdEntry {
  const char* name;
  int default_size;
  Scene (*make)(int);
};
// Default size factors: those of Haines' generators (and of the reference files).
constexpr SpdEntry kSpd[] = {
    {"balls", 4, spd::balls}, {"gears", 4, spd::gears},   {"mount", 6, spd::mount}, {"rings", 7, spd::rings},
    {"teapot", 6, spd::teapot}, {"tetra", 6, spd::tetra}, {"tree", 11, spd::tree},
};

const SpdEntry& find_spd(const std::string& name) {
  for (const auto& e : kSpd)
    if (name == e.name) return e;
  std::string known;
  std::vector<std::string> names;
  for (const auto& e : kSpd) known += std::string(known.empty() ? "" : " ") + e.name, names.emplace_back(e.name);
  throw SceneError(fmt::format("spd:{}: unknown SPD database (known: {}){}", name, known, did_you_mean(name, names)));
}
}  // namespace

std::vector<std::string> spd_names() {
  std::vector<std::string> r;
  for (const auto& e : kSpd) r.emplace_back(e.name);
  return r;
}

int spd_default_size(const std::string& name) { return find_spd(name).default_size; }

Scene generate_spd(const std::string& name, int size) { return find_spd(name).make(size); }

}  // namespace rb::scene
