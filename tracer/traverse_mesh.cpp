// The traversals of triangle-only scenes traced with Woop in float (MeshLeaves: the kernel inlined),
// as timed; the counted ones are in tracer/traverse_counted.cpp.
#include "tracer/traversal.hpp"

namespace rb::tracer {
RB_TRAVERSAL(MeshLeaves, false)
}  // namespace rb::tracer
