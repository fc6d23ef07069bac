// The generic hit the shader works on: whatever kind of primitive a ray hit, the tracer asks this
// one place for the point, the normals and the material. A new primitive kind plugs in by adding
// its case to surface_at (render/surface.cpp); the shading never looks at the kind.
#pragma once

#include "bvh/accel.hpp"
#include "core/ray.hpp"
#include "scene/batches.hpp"

#include <cstdint>

namespace rb::render {

struct Surface {
  Vec3f p;             // the hit point o + t d
  Vec3f ng;            // unit geometric normal: outward for spheres and cones (inward for an
                       // NFF cone with negative radii), by the vertex order (Newell) for polygons
                       // and triangles
  Vec3f ns;            // unit shading normal: interpolated vertex normals (NFF `pp`, mesh
                       // normals) where the scene has them, else ng; on ng's side
  std::uint32_t mat;   // index into Scene::materials
  scene::Kind kind;
};

// The surface at distance t along r on the primitive `prim` (bvh::prim_code: kind and scene index).
Surface surface_at(const scene::Scene& s, std::uint32_t prim, const Ray<float>& r, float t);

// The surface colour at p: Material::color, or the checkerboard's two colours by cell parity.
Vec3f surface_color(const scene::Material& m, const Vec3f& p);

}  // namespace rb::render
