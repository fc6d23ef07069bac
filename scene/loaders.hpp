// Scene file formats: Wavefront OBJ, Stanford PLY, Haines' NFF (and an NFF writer).
//
// Every loader throws rb::scene::SceneError on malformed, truncated or hostile input, with a
// message "FILE:LINE: what was expected" (text) or "FILE: byte N: ..." (binary PLY). Counts in
// headers are checked against the bytes left before anything is allocated, every index is
// checked, and NaN or infinite numbers are rejected (a scene coordinate that is not finite is
// an error, never silently dropped). `parse_*` take the file contents (the fuzz test feeds
// them mutated buffers); `name` only labels the messages.
//
// What each format becomes (see also data/README.md):
//  - OBJ: `v` (x y z; a w or vertex colour after them is ignored), `f` with `i`, `i/t`,
//    `i//n`, `i/t/n` and negative (relative) indices. Faces with more than three vertices are
//    triangulated into Scene::triangles: convex ones as a fan, non-convex ones (tested in the
//    plane of their Newell normal) by ear clipping up to kMaxEarClip vertices and as a fan
//    beyond that. Normals, texture coordinates, groups, materials, lines and points are
//    ignored; unknown statements are skipped. Vertices are shared as in the file.
//  - PLY: ascii, binary_little_endian, binary_big_endian. Element `vertex` needs scalar
//    x y z (any numeric type); other properties are skipped by their declared types. Element
//    `face` with a `vertex_indices` or `vertex_index` list (any count and index type) is
//    triangulated as OBJ faces are; element `tristrips` with a `vertex_indices` list uses -1
//    as a restart, alternates the winding, and drops the zero-area joining triangles (two
//    equal indices). Other elements are skipped.
//  - NFF (every entity of NFF.TXT): `v` block, `b`, `l` (optional colour), `f`, `c` (ConeIn,
//    radii as written; negative radii mean inside-visible and are kept), `s`, `p`, `pp`.
//    A 3-vertex `p` or `pp` becomes a triangle (Scene::triangles, three unshared vertices;
//    `pp` normals in vert_normals), because the triangle is a kernel of its own; polygons with
//    four or more vertices stay polygons (gears' 144-vertex concave faces are not
//    triangulated). When a scene mixes primitives with and without vertex normals, those
//    without get their geometric (Newell) normal at every vertex, so the normal arrays stay
//    parallel to the vertex arrays. Equal `f` lines are merged into one material (the SPD
//    programs repeat them; the generators merge them the same way), and a primitive before
//    any `f` gets a default material. Counts for Haines' SPD files at their
//    default sizes: balls 7,381 spheres + 1 polygon; gears 9,345 polygons; mount 8,192
//    triangles + 4 spheres; rings 4,200 spheres + 4,200 cones + 1 polygon; teapot 2,256
//    triangles (from `pp 3`) + 36 polygons; tetra 4,096 triangles; tree 4,095 spheres +
//    4,095 cones + 1 polygon (Haines' table; its teapot figure 9,264 is for size 12:
//    9,120 triangles + 144 squares, as teapot.c's header says).
//  - save_nff writes every material, then spheres, cones, polygons and triangles, each kind in
//    its order with an `f` line where the material changes, and every number as the shortest
//    decimal that reads back to the same number: load -> save -> load reproduces a loaded scene
//    exactly (a scene with two equal materials comes back with them merged). Triangles are
//    written as unshared `p 3` / `pp 3`, so a mesh comes back with 3 vertices per triangle.
#pragma once

#include "scene/scene.hpp"
#include "scene/sources.hpp"

#include <string>
#include <string_view>

namespace rb::scene {

inline constexpr std::size_t kMaxEarClip = 256;

Scene load_obj(const std::string& path);
Scene load_ply(const std::string& path);
Scene load_nff(const std::string& path);
Scene parse_obj(std::string_view text, const std::string& name);
Scene parse_ply(std::string_view bytes, const std::string& name);
Scene parse_nff(std::string_view text, const std::string& name);

void save_nff(const Scene& scene, const std::string& path);
std::string to_nff(const Scene& scene);

namespace detail {
// Triangulates polygon `idx` (indices into `verts`) into `out` (see OBJ above); `mat` for all.
void triangulate(const std::uint32_t* idx, std::size_t n, const std::vector<Vec3d>& verts, std::uint32_t mat,
                 std::vector<TriangleIn>& out);
}  // namespace detail

}  // namespace rb::scene
