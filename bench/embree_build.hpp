// A diagnostic builder: Embree's own BVH builder (rtcBuildBVH) producing raybench's binary tree, so
// that the tree Embree would build is traced by raybench's traversal and leaves. Embree gets the
// same primitive boxes, leaf size (at most opt.max_leaf), SAH block (opt.leaf_block) and SAH costs
// (opt.traversal_cost, opt.intersection_cost) as bvh::build_sah, builds a binary tree through its
// callbacks, and the tree is written as bvh::Bvh2 (children side by side, leaves as ranges of
// `order`), which tracer::SceneAccel::build reorders and collapses to 8-wide nodes exactly as it
// does its own. Comparing the two trees under one traversal separates the tree's share of a speed
// gap from the kernel's.
#pragma once

#include "tracer/accel.hpp"

#include <string>

namespace rb::trace {

enum class EmbreeQuality { medium, high };  // RTC_BUILD_QUALITY_MEDIUM / _HIGH
// "sah" (raybench's), "embree" (Embree's builder at medium quality) or "embree-high" (high
// quality: with a split callback, so Embree may make spatial splits of triangles).
bool is_builder_name(const std::string& s);

// Embree's binary tree over the boxes; `threads`: the Embree device's build threads. For high
// quality, `split` (may be empty) clips primitive `prim` at `pos` on axis `dim` into the boxes of
// its two sides (each within the box it was given); without it Embree builds as at medium quality.
using SplitFn = std::function<void(std::uint32_t prim, int dim, float pos, const float lo[3], const float hi[3], float llo[3], float lhi[3],
                                   float rlo[3], float rhi[3])>;
bvh::Bvh2 embree_binary_tree(std::span<const float> lo, std::span<const float> hi, const std::vector<std::uint8_t>& kind,
                             const bvh::BuildOptions& opt, EmbreeQuality q, int threads, const SplitFn& split = {});

// The builder hook for tracer::SceneAccel::build ("embree" or "embree-high"; empty for "sah").
// Spatial splits at high quality are offered for scenes of triangles only (their clip is exact in
// the frame; other kinds are never split).
tracer::BinaryBuilder embree_builder(const std::string& name, const scene::Scene& s, const tracer::Plan& plan, int threads);

}  // namespace rb::trace
