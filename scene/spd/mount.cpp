// SPD "mount": a fractal mountain by Carpenter's midpoint subdivision on a square grid, with a
// pyramid of four glass spheres in front of it; one light.
// Triangles = 2 * 4^size (8,192 at size 6) + 4 spheres.
//
// The midpoint heights come from Haines' deliberately kept "old, faulty" hash of the grid
// position (it repeats, but it is what the published images and the reference files use) fed as
// a seed to a Numerical-Recipes style Gaussian deviate. Both are reproduced exactly: the mountain
// equals the reference file's, vertex for vertex.
#include "scene/spd.hpp"

#include <cmath>
#include <cstdint>
#include <fmt/format.h>

namespace rb::scene::spd {

namespace {

constexpr double kFractalDimension = 2.2;  // between 2 and 3: roughness
constexpr long kMountainNo = 21;           // which mountain
constexpr double kXCorner = -1.0, kYCorner = -1.0, kWidth = 2.0;

// The original hash: ((A << (23-C)) + (B << (15-C)) + (A << (7-C))) & 0xffff over unsigned long.
// For C > 7 a shift count goes negative, undefined in C; the reference binaries (x86-64, 64-bit
// unsigned long, run-time count) shift by the count modulo 64, which is what we do.
std::uint64_t shl(std::uint64_t v, int count) { return v << (unsigned(count) & 63u); }
long hash_rand(long a, long b, int c) {
  const auto ua = std::uint64_t(a), ub = std::uint64_t(b);
  return long((shl(ua, 23 - c) + shl(ub, 15 - c) + shl(ua, 7 - c)) & 0xffffu);
}

// Gaussian deviate from a seed (polar Box-Muller over a small linear congruential generator).
double gauss_rand(long seed) {
  constexpr long m1 = 134456, ia1 = 8121, ic1 = 28411;
  constexpr double rm1 = 1.0 / double(m1);
  long ix1, ix2 = seed;
  double v1, v2, r;
  do {
    ix1 = (ic1 + ix2 * ia1) % m1;
    ix2 = (ic1 + ix1 * ia1) % m1;
    v1 = double(ix1) * 2.0 * rm1 - 1.0;
    v2 = double(ix2) * 2.0 * rm1 - 1.0;
    r = v1 * v1 + v2 * v2;
  } while (r >= 1.0);
  return v1 * std::sqrt(-2.0 * std::log(r) / r);
}

struct Mountain {
  Builder& out;
  int size;
  double fnum;       // grid cells per side
  double roughness;

  double rand_at(long x, long y) const { return gauss_rand(kMountainNo + hash_rand(x, y, size)); }

  void grow(int width, int llx, int lly, double ll, double lr, double ur, double ul) {
    if (width == 1) {
      const double lx = kXCorner + double(llx) * kWidth / fnum, rx = kXCorner + double(llx + 1) * kWidth / fnum;
      const double ly = kYCorner + double(lly) * kWidth / fnum, uy = kYCorner + double(lly + 1) * kWidth / fnum;
      const Vec3d c[4] = {{lx, ly, ll}, {rx, ly, lr}, {rx, uy, ur}, {lx, uy, ul}};
      const Vec3d t0[3] = {c[0], c[1], c[2]}, t1[3] = {c[2], c[3], c[0]};
      out.polygon(t0);
      out.polygon(t1);
      return;
    }
    const int h = width >> 1;
    const double rise = double(h) * kWidth / fnum * roughness;
    const double lower = (ll + lr) / 2.0 + rise * rand_at(llx + h, lly);
    const double right = (lr + ur) / 2.0 + rise * rand_at(llx + width, lly + h);
    const double upper = (ur + ul) / 2.0 + rise * rand_at(llx + h, lly + width);
    const double left = (ul + ll) / 2.0 + rise * rand_at(llx, lly + h);
    const double middle = (ll + lr + ur + ul) / 4.0 + 1.4142136 * rise * rand_at(llx + h, lly + h);
    grow(h, llx, lly, ll, lower, middle, left);
    grow(h, llx + h, lly, lower, lr, right, middle);
    grow(h, llx + h, lly + h, middle, right, ur, upper);
    grow(h, llx, lly + h, left, middle, upper, ul);
  }
};

// A tetrahedral pyramid of spheres of radius r resting around `c`.
void crystal_spheres(Builder& b, const Vec3d& c, double r) {
  const Vec3d pt{0.0, 0.0, r * std::sqrt(3.0 / 2.0)};
  b.sphere(c + pt, r);
  const Vec3d p = xform_vector(pt, rotate_about(unit(Vec3d{1.0, 1.0, 0.0}), std::acos(-1.0 / 3.0)));
  for (int i = 0; i < 3; ++i) b.sphere(xform_vector(p, rotate_z(double(i) * 2.0 * kPi / 3.0)) + c, r);
}

}  // namespace

Scene mount(int size) {
  check_size("mount", size, 2.0 * std::pow(4.0, size) + 4.0);
  if (size > 30) throw SceneError(fmt::format("spd:mount:{}: size too large", size));
  Builder b(fmt::format("mount({})", size));
  b.background({0.078, 0.361, 0.753});
  b.view({-1.6, 1.6, 1.7}, {0, 0, 0}, {0, 0, 1}, 45.0, 0.01, 512, 512);
  b.light({-100.0, -100.0, 100.0});

  b.surface({1.0, 1.0, 1.0}, 0.0, 0.1, 0.1, 0.4, 6.7, 0.9, 1.5);  // clear crystal
  crystal_spheres(b, {-0.8, 0.8, 1.0}, 0.17);

  b.surface({0.5, 0.45, 0.35}, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);  // grey mountain
  const int n = 1 << size;
  const std::size_t tris = 2 * std::size_t(n) * std::size_t(n);
  b.scene().triangles.reserve(tris);
  b.scene().verts.reserve(3 * tris);
  const double ratio = 2.0 / std::exp(std::log(2.0) / (kFractalDimension - 1.0));
  Mountain m{b, size, double(n), std::sqrt(ratio * ratio - 1.0)};
  m.grow(n, 0, 0, 0.0, 0.0, 0.0, 0.0);
  return b.take();
}

}  // namespace rb::scene::spd
