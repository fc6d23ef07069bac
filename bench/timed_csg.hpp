// CSG queries timed (the report's CSG section, `raybench csg`): the closest hit of each ray, one
// float ray at a time (csg_hit: linear merges, closest-hit stop) against 8 rays in lanes (csg_hit8:
// branch-free merges), on the same rays, one thread, on this thread's CPU time; and the two ray
// sets they are timed on.
#pragma once

#include "kernels/csg_ray.hpp"
#include "scene/scene.hpp"
#include "soa/rays.hpp"

#include <cstddef>

namespace rb::bench {

struct CsgSpeed {
  double scalar = 0, simd = 0;        // queries per second: the median repetition
  std::size_t n = 0, hits = 0, hits8 = 0;
  double sink = 0;                     // a checksum of the hits, so that no query is optimised away
};
// `repetitions` rounds, each timing the scalar then the 8-lane queries over the first multiple of
// 8 of the rays.
CsgSpeed time_csg_queries(const CsgTree& T, const RaySoA& rays, int repetitions);

// n rays from a sphere twice the size of the tree's box towards random points inside the box.
RaySoA csg_rays(const CsgTree& T, std::size_t n, unsigned seed);
// Primary rays of a camera over a w x h image, row by row: 8 consecutive rays are 8 neighbouring
// pixels (coherent packets).
RaySoA camera_rays(const scene::Camera& c, int w, int h);

}  // namespace rb::bench
