// A scene ready to trace: one SAH build over every primitive the scene holds, the binary and the
// 8-wide layouts of that build, and each kind's SoA batch reordered into BVH leaf order (every
// leaf is one 8-slot lane group of its kind's batch, padded with never-hit slots), so a leaf is
// tested by one kernel call with the primitives in lanes and no index indirection (polygons,
// whose batch groups slots by dropped axis, go through one slot index per leaf lane).
//
// Traversal (bvh/trace.cpp): closest hit or any hit; single rays (SIMD over the wide node's 8
// child boxes and over the leaf's 8 primitives) or SoA packets of 8 rays (rays in lanes, an
// active mask, the packet against each child box and each leaf primitive); the fast slab test
// (one FMA per plane from the per-ray o * (1/d)) or the robust one (Ize 2013: the far distance
// scaled by 1 + 2 gamma(3)), by a template switch.
#pragma once

#include "bvh/bvh.hpp"
#include "kernels/csg.hpp"
#include "scene/batches.hpp"
#include "soa/rays.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rb::bvh {

// A hit: t (+inf when none) and the primitive as kind << kKindShift | scene index (kNoPrim).
struct HitRec {
  float t;
  std::uint32_t prim;
};
inline constexpr std::uint32_t kNoPrim = 0xFFFFFFFFu;
inline std::uint32_t prim_code(scene::Kind k, std::uint32_t index) { return std::uint32_t(k) << kKindShift | index; }

enum class Layout { binary, wide };
struct TraceOptions {
  Layout layout = Layout::wide;
  int packet = 1;       // 1: single rays; 8: packets of 8 rays; 16: packets of 16 (two 8-lane halves)
  bool robust = false;  // Ize's conservative slab test
  bool any = false;     // any hit (shadow rays): stop at the first hit
};
// Traversal cost, summed over rays: nodes visited, box tests, primitive tests (real slots), and
// the primitive tests split by kind (scene::Kind).
struct TraceCounters {
  std::uint64_t nodes = 0, boxes = 0, prims = 0;
  std::uint64_t kind_prims[scene::kKinds] = {};
  void add(const TraceCounters& o) {
    nodes += o.nodes; boxes += o.boxes; prims += o.prims;
    for (int k = 0; k < scene::kKinds; ++k) kind_prims[k] += o.kind_prims[k];
  }
};

struct Accel {
  Bvh2 bin;
  Bvh8 wide;
  BuildOptions options;
  double build_ms = 0;      // builder + reorder + collapse
  double reorder_ms = 0;
  std::size_t scene_prims = 0;

  // Batches in leaf order; ids (scene index per slot, UINT32_MAX padding) beside them.
  PrimSoA<TriVerts> tri;
  PrimSoA<Sphere> sph;
  PrimSoA<Transformed<Cylinder>::T> cyl;
  PrimSoA<Transformed<Cone>::T> cone;
  std::vector<std::uint32_t> id[scene::kKinds];
  PolygonSoA poly;                       // grouped by its own rule
  std::vector<std::uint32_t> poly_slot;  // per leaf lane: slot in `poly` (UINT32_MAX: padding)
  std::vector<const CsgTree*> csg;       // the scene's CSG trees by scene index (id[csg] slots index it)
  std::vector<std::shared_ptr<const CsgTree>> csg_owner;  // keeps them alive with the Accel

  static Accel build(const scene::Scene& s, const BuildOptions& opt = {});

  bool empty() const { return bin.nodes.empty(); }
  std::size_t bytes_nodes_binary() const { return bin.nodes.size() * sizeof(BNode); }
  std::size_t bytes_nodes_wide() const { return wide.nodes.size() * sizeof(WNode); }
  std::size_t bytes_prims() const;  // batches + ids
  std::size_t bytes(Layout l) const { return (l == Layout::wide ? bytes_nodes_wide() : bytes_nodes_binary()) + bytes_prims(); }

  // Traces rays [begin, end) (begin a multiple of 8) into out[begin, end).
  void trace(const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, const TraceOptions& o) const;
  // The same, counting traversal cost (slower: used for the per-ray figures, not for timing).
  void trace_counted(const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, const TraceOptions& o,
                     TraceCounters& c) const;
};

// The lecture's loop over all objects (seed 002, "Intersecting a Group of Objects"): every
// primitive of every kind against every ray, 8 primitives per kernel call. The oracle.
struct BruteForce {
  PrimSoA<TriVerts> tri;
  PrimSoA<Sphere> sph;
  PrimSoA<Transformed<Cylinder>::T> cyl;
  PrimSoA<Transformed<Cone>::T> cone;
  std::vector<std::uint32_t> id[scene::kKinds];
  PolygonSoA poly;
  std::vector<const CsgTree*> csg;
  std::vector<std::shared_ptr<const CsgTree>> csg_owner;
  explicit BruteForce(const scene::Scene& s);
  HitRec trace(const Ray<float>& r, bool any) const;
};

}  // namespace rb::bvh
