// Every bench spec of every kernel family, in the order the benchmarks are registered.
#pragma once

#include "bench/specs.hpp"
#include "bench/specs_planar.hpp"
#include "bench/specs_quadric.hpp"
#include "bench/specs_solver.hpp"

namespace rb::bench {

template <class V>
void for_every_spec(V&& v) {
  for_each_spec(v);
  for_each_spec_planar(v);
  for_each_spec_quadric(v);
  for_each_spec_solver(v);
}

// The most primitives a spec's batch serves in lanes at once (a spec that stores its primitives in
// groups of 8 says so: `max_prim_lanes`); its 16-lane primitives-in-lanes row is left out.
template <class Spec>
constexpr int max_prim_lanes() {
  if constexpr (requires { Spec::max_prim_lanes; }) return Spec::max_prim_lanes;
  else return 1 << 30;
}

}  // namespace rb::bench
