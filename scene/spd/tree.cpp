// SPD "tree": a binary tree of truncated cones with a sphere at every joint, by Aono & Kunii's
// method (IEEE CG&A May 1984); a square field below; seven lights.
// Cones = spheres = 2^(size+1) - 1 (4,095 at size 11) + 1 polygon. Deterministic (no random
// numbers): each branch is its parent's frame times one of two fixed rotate-scale-translate
// matrices.
#include "scene/spd.hpp"

#include <cmath>
#include <fmt/format.h>

namespace rb::scene::spd {

namespace {

constexpr double kBrAngle[2] = {40.0, 25.0};       // branching angle (degrees)
constexpr double kBrContr[2] = {0.65, 0.70};       // branch contraction
constexpr double kDivergence[2] = {90.0, 140.0 + 90.0};
constexpr double kBrDiameter = 0.67;
constexpr double kWidthHeightRatio = 0.15;

struct Tree {
  Builder& out;
  Mat4 branch[2];

  void grow(const Mat4& frame, double scale, int depth) {
    const Vec3d base = xform_point({0, 0, 0}, frame), apex = xform_point({0, 0, 1}, frame);
    const double base_r = scale * kWidthHeightRatio, apex_r = base_r * kBrDiameter;
    out.cone(base, base_r, apex, apex_r);
    out.sphere(apex, apex_r);
    if (depth <= 0) return;
    for (const Mat4& m : branch) grow(m * frame, scale * kBrDiameter, depth - 1);
  }
};

}  // namespace

Scene tree(int size) {
  check_size("tree", size, 2.0 * (std::pow(2.0, size + 1) - 1.0) + 1.0);
  Builder b(fmt::format("tree({})", size));
  b.background({0.078, 0.361, 0.753});
  b.view({4.5, 0.4, 2.0}, {0.0, 0.0, 1.5}, {0, 0, 1}, 45.0, 1.0, 512, 512);
  for (const Vec3d& l : {Vec3d{-5, 5, 50}, Vec3d{30, -30, 30}, Vec3d{-40, -30, 20}, Vec3d{10, 30, 40},
                         Vec3d{-30, 40, 10}, Vec3d{50, 25, 20}, Vec3d{-10, -60, 30}})
    b.light(l);

  b.surface({0.2, 0.7, 0.2}, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);  // green field
  const Vec3d field[4] = {{50.0, 50.0, 0.0}, {-50.0, 50.0, 0.0}, {-50.0, -50.0, 0.0}, {50.0, -50.0, 0.0}};
  b.polygon(field);

  b.surface({0.55, 0.4, 0.2}, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);  // brown tree
  Tree t{b, {}};
  for (int i = 0; i < 2; ++i) {
    const Mat4 r = rotate_x(kBrAngle[i] * kPi / 180.0) * rotate_z(kDivergence[i] * kPi / 180.0);
    Mat4 st = Mat4::identity();
    st.m[0][0] = st.m[1][1] = st.m[2][2] = kBrContr[i];
    st.m[3][2] = 1.0;  // move to the parent's tip
    t.branch[i] = r * st;
  }
  const auto n = std::size_t(std::pow(2.0, size + 1) - 1.0);
  b.scene().cones.reserve(n);
  b.scene().spheres.reserve(n);
  t.grow(Mat4::identity(), 1.0, size);
  return b.take();
}

}  // namespace rb::scene::spd
