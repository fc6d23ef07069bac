// The number-type layer and Counted: counting rules, minps semantics, lane access, counting
// inside TBB worker threads.
#include "core/counted.hpp"
#include "core/lanes.hpp"
#include "core/ray.hpp"
#include "core/spawn.hpp"
#include "core/vec3.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace rb {
namespace {

TEST(Counted, CountsEachKindOnce) {
  const ops::Scope s;
  const cfloat a(2.f), b(3.f);
  cfloat c = a + b;         // add
  c = c - a;                // add
  c = c * b;                // mul
  c = c / a;                // div
  c = vsqrt(c);             // sqrt
  c = vmin(c, a);           // minmax
  c = vmax(c, a);           // minmax
  c = vselect<cfloat>(a < b, a, b);  // cmp + select
  c = vfma(a, b, c);        // fma
  c = -c;                   // free
  c = vabs(c);              // free
  const OpCounts o = s.elapsed();
  EXPECT_EQ(o.add, 2u);
  EXPECT_EQ(o.mul, 1u);
  EXPECT_EQ(o.div, 1u);
  EXPECT_EQ(o.sqrt, 1u);
  EXPECT_EQ(o.minmax, 2u);
  EXPECT_EQ(o.cmp, 1u);
  EXPECT_EQ(o.select, 1u);
  EXPECT_EQ(o.fma, 1u);
  EXPECT_EQ(o.flops(), 2u + 1 + 1 + 1 + 2);
  EXPECT_FLOAT_EQ(c.v, std::fabs(-(2.f * 3.f + 2.f)));
}

TEST(Counted, SimdCountsPerInstruction) {
  const ops::Scope s;
  const cf8 a(f8(1.f)), b(f8(2.f));
  const Vec3<cf8> u{a, b, a}, v{b, a, b};
  (void)dot(u, v);  // 3 mul, 2 add: one per vector instruction, the per-lane count
  EXPECT_EQ(s.elapsed().mul, 3u);
  EXPECT_EQ(s.elapsed().add, 2u);
}

TEST(Counted, CountingWorksInTbbWorkers) {
  ops::reset_all();
  const int n = 10000;
  tbb::task_arena arena(2);
  arena.execute([&] {
    tbb::parallel_for(0, n, [](int i) {
      const cfloat x{float(i)};
      (void)(x * x + x);
    });
  });
  const OpCounts t = ops::total();
  EXPECT_EQ(t.mul, std::uint64_t(n));
  EXPECT_EQ(t.add, std::uint64_t(n));
}

// Counted<T> computes exactly what T computes: every operation a kernel may call gives T's value
// bit for bit (NaN where T gives NaN), on values that include signed zeros, infinities and NaN. The
// kernel families' typed tests therefore run the value types only; the first kernels run every
// Counted type end to end (test_first_kernels.cpp).
template <class T>
struct CountedValue : ::testing::Test {};
using CountedBases = ::testing::Types<float, double, f8, d4>;
TYPED_TEST_SUITE(CountedValue, CountedBases);

template <class T>
bool same_bits(const T& a, const Counted<T>& b) {
  for (int k = 0; k < lanes_v<T>; ++k) {
    const auto x = lane(a, k), y = lane(b, k);
    if (!(x == y || (std::isnan(x) && std::isnan(y))) || std::signbit(x) != std::signbit(y)) return false;
  }
  return true;
}

TYPED_TEST(CountedValue, EveryOperationGivesTheBaseValue) {
  using T = TypeParam;
  using S = scalar_t<T>;
  using C = Counted<T>;
  const S inf = std::numeric_limits<S>::infinity(), nan = std::numeric_limits<S>::quiet_NaN();
  const S vals[] = {S(0), -S(0), S(1), S(-2.5), S(3) / S(7), S(1e-30), S(6.4e6), inf, -inf, nan};
  // Each lane of a SIMD operand takes another value, so lanes also mix.
  auto make = [&](std::size_t i) {
    alignas(64) S b[8];
    for (int k = 0; k < 8; ++k) b[k] = vals[(i + std::size_t(k) * 3) % std::size(vals)];
    return load<T>(b);
  };
  const std::size_t n = std::size(vals);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      const T a = make(i), b = make(j), c = make(i + j);
      const C ca(a), cb(b), cc(c);
      SCOPED_TRACE(testing::Message() << "values " << i << ", " << j);
      EXPECT_TRUE(same_bits(a + b, ca + cb));
      EXPECT_TRUE(same_bits(a - b, ca - cb));
      EXPECT_TRUE(same_bits(a * b, ca * cb));
      EXPECT_TRUE(same_bits(a / b, ca / cb));
      EXPECT_TRUE(same_bits(T(-a), -ca));
      EXPECT_TRUE(same_bits(vsqrt(a), vsqrt(ca)));
      EXPECT_TRUE(same_bits(vabs(a), vabs(ca)));
      EXPECT_TRUE(same_bits(vmin(a, b), vmin(ca, cb)));
      EXPECT_TRUE(same_bits(vmax(a, b), vmax(ca, cb)));
      EXPECT_TRUE(same_bits(vfma(a, b, c), vfma(ca, cb, cc)));
      EXPECT_TRUE(same_bits(vcopysign(a, b), vcopysign(ca, cb)));
      EXPECT_TRUE(same_bits(vrounded(a), vrounded(ca)));
      EXPECT_TRUE(same_bits(vselect<T>(a < b, a, c), vselect<C>(ca < cb, ca, cc)));
      EXPECT_TRUE(same_bits(vsin(a), vsin(ca)));
      EXPECT_TRUE(same_bits(vcos(a), vcos(ca)));
      EXPECT_TRUE(same_bits(vacos(a), vacos(ca)));
      EXPECT_TRUE(same_bits(vatan2(a, b), vatan2(ca, cb)));
      EXPECT_TRUE(same_bits(vcbrt(a), vcbrt(ca)));
      const mask_t<T> masks[] = {a < b, a <= b, a > b, a >= b, a == b, a != b};
      const mask_t<C> cmasks[] = {ca < cb, ca <= cb, ca > cb, ca >= cb, ca == cb, ca != cb};
      for (int m = 0; m < 6; ++m) {
        EXPECT_EQ(any_of<T>(masks[m]), any_of<C>(cmasks[m])) << m;
        EXPECT_EQ(all_of<T>(masks[m]), all_of<C>(cmasks[m])) << m;
        EXPECT_EQ(count_true<T>(masks[m]), count_true<C>(cmasks[m])) << m;
        for (int k = 0; k < lanes_v<T>; ++k) EXPECT_EQ(lane_mask<T>(masks[m], k), lane_mask<C>(cmasks[m], k)) << m;
      }
    }
}

TEST(Num, MinMaxFollowMinpsNaNRule) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // a < b ? a : b: a NaN in either argument returns the second argument.
  EXPECT_EQ(vmin(nan, 1.f), 1.f);
  EXPECT_TRUE(std::isnan(vmin(1.f, nan)));
  EXPECT_EQ(vmax(nan, 1.f), 1.f);
  EXPECT_TRUE(std::isnan(vmax(1.f, nan)));
  // The SIMD instantiation agrees lane by lane.
  EXPECT_EQ(lane(vmin(f8(nan), f8(1.f)), 3), 1.f);
  EXPECT_TRUE(std::isnan(lane(vmin(f8(1.f), f8(nan)), 5)));
  EXPECT_EQ(lane(vmax(f8(nan), f8(1.f)), 0), 1.f);
}

// The scalar min/max are the minss/maxss (minsd/maxsd) instructions where AVX is on: bit for bit the
// expression a < b ? a : b (a > b ? a : b) on every pair of special values, signed zeros included,
// and the 8-lane form's lanes.
template <class T>
bool bits_equal(T a, T b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

template <class T>
void expect_minmax_is_the_ternary() {
  using L = std::numeric_limits<T>;
  const T vals[] = {T(0), -T(0), T(1), T(-1), L::infinity(), -L::infinity(), L::quiet_NaN(), -L::quiet_NaN(),
                    L::denorm_min(), -L::denorm_min(), L::max(), L::lowest(), T(0.5), T(1e-30)};
  for (const T a : vals)
    for (const T b : vals) {
      const T a0 = a, b0 = b;  // the expression the comment promises, on copies
      EXPECT_TRUE(bits_equal(vmin(a, b), a0 < b0 ? a0 : b0)) << a << " " << b;
      EXPECT_TRUE(bits_equal(vmax(a, b), a0 > b0 ? a0 : b0)) << a << " " << b;
      if constexpr (std::is_same_v<T, float>) {
        EXPECT_TRUE(bits_equal(lane(vmin(f8(a), f8(b)), 2), vmin(a, b))) << a << " " << b;
        EXPECT_TRUE(bits_equal(lane(vmax(f8(a), f8(b)), 6), vmax(a, b))) << a << " " << b;
      }
    }
}

TEST(Num, ScalarMinMaxAreTheTernaryBitForBit) {
  expect_minmax_is_the_ternary<float>();
  expect_minmax_is_the_ternary<double>();
}

TEST(Num, LoadsStoresAndLanes) {
  alignas(32) float in[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  const f8 v = load<f8>(in);
  for (int k = 0; k < 8; ++k) EXPECT_EQ(lane(v, k), float(k));
  const d4 w = load<d4>(in + 4);  // float data into a double batch
  for (int k = 0; k < 4; ++k) EXPECT_EQ(lane(w, k), double(4 + k));
  const f8_mask m = v > f8(3.5f);
  EXPECT_FALSE(lane_mask<f8>(m, 3));
  EXPECT_TRUE(lane_mask<f8>(m, 4));
  EXPECT_TRUE(any_of<f8>(m));
  EXPECT_FALSE(all_of<f8>(m));
  EXPECT_TRUE(none_of<f8>(mask_false<f8>()));
  EXPECT_TRUE(all_of<f8>(mask_true<f8>()));
  EXPECT_EQ(lanes_v<f8>, 8);
  EXPECT_EQ(lanes_v<d4>, 4);
  EXPECT_EQ(lanes_v<cf8>, 8);
}

// make_rays: every lane the scalar make_ray's bits, on rays of every scale (origins and directions
// in double, some beyond float's range) and on the invalid ones (NaN and infinite components, a zero
// direction).
TEST(Num, RaysMadeInLanesAreTheScalarRays) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> e(-60, 60);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const double odd[] = {0.0, -0.0, inf, -inf, nan, 1e-320, 1e300};
  auto value = [&] { return rng() % 16 == 0 ? odd[rng() % 7] : std::ldexp(u(rng), e(rng)); };
  auto bits = [](float x) { return std::bit_cast<std::uint32_t>(x); };
  int invalid = 0, valid = 0;
  for (int round = 0; round < 4000; ++round) {
    alignas(32) double in[6][8];  // o, d per lane
    for (int l = 0; l < 8; ++l) {
      for (int c = 0; c < 6; ++c) in[c][l] = value();
      if (round % 5 == 0) in[3][l] = in[4][l] = in[5][l] = rng() % 2 ? 0.0 : -0.0;
    }
    Vec3<d4> o[2], d[2];
    for (int h = 0; h < 2; ++h) {
      o[h] = {load<d4>(&in[0][4 * h]), load<d4>(&in[1][4 * h]), load<d4>(&in[2][4 * h])};
      d[h] = {load<d4>(&in[3][4 * h]), load<d4>(&in[4][4 * h]), load<d4>(&in[5][4 * h])};
    }
    const Ray<f8> r = lanes::make_rays(o, d);
    for (int l = 0; l < 8; ++l) {
      const Ray<float> s = make_ray(Vec3d{in[0][l], in[1][l], in[2][l]}, Vec3d{in[3][l], in[4][l], in[5][l]});
      (s.tmin > s.tmax ? invalid : valid) += 1;
      const float got[11] = {lane(r.o.x, l), lane(r.o.y, l), lane(r.o.z, l), lane(r.d.x, l), lane(r.d.y, l), lane(r.d.z, l),
                             lane(r.rd.x, l), lane(r.rd.y, l), lane(r.rd.z, l), lane(r.tmin, l), lane(r.tmax, l)};
      const float want[11] = {s.o.x, s.o.y, s.o.z, s.d.x, s.d.y, s.d.z, s.rd.x, s.rd.y, s.rd.z, s.tmin, s.tmax};
      for (int c = 0; c < 11; ++c) ASSERT_EQ(bits(got[c]), bits(want[c])) << "round " << round << " lane " << l << " field " << c;
    }
  }
  // Both kinds exercised: valid rays, and invalid ones (zero directions, NaN and infinite components).
  EXPECT_GT(invalid, 5000);
  EXPECT_GT(valid, 10000);
}

}  // namespace
}  // namespace rb
