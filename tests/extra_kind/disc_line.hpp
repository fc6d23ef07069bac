// The disc kind's line in the kind table (tracer/kinds.hpp, RB_KIND_TABLE): what an engine kind
// writes into that table, a test writes here (the build names this file in RB_EXTRA_KIND_LIST).
#pragma once

#define RB_EXTRA_KIND(X) X(disc, DiscKind)
