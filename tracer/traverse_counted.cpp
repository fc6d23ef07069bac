// The counted traversals of both leaf sources (SceneAccel::trace_counted: nodes visited, boxes and
// primitives tested), which no timed loop runs. A library of their own (rb_tracer_counted), apart
// from the timed walks, so that the PGO builds take them from the release build instead of
// compiling them twice more (root CMakeLists.txt, RB_PGO_REUSE).
#include "tracer/traversal.hpp"

namespace rb::tracer {
RB_TRAVERSAL(MeshLeaves, true)
RB_TRAVERSAL(TableLeaves, true)
}  // namespace rb::tracer
