// The BVH as plain data: a binary tree of slabs (BNode) and the 8-wide tree collapsed from it
// (WNode, SoA child boxes). Builders (bvh/build.cpp) and the traversal (bvh/traverse.hpp) are
// separate, and neither knows what a primitive is: the builder sees boxes with a small kind tag,
// the traversal calls a leaf source (bvh/traverse.hpp says what one provides) with a leaf's reference.
//
// Node byte budgets: BNode 32 bytes (box 24 + child-or-leaf 4 + count/kind 4); WNode 224 bytes
// (six arrays of 8 floats: lo_x hi_x lo_y hi_y lo_z hi_z, then 8 child references).
#pragma once

#include "core/memory.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace rb::bvh {

// Binary node. Internal (count == 0): children are nodes `first` and `first + 1`.
// Leaf (count > 0): `count` primitives of one kind, starting at `first` (in the builder's
// primitive order; after bvh::Accel's reordering, the leaf's 8-slot group in its kind's batch).
struct BNode {
  float lo[3], hi[3];
  std::uint32_t first;
  std::uint16_t count;
  std::uint8_t kind;
  std::uint8_t pad_;  // not initialised: a node pool is sized before the build writes it
  bool leaf() const { return count != 0; }
};
static_assert(sizeof(BNode) == 32);

// Wide node: 8 children tested by one 8-lane slab test. Child references: kEmpty, an internal
// node index (< kLeafBit), or a leaf: kLeafBit | kind << kLeafKindShift | group (the leaf's 8-slot
// group in its kind's batch; `kind` is the builder's tag, 4 bits: a tracer may give one primitive
// kind several batches, one per storage class). Empty slots have the box (+inf, -inf): no ray
// enters them.
inline constexpr std::uint32_t kEmpty = 0xFFFFFFFFu;
inline constexpr std::uint32_t kLeafBit = 0x80000000u;
inline constexpr int kLeafKindShift = 27;
inline constexpr int kMaxKinds = 16;  // leaf tags: 4 bits of a leaf reference
inline constexpr std::uint32_t kLeafGroupMask = (1u << kLeafKindShift) - 1;
inline bool is_leaf(std::uint32_t ref) { return (ref & kLeafBit) != 0; }
inline int leaf_kind(std::uint32_t ref) { return int((ref >> kLeafKindShift) & 15u); }
inline std::uint32_t leaf_group(std::uint32_t ref) { return ref & kLeafGroupMask; }
inline std::uint32_t make_leaf_ref(int kind, std::uint32_t group) { return kLeafBit | (std::uint32_t(kind) << kLeafKindShift) | group; }

struct alignas(32) WNode {
  float b[6][8];  // [2 axis + 0] lo, [2 axis + 1] hi, per child
  std::uint32_t child[8];
};
static_assert(sizeof(WNode) == 224);

struct BuildOptions {
  int max_leaf = 8;        // primitives per leaf (one 8-lane group)
  int bins = 32;           // SAH bins per axis at most: a node of n primitives bins with min(bins, 8 + n / 16)
  // SAH: cost of a node visit and of one leaf kernel call over a block of `leaf_block` primitives
  // (primitives in lanes: a leaf of 1..8 costs one call).
  float traversal_cost = 1.0f, intersection_cost = 1.0f;
  int leaf_block = 8;
  int max_depth = 48;      // below this depth SAH may split unevenly; deeper nodes split at the median
                           // (clamped to kMaxSahDepth, so that every tree fits the traversal's bound)
  bool parallel = true;    // TBB tasks for subtrees, parallel binning at large nodes
  bool stats = true;       // fill Bvh2::stats (tree_stats) before returning; false: the caller does
  // Refuse (std::length_error, before allocating) a build whose estimated peak memory,
  // kBuildBytesPerPrim per primitive, exceeds this; 0: no limit.
  std::size_t max_bytes = std::size_t(16) << 30;
};
// The deepest tree the traversal serves. Above depth max_depth (at most kMaxSahDepth) the builder
// splits at the object median (after at most 8 splits that part a range's kinds), so a binary tree
// over n < 2^32 primitives is at most kMaxSahDepth + 8 + 32 levels deep whatever the geometry
// (shrinking primitives, nested boxes, coincident centroids); the wide tree is no deeper than the
// binary one. collapse8 refuses
// (std::length_error, naming both depths) a tree deeper than kMaxTreeDepth, built by other means.
inline constexpr int kMaxSahDepth = 64;
inline constexpr int kMaxTreeDepth = kMaxSahDepth + 8 + 32;

// Peak bytes per primitive of Accel::build (builder arrays, 2 binary nodes, batch slot, id,
// wide nodes), an upper estimate checked against BuildOptions::max_bytes.
inline constexpr std::size_t kBuildBytesPerPrim = 192;

struct BuildStats {
  double build_ms = 0;
  std::size_t nodes = 0, leaves = 0, prims = 0;
  int depth = 0;
  double sah_cost = 0;
  std::vector<std::size_t> leaf_hist;  // leaf_hist[n]: leaves with n primitives
};

// The builder's output: binary nodes (root 0) and the primitive order (leaves index contiguous
// ranges of it). Primitives with an empty or non-finite box are left out (they never hit).
struct Bvh2 {
  // Sized to the bound of 2 n - 1 nodes before the build and shrunk after it, without writing
  // the nodes in between: only the pages of the nodes the build makes are touched.
  std::vector<BNode, DefaultInitAllocator<BNode>> nodes;
  std::vector<std::uint32_t> order;  // input primitive index per position
  BuildStats stats;
};

// Binned SAH over the boxes of n primitives; kind: per primitive (leaves hold one kind only: a
// small mixed range is split by kind). The boxes come from `boxes(b, e, lo, hi)`, which writes
// primitive i's box (b <= i < e) to lo[3 (i - b) + axis] and hi[3 (i - b) + axis]; it is called
// once for each primitive, on ranges of at most kBoxChunk, from several threads at once.
inline constexpr std::size_t kBoxChunk = 256;
using BoxFill = std::function<void(std::size_t b, std::size_t e, float* lo, float* hi)>;
Bvh2 build_sah(std::size_t n, const BoxFill& boxes, const std::vector<std::uint8_t>& kind, const BuildOptions& opt = {});
// The same over boxes given as arrays, 3 floats per primitive.
Bvh2 build_sah(std::span<const float> lo, std::span<const float> hi, const std::vector<std::uint8_t>& kind,
               const BuildOptions& opt = {});

// Surface-area cost and depth of a finished tree (fills stats.sah_cost, depth, leaves, hist).
void tree_stats(Bvh2& b, const BuildOptions& opt);

// The 8-wide tree from the binary one: each wide node opens its largest internal children until
// it has 8. `leaf_ref(node)` gives the reference of a binary leaf.
struct Bvh8 {
  big_vector<WNode> nodes;  // root 0 (when the tree is not empty); from 2 MiB on huge pages (core/memory.hpp)
  std::uint32_t root = kEmpty;  // a leaf reference when the whole tree is one leaf
  double collapse_ms = 0;
  int depth = 0;  // wide nodes on the longest root-to-leaf path
  // Conservative boxes (make_conservative): the bound on |ray origin| (max norm, in the tree's
  // coordinates) up to which the fast slab test cannot cull a box that the exact ray meets; 0
  // when the boxes are as built.
  float origin_bound = 0;
  // Entries the traversal stack can hold at most: a node visit pushes at most 7 of its 8
  // children, once per level (depth <= kMaxTreeDepth: at most 729).
  std::size_t stack_entries() const { return std::size_t(7) * std::size_t(depth) + 1; }
};
// Throws std::length_error when the tree is deeper than kMaxTreeDepth.
Bvh8 collapse8(const Bvh2& b);

// Widens every child box of the wide tree outward so that the fast slab test of bvh/slab.hpp
// (t = box * (1/d) - o * (1/d), one FMA) is conservative for every ray whose origin has
// max(|o.x|, |o.y|, |o.z|) <= origin_bound: it never culls a box the exact ray meets. Each
// coordinate c moves out by 4 u (|c| + origin_bound) (u = 2^-24), rounded up (derivation in
// docs/DESIGN.md section 12). Rays from farther away use the robust test (the traversal decides
// per ray). Sets t.origin_bound.
void make_conservative(Bvh8& t, float origin_bound);

// ---- what the traversal returns and counts -------------------------------------------------------
// A traced ray's hit: t (+inf when none) and the primitive as kind << kKindShift | index within its
// kind (kNoPrim): the primitive's own kind (3 bits), whichever batch it was traced in; and what the
// kernel knew of the hit beyond t that its surface would otherwise have to intersect again to learn:
// a CSG solid's leaf tag (+-(leaf + 1), negative on a subtracted surface; kernels/csg_ray.hpp). aux is
// 0 for the other kinds, and read only for the kinds that write it (a walk may keep a CSG hit's tag
// after a nearer hit of another kind replaced it).
struct HitRec {
  float t;
  std::uint32_t prim;
  float aux = 0;
};
// The closest hit so far of one ray, as a walk and its leaves keep it (bvh/hit.hpp): t and the
// primitive, 8 bytes that stay in registers through a single ray's walk; a leaf source whose hits
// carry an aux datum keeps it in its ray cache (bvh/hit.hpp, carries_aux).
struct Closest {
  float t;
  std::uint32_t prim;
};
inline constexpr std::uint32_t kNoPrim = 0xFFFFFFFFu;
inline constexpr int kKindShift = 28;
inline constexpr std::uint32_t kIndexMask = (1u << kKindShift) - 1;
inline std::uint32_t prim_code(int kind, std::uint32_t index) { return std::uint32_t(kind) << kKindShift | index; }
inline int prim_kind(std::uint32_t code) { return int(code >> kKindShift); }
inline std::uint32_t prim_index(std::uint32_t code) { return code & kIndexMask; }

// Traversal cost, summed over rays: nodes visited, box tests, primitive tests (real slots), and the
// primitive tests split by leaf tag (the builder's kind).
struct TraceCounters {
  std::uint64_t nodes = 0, boxes = 0, prims = 0;
  std::uint64_t kind_prims[kMaxKinds] = {};
  void add(const TraceCounters& o) {
    nodes += o.nodes; boxes += o.boxes; prims += o.prims;
    for (int k = 0; k < kMaxKinds; ++k) kind_prims[k] += o.kind_prims[k];
  }
};

}  // namespace rb::bvh
