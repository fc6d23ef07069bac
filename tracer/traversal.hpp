// The traversals a SceneAccel runs: bvh::trace_range for its leaf source, with the slab test and the
// hit query chosen once per call. Each leaf source's traversals are instantiated once, in a
// translation unit of their own (tracer/traverse_mesh.cpp, tracer/traverse_table.cpp: they compile
// in parallel); everyone else sees the extern declarations below.
//
// Packets of 16 or more rays of a triangle mesh can also walk in 16 AVX-512 lanes (groups of 16
// rays: tracer/traverse_mesh16.cpp, compiled for AVX-512 in the same binary and chosen at run time,
// `lanes16`); the uncounted traversal only (counted traversals walk in 8 lanes).
#pragma once

#include "bvh/traverse.hpp"
#include "tracer/mesh_leaves.hpp"
#include "tracer/simd16.hpp"

#include <type_traits>

namespace rb::tracer {

template <bool Count, class L>
void run_traversal(const bvh::Bvh8& t, const L& leaves, const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, int packet,
                   bool any, bvh::Slab slab, bvh::TraceCounters& c, bool lanes16) {
  using bvh::Slab;
  auto go = [&]<Slab S, bool Any>(auto wide) {
    bvh::trace_range<S, Any, Count>(t, leaves, rays, begin, end, out, packet, c, wide);
  };
  auto by_slab = [&](auto wide) {
    switch (slab) {
      case Slab::conservative: any ? go.template operator()<Slab::conservative, true>(wide) : go.template operator()<Slab::conservative, false>(wide); return;
      case Slab::fast: any ? go.template operator()<Slab::fast, true>(wide) : go.template operator()<Slab::fast, false>(wide); return;
      case Slab::robust: any ? go.template operator()<Slab::robust, true>(wide) : go.template operator()<Slab::robust, false>(wide); return;
    }
  };
  if constexpr (std::is_same_v<L, MeshLeaves> && !Count) {
    if (lanes16 && packet >= 16) {
      by_slab([&](bool robust, std::size_t i, std::size_t p) { trace_packet_simd16(t, leaves, rays, i, int(p), robust, any, out); });
      return;
    }
  }
  by_slab(nullptr);
}

#define RB_TRAVERSAL(L, Count)                                                                                                   \
  template void run_traversal<Count, L>(const bvh::Bvh8&, const L&, const RaySoA&, std::size_t, std::size_t, HitRec*, int, bool, \
                                        bvh::Slab, bvh::TraceCounters&, bool);
#define RB_EXTERN_TRAVERSAL(L, Count) extern RB_TRAVERSAL(L, Count)
RB_EXTERN_TRAVERSAL(MeshLeaves, false)
RB_EXTERN_TRAVERSAL(MeshLeaves, true)
RB_EXTERN_TRAVERSAL(TableLeaves, false)
RB_EXTERN_TRAVERSAL(TableLeaves, true)

}  // namespace rb::tracer
