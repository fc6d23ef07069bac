// CSG trees (seed 000 "CSG representation", "Implementation", "Set operations on the ray").
//
// Leaves are closed solids, each giving its entry/exit list along the whole line: sphere, box,
// convex polyhedron (up to kCsgPlanes halfspaces), capped cylinder, capped single-nappe cone,
// torus, and a bounded quadric (ellipsoid). Inner nodes are union, intersection and difference
// (left minus right), merged in 1D ray space (core/intervals.hpp). Every node may carry an affine
// transform; the builder (scene/csg_scene.hpp) composes the transforms on the path from the root into
// each leaf's own matrix, so a transformed leaf costs one ray transformation (the slide's
// 15+- 18*) and an untransformed one none, and t is the world distance everywhere (affine maps keep
// the line parameter: kernels/transform.hpp). Normals come back by (M^-1)^T.
//
// Each boundary carries its surface tag (core/intervals.hpp): the leaf, and a flip for a
// subtracted surface, so the normal of a hit is its leaf's outward normal, negated when flipped:
// it points out of the result.
//
// Early exits, all explicit:
//   - every node has a world box; a ray segment missing it gives the node an empty list without
//     evaluating the subtree (full lists test the whole line);
//   - intersection and difference skip their right subtree when the left list is empty;
//     intersection gives empty and difference gives the left list when the right one is empty;
//   - the closest-hit query (scalar) stops the root's merge at the first boundary at or after tmin.
// Scalar lists merge with merge_linear; packets (F = f8: 8 rays in lanes) with merge_lanes.
#pragma once

#include "core/intervals.hpp"
#include "kernels/box.hpp"
#include "kernels/cylinder_cone.hpp"
#include "kernels/polyhedron.hpp"
#include "kernels/quadric.hpp"
#include "kernels/sphere.hpp"
#include "kernels/torus.hpp"
#include "kernels/transform.hpp"

#include <cstdint>
#include <limits>
#include <vector>

namespace rb {

inline constexpr int kCsgPlanes = 12;  // halfspaces per convex polyhedron leaf
inline constexpr int kCsgMaxDepth = 24;

enum class CsgLeafKind : std::uint8_t { sphere, box, polyhedron, cylinder, cone, torus, quadric };
enum class CsgOp : std::uint8_t { leaf, unite, intersect, subtract };
const char* csg_leaf_name(CsgLeafKind k);
const char* csg_op_name(CsgOp o);

struct CsgLeaf {
  CsgLeafKind kind = CsgLeafKind::sphere;
  bool placed = false;        // inv is used (else the primitive is in world coordinates)
  Affine34<float> inv{};      // world -> local
  Sphere<float> sphere = Sphere<float>::never();
  Box<float> box = Box<float>::never();
  HalfspacesK<float, kCsgPlanes> poly = HalfspacesK<float, kCsgPlanes>::never();
  Cylinder<float> cyl = Cylinder<float>::never();
  Cone<float> cone = Cone<float>::never();
  Torus<float> torus = Torus<float>::never();
  Quadric<float> quad = Quadric<float>::never();
  std::uint32_t material = 0;  // index into the scene's materials
  int slots() const { return kind == CsgLeafKind::torus ? 4 : 2; }
};

struct CsgNode {
  CsgOp op = CsgOp::leaf;
  std::uint32_t a = 0, b = 0;  // leaf: a = leaf index; else the children (a op b)
  float lo[3] = {0, 0, 0}, hi[3] = {-1, -1, -1};  // world box; lo > hi: empty (never hit)
};

struct CsgTree {
  std::vector<CsgNode> nodes;
  std::vector<CsgLeaf> leaves;
  std::uint32_t root = 0;
  int depth = 0;  // levels of nodes from the root to the deepest leaf
  bool empty() const { return nodes.empty() || !(nodes[root].lo[0] <= nodes[root].hi[0]); }
  std::size_t bytes() const { return nodes.size() * sizeof(CsgNode) + leaves.size() * sizeof(CsgLeaf); }
};

namespace detail {
template <class F>
RB_INLINE Affine34<F> affine_cast(const Affine34<float>& a) {
  return {F(a.m00), F(a.m01), F(a.m02), F(a.m03), F(a.m10), F(a.m11), F(a.m12), F(a.m13), F(a.m20), F(a.m21), F(a.m22), F(a.m23)};
}

// The node's box against the ray's segment [t0, t1] by slabs; conservative: a NaN slab (0 * inf)
// keeps the lane. 6+- 6* 12 min/max 1 cmp.
template <class F>
RB_INLINE mask_t<F> csg_box_test(const CsgNode& n, const Ray<F>& r, const F& t0, const F& t1) {
  const F x0 = (F(n.lo[0]) - r.o.x) * r.rd.x, x1 = (F(n.hi[0]) - r.o.x) * r.rd.x;
  const F y0 = (F(n.lo[1]) - r.o.y) * r.rd.y, y1 = (F(n.hi[1]) - r.o.y) * r.rd.y;
  const F z0 = (F(n.lo[2]) - r.o.z) * r.rd.z, z1 = (F(n.hi[2]) - r.o.z) * r.rd.z;
  const F tn = vmax(vmax(vmin(x0, x1), vmin(y0, y1)), vmax(vmin(z0, z1), t0));
  const F tf = vmin(vmin(vmax(x0, x1), vmax(y0, y1)), vmin(vmax(z0, z1), t1));
  return mask_not<F>(tn > tf);
}
}  // namespace detail

// A leaf's entry/exit list along the whole line, tagged +(leaf + 1).
template <class F>
RB_INLINE void csg_leaf_spans(const CsgLeaf& L, std::uint32_t leaf, const Ray<F>& world, Spans<F>& out) {
  Ray<F> r = world;
  if (L.placed) {
    const Affine34<F> a = detail::affine_cast<F>(L.inv);
    r = L.kind == CsgLeafKind::box ? transform_ray<true>(world, a) : transform_ray<false>(world, a);
  }
  const scalar_t<F> tag = scalar_t<F>(leaf + 1);
  switch (L.kind) {
    case CsgLeafKind::sphere: out.assign(sphere_roots(r, prim_cast<F>(L.sphere)), tag); return;
    case CsgLeafKind::box: out.assign(box_roots(r, prim_cast<F>(L.box)), tag); return;
    case CsgLeafKind::polyhedron: out.assign(polyhedron_roots(r, prim_cast<F>(L.poly)), tag); return;
    case CsgLeafKind::cylinder: out.assign(cylinder_roots(r, prim_cast<F>(L.cyl)), tag); return;
    case CsgLeafKind::cone: out.assign(cone_roots(r, prim_cast<F>(L.cone)), tag); return;
    case CsgLeafKind::torus: {
      // The torus solver reports roots within [tmin, tmax]: give it the whole (float) line.
      const F big = F(std::numeric_limits<scalar_t<F>>::max());
      r.tmin = -big;
      r.tmax = big;
      out.assign(torus_roots_robust(r, prim_cast<F>(L.torus)), tag);
      return;
    }
    case CsgLeafKind::quadric: out.assign(quadric_solid_roots(r, prim_cast<F>(L.quad)), tag); return;
  }
  out.n = 0;
}

// The list of node `node` on the ray, exact on the segment [t0, t1] (subtrees whose box misses
// the segment are left out).
template <class F>
void csg_eval(const CsgTree& T, std::uint32_t node, const Ray<F>& r, const F& t0, const F& t1, Spans<F>& out) {
  const CsgNode& n = T.nodes[node];
  if (none_of<F>(detail::csg_box_test(n, r, t0, t1))) {
    out.n = 0;
    return;
  }
  if (n.op == CsgOp::leaf) {
    csg_leaf_spans(T.leaves[n.a], n.a, r, out);
    return;
  }
  Spans<F> a, b;
  csg_eval(T, n.a, r, t0, t1, a);
  if (a.n == 0 && n.op != CsgOp::unite) {
    out.n = 0;
    return;
  }
  csg_eval(T, n.b, r, t0, t1, b);
  if (b.n == 0) {
    if (n.op == CsgOp::intersect) out.n = 0;
    else out.copy_from(a);
    return;
  }
  if (a.n == 0) {
    out.copy_from(b);
    return;
  }
  const SetOp op = n.op == CsgOp::unite ? SetOp::kUnion : (n.op == CsgOp::intersect ? SetOp::kIntersection : SetOp::kDifference);
  if constexpr (lanes_v<F> == 1) merge_linear(op, a, b, out);
  else merge_lanes(op, a, b, out);
}

// The whole list (every boundary along the line).
template <class F>
RB_INLINE void csg_spans(const CsgTree& T, const Ray<F>& r, Spans<F>& out) {
  if (T.nodes.empty()) {
    out.n = 0;
    return;
  }
  const F big = F(kInf<F>);
  csg_eval(T, T.root, r, -big, big, out);
}

// Closest hit in [tmin, tmax]: the first boundary of the result there (an exit when the origin
// is inside), with its surface tag (0 on a miss).
template <class F>
Hit<F> csg_closest(const CsgTree& T, const Ray<F>& r, F& tag) {
  tag = F(0);
  if (T.nodes.empty()) return miss_hit<F>();
  const CsgNode& n = T.nodes[T.root];
  if (none_of<F>(detail::csg_box_test(n, r, r.tmin, r.tmax))) return miss_hit<F>();
  Spans<F> out;
  if constexpr (lanes_v<F> == 1) {
    if (n.op != CsgOp::leaf) {
      // The root's merge stops at the first result boundary at or after tmin.
      Spans<F> a, b;
      csg_eval(T, n.a, r, r.tmin, r.tmax, a);
      if (a.n == 0 && n.op != CsgOp::unite) return miss_hit<F>();
      csg_eval(T, n.b, r, r.tmin, r.tmax, b);
      const SetOp op = n.op == CsgOp::unite ? SetOp::kUnion : (n.op == CsgOp::intersect ? SetOp::kIntersection : SetOp::kDifference);
      const int k = merge_linear(op, a, b, out, true, r.tmin);
      if (k < 0) return miss_hit<F>();
      const mask_t<F> m = out.t[k] <= r.tmax;
      tag = vselect(m, out.tag[k], F(0));
      return make_hit<F>(m, out.t[k]);
    }
  }
  csg_eval(T, T.root, r, r.tmin, r.tmax, out);
  return first_span_hit(r, out, tag);
}

// Outward unit normal of the result at world point p on the surface with tag `tag` (scalar).
Vec3f csg_normal(const CsgTree& T, float tag, Vec3f p);
// Whether world point p is inside leaf `leaf` (closed solid; for tests and point sampling) and
// inside the whole tree (the boolean of the leaves' insideness).
bool csg_leaf_contains(const CsgLeaf& L, Vec3d p);
bool csg_contains(const CsgTree& T, Vec3d p);

// Compiled once (scene/csg_eval.cpp): the float scalar query and the 8-ray packet query.
Hit<float> csg_hit(const CsgTree& T, const Ray<float>& r, float& tag);
Hit<f8> csg_hit8(const CsgTree& T, const Ray<f8>& r, f8& tag);
void csg_list(const CsgTree& T, const Ray<float>& r, Spans<float>& out);

}  // namespace rb
