// The packet walk in 16 AVX-512 lanes (tracer/traverse_mesh16.cpp): whether this binary holds it and
// this CPU runs it (tracer/simd16.cpp, compiled for AVX2), and its entry point. A light header: the
// machine description and the command line ask these without the traversal's templates.
#pragma once

#include <cstddef>

namespace rb {
struct RaySoA;
namespace bvh {
struct Bvh8;
struct HitRec;
}  // namespace bvh
}  // namespace rb

namespace rb::tracer {

struct MeshLeaves;

// Whether this binary holds the 16-lane walk (built where the compiler targets AVX-512, not in the
// sanitizer preset) and whether this CPU runs it (AVX-512 F, CD, DQ, BW and VL, registers saved by
// the OS).
bool simd16_traversal_built();
bool simd16_cpu();
// Both: packets can walk in 16 lanes here.
bool simd16_traversal_runs();
// Rays [i, i + packet) (packet 16, 64 or 256; one direction octant) as one packet of 16-lane groups
// over a triangle mesh, closest or any hit, the robust slab test or the fast one; hits into out.
// Only where simd16_traversal_built() and simd16_cpu() (throws std::logic_error in a build without it).
void trace_packet_simd16(const bvh::Bvh8& t, const MeshLeaves& leaves, const RaySoA& rays, std::size_t i, int packet, bool robust, bool any,
                         bvh::HitRec* out);

}  // namespace rb::tracer
