// Helpers of the planar kernel family's tests (tests/test_planar_hand_worked.cpp,
// tests/test_planar_family_checks.cpp): a one-primitive batch and a ray along z.
#pragma once

#include "kernel_test_util.hpp"

namespace rb::test {

// A one-primitive batch.
template <template <class> class P>
PrimSoA<P> one(const P<float>& p) {
  PrimSoA<P> s;
  s.push(p);
  return s;
}

inline Ray<float> zray(float x, float y, float z = 0.f, float dz = 1.f) { return make_ray(Vec3f{x, y, z}, Vec3f{0, 0, dz}); }

}  // namespace rb::test
