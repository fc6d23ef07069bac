// CSG solids (Scene::csgs: JSON trees of union, intersection and difference over closed leaves,
// kernels/csg_ray.hpp): each slot is one tree, queried one ray at a time (the scalar closest-hit query
// with its early exits) or 8 rays at a time (packets). The batch holds each tree as built in the
// tracer's frame (CsgIn::in_frame: the placement composed in double relative to the origin).
#pragma once

#include "bvh/hit.hpp"
#include "kernels/csg_ray.hpp"
#include "scene/csg_scene.hpp"

#include <map>
#include <memory>
#include <vector>

namespace rb::kinds {

struct CsgKind {
  static constexpr Kind id = Kind::csg;
  static constexpr const char* name = "csg";
  static constexpr bool custom = true;

  static std::size_t count(const Scene& s) { return s.csgs.size(); }
  template <class Fn>
  static void each(const Scene& s, Fn&& f) {
    for (std::size_t i = 0; i < s.csgs.size(); ++i) f(std::uint32_t(i));
  }
  static std::uint32_t material(const Scene& s, std::uint32_t i) { return s.csgs[i].mat; }
  static Bounds bounds(const Scene& s, std::uint32_t i) {
    Bounds b;
    const CsgTree& t = *s.csgs[i].tree;
    if (t.empty()) return b;
    const CsgNode& n = t.nodes[t.root];
    b.grow(Vec3d{n.lo[0], n.lo[1], n.lo[2]});
    b.grow(Vec3d{n.hi[0], n.hi[1], n.hi[2]});
    return b;
  }
  static Feature feature(const Scene& s, std::uint32_t i) {
    const Bounds b = bounds(s, i);
    if (b.empty()) return {};
    const Vec3d e = b.extent();
    return {b.centre(), std::min({e.x, e.y, e.z}), std::max({e.x, e.y, e.z})};
  }

  template <class F>
  struct Pre {};
  template <class F>
  static Pre<F> pre(const Ray<F>&) { return {}; }
  static constexpr std::array<MethodInfo, 1> methods{
      {{"intervals", "each leaf's entry/exit list along the ray, merged in 1D ray space (seed 000)", false, false}}};
  // The lab's evidence (PlanOption in tracer/kinds.hpp): one method.
  static constexpr std::array<PlanOption, 1> plan{{{0, false, kAny, kAny, kAny, "", "the CSG tree's only method (float leaves)"}}};

  struct Batch {
    std::vector<std::shared_ptr<const CsgTree>> trees;  // by scene index, in the frame
    SlotIds id;                                         // per leaf slot: the scene index (UINT32_MAX: padding)
    std::size_t bytes() const {
      std::size_t n = id.size() * sizeof(std::uint32_t);
      for (const auto& t : trees) n += t ? t->bytes() + sizeof(void*) : 0;
      return n;
    }
  };
  static void build(Batch& b, const Scene& s, SlotIds ids, const Vec3d& origin, int /*method*/, bool /*f64*/,
                    bool /*f64_storage*/) {
    b.id = std::move(ids);
    b.trees.clear();
    const bool moved = !(origin.x == 0 && origin.y == 0 && origin.z == 0);
    for (const auto& c : s.csgs) b.trees.push_back(moved && c.in_frame ? c.in_frame(origin) : c.tree);
  }
  static bool single(const Batch& b, std::size_t base, const Ray<float>& r, bvh::Closest& h, float& aux) {
    bool any = false;
    Ray<float> rr = r;
    rr.tmax = h.t;
    for (std::size_t j = base; j < base + 8 && j < b.id.size(); ++j) {
      const std::uint32_t sid = b.id[j];
      if (sid == UINT32_MAX) continue;
      float tag;
      const Hit<float> hc = csg_hit(*b.trees[sid], rr, tag);
      if (hc.mask && bvh::nearer(hc.t, code(id, sid), h)) {
        rr.tmax = hc.t;
        h = {hc.t, code(id, sid)};
        aux = tag;
        any = true;
      }
    }
    return any;
  }
  // Each group of the packet against the leaf's trees in slot order (the groups are independent:
  // the order of the two loops changes no hit), the group's rays copied once.
  template <bool Any>
  static void packet(const Batch& b, std::size_t base, bvh::PacketRays& p) {
    for (int q = 0; q < p.n; ++q) {
      const int k = p.list[q];
      Ray<f8> rr = p.r[k];
      for (std::size_t j = base; j < base + 8 && j < b.id.size(); ++j) {
        const std::uint32_t sid = b.id[j];
        if (sid == UINT32_MAX) continue;
        if (none_of<f8>(p.active[k])) break;
        rr.tmax = p.tbest[k];
        f8 tag;
        const Hit<f8> hit = csg_hit8(*b.trees[sid], rr, tag);
        bvh::packet_update<Any>(p, k, hit.mask, hit.t, code(id, sid), &tag);
      }
    }
  }

  static std::size_t input_bytes(const Scene& s) { return s.csgs.size() * sizeof(scene::CsgIn) + s.csg_tree_bytes(); }
  // The kernel batch: the trees themselves, and what they hold.
  static std::size_t batch_bytes(const Scene& s, std::string& what) {
    std::size_t nodes = 0, bytes = 0;
    int depth = 0;
    std::map<std::string, std::size_t> by_kind;
    for (const auto& obj : s.csgs) {
      nodes += obj.tree->nodes.size();
      bytes += obj.tree->bytes();
      depth = std::max(depth, obj.tree->depth);
      for (const auto& l : obj.tree->leaves) ++by_kind[std::string(csg_leaf_name(l.kind)) + (l.placed ? " (transformed)" : "")];
    }
    std::string mix;
    for (const auto& [k, n] : by_kind) mix += (mix.empty() ? "" : ", ") + std::to_string(n) + " " + k;
    what = "CSG trees (" + std::to_string(nodes) + " nodes, depth " + std::to_string(depth) + "; leaves: " + mix + ")";
    return bytes;
  }

  // The leaf surface hit gives the outward normal (flipped on subtracted surfaces) and the
  // material: the leaf the traversal found (the hit's tag, HitQuery::aux), or, for a hit that does
  // not carry it, the tree's own closest-hit query run again on the ray as traced.
  static Surface surface(const HitQuery& q, std::uint32_t i) {
    const CsgTree& tree = hit_tree(q, i);
    const auto c = q.aux != 0 ? scene::csg_surface(tree, q.aux, q.ray.at(q.t)) : scene::csg_surface(tree, q.ray);
    Surface h;
    h.p = q.p;
    h.ng = h.ns = c.hit ? detail::unit_or(to_double(c.normal), -q.ray.d) : -q.ray.d;
    h.mat = c.material;
    return h;
  }
  // surface(q, i).mat alone: a tree's material is its leaves' (the kinds of one material per
  // primitive give theirs by material()).
  static std::uint32_t hit_material(const HitQuery& q, std::uint32_t i) {
    const CsgTree& tree = hit_tree(q, i);
    return q.aux != 0 ? scene::csg_material(tree, q.aux) : scene::csg_surface(tree, q.ray).material;
  }

 private:
  static const CsgTree& hit_tree(const HitQuery& q, std::uint32_t i) {
    const auto* b = static_cast<const Batch*>(q.batch);
    return b && i < b->trees.size() ? *b->trees[i] : *q.scene->csgs.at(i).tree;
  }
};

}  // namespace rb::kinds
