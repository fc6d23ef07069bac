// Scene to kernel batches: the one place that turns a Scene's input-form arrays into the SoA
// batches the kernels read, with ids back to the scene's primitives and a bounds function per
// kind. `raybench info` sizes them; the BVH (bvh/accel.hpp) builds them in leaf order.
//
// Kinds and their batches:
//   triangle  TriVerts (Woop's watertight test: the vertices exactly as given) or Triangle
//             (Moller-Trumbore: v0 and two edges) or TriLectureSoA (lecture, grouped by axis)
//   sphere    Sphere (c, r^2, 1/r)
//   cylinder  Transformed<Cylinder>::T: an NFF cone with equal radii, placed unit cylinder
//   cone      Transformed<Cone>::T: an NFF cone with different radii, placed unit cone
//   polygon   PolygonSoA (plane, projected vertices grouped by dropped axis)
//   csg       no SoA batch: each slot is a CSG tree (kernels/csg.hpp), queried one ray at a time
//             (csg_hit) or 8 rays at a time (csg_hit8); its box is the root node's
// Degenerate input becomes the kind's never() (a slot that no ray hits), so ids stay aligned.
#pragma once

#include "kernels/cylinder_cone.hpp"
#include "kernels/polygon.hpp"
#include "kernels/sphere.hpp"
#include "kernels/triangle.hpp"
#include "kernels/triangle_woop.hpp"
#include "scene/scene.hpp"

#include <cstdint>
#include <vector>

namespace rb::scene {

enum class Kind : std::uint8_t { triangle = 0, sphere = 1, cylinder = 2, cone = 3, polygon = 4, csg = 5 };
inline constexpr int kKinds = 6;
const char* kind_name(Kind k);

// A reference to one scene primitive: its kind and its index in the scene array of that kind
// (Scene::triangles, spheres, cones, polygons, csgs; cylinders and cones both index Scene::cones).
struct PrimRef {
  Kind kind;
  std::uint32_t index;
};

// One primitive, by scene index (the makers the batches use).
TriVerts<float> tri_verts(const Scene& s, std::size_t i);
Triangle<float> tri_mt(const Scene& s, std::size_t i);
Sphere<float> sphere_prim(const Scene& s, std::size_t i);
bool cone_is_cylinder(const Scene& s, std::size_t i);  // equal radii
Transformed<Cylinder>::T<float> cylinder_prim(const Scene& s, std::size_t i);
Transformed<Cone>::T<float> cone_prim(const Scene& s, std::size_t i);
std::vector<Vec3f> polygon_vertices(const Scene& s, std::size_t i);

// A box around one primitive (conservative; empty for a degenerate one, which never hits).
Bounds prim_bounds(const Scene& s, PrimRef p);

// Every primitive of the scene, kinds in the order above, each kind in scene order.
std::vector<PrimRef> prim_refs(const Scene& s);

// Whole-scene batches in scene order, with the scene index of every slot (UINT32_MAX: padding).
template <template <class> class P>
struct IdBatch {
  PrimSoA<P> prims;
  std::vector<std::uint32_t> id;  // per real slot
  std::size_t bytes() const { return prims.bytes() + id.size() * sizeof(std::uint32_t); }
};
IdBatch<TriVerts> triangle_verts_batch(const Scene& s);
IdBatch<Triangle> triangle_mt_batch(const Scene& s);
TriLectureSoA triangle_lecture_batch(const Scene& s);
IdBatch<Sphere> sphere_batch(const Scene& s);
IdBatch<Transformed<Cylinder>::T> cylinder_batch(const Scene& s);  // ids index Scene::cones
IdBatch<Transformed<Cone>::T> cone_batch(const Scene& s);          // ids index Scene::cones
PolygonSoA polygon_batch(const Scene& s);                          // ids in PolygonSoA::id

}  // namespace rb::scene
