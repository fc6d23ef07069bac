// The traversals of every other scene (TableLeaves: one leaf function per kind, chosen by the plan).
#include "tracer/traversal.hpp"

namespace rb::tracer {
RB_TRAVERSAL(TableLeaves, false)
RB_TRAVERSAL(TableLeaves, true)
}  // namespace rb::tracer
