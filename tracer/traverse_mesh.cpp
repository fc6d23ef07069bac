// The traversals of triangle-only scenes traced with Woop in float (MeshLeaves: the kernel inlined).
#include "tracer/traversal.hpp"

namespace rb::tracer {
RB_TRAVERSAL(MeshLeaves, false)
RB_TRAVERSAL(MeshLeaves, true)
}  // namespace rb::tracer
