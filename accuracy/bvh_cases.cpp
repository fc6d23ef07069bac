// The lab's cases that run through the whole tracer, apart from the kernel families so that a
// program (or a test) that needs only the kernels' figures does not build the tracer: the BVH rows
// of the closed-mesh triangle cases (family "bvh", below) and the whole scenes (family "scene",
// accuracy/scenes.cpp). A lab run includes them when its Options::tracer is tracer_cases().
#include "accuracy/common.hpp"
#include "accuracy/exact.hpp"
#include "tracer/accel.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <limits>

namespace rb::acc {

namespace {

// The closed-mesh cases through the whole tracer: one BVH over the mesh, single rays (8-wide
// nodes, "float") and 8-ray packets ("simd8"). Methods of family "bvh": `default` is the tracer's
// default configuration (the auto model's plan: conservative node boxes, the fast slab test
// within their bound, the robust one beyond it), `fast_slabs` the fast test on boxes as built (the
// fast model), `robust_slabs` Ize's test on every node. The lab's rays and references are in
// world coordinates, so every plan here keeps the world frame. Per ray, the exact first crossing
// against the traced hit; leaks counted as in the triangle family (accuracy/triangle_cases.cpp).
void mesh_rows(Ctx& x, const Case<TriVerts>& woop, const std::vector<Vec3f>& verts, const std::vector<std::array<int, 3>>& faces) {
  if (woop.must_hit.empty()) return;
  scene::Scene s;
  s.name = woop.name;
  for (const auto& v : verts) s.verts.push_back(to_double(v));
  for (const auto& f : faces) s.triangles.push_back({{std::uint32_t(f[0]), std::uint32_t(f[1]), std::uint32_t(f[2])}, 0});
  // Ray origins: the box of every ray of the case (the lab has no camera).
  tracer::Plan plan = tracer::make_plan(s, tracer::Model::automatic);
  plan.frame = tracer::FrameKind::world;
  plan.origin = {0, 0, 0};
  double ob = 0;
  for (const auto& v : s.verts) ob = std::max({ob, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  plan.origin_bound = float(ob * (1 + 0x1p-10));
  const tracer::SceneAccel a = tracer::SceneAccel::build(s, plan);
  const tracer::SceneAccel fast = tracer::SceneAccel::build(s, tracer::make_plan(s, tracer::Model::fast));
  const std::size_t nr = woop.nrays(), np = woop.nprims();
  std::vector<Ref> ref(nr);
  for (std::size_t i = 0; i < nr; ++i) {
    Ref& f = ref[i];
    for (std::size_t j = 0; j < np; ++j) {
      const Ref& t = woop.ref[j * nr + i];
      f.scale = t.scale;
      if (t.cls == Cls::hit) f.cls = Cls::hit;
      if (t.cls == Cls::either && f.cls == Cls::miss) f.cls = Cls::either;
      if (t.has_t && (!f.has_t || t.t < f.t)) f.t = t.t, f.has_t = true;
    }
  }
  for (int mode = 0; mode < 3; ++mode)
    for (int packet : {1, 8}) {
      tracer::TraceOptions opt;
      opt.packet = packet;
      if (mode == 2) opt.slab_given = true, opt.slab = bvh::Slab::robust;
      const tracer::SceneAccel& accel = mode == 1 ? fast : a;
      const char* method = mode == 0 ? "default" : mode == 1 ? "fast_slabs" : "robust_slabs";
      x.tick("bvh", woop.name);
      std::vector<bvh::HitRec> hits(woop.rays.size());
      accel.trace(woop.rays, 0, woop.rays.size(), hits.data(), opt);
      std::vector<Out> out(nr);
      for (std::size_t i = 0; i < nr; ++i) out[i] = {hits[i].prim != bvh::kNoPrim, double(hits[i].t)};
      Row r = tally("bvh", method, packet == 1 ? "float" : "simd8", woop.name,
                    woop.what + " (traced through an 8-wide BVH)", nr, ref, out, double(std::numeric_limits<float>::epsilon()), true,
                    {}, true);  // a hit 1e3 eps scale past the first crossing: a farther face (the near one culled)
      std::size_t leaks = 0, crossing = 0;
      for (std::size_t i = 0; i < nr; ++i)
        if (woop.must_hit[i]) ++crossing, leaks += !out[i].hit;
      r.leaks = leaks;
      r.leak_ppm = 1e6 * double(leaks) / double(std::max<std::size_t>(crossing, 1));
      r.iterations = std::numeric_limits<double>::quiet_NaN();
      r.ns_per_test = std::numeric_limits<double>::quiet_NaN();
      if (x.o->timing) {
        double best = 1e300;
        for (int k = 0; k < 10; ++k) {
          const auto t0 = std::chrono::steady_clock::now();
          accel.trace(woop.rays, 0, woop.rays.size(), hits.data(), opt);
          best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        r.ns_per_test = best * 1e9 / double(nr);
      }
      x.rows->push_back(r);
    }
}

}  // namespace

const TracerCases& tracer_cases() {
  static const TracerCases c{mesh_rows, scene_cases, run_scenes};
  return c;
}

}  // namespace rb::acc
