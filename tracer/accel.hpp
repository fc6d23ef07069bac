// A scene ready to trace under a plan (tracer/plan.hpp): every primitive's box in the plan's frame,
// one SAH build over them (bvh/build.cpp), the 8-wide tree with conservative boxes, and each kind's
// batch in leaf order, made relative to the frame origin in the plan's precision, with the leaf
// functions of the plan's method; the primitives the plan stores apart (KindPlan::split) in a
// second batch of their kind (in local frames, or in double), in leaves of their own (tag apart_tag(kind)). Rays are traced in frame coordinates: `frame_ray` turns a world
// ray (double) into one, `surface` turns a hit back into a world surface point and normals.
//
// The scene must outlive the SceneAccel (surfaces read the scene's own arrays).
#pragma once

#include "bvh/bvh.hpp"
#include "soa/rays.hpp"
#include "tracer/mesh_leaves.hpp"
#include "tracer/plan.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rb::tracer {

struct TraceOptions {
  int packet = 1;    // 1: single rays; 8, 16, 64, 256: packets of that many rays (bvh/traverse.hpp)
  bool any = false;  // any hit (shadow rays): stop at the first hit
  // The width of a packet's groups of rays: 8 (AVX2), or 16 (AVX-512) for packets of 16 or more rays
  // of a triangle-only scene where the binary and the CPU have the 16-lane walk (otherwise 8:
  // SceneAccel::group_lanes says which ran). Counted traces walk in 8 lanes.
  int lanes = 8;
  // The plan's slab test unless set (the lab compares the three).
  bool slab_given = false;
  bvh::Slab slab = bvh::Slab::conservative;
};

// A binary-tree builder: the primitives' boxes (3 floats each, in the frame), their kinds and the
// build options in, a tree under bvh::Bvh2's contract out (children of an internal node at
// `first` and `first + 1`, leaves of at most opt.max_leaf primitives of one kind, ranges of
// `order`; stats filled by bvh::tree_stats). Empty: bvh::build_sah. Another builder (Embree's, in
// bench/embree_build.hpp) feeds the same reorder and 8-wide collapse, so that its tree is traced by
// the same traversal.
using BinaryBuilder = std::function<bvh::Bvh2(std::span<const float> lo, std::span<const float> hi,
                                              const std::vector<std::uint8_t>& kind, const bvh::BuildOptions& opt)>;

class SceneAccel {
 public:
  // Throws std::length_error before allocating when the estimated peak memory exceeds
  // opt.max_bytes.
  static SceneAccel build(const scene::Scene& s, const Plan& plan, const bvh::BuildOptions& opt = {},
                          const BinaryBuilder& builder = {});
  // The same under the auto model's plan.
  static SceneAccel build(const scene::Scene& s, const bvh::BuildOptions& opt = {}) {
    check_size(s, opt);
    return build(s, make_plan(s, Model::automatic), opt);
  }
  // Throws std::length_error when the build's estimated peak memory exceeds opt.max_bytes.
  static void check_size(const scene::Scene& s, const bvh::BuildOptions& opt);

  const scene::Scene& scene() const { return *scene_; }
  const Plan& plan() const { return plan_; }
  const Vec3d& origin() const { return plan_.origin; }
  bool empty() const { return bin.nodes.empty(); }

  // A world ray (double origin, any direction) in frame coordinates; invalid input gives the
  // invalid ray (a defined miss).
  Ray<float> frame_ray(const Vec3d& o, const Vec3d& d, double tmin = 0, double tmax = std::numeric_limits<double>::infinity()) const;
  Vec3f to_frame(const Vec3d& p) const { return to_float(p - plan_.origin); }
  Vec3d to_world(const Vec3f& p) const { return to_double(p) + plan_.origin; }
  // The world hit point of a frame ray at t, in double.
  Vec3d world_point(const Ray<float>& r, float t) const {
    return plan_.origin + to_double(r.o) + to_double(r.d) * double(t);
  }
  // The surface of the hit h (its primitive, bvh::prim_code, at h.t, with what the kernel kept in
  // h.aux) of the frame ray r; for a miss (bvh::kNoPrim) the empty Surface (zero normals).
  kinds::Surface surface(const bvh::HitRec& h, const Ray<float>& r) const;
  // surface(h, r).mat alone, without the point and normals: what a shadow ray needs to know of an
  // occluder (whether it transmits). 0 for a miss.
  std::uint32_t material(const bvh::HitRec& h, const Ray<float>& r) const;
  // Where a secondary ray leaving the surface along `dir` (unit, frame = world directions) starts,
  // by the plan's spawn scheme: the hit point in frame coordinates moved off the surface on the
  // side `dir` leaves to. `n` is the unit geometric normal.
  Vec3f spawn_point(const kinds::Surface& sf, const Vec3f& dir) const;
  // The same in two steps, for a hit that spawns several rays (shadow rays to every light, a
  // reflection and a refraction ray): what depends on the hit alone once, then each ray's side.
  struct SpawnBase {
    Vec3f p, err;      // the hit point in frame coordinates; the error-bound scheme's bound per axis
    Vec3f ng;          // the unit geometric normal
  };
  SpawnBase spawn_base(const kinds::Surface& sf) const;
  Vec3f spawn_point(const SpawnBase& b, const Vec3f& dir) const;
  // spawn_point for 8 hits at once (the bases' p, err and ng as lanes), lane for lane the same.
  Vec3<f8> spawn_point(const Vec3<f8>& p, const Vec3<f8>& err, const Vec3<f8>& ng, const Vec3<f8>& dir) const;

  // Traces rays [begin, end) (frame coordinates; begin a multiple of 8) into out[begin, end).
  void trace(const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, const TraceOptions& o) const;
  // The lanes per group of rays a trace with these options walks in (TraceOptions::lanes): 1 for
  // single rays, else 8 or 16.
  int group_lanes(const TraceOptions& o) const;
  // The same, counting traversal cost (slower: for the per-ray figures, not for timing).
  void trace_counted(const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, const TraceOptions& o,
                     bvh::TraceCounters& c) const;
  // The lecture's loop over all objects (seed 002, "Intersecting a Group of Objects"): every
  // primitive against the ray, 8 per kernel call, with the same leaf functions: the oracle.
  HitRec brute_force(const Ray<float>& r, bool any) const;

  std::size_t scene_prims() const { return scene_prims_; }
  std::size_t bytes_nodes() const { return wide.nodes.size() * sizeof(bvh::WNode); }
  std::size_t bytes_prims() const;  // batches + ids
  std::size_t bytes() const { return bytes_nodes() + bytes_prims(); }
  std::size_t kind_bytes(Kind k) const;   // both of the kind's batches
  std::size_t apart_bytes(Kind k) const;  // its primitives stored apart
  // Of those, the ones in double (all of them unless the plan put them in local frames: then those
  // of leaves that no origin of their own holds in float), and the largest coordinate a local frame
  // holds.
  std::size_t apart_deep(Kind k) const;
  double apart_reach(Kind k) const;
  // The scene index in slot `slot` of the leaf-ordered batch of leaf tag `tag` (a kind, or
  // apart_tag(kind)); UINT32_MAX: padding or beyond.
  std::uint32_t slot_id(int tag, std::size_t slot) const;
  // Whether primitive `index` of kind k is stored apart, in double.
  bool stored_apart(Kind k, std::uint32_t index) const;
  // The leaf source of a triangle-only scene traced with Woop in float (tracer/mesh_leaves.hpp), for
  // a walk of the caller's choice over `wide`; null for every other scene.
  const MeshLeaves* mesh_leaves() const { return mesh_only_ ? &mesh_ : nullptr; }

  bvh::Bvh2 bin;
  bvh::Bvh8 wide;
  bvh::BuildOptions options;
  double build_ms = 0;    // boxes + builder + reorder + collapse
  double reorder_ms = 0;

 private:
  const scene::Scene* scene_ = nullptr;
  Plan plan_;
  std::size_t scene_prims_ = 0;
  Batches batches_;
  Batches apart_;  // the primitives stored apart (standard kinds only; the rest empty)
  std::array<LeafFns, kLeafKinds> fns_{};
  TableLeaves table_;
  MeshLeaves mesh_;
  bool mesh_only_ = false;  // one kind, triangles, Woop in float (any apart in double): MeshLeaves

  template <bool Count>
  void dispatch(const RaySoA& rays, std::size_t begin, std::size_t end, HitRec* out, const TraceOptions& o,
                bvh::TraceCounters& c) const;
  void wire();  // points the leaf sources at the batches (after build and after a move)

 public:
  SceneAccel() = default;
  SceneAccel(SceneAccel&& o) noexcept;
  SceneAccel& operator=(SceneAccel&& o) noexcept;
  SceneAccel(const SceneAccel&) = delete;
  SceneAccel& operator=(const SceneAccel&) = delete;
};

}  // namespace rb::tracer
