// Roots<F, N> (core/roots.hpp): canonical lists and CSG in 1D ray space. Hand-worked cases on
// every number type, random lists against point membership, and SIMD lanes against scalar.
#include "core/counted.hpp"
#include "core/roots.hpp"
#include "kernel_test_util.hpp"

#include <random>
#include <vector>

namespace rb::test {
namespace {

template <class F, int N>
Roots<F, N> list(std::vector<double> t) {
  F a[N];
  for (int k = 0; k < N; ++k) a[k] = F(k < int(t.size()) ? scalar_t<F>(t[std::size_t(k)]) : kInf<F>);
  return Roots<F, N>::canonical(a);
}

template <class F, int N>
std::vector<double> lane_list(const Roots<F, N>& r, int ln = 0) {
  std::vector<double> v;
  for (int k = 0; k < N; ++k)
    if (lane_mask<F>(r.valid[k], ln)) v.push_back(double(lane(r.t[k], ln)));
  return v;
}

template <class F>
struct RootLists : ::testing::Test {};
TYPED_TEST_SUITE(RootLists, AllNumbers);

TYPED_TEST(RootLists, CanonicalFormAndSpans) {
  using F = TypeParam;
  const auto r = list<F, 4>({3, 1});
  EXPECT_EQ(lane_list(r), (std::vector<double>{1, 3}));
  EXPECT_EQ(r.count_in_lane(0), 2);
  EXPECT_EQ(double(lane(r.t[3], 0)), double(kInf<F>));
  const auto s = Roots<F, 2>::closed_span(mask_false<F>(), F(1), F(2));
  EXPECT_EQ(s.count_in_lane(0), 0);
  EXPECT_EQ(double(lane(s.t[0], 0)), double(kInf<F>));
  EXPECT_EQ((Roots<F, 3>::none().count_in_lane(0)), 0);
}

TYPED_TEST(RootLists, UnionIntersectionDifference) {
  using F = TypeParam;
  const auto A = list<F, 4>({0, 2, 5, 8});  // [0,2] [5,8]
  const auto B = list<F, 2>({1, 6});        // [1,6]
  EXPECT_EQ(lane_list(csg_union(A, B)), (std::vector<double>{0, 8}));
  EXPECT_EQ(lane_list(csg_intersection(A, B)), (std::vector<double>{1, 2, 5, 6}));
  EXPECT_EQ(lane_list(csg_difference(A, B)), (std::vector<double>{0, 1, 6, 8}));
  EXPECT_EQ(lane_list(csg_difference(B, A)), (std::vector<double>{2, 5}));
  // Empty operands.
  const auto E = Roots<F, 2>::none();
  EXPECT_EQ(lane_list(csg_union(A, E)), lane_list(A));
  EXPECT_TRUE(lane_list(csg_intersection(A, E)).empty());
  EXPECT_EQ(lane_list(csg_difference(A, E)), lane_list(A));
  // Touching and shared boundaries: [0,1] u [1,2] covers [0,2]; [0,1] n [1,2] is the point 1 or
  // empty, never a wrong interval; equal spans: A - A has no interior, A n A = A.
  const auto P = list<F, 2>({0, 1}), Q = list<F, 2>({1, 2});
  const auto u = lane_list(csg_union(P, Q));
  ASSERT_EQ(u.size() % 2, 0u);
  EXPECT_EQ(u.front(), 0);
  EXPECT_EQ(u.back(), 2);
  EXPECT_EQ(lane_list(csg_intersection(P, P)), (std::vector<double>{0, 1}));
  const auto d = lane_list(csg_difference(P, P));  // at most zero-length pieces where boundaries coincide
  for (std::size_t k = 0; k + 1 < d.size(); k += 2) EXPECT_EQ(d[k], d[k + 1]);
  EXPECT_EQ(lane_list(csg_union(P, P)), (std::vector<double>{0, 1}));
}

// Whether x lies in the union of [t0,t1], [t2,t3], ...
bool inside(const std::vector<double>& v, double x) {
  for (std::size_t k = 0; k + 1 < v.size(); k += 2)
    if (v[k] <= x && x <= v[k + 1]) return true;
  return false;
}

TEST(RootLists, RandomListsAgreeWithPointMembership) {
  std::mt19937 g(7);
  std::uniform_int_distribution<int> cnt(0, 2), val(0, 12);  // small integers: many shared boundaries
  auto random_list = [&](int pairs_max) {
    std::vector<double> v;
    const int n = 2 * std::min(cnt(g), pairs_max);
    for (int k = 0; k < n; ++k) v.push_back(val(g));
    std::sort(v.begin(), v.end());
    return v;
  };
  for (int it = 0; it < 2000; ++it) {
    const auto a = random_list(2), b = random_list(1);
    const auto A = list<float, 4>(a);
    const auto B = list<float, 2>(b);
    for (const SetOp op : {SetOp::kUnion, SetOp::kIntersection, SetOp::kDifference}) {
      const auto r = lane_list(combine(op, A, B));
      ASSERT_EQ(r.size() % 2, 0u);
      for (std::size_t k = 1; k < r.size(); ++k) ASSERT_LE(r[k - 1], r[k]);
      // Check at the midpoints between all boundaries (membership of open pieces).
      std::vector<double> xs;
      for (double x : a) xs.push_back(x);
      for (double x : b) xs.push_back(x);
      std::sort(xs.begin(), xs.end());
      for (std::size_t k = 0; k + 1 < xs.size(); ++k) {
        const double x = 0.5 * (xs[k] + xs[k + 1]);
        if (xs[k] == xs[k + 1]) continue;
        const bool ia = inside(a, x), ib = inside(b, x);
        const bool want = op == SetOp::kUnion ? (ia || ib) : op == SetOp::kIntersection ? (ia && ib) : (ia && !ib);
        ASSERT_EQ(inside(r, x), want) << "op " << int(op) << " x " << x;
      }
    }
  }
}

TEST(RootLists, SimdLanesMatchScalar) {
  std::mt19937 g(11);
  std::uniform_real_distribution<float> u(0.f, 10.f);
  for (int it = 0; it < 200; ++it) {
    alignas(32) float a[4][8], b[2][8];
    for (int ln = 0; ln < 8; ++ln) {
      float x[4] = {u(g), u(g), u(g), u(g)};
      std::sort(x, x + 4);
      const int na = ln % 3 == 0 ? 2 : 4;  // lanes with different counts
      for (int k = 0; k < 4; ++k) a[k][ln] = k < na ? x[k] : kInf<float>;
      float y[2] = {u(g), u(g)};
      std::sort(y, y + 2);
      b[0][ln] = y[0];
      b[1][ln] = y[1];
    }
    f8 ta[4], tb[2];
    for (int k = 0; k < 4; ++k) ta[k] = load<f8>(a[k]);
    for (int k = 0; k < 2; ++k) tb[k] = load<f8>(b[k]);
    const auto A = Roots<f8, 4>::canonical(ta);
    const auto B = Roots<f8, 2>::canonical(tb);
    const auto R = csg_difference(A, B);
    for (int ln = 0; ln < 8; ++ln) {
      float sa[4] = {a[0][ln], a[1][ln], a[2][ln], a[3][ln]}, sb[2] = {b[0][ln], b[1][ln]};
      const auto r = csg_difference(Roots<float, 4>::canonical(sa), Roots<float, 2>::canonical(sb));
      EXPECT_EQ(lane_list(R, ln), lane_list(r)) << "lane " << ln;
    }
  }
}

}  // namespace
}  // namespace rb::test
