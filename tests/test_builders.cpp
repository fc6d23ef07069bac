// The builders' error convention (docs/DESIGN.md section 7), builder by builder: degenerate input
// gives exactly P::never() (bit for bit) and one line in *why naming the problem; valid input
// builds a primitive other than never() and leaves *why alone.
#include "kernels/box.hpp"
#include "kernels/cylinder_cone.hpp"
#include "kernels/parallel_planes.hpp"
#include "kernels/plane.hpp"
#include "kernels/plane_uv.hpp"
#include "kernels/polyhedron.hpp"
#include "kernels/quadric.hpp"
#include "kernels/sphere.hpp"
#include "kernels/triangle.hpp"
#include "kernels/triangle_woop.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <string>

namespace rb::test {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// The primitives are plain arrays of floats: never() is recognised by its bytes (its fields may
// be NaN, which no == comparison would match).
template <class P>
bool same_bytes(const P& a, const P& b) {
  return std::memcmp(&a, &b, sizeof(P)) == 0;
}

// `build(why)` must give never() with a reason containing `part`.
template <class P, class Build>
void expect_never(Build build, const std::string& part) {
  std::string why;
  const P p = build(&why);
  EXPECT_TRUE(same_bytes(p, P::never())) << "expected never() for: " << part;
  EXPECT_NE(why.find(part), std::string::npos) << "why = \"" << why << "\", expected it to mention \"" << part << "\"";
  EXPECT_EQ(why.find('\n'), std::string::npos) << "one line: " << why;
  // Without a why pointer the builder gives the same never().
  EXPECT_TRUE(same_bytes(build(nullptr), P::never()));
}

// `build(why)` must give a primitive other than never() and leave *why alone.
template <class P, class Build>
void expect_built(Build build) {
  std::string why = "untouched";
  const P p = build(&why);
  EXPECT_FALSE(same_bytes(p, P::never()));
  EXPECT_EQ(why, "untouched");
}

TEST(Builders, Sphere) {
  using P = Sphere<float>;
  expect_built<P>([](std::string* w) { return make_sphere(Vec3f{0, 0, 5}, 1.f, w); });
  expect_never<P>([](std::string* w) { return make_sphere(Vec3f{0, 0, 5}, 0.f, w); }, "radius");
  expect_never<P>([](std::string* w) { return make_sphere(Vec3f{0, 0, 5}, -1.f, w); }, "radius");
  expect_never<P>([](std::string* w) { return make_sphere(Vec3f{0, 0, 5}, kNaN, w); }, "radius");
  expect_never<P>([](std::string* w) { return make_sphere(Vec3f{kInf, 0, 5}, 1.f, w); }, "centre");
  expect_never<P>([](std::string* w) { return make_sphere(Vec3d{0, 0, 5}, 1e30, w); }, "float");
  // The uv sphere passes the sphere's own reason on.
  std::string why;
  (void)make_sphere_uv(Vec3f{0, 0, 5}, 0.f, Vec3f{0, 0, 1}, Vec3f{1, 0, 0}, &why);
  EXPECT_NE(why.find("radius"), std::string::npos) << why;
}

TEST(Builders, Box) {
  using P = Box<float>;
  expect_built<P>([](std::string* w) { return make_box(Vec3f{0, 0, 0}, Vec3f{1, 1, 1}, w); });
  expect_built<P>([](std::string* w) { return make_box(Vec3f{0, 0, 0}, Vec3f{1, 0, 1}, w); });  // flat is kept
  expect_never<P>([](std::string* w) { return make_box(Vec3f{0, 2, 0}, Vec3f{1, 1, 1}, w); }, "min is above max");
  expect_never<P>([](std::string* w) { return make_box(Vec3f{0, 0, kNaN}, Vec3f{1, 1, 1}, w); }, "not finite");
  using H = Halfspaces8<float>;
  expect_built<H>([](std::string* w) { return make_box_halfspaces(Vec3f{0, 0, 0}, Vec3f{1, 1, 1}, w); });
  expect_never<H>([](std::string* w) { return make_box_halfspaces(Vec3f{2, 0, 0}, Vec3f{1, 1, 1}, w); }, "box");
  using S = Slabs3<float>;
  expect_built<S>([](std::string* w) { return make_box_slabs(Vec3f{0, 0, 0}, Vec3f{1, 1, 1}, w); });
  expect_never<S>([](std::string* w) { return make_box_slabs(Vec3f{0, 0, 0}, Vec3f{1, kInf, 1}, w); }, "box");
}

TEST(Builders, PlaneAndParallelPlanes) {
  using P = Plane<float>;
  expect_built<P>([](std::string* w) { return make_plane(Vec3f{0, 0, 5}, Vec3f{0, 0, 1}, w); });
  expect_never<P>([](std::string* w) { return make_plane(Vec3f{0, 0, 5}, Vec3f{0, 0, 0}, w); }, "normal");
  expect_never<P>([](std::string* w) { return make_plane(Vec3f{0, kNaN, 5}, Vec3f{0, 0, 1}, w); }, "point");
  using PP = ParallelPlanes4<float>;
  expect_built<PP>([](std::string* w) { return make_parallel_planes<4>(Vec3f{0, 0, 1}, std::vector<float>{1.f, 2.f}, w); });
  expect_never<PP>([](std::string* w) { return make_parallel_planes<4>(Vec3f{0, 0, 0}, std::vector<float>{1.f}, w); }, "normal");
}

TEST(Builders, TrianglesAndFrames) {
  const Vec3f a{0, 0, 5}, b{1, 0, 5}, c{0, 1, 5}, on_ab{2, 0, 5};
  expect_built<Triangle<float>>([&](std::string* w) { return make_triangle(a, b, c, w); });
  expect_never<Triangle<float>>([&](std::string* w) { return make_triangle(a, b, on_ab, w); }, "zero area");
  expect_never<Triangle<float>>([&](std::string* w) { return make_triangle(a, b, Vec3f{0, kInf, 5}, w); }, "not finite");
  expect_built<TriVerts<float>>([&](std::string* w) { return make_tri_verts(a, b, c, w); });
  expect_never<TriVerts<float>>([&](std::string* w) { return make_tri_verts(a, a, c, w); }, "zero area");
  using L = TriLecture<float>;
  int axis = -1;
  expect_built<L>([&](std::string* w) { return make_tri_lecture(a, b, c, axis, w); });
  EXPECT_EQ(axis, 2);
  expect_never<L>([&](std::string* w) { return make_tri_lecture(a, b, on_ab, axis, w); }, "zero area");
  EXPECT_EQ(axis, 2);  // never() drops z
  expect_never<L>([&](std::string* w) { return make_parallelogram(a, Vec3f{1, 0, 0}, Vec3f{kNaN, 0, 0}, axis, w); }, "not finite");
  expect_never<L>([&](std::string* w) { return make_plane_uv(a, Vec3f{1, 0, 0}, Vec3f{3, 0, 0}, axis, w); }, "zero area");
  expect_never<L>([&](std::string* w) { return make_tri_lecture(Vec3d{0, 0, 0}, Vec3d{1e30, 0, 0}, Vec3d{0, 1e30, 0}, axis, w); },
                  "float");
}

TEST(Builders, CylinderAndCone) {
  using C = Cylinder<float>;
  expect_built<C>([](std::string* w) { return make_cylinder(0.f, 0.f, 1.f, 0.f, 2.f, w); });
  expect_built<C>([](std::string* w) { return make_cylinder(0.f, 0.f, 1.f, -kInf, kInf, w); });  // infinite is allowed
  expect_never<C>([](std::string* w) { return make_cylinder(0.f, 0.f, 0.f, 0.f, 2.f, w); }, "radius");
  expect_never<C>([](std::string* w) { return make_cylinder(kInf, 0.f, 1.f, 0.f, 2.f, w); }, "axis position");
  expect_never<C>([](std::string* w) { return make_cylinder(0.f, 0.f, 1.f, 2.f, 2.f, w); }, "height range");
  expect_never<C>([](std::string* w) { return make_cylinder(0.0, 0.0, 1.0, 1.0, 1.0 + 1e-12, w); }, "in float");
  using K = Cone<float>;
  expect_built<K>([](std::string* w) { return make_cone(Vec3f{0, 0, 0}, 0.f, 1.f, w); });
  expect_never<K>([](std::string* w) { return make_cone(Vec3f{0, 0, kNaN}, 0.f, 1.f, w); }, "apex");
  expect_never<K>([](std::string* w) { return make_cone(Vec3f{0, 0, 0}, 1.f, 0.f, w); }, "height range");
  expect_never<K>([](std::string* w) { return make_capped_cone(Vec3f{0, 0, 0}, 1.f, kNaN, w); }, "height range");
}

TEST(Builders, Quadrics) {
  using Q = Quadric<float>;
  expect_built<Q>([](std::string* w) { return make_quadric(QuadricCoeffs{1, 1, 1, 0, 0, 0, 0, 0, 0, -1}, w); });
  expect_never<Q>([](std::string* w) { return make_quadric(QuadricCoeffs{1, 1, kNaN, 0, 0, 0, 0, 0, 0, -1}, w); }, "not finite");
  expect_never<Q>([](std::string* w) { return make_quadric(QuadricCoeffs{0, 0, 0, 0, 0, 0, 0, 0, 0, -1}, w); }, "zero");
  const double Q0[4][4] = {{0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 2}};
  std::string why;
  EXPECT_TRUE(same_bytes(make_quadric_matrix(Q0, &why), Q::never()));
  EXPECT_NE(why.find("zero"), std::string::npos) << why;  // the matrix builder passes make_quadric's reason on
  using R = QuadricRev<float>;
  expect_built<R>([](std::string* w) { return make_quadric_rev(Vec3f{0, 0, 0}, 1.f, 0.f, -1.f, w); });
  expect_never<R>([](std::string* w) { return make_quadric_rev(Vec3f{0, 0, 0}, 1.f, kInf, -1.f, w); }, "not finite");
}

TEST(Builders, Polyhedra) {
  using H = Halfspaces8<float>;
  const std::vector<HalfspaceIn> tetra = {{{0, 0, -1}, {0, 0, 0}}, {{0, -1, 0}, {0, 0, 0}}, {{-1, 0, 0}, {0, 0, 0}}, {{1, 1, 1}, {1, 0, 0}}};
  expect_built<H>([&](std::string* w) { return make_halfspaces<8>(tetra, w); });
  std::vector<HalfspaceIn> bad = tetra;
  bad[2].normal = {0, 0, 0};
  expect_never<H>([&](std::string* w) { return make_halfspaces<8>(bad, w); }, "normal");
  using S = Slabs3<float>;
  const std::array<Vec3f, 3> ax = {Vec3f{1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{0, 0, 1}};
  expect_built<S>([&](std::string* w) { return make_slabs<3>(ax, {0.f, 0.f, 0.f}, {1.f, 1.f, 1.f}, w); });
  expect_never<S>([&](std::string* w) { return make_slabs<3>(ax, {0.f, 2.f, 0.f}, {1.f, 1.f, 1.f}, w); }, "lo is above hi");
  const std::array<Vec3f, 3> zero_axis = {Vec3f{1, 0, 0}, Vec3f{0, 0, 0}, Vec3f{0, 0, 1}};
  expect_never<S>([&](std::string* w) { return make_slabs<3>(zero_axis, {0.f, 0.f, 0.f}, {1.f, 1.f, 1.f}, w); }, "axis");
}

}  // namespace
}  // namespace rb::test
