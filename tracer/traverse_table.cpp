// The traversals of every other scene (TableLeaves: one leaf function per kind, chosen by the plan),
// as timed; the counted ones are in tracer/traverse_counted.cpp.
#include "tracer/traversal.hpp"

namespace rb::tracer {
RB_TRAVERSAL(TableLeaves, false)
}  // namespace rb::tracer
