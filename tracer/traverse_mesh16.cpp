// The packet walk of triangle meshes (MeshLeaves) in groups of 16 rays, one AVX-512 register each:
// bvh::trace_packet with V = f16, for packets of 16, 64 and 256 rays (one, four or sixteen groups).
// The node tests stay the 8-lane ones (8 children); the groups' box tests, the Woop kernel with 16
// rays in lanes and the packet's bookkeeping run in 16 lanes.
//
// An AVX-512 translation unit in a binary that also runs on AVX2-only CPUs: it defines no function
// that another translation unit may define too (an inline function compiled here with AVX-512
// instructions could be the copy the linker keeps). Everything it instantiates carries f16 in its
// name, or is inlined, or is local to this file; tools/check_simd16.py checks the object at every
// build. Called only when the CPU has AVX-512 (tracer/simd16.cpp).
#include "core/lanes16.hpp"
#include "tracer/traversal.hpp"

namespace rb::tracer {
namespace {

template <bool Robust, bool Any>
void packet16(const bvh::Bvh8& t, const MeshLeaves& leaves, const RaySoA& rays, std::size_t i, int packet, HitRec* out) {
  bvh::TraceCounters c;  // not counted: counted traversals walk in 8 lanes
  switch (packet) {
    case 16: bvh::trace_packet<Robust, Any, false, 1, MeshLeaves, f16>(t, leaves, rays, i, out, c); return;
    case 64: bvh::trace_packet<Robust, Any, false, 4, MeshLeaves, f16>(t, leaves, rays, i, out, c); return;
    case 256: bvh::trace_packet<Robust, Any, false, 16, MeshLeaves, f16>(t, leaves, rays, i, out, c); return;
    default: throw std::invalid_argument("16-lane packets hold 16, 64 or 256 rays");
  }
}

}  // namespace

void trace_packet_simd16(const bvh::Bvh8& t, const MeshLeaves& leaves, const RaySoA& rays, std::size_t i, int packet, bool robust, bool any,
                         HitRec* out) {
  if (robust) any ? packet16<true, true>(t, leaves, rays, i, packet, out) : packet16<true, false>(t, leaves, rays, i, packet, out);
  else any ? packet16<false, true>(t, leaves, rays, i, packet, out) : packet16<false, false>(t, leaves, rays, i, packet, out);
}

}  // namespace rb::tracer
