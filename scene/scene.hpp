// The scene model: model no more than a scene needs.
//
// A scene is a camera, lights, the few material parameters the lecture's shading uses (NFF's
// `f` line), and one array per primitive kind it actually contains, in input form (what the
// file or generator said). Kernel batches (SoA, kernels/*.hpp) are built from these arrays by
// the code that traces; a kind with no primitives costs nothing. A sphere stays a sphere, a
// cone a cone; polygons with more than three vertices stay polygons. No virtual dispatch.
//
// Positions and sizes are kept in double, as the input gave them: a scene 6.4e6 from the origin,
// or a planet with a ball on it, keeps its small features until the tracer has chosen a frame of
// reference (tracer/plan.hpp) and rounds each coordinate to float once, relative to that frame.
// Directions (normals, the camera's up) and colours are float.
#pragma once

#include "core/vec3.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace rb {
struct CsgTree;  // kernels/csg_ray.hpp
}

namespace rb::scene {

// NFF `f`: colour, diffuse Kd, specular Ks, Phong exponent, transmittance T, index of refraction.
// Reflectance of mirror-like surfaces is Ks (as in Haines' SPD renderer conventions).
struct Material {
  Vec3f color{1, 1, 1};
  float kd = 1, ks = 0, shine = 0, t = 0, ior = 1;
  // Checkerboard (the lecture's scenes, scene/lecture_scenes.cpp; no NFF file sets it): when
  // checker > 0 the surface colour alternates between `color` (even cells) and `color2` (odd
  // cells) of a solid checker of cell size `checker`, parity of
  // floor(x/checker) + floor(y/checker) + floor(z/checker) at the hit point. A floor lies
  // mid-cell along its normal axis (so that axis never flips the parity).
  float checker = 0;
  Vec3f color2{0, 0, 0};
};

// NFF `v` block (from, at, up, angle in degrees, hither, resolution).
struct Camera {
  Vec3d from{0, 0, -1}, at{0, 0, 0}, up{0, 1, 0};
  double angle = 45, hither = 0;
  int width = 512, height = 512;
};

struct Light {
  Vec3d pos{0, 0, 0};
  Vec3f color{1, 1, 1};
};

struct SphereIn {
  Vec3d c;
  double r;
  std::uint32_t mat;
};

// NFF `c`: a truncated cone between two capless circles (a cylinder when the radii are equal).
struct ConeIn {
  Vec3d base;
  double base_r;
  Vec3d apex;
  double apex_r;
  std::uint32_t mat;
};

// A planar polygon: vertices [first, first + count) of Scene::poly_verts (and poly_normals when
// the scene has per-vertex normals, NFF `pp`).
struct PolygonIn {
  std::uint32_t first, count;
  std::uint32_t mat;
};

// A triangle: three indices into Scene::verts (meshes share vertices).
struct TriangleIn {
  std::array<std::uint32_t, 3> v;
  std::uint32_t mat;
};

// A torus (JSON "torus" without a transform): centre, axis (any length), major radius R, minor r.
struct TorusIn {
  Vec3d c, axis;
  double R, r;
  std::uint32_t mat;
};

// A CSG solid (kernels/csg_ray.hpp; built by scene/csg_scene.hpp from JSON). Materials are per leaf (each
// leaf's surface keeps its own); `mat` is the object's default. The tree is shared, immutable;
// `tree` is placed in world coordinates (rounded to float there), `in_frame(origin)` builds the
// same tree with every coordinate taken relative to `origin` before it is rounded.
struct CsgIn {
  std::shared_ptr<const CsgTree> tree;
  std::uint32_t mat;
  std::function<std::shared_ptr<const CsgTree>(const Vec3d& origin)> in_frame;
  // The node as the JSON scene format wrote it, every "material" renamed "m<index>" (the index
  // into Scene::materials): what scene_json (scene/csg_scene.hpp) writes back.
  std::string json;
};

// An axis-aligned box in double (world coordinates).
struct Bounds {
  Vec3d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Vec3d hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  void grow(const Vec3d& p) { lo = vmin3(lo, p); hi = vmax3(hi, p); }
  void grow(const Bounds& b) { if (!b.empty()) { grow(b.lo); grow(b.hi); } }
  bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
  Vec3d centre() const { return (lo + hi) * 0.5; }
  Vec3d extent() const { return hi - lo; }
  double max_extent() const { const Vec3d e = extent(); return std::max({e.x, e.y, e.z}); }
};

struct Scene {
  std::string name;    // file name or generator call, e.g. "balls(4)"
  Camera camera;
  Vec3f background{0, 0, 0};
  std::vector<Light> lights;
  std::vector<Material> materials;  // primitives index into this

  std::vector<SphereIn> spheres;
  std::vector<ConeIn> cones;
  std::vector<Vec3d> poly_verts;
  std::vector<Vec3f> poly_normals;              // empty or parallel to poly_verts
  std::vector<PolygonIn> polygons;
  std::vector<Vec3d> verts;                     // triangle mesh vertices
  std::vector<Vec3f> vert_normals;              // empty or parallel to verts
  std::vector<TriangleIn> triangles;
  std::vector<CsgIn> csgs;
  std::vector<TorusIn> tori;


  Bounds bounds() const;
  std::size_t primitive_count() const {
    return spheres.size() + cones.size() + polygons.size() + triangles.size() + csgs.size() + tori.size();
  }
  std::size_t csg_tree_bytes() const;  // nodes and leaves of every CSG tree
  // Bytes of the input-form arrays (sizes, not capacities).
  std::size_t memory_bytes() const {
    return lights.size() * sizeof(Light) + materials.size() * sizeof(Material) + spheres.size() * sizeof(SphereIn) +
           cones.size() * sizeof(ConeIn) + (poly_verts.size() + verts.size()) * sizeof(Vec3d) +
           (poly_normals.size() + vert_normals.size()) * sizeof(Vec3f) + polygons.size() * sizeof(PolygonIn) +
           triangles.size() * sizeof(TriangleIn) + csgs.size() * sizeof(CsgIn) + tori.size() * sizeof(TorusIn) + csg_tree_bytes();
  }
};

}  // namespace rb::scene
