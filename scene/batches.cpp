#include "scene/batches.hpp"
#include "kernels/csg.hpp"

#include <algorithm>
#include <cmath>

namespace rb::scene {

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::triangle: return "triangle";
    case Kind::sphere: return "sphere";
    case Kind::cylinder: return "cylinder";
    case Kind::cone: return "cone";
    case Kind::polygon: return "polygon";
    case Kind::csg: return "csg";
  }
  return "?";
}

TriVerts<float> tri_verts(const Scene& s, std::size_t i) {
  const auto& t = s.triangles[i];
  return make_tri_verts(s.verts[t.v[0]], s.verts[t.v[1]], s.verts[t.v[2]]);
}
Triangle<float> tri_mt(const Scene& s, std::size_t i) {
  const auto& t = s.triangles[i];
  return make_triangle(s.verts[t.v[0]], s.verts[t.v[1]], s.verts[t.v[2]]);
}
Sphere<float> sphere_prim(const Scene& s, std::size_t i) { return make_sphere(s.spheres[i].c, s.spheres[i].r); }
bool cone_is_cylinder(const Scene& s, std::size_t i) { return s.cones[i].base_r == s.cones[i].apex_r; }
Transformed<Cylinder>::T<float> cylinder_prim(const Scene& s, std::size_t i) {
  const auto& c = s.cones[i];
  return place_cylinder(to_double(c.base), to_double(c.apex), double(c.base_r));
}
Transformed<Cone>::T<float> cone_prim(const Scene& s, std::size_t i) {
  const auto& c = s.cones[i];
  return place_cone(to_double(c.base), double(c.base_r), to_double(c.apex), double(c.apex_r));
}
std::vector<Vec3f> polygon_vertices(const Scene& s, std::size_t i) {
  const auto& p = s.polygons[i];
  return {s.poly_verts.begin() + p.first, s.poly_verts.begin() + p.first + p.count};
}

namespace {
// Box of a disc (centre c, unit normal n, radius r): extent r sqrt(1 - n_i^2) per axis.
void grow_disc(Bounds& b, Vec3d c, Vec3d n, double r) {
  const Vec3d e{r * std::sqrt(std::max(0.0, 1 - n.x * n.x)), r * std::sqrt(std::max(0.0, 1 - n.y * n.y)),
                r * std::sqrt(std::max(0.0, 1 - n.z * n.z))};
  b.grow(to_float(c - e));
  b.grow(to_float(c + e));
}
// Widens a float box by a few ulps so that float rounding of the double corners stays inside.
Bounds widen(Bounds b) {
  if (b.empty()) return b;
  const float inf = std::numeric_limits<float>::infinity();
  for (int k = 0; k < 3; ++k) {
    float& lo = k == 0 ? b.lo.x : (k == 1 ? b.lo.y : b.lo.z);
    float& hi = k == 0 ? b.hi.x : (k == 1 ? b.hi.y : b.hi.z);
    lo = std::nextafter(std::nextafter(lo, -inf), -inf);
    hi = std::nextafter(std::nextafter(hi, inf), inf);
  }
  return b;
}
bool finite_box(const Bounds& b) { return !b.empty() && finite3(b.lo) && finite3(b.hi); }
}  // namespace

Bounds prim_bounds(const Scene& s, PrimRef p) {
  Bounds b;
  switch (p.kind) {
    case Kind::triangle: {
      // Exactly the vertices the watertight kernel reads: no widening needed.
      const auto q = tri_verts(s, p.index);
      if (std::isnan(q.a.x)) return {};
      b.grow(q.a); b.grow(q.b); b.grow(q.c);
      return b;
    }
    case Kind::sphere: {
      const auto& sp = s.spheres[p.index];
      if (sphere_prim(s, p.index).r2 == -std::numeric_limits<float>::infinity()) return {};
      const double r = double(sp.r);
      b.grow(to_float(to_double(sp.c) - Vec3d{r, r, r}));
      b.grow(to_float(to_double(sp.c) + Vec3d{r, r, r}));
      b = widen(b);
      break;
    }
    case Kind::cylinder:
    case Kind::cone: {
      const auto& c = s.cones[p.index];
      const bool ok = p.kind == Kind::cylinder ? cylinder_prim(s, p.index).prim.r2 != -std::numeric_limits<float>::infinity()
                                               : cone_prim(s, p.index).prim.z0 != std::numeric_limits<float>::infinity();
      if (!ok) return {};
      const Vec3d w = to_double(c.apex) - to_double(c.base);
      const double len = std::sqrt(dot(w, w));
      const Vec3d n = w * (1.0 / len);
      grow_disc(b, to_double(c.base), n, double(c.base_r));
      grow_disc(b, to_double(c.apex), n, double(c.apex_r));
      b = widen(b);
      break;
    }
    case Kind::polygon: {
      const auto v = polygon_vertices(s, p.index);
      if (!polygon_info(v).valid) return {};
      for (const auto& q : v) b.grow(q);
      return b;
    }
    case Kind::csg: {
      const CsgTree& t = *s.csgs[p.index].tree;
      if (t.empty()) return {};
      const CsgNode& n = t.nodes[t.root];
      b.grow({n.lo[0], n.lo[1], n.lo[2]});
      b.grow({n.hi[0], n.hi[1], n.hi[2]});
      break;
    }
  }
  return finite_box(b) ? b : Bounds{};
}

std::vector<PrimRef> prim_refs(const Scene& s) {
  std::vector<PrimRef> r;
  r.reserve(s.primitive_count());
  for (std::size_t i = 0; i < s.triangles.size(); ++i) r.push_back({Kind::triangle, std::uint32_t(i)});
  for (std::size_t i = 0; i < s.spheres.size(); ++i) r.push_back({Kind::sphere, std::uint32_t(i)});
  for (std::size_t i = 0; i < s.cones.size(); ++i) r.push_back({cone_is_cylinder(s, i) ? Kind::cylinder : Kind::cone, std::uint32_t(i)});
  for (std::size_t i = 0; i < s.polygons.size(); ++i) r.push_back({Kind::polygon, std::uint32_t(i)});
  for (std::size_t i = 0; i < s.csgs.size(); ++i) r.push_back({Kind::csg, std::uint32_t(i)});
  return r;
}

IdBatch<TriVerts> triangle_verts_batch(const Scene& s) {
  IdBatch<TriVerts> b;
  b.prims.reserve(s.triangles.size());
  for (std::size_t i = 0; i < s.triangles.size(); ++i) { b.prims.push(tri_verts(s, i)); b.id.push_back(std::uint32_t(i)); }
  return b;
}
IdBatch<Triangle> triangle_mt_batch(const Scene& s) {
  IdBatch<Triangle> b;
  b.prims.reserve(s.triangles.size());
  for (std::size_t i = 0; i < s.triangles.size(); ++i) { b.prims.push(tri_mt(s, i)); b.id.push_back(std::uint32_t(i)); }
  return b;
}
TriLectureSoA triangle_lecture_batch(const Scene& s) {
  std::vector<std::array<Vec3f, 3>> tris(s.triangles.size());
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const auto& t = s.triangles[i];
    tris[i] = {s.verts[t.v[0]], s.verts[t.v[1]], s.verts[t.v[2]]};
  }
  return TriLectureSoA::build(tris);
}
IdBatch<Sphere> sphere_batch(const Scene& s) {
  IdBatch<Sphere> b;
  b.prims.reserve(s.spheres.size());
  for (std::size_t i = 0; i < s.spheres.size(); ++i) { b.prims.push(sphere_prim(s, i)); b.id.push_back(std::uint32_t(i)); }
  return b;
}
IdBatch<Transformed<Cylinder>::T> cylinder_batch(const Scene& s) {
  IdBatch<Transformed<Cylinder>::T> b;
  for (std::size_t i = 0; i < s.cones.size(); ++i)
    if (cone_is_cylinder(s, i)) { b.prims.push(cylinder_prim(s, i)); b.id.push_back(std::uint32_t(i)); }
  return b;
}
IdBatch<Transformed<Cone>::T> cone_batch(const Scene& s) {
  IdBatch<Transformed<Cone>::T> b;
  for (std::size_t i = 0; i < s.cones.size(); ++i)
    if (!cone_is_cylinder(s, i)) { b.prims.push(cone_prim(s, i)); b.id.push_back(std::uint32_t(i)); }
  return b;
}
PolygonSoA polygon_batch(const Scene& s) {
  std::vector<std::vector<Vec3f>> polys(s.polygons.size());
  for (std::size_t i = 0; i < s.polygons.size(); ++i) polys[i] = polygon_vertices(s, i);
  return PolygonSoA::build(polys);
}

}  // namespace rb::scene
