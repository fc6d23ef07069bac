// The table of primitive kinds: the one place a kind is declared. Each kind (tracer/kinds/*.hpp) is
// a struct that says, for the scene's primitives of that kind:
//   - which they are (each: the scene indices, in the scene array the kind reads), their world box
//     (bounds) and their numerical features (feature: centre, smallest and largest size), the
//     inputs of the BVH build and of the scene's numerical profile (tracer/profile.hpp);
//   - the kernel primitive stored in the leaf batches (Prim<S>, S = float, or double where the
//     kind supports double storage) and how one is made relative to a frame origin (make;
//     optionally prefetch_input, which fetches make's scene data ahead when the batch is written in
//     leaf order);
//   - optionally mesh_vertices (the indices into Scene::verts of a primitive's vertices), with which
//     the profile tells whether float storage reproduces the input (tracer/profile.hpp);
//   - its methods, cheapest first, each a kernel over any number type (hit<M>), with what each
//     precision costs and which lab cases show where it fails (tracer/plan.cpp chooses);
//   - the surface at a hit (point, normals, material: the renderer's shading input).
// What other layers know of a kind lives with them: how Embree models it in bench/embree_trace.cpp,
// the accuracy lab's long-double reference in accuracy/kind_reference.hpp.
// Kinds whose batch is not a PrimSoA (polygons: projected vertices by slot; CSG: one tree per
// slot) say `custom = true` and bring their own batch and leaf functions (tracer/leaves.hpp
// calls them). Nothing else in the engine switches on a kind: the tracer, the renderer, the
// Embree adapter, the lab, the profile and the plan iterate over the list at the bottom of this file.
// Adding a kind: write its header in tracer/kinds/, include it below and add its line to
// RB_KIND_TABLE (docs/DESIGN.md section 17 lists the other steps; tests/extra_kind/ adds one in a test).
#pragma once

#include "bvh/bvh.hpp"
#include "core/memory.hpp"
#include "core/ray.hpp"
#include "core/spawn.hpp"
#include "scene/scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace rb::kinds {

using scene::Bounds;
using scene::Scene;

// The scene index of every leaf slot of a kind's batch (UINT32_MAX: padding), in leaf order. Read
// once per leaf a ray enters: from 2 MiB on, on huge pages like the batches (core/memory.hpp).
using SlotIds = big_vector<std::uint32_t>;

// The kind table: every kind's enumerator and struct, in Kind order. A new kind is one line here
// and the include of its header below; the enum, the kind count, AllKinds and every name list
// derived from them (kind_name, parse_kind, kind_counts, the per-kind figures of trace, render,
// info and the report) follow from it. RB_KIND_TABLE(X) expands X(enumerator, Struct) per kind.
#define RB_KIND_TABLE(X)                                                                                         \
  X(triangle, TriangleKind) X(sphere, SphereKind) X(cylinder, CylinderKind) X(cone, ConeKind) X(polygon, PolygonKind) \
  X(csg, CsgKind) X(torus, TorusKind)
// A build may add one kind from outside the engine's folders (a test's: tests/extra_kind/):
// RB_EXTRA_KIND_LIST names a header that defines RB_EXTRA_KIND(X), its line of the table, and
// RB_EXTRA_KIND_HEADER the header of its struct (included after the engine's kinds).
#ifdef RB_EXTRA_KIND_LIST
#include RB_EXTRA_KIND_LIST
#else
#define RB_EXTRA_KIND(X)
#endif
#define RB_ALL_KINDS(X) RB_KIND_TABLE(X) RB_EXTRA_KIND(X)

#define RB_KIND_ENUMERATOR(e, K) e,
#define RB_KIND_ONE(e, K) +1
enum class Kind : std::uint8_t { RB_ALL_KINDS(RB_KIND_ENUMERATOR) };
inline constexpr int kKinds = 0 RB_ALL_KINDS(RB_KIND_ONE);
static_assert(2 * kKinds <= bvh::kMaxKinds, "a leaf tag holds a kind or its primitives stored apart (tracer/leaves.hpp)");

// What the profile reads of one primitive: where it is and how small and large it is. size is
// the smallest length that matters for it (a sphere's radius, a triangle's shortest edge, a torus'
// tube radius), extent its largest dimension; both 0 for a degenerate primitive.
struct Feature {
  Vec3d centre{0, 0, 0};
  double size = 0, extent = 0;
  bool flat = false;  // no area though its size is not 0 (a triangle's three vertices on one line)
};

// The surface at a hit, in world coordinates (double point: a surface 6.4e6 from the origin keeps
// its shading detail).
struct Surface {
  Vec3d p;    // the hit point, projected onto the primitive's surface in double where the kind can
              // (the traced t carries the kernel's error times the distance the ray came from)
  Vec3f ng;   // unit geometric normal (outward for solids; by vertex order for faces)
  Vec3f ns;   // unit shading normal (interpolated vertex normals where given, else ng), on ng's side
  std::uint32_t mat = 0;
  // How far the traced primitive's surface may lie from p: the rounding of the stored primitive
  // (SceneAccel::surface sets it from the plan's storage; 0 for a primitive stored in double).
  double err = 0;
};

// A method of a kind: its name, what it is, and the precisions the tracer can run it in.
struct MethodInfo {
  const char* name;
  const char* what;
  bool f64 = true;          // the kernel in double on the stored primitive widened
  bool f64_storage = false; // the primitive stored in double (the kind's make<double>)
};

// The plan's evidence for a kind (its `plan` array, beside its methods): the (method, precision)
// options the tracer can run, cheapest first, each with the conditions under which the accuracy lab
// measures it with no failure and the lab cases that show it (`raybench accuracy --filter CASE`;
// tests/test_plan.cpp runs every cited case and checks that the option has no failure there).
// Conditions are the scene profile's (tracer/profile.hpp):
//   far     the kind's far_ratio (farthest ray origin over the primitive's size) is at most this;
//   scale   its scale_ratio (largest primitive over the scene's smallest object) is at most this;
//   aspect  its aspect_max is at most this.
// An option whose conditions do not cover the scene is skipped; when none covers it, the most
// accurate option (the last) runs and the plan says that the scene is beyond the lab's cases.
struct PlanOption {
  int method = 0;
  bool f64 = false;
  double far = 0, scale = 0, aspect = 0;  // the profile's far_ratio, scale_ratio, aspect_max covered
  const char* evidence = "";              // the lab cases ("family/case ...")
  const char* why = "";
};
inline constexpr double kAny = std::numeric_limits<double>::infinity();  // no bound on a condition

// What storing a kind's primitives apart costs (kinds that store double): the time of a primary ray
// in 8-ray packets with every primitive of the kind stored apart in float in local frames (the ray
// re-based at each leaf), and in double, over the time with the kind in float in the frame. The
// accuracy lab measures them (`raybench accuracy --filter storage/CASE`, CASE = `evidence`: the
// ratio of medians over its rounds); the plan stores a kind's coarse primitives in the cheaper of
// the two, and judges frames by what they leave apart at these costs. The report measures them
// again on its machine and says whether the plan's choice still holds there.
struct StorageCost {
  double local = 1, f64 = 1;
  const char* evidence = "";
  const char* measured_on = "";  // the machine and build of the figures
};

// What a kind's surface rule is given: the ray as traced (frame coordinates), its hit distance,
// the frame's origin and the world hit point origin + o + t d in double; `batch` is the kind's
// batch in the tracer (custom kinds read it: the CSG trees in the frame).
struct HitQuery {
  const Scene* scene = nullptr;
  Vec3d origin{0, 0, 0};
  Ray<float> ray{};
  float t = 0;
  Vec3d p{0, 0, 0};
  const void* batch = nullptr;
  float aux = 0;  // the hit's HitRec::aux
};

namespace detail {
// p moved along the unit normal n onto the plane through a (n . (x - a) = 0).
inline Vec3d onto_plane(const Vec3d& p, const Vec3d& n, const Vec3d& a) { return p - n * dot(p - a, n); }
inline Vec3d unit_d(const Vec3d& v) {
  const double l = std::sqrt(dot(v, v));
  return l > 0 && std::isfinite(l) ? v * (1.0 / l) : v;
}
inline Vec3f unit_or(const Vec3d& v, const Vec3f& fallback) {
  const double l = std::sqrt(dot(v, v));
  if (!(l > 0.0) || !std::isfinite(l)) return fallback;
  return to_float(v * (1.0 / l));
}
// Barycentric weights of p in triangle (a, b, c), by sub-areas along the triangle's normal.
inline bool barycentric(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& p, double w[3]) {
  const Vec3d n = cross(b - a, c - a);
  const double nn = dot(n, n);
  if (!(nn > 0.0)) return false;
  w[0] = dot(cross(c - b, p - b), n) / nn;
  w[1] = dot(cross(a - c, p - c), n) / nn;
  w[2] = 1.0 - w[0] - w[1];
  return true;
}
// The shading normal from vertex normals: barycentric on a triangle; on a polygon, barycentric in
// the fan triangle (v0, vi, vi+1) that contains p (the one least outside it, at the edges).
inline Vec3f interpolate(const Vec3d* v, const Vec3f* n, std::size_t count, const Vec3d& p, const Vec3f& ng) {
  double best_out = -1e300;
  Vec3d best{0, 0, 0};
  for (std::size_t i = 1; i + 1 < count; ++i) {
    double w[3];
    if (!barycentric(v[0], v[i], v[i + 1], p, w)) continue;
    const double inside = std::min({w[0], w[1], w[2]});
    if (inside > best_out) {
      best_out = inside;
      best = to_double(n[0]) * w[0] + to_double(n[i]) * w[1] + to_double(n[i + 1]) * w[2];
    }
    if (inside >= 0) break;
  }
  Vec3f ns = unit_or(best, ng);
  if (dot(ns, ng) < 0.0f) ns = -ns;
  return ns;
}
}  // namespace detail

// A primitive's scene index and kind, packed as the tracer's hits are (bvh::prim_code).
inline std::uint32_t code(Kind k, std::uint32_t index) { return bvh::prim_code(int(k), index); }
inline Kind kind_of(std::uint32_t code) { return Kind(bvh::prim_kind(code)); }
inline std::uint32_t index_of(std::uint32_t code) { return bvh::prim_index(code); }

// A float box that contains the double box b translated by -origin: each bound rounded to the
// nearest float, then 3 floats outward (a primitive made from the same double values and rounded to
// nearest per coordinate, a sphere's centre, stays inside: rounding to nearest is at most one
// step inward). Empty b: the empty box (+inf, -inf). The 6 bounds in the lanes of one register
// (the build runs this once per primitive).
inline void frame_box(const Bounds& b, const Vec3d& origin, float lo[3], float hi[3]) {
  const float inf = std::numeric_limits<float>::infinity();
  if (b.empty()) {
    for (int k = 0; k < 3; ++k) lo[k] = inf, hi[k] = -inf;
    return;
  }
  spawn::relative_box_outward(b.lo, b.hi, origin, 3, lo, hi);
}

}  // namespace rb::kinds

#include "tracer/kinds/cone_kind.hpp"
#include "tracer/kinds/csg_kind.hpp"
#include "tracer/kinds/cylinder_kind.hpp"
#include "tracer/kinds/polygon_kind.hpp"
#include "tracer/kinds/sphere_kind.hpp"
#include "tracer/kinds/torus_kind.hpp"
#include "tracer/kinds/triangle_kind.hpp"
#ifdef RB_EXTRA_KIND_HEADER
#include RB_EXTRA_KIND_HEADER
#endif

namespace rb::kinds {


template <class... K>
struct KindList {
  static constexpr std::size_t size = sizeof...(K);
  // Each kind's id is its place in the list (the tables indexed by Kind rely on it).
  static constexpr bool ids_in_order() {
    std::size_t i = 0;
    return ((std::size_t(K::id) == i++) && ...);
  }
  // f.template operator()<K>() for every kind, in order.
  template <class Fn>
  static void each(Fn&& f) { (f.template operator()<K>(), ...); }
  // f.template operator()<K>() for the kind k.
  template <class R, class Fn>
  static R at(Kind k, Fn&& f) {
    R r{};
    ((K::id == k ? (void)(r = f.template operator()<K>()) : void()), ...);
    return r;
  }
};
// Every kind, in Kind order (the table's structs; the leading void takes the first comma).
template <class Void, class... K>
struct KindTable {
  using type = KindList<K...>;
};
#define RB_KIND_STRUCT(e, K) , K
using AllKinds = KindTable<void RB_ALL_KINDS(RB_KIND_STRUCT)>::type;
static_assert(AllKinds::size == kKinds && AllKinds::ids_in_order(), "each kind's id is its enumerator in RB_KIND_TABLE");

const char* kind_name(Kind k);
// The kind of a name ("sphere", ...); false when there is none.
bool parse_kind(const std::string& name, Kind& k);
// Primitives of each kind in the scene.
std::array<std::size_t, kKinds> kind_counts(const Scene& s);

}  // namespace rb::kinds
