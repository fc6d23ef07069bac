// The compiled CSG queries (each instantiation once): scalar float, 8-ray packets; normals and
// point membership.
#include "scene/csg_scene.hpp"

#include <cmath>

namespace rb {

const char* csg_leaf_name(CsgLeafKind k) {
  switch (k) {
    case CsgLeafKind::sphere: return "sphere";
    case CsgLeafKind::box: return "box";
    case CsgLeafKind::polyhedron: return "polyhedron";
    case CsgLeafKind::cylinder: return "cylinder";
    case CsgLeafKind::cone: return "cone";
    case CsgLeafKind::torus: return "torus";
    case CsgLeafKind::quadric: return "quadric";
  }
  return "?";
}
const char* csg_op_name(CsgOp o) {
  switch (o) {
    case CsgOp::leaf: return "leaf";
    case CsgOp::unite: return "union";
    case CsgOp::intersect: return "intersection";
    case CsgOp::subtract: return "difference";
  }
  return "?";
}

Hit<float> csg_hit(const CsgTree& T, const Ray<float>& r, float& tag) { return csg_closest(T, r, tag); }
Hit<f8> csg_hit8(const CsgTree& T, const Ray<f8>& r, f8& tag) { return csg_closest(T, r, tag); }
void csg_list(const CsgTree& T, const Ray<float>& r, Spans<float>& out) { csg_spans(T, r, out); }

namespace {
Vec3f local_point(const CsgLeaf& L, Vec3f p) {
  if (!L.placed) return p;
  const auto& a = L.inv;
  return {a.m00 * p.x + a.m01 * p.y + a.m02 * p.z + a.m03, a.m10 * p.x + a.m11 * p.y + a.m12 * p.z + a.m13,
          a.m20 * p.x + a.m21 * p.y + a.m22 * p.z + a.m23};
}
Vec3d local_point(const CsgLeaf& L, Vec3d p) {
  if (!L.placed) return p;
  const auto& f = L.inv;
  const double a[12] = {f.m00, f.m01, f.m02, f.m03, f.m10, f.m11, f.m12, f.m13, f.m20, f.m21, f.m22, f.m23};
  return {a[0] * p.x + a[1] * p.y + a[2] * p.z + a[3], a[4] * p.x + a[5] * p.y + a[6] * p.z + a[7],
          a[8] * p.x + a[9] * p.y + a[10] * p.z + a[11]};
}
}  // namespace

Vec3f csg_normal(const CsgTree& T, float tag, Vec3f p) {
  const long k = std::lround(std::fabs(tag)) - 1;
  if (k < 0 || std::size_t(k) >= T.leaves.size()) return {0, 0, 0};
  const CsgLeaf& L = T.leaves[std::size_t(k)];
  const Vec3f q = local_point(L, p);
  Vec3f n{0, 0, 0};
  switch (L.kind) {
    case CsgLeafKind::sphere: n = sphere_normal(L.sphere, q); break;
    case CsgLeafKind::box: n = box_normal(L.box, q); break;
    case CsgLeafKind::polyhedron: n = polyhedron_normal(L.poly, q); break;
    case CsgLeafKind::cylinder: n = capped_cylinder_normal(L.cyl, q); break;
    case CsgLeafKind::cone: n = capped_cone_normal(L.cone, q); break;
    case CsgLeafKind::torus: n = torus_normal(L.torus, q); break;
    case CsgLeafKind::quadric: n = quadric_normal(L.quad, q); break;
  }
  n = L.placed ? transform_normal(L.inv, n) : normalize(n);
  return tag < 0 ? -n : n;
}

bool csg_leaf_contains(const CsgLeaf& L, Vec3d p) {
  const Vec3d q = local_point(L, p);
  switch (L.kind) {
    case CsgLeafKind::sphere: {
      const Vec3d d = q - to_double(L.sphere.c);
      return dot(d, d) <= double(L.sphere.r2);
    }
    case CsgLeafKind::box: {
      const Vec3d lo = to_double(L.box.lo), hi = to_double(L.box.hi);
      return q.x >= lo.x && q.x <= hi.x && q.y >= lo.y && q.y <= hi.y && q.z >= lo.z && q.z <= hi.z;
    }
    case CsgLeafKind::polyhedron:
      for (int i = 0; i < kCsgPlanes; ++i)
        if (dot(to_double(L.poly.n[i]), q) + double(L.poly.D[i]) > 0) return false;
      return true;
    case CsgLeafKind::cylinder: {
      const double x = q.x - double(L.cyl.cx), y = q.y - double(L.cyl.cy);
      return x * x + y * y <= double(L.cyl.r2) && q.z >= double(L.cyl.z0) && q.z <= double(L.cyl.z1);
    }
    case CsgLeafKind::cone: {
      const Vec3d l = q - to_double(L.cone.apex);
      return l.x * l.x + l.y * l.y <= l.z * l.z && l.z >= double(L.cone.z0) && l.z <= double(L.cone.z1);
    }
    case CsgLeafKind::torus: {
      const Torus<float>& T = L.torus;
      const Vec3d d = q - to_double(T.c);
      const double R2 = double(T.R) * double(T.R), r2 = double(T.r) * double(T.r);
      const double G = dot(d, d) - R2 - r2, z = dot(d, to_double(T.w));
      return G * G - 4 * R2 * (r2 - z * z) <= 0;
    }
    case CsgLeafKind::quadric: {
      const Quadric<float>& c = L.quad;
      const QuadricCoeffs k{double(c.a), double(c.b), double(c.c), double(c.d), double(c.e),
                           double(c.f), double(c.g), double(c.h), double(c.j), double(c.k)};
      return k.value(q) <= 0;
    }
  }
  return false;
}

namespace {
bool contains_node(const CsgTree& T, std::uint32_t i, Vec3d p) {
  const CsgNode& n = T.nodes[i];
  switch (n.op) {
    case CsgOp::leaf: return csg_leaf_contains(T.leaves[n.a], p);
    case CsgOp::unite: return contains_node(T, n.a, p) || contains_node(T, n.b, p);
    case CsgOp::intersect: return contains_node(T, n.a, p) && contains_node(T, n.b, p);
    case CsgOp::subtract: return contains_node(T, n.a, p) && !contains_node(T, n.b, p);
  }
  return false;
}
}  // namespace

bool csg_contains(const CsgTree& T, Vec3d p) { return !T.nodes.empty() && contains_node(T, T.root, p); }

namespace scene {
namespace {
// The leaf a closest-hit query's tag names (its index + 1, negated on a subtracted surface), or -1.
long leaf_of(const CsgTree& tree, float tag) {
  const long k = std::lround(std::fabs(tag)) - 1;
  return k < 0 || std::size_t(k) >= tree.leaves.size() ? -1 : k;
}
}  // namespace

CsgSurface csg_surface(const CsgTree& tree, float tag, Vec3f p) {
  CsgSurface s;
  const long k = leaf_of(tree, tag);
  if (k < 0) return s;
  s.hit = true;
  s.normal = csg_normal(tree, tag, p);
  s.material = tree.leaves[std::size_t(k)].material;
  return s;
}

std::uint32_t csg_material(const CsgTree& tree, float tag) {
  const long k = leaf_of(tree, tag);
  return k < 0 ? 0 : tree.leaves[std::size_t(k)].material;
}

CsgSurface csg_surface(const CsgTree& tree, const Ray<float>& r) {
  float tag = 0;
  const Hit<float> h = csg_closest(tree, r, tag);
  if (!h.mask) return {};
  CsgSurface s = csg_surface(tree, tag, r.at(h.t));
  s.t = h.t;
  return s;
}
}  // namespace scene

}  // namespace rb
