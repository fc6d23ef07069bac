// The traversals a SceneAccel runs: bvh::trace_range for its leaf source, with the slab test and the
// hit query chosen once per call. Each leaf source's traversals are instantiated once, in a
// translation unit of their own (tracer/traverse_mesh.cpp, tracer/traverse_table.cpp: they compile
// in parallel); everyone else sees the extern declarations below.
#pragma once

#include "bvh/traverse.hpp"
#include "tracer/mesh_leaves.hpp"

namespace rb::tracer {

template <bool Count, class L>
void run_traversal(const bvh::Bvh8& t, const L& leaves, const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, int packet,
                   bool any, bvh::Slab slab, bvh::TraceCounters& c) {
  using bvh::Slab;
  switch (slab) {
    case Slab::conservative:
      if (any) bvh::trace_range<Slab::conservative, true, Count>(t, leaves, rays, begin, end, out, packet, c);
      else bvh::trace_range<Slab::conservative, false, Count>(t, leaves, rays, begin, end, out, packet, c);
      return;
    case Slab::fast:
      if (any) bvh::trace_range<Slab::fast, true, Count>(t, leaves, rays, begin, end, out, packet, c);
      else bvh::trace_range<Slab::fast, false, Count>(t, leaves, rays, begin, end, out, packet, c);
      return;
    case Slab::robust:
      if (any) bvh::trace_range<Slab::robust, true, Count>(t, leaves, rays, begin, end, out, packet, c);
      else bvh::trace_range<Slab::robust, false, Count>(t, leaves, rays, begin, end, out, packet, c);
      return;
  }
}

#define RB_TRAVERSAL(L, Count)                                                                                                   \
  template void run_traversal<Count, L>(const bvh::Bvh8&, const L&, const RaySoA&, std::size_t, std::size_t, HitRec*, int, bool, \
                                        bvh::Slab, bvh::TraceCounters&);
#define RB_EXTERN_TRAVERSAL(L, Count) extern RB_TRAVERSAL(L, Count)
RB_EXTERN_TRAVERSAL(MeshLeaves, false)
RB_EXTERN_TRAVERSAL(MeshLeaves, true)
RB_EXTERN_TRAVERSAL(TableLeaves, false)
RB_EXTERN_TRAVERSAL(TableLeaves, true)

}  // namespace rb::tracer
