// SceneAccel's traces: the walk of bvh/traverse.hpp for the scene's leaf source (tracer/traversal.hpp).
// Apart from the build (tracer/accel.cpp) in library rb_tracer, above rb_tracer_core: what builds
// scenes without tracing them through every walk (the 16-lane walk's test in the `exact` preset)
// does not compile the traversal units.
#include "tracer/accel.hpp"
#include "tracer/traversal.hpp"

namespace rb::tracer {

template <bool Count>
void SceneAccel::dispatch(const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, const TraceOptions& o,
                          bvh::TraceCounters& c) const {
  const bvh::Slab slab = o.slab_given ? o.slab : plan_.slab;
  const bool lanes16 = !Count && group_lanes(o) == 16;
  if (mesh_only_) run_traversal<Count>(wide, mesh_, rays, begin, end, out, o.packet, o.any, slab, c, lanes16);
  else run_traversal<Count>(wide, table_, rays, begin, end, out, o.packet, o.any, slab, c, false);
}

void SceneAccel::trace(const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, const TraceOptions& o) const {
  bvh::TraceCounters c;
  dispatch<false>(rays, begin, end, out, o, c);
}
void SceneAccel::trace_counted(const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, const TraceOptions& o,
                               bvh::TraceCounters& c) const {
  dispatch<true>(rays, begin, end, out, o, c);
}

}  // namespace rb::tracer
