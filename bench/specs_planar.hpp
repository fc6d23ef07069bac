// Bench specs of the planar kernel family (see bench/specs.hpp for the shape of a spec).
#pragma once

#include "bench/specs.hpp"

namespace rb::bench {

// Every benchmarked (kernel, method) of this family.
template <class V>
void for_each_spec_planar(V&& v) {
  (void)v;
}

}  // namespace rb::bench
