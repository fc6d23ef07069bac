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

}  // namespace
}  // namespace rb::test
