// Internal to scene/spd/*.cpp: the little that Eric Haines' Standard Procedural Databases need
// to be regenerated in memory rather than read from NFF files.
//
// The SPD generators (github erich666/StandardProceduralDatabases, CC0) compute in double with
// row-vector 4x4 matrices (p' = p * M, translation in row 3) and print with %g. We follow the
// same conventions and the same order of operations, in double, and store double positions (the
// scene model's), so that at the default sizes the scenes equal the reference NFF files
// (tests/data/spd/*.nff) to the printed precision.
#pragma once

#include "scene/sources.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>

namespace rb::scene::spd {

inline constexpr double kPi = 3.141592653589793;  // the SPD library's PI

// Row-vector 4x4 matrix, as the SPD library's MATRIX (row major, p' = p * M).
struct Mat4 {
  double m[4][4];
  static Mat4 identity();
};
Mat4 operator*(const Mat4& a, const Mat4& b);           // a then b (row vectors)
Mat4 rotate_x(double radians);
Mat4 rotate_y(double radians);
Mat4 rotate_z(double radians);
Mat4 rotate_about(const Vec3d& unit_axis, double radians);  // right-handed, axis = direction cosines
Vec3d xform_vector(const Vec3d& v, const Mat4& m);      // no translation
Vec3d xform_point(const Vec3d& p, const Mat4& m);       // with row 3 as translation
std::array<double, 4> xform4(const std::array<double, 4>& v, const Mat4& m);

Vec3d unit(const Vec3d& v);  // v / |v|, or v unchanged when |v| == 0 (lib_normalize_vector)

// Throws SceneError unless 1 <= size and the primitive count (computed in double, before any
// allocation) is at most kMaxPrimitives.
inline constexpr double kMaxPrimitives = 50e6;
void check_size(const std::string& db, int size, double primitive_count);

// Collects what the SPD library would have printed as NFF, into a Scene.
//   NFF `p` with 3 vertices -> Scene::triangles (3 fresh vertices each), more -> Scene::polygons;
//   NFF `pp` with 3 vertices -> triangles + vert_normals, more -> polygons + poly_normals.
// Vertex-normal arrays stay empty until the first patch; from then on (and backwards) plain faces
// get their geometric (Newell) normal, so the arrays stay parallel.
// Materials are deduplicated by value (the SPD programs repeat identical `f` lines).
class Builder {
 public:
  explicit Builder(std::string name);
  void background(const Vec3d& rgb);
  void view(const Vec3d& from, const Vec3d& at, const Vec3d& up, double angle_deg, double hither, int resx,
            int resy);
  void light(const Vec3d& pos);
  // lib_output_color(name, color, ka, kd, ks, ks_spec, ang, kt, ior) as NFF prints it: the Phong
  // exponent is derived from `ang`, the half angle in degrees at which the highlight halves.
  void surface(const Vec3d& color, double ka, double kd, double ks, double ks_spec, double ang, double kt, double ior);
  void sphere(const Vec3d& c, double r);
  void cone(const Vec3d& base, double base_r, const Vec3d& apex, double apex_r);
  void polygon(std::span<const Vec3d> verts);
  void patch(std::span<const Vec3d> verts, std::span<const Vec3d> normals);

  Scene& scene() { return s_; }
  Scene take() { return std::move(s_); }

 private:
  void fill_vert_normals();
  void fill_poly_normals();
  Scene s_;
  std::uint32_t mat_ = 0;
};

Scene balls(int size);
Scene gears(int size);
Scene mount(int size);
Scene rings(int size);
Scene teapot(int size);
Scene tetra(int size);
Scene tree(int size);

}  // namespace rb::scene::spd
