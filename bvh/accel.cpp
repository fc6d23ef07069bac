// Accel::build: prim boxes -> binned SAH -> batches reordered into leaf order -> 8-wide collapse.
#include "bvh/accel.hpp"

#include <tbb/parallel_for.h>

#include <chrono>
#include <stdexcept>
#include <string>

namespace rb::bvh {

using scene::Kind;

namespace {
// A batch of `slots` never-hit slots (count = slots: every leaf group is already padded).
template <template <class> class P>
void fill_never(PrimSoA<P>& b, std::size_t slots) {
  P<float> nv = P<float>::never();
  auto t = nv.fields();
  [&]<std::size_t... I>(std::index_sequence<I...>) { ((b.f[I].assign(slots, std::get<I>(t))), ...); }(std::make_index_sequence<PrimSoA<P>::kFields>{});
  b.count = slots;
}
template <template <class> class P>
void set_slot(PrimSoA<P>& b, std::size_t i, P<float> p) {
  auto t = p.fields();
  [&]<std::size_t... I>(std::index_sequence<I...>) { ((b.f[I][i] = std::get<I>(t)), ...); }(std::make_index_sequence<PrimSoA<P>::kFields>{});
}
}  // namespace

Accel Accel::build(const scene::Scene& s, const BuildOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  Accel a;
  a.options = opt;
  const std::size_t need = s.primitive_count() * kBuildBytesPerPrim;
  if (opt.max_bytes && need > opt.max_bytes)
    throw std::length_error("the BVH of " + std::to_string(s.primitive_count()) + " primitives needs about " +
                            std::to_string(need >> 20) + " MiB, above the limit of " + std::to_string(opt.max_bytes >> 20) + " MiB");
  const std::vector<scene::PrimRef> refs = scene::prim_refs(s);
  a.scene_prims = refs.size();
  std::vector<float> lo(3 * refs.size()), hi(3 * refs.size());
  std::vector<std::uint8_t> kind(refs.size());
  auto boxes = [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const scene::Bounds bb = scene::prim_bounds(s, refs[i]);
      const float v[6] = {bb.lo.x, bb.lo.y, bb.lo.z, bb.hi.x, bb.hi.y, bb.hi.z};
      for (int k = 0; k < 3; ++k) { lo[3 * i + std::size_t(k)] = v[k]; hi[3 * i + std::size_t(k)] = v[3 + k]; }
      kind[i] = std::uint8_t(refs[i].kind);
    }
  };
  if (opt.parallel)
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, refs.size(), 4096), [&](const auto& r) { boxes(r.begin(), r.end()); });
  else
    boxes(0, refs.size());
  a.bin = build_sah(lo, hi, kind, opt);

  // Reorder: every leaf becomes one 8-slot group of its kind's batch. Groups are assigned in
  // node order, then the slots are written in parallel.
  const auto t1 = std::chrono::steady_clock::now();
  std::vector<std::uint32_t> leaves, leaf_first;  // binary leaf node, its first position in `order`
  std::size_t groups[scene::kKinds] = {};
  for (std::uint32_t i = 0; i < a.bin.nodes.size(); ++i) {
    BNode& n = a.bin.nodes[i];
    if (!n.leaf()) continue;
    leaves.push_back(i);
    const std::uint32_t first = n.first;
    n.first = std::uint32_t(groups[n.kind]++);
    n.pad_ = 0;
    leaf_first.push_back(first);
  }
  fill_never(a.tri, groups[0] * 8);
  fill_never(a.sph, groups[1] * 8);
  fill_never(a.cyl, groups[2] * 8);
  fill_never(a.cone, groups[3] * 8);
  for (int k = 0; k < scene::kKinds; ++k) a.id[k].assign(groups[k] * 8, UINT32_MAX);
  auto write = [&](std::size_t lb, std::size_t le) {
    for (std::size_t l = lb; l < le; ++l) {
      const BNode& n = a.bin.nodes[leaves[l]];
      const Kind k = Kind(n.kind);
      const std::size_t base = std::size_t(n.first) * 8;
      for (std::uint32_t j = 0; j < n.count; ++j) {
        const scene::PrimRef r = refs[a.bin.order[leaf_first[l] + j]];
        switch (k) {
          case Kind::triangle: set_slot(a.tri, base + j, scene::tri_verts(s, r.index)); break;
          case Kind::sphere: set_slot(a.sph, base + j, scene::sphere_prim(s, r.index)); break;
          case Kind::cylinder: set_slot(a.cyl, base + j, scene::cylinder_prim(s, r.index)); break;
          case Kind::cone: set_slot(a.cone, base + j, scene::cone_prim(s, r.index)); break;
          case Kind::polygon: break;
          case Kind::csg: break;
        }
        a.id[int(k)][base + j] = r.index;
      }
    }
  };
  if (opt.parallel)
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 256), [&](const auto& r) { write(r.begin(), r.end()); });
  else
    write(0, leaves.size());
  std::vector<std::vector<Vec3f>> polys;
  for (std::uint32_t p : a.id[4])
    if (p != UINT32_MAX) polys.push_back(scene::polygon_vertices(s, p));
  // Polygons: one PolygonSoA over the leaf-ordered polygons; each leaf lane keeps its slot.
  if (!polys.empty()) {
    a.poly = PolygonSoA::build(polys);
    std::vector<std::uint32_t> slot_of(polys.size(), UINT32_MAX);
    for (std::size_t j = 0; j < a.poly.id.size(); ++j)
      if (a.poly.id[j] != UINT32_MAX) slot_of[a.poly.id[j]] = std::uint32_t(j);
    a.poly_slot.assign(a.id[4].size(), UINT32_MAX);
    std::size_t p = 0;
    for (std::size_t j = 0; j < a.id[4].size(); ++j)
      if (a.id[4][j] != UINT32_MAX) a.poly_slot[j] = slot_of[p++];
  }
  for (const auto& c : s.csgs) {
    a.csg_owner.push_back(c.tree);
    a.csg.push_back(c.tree.get());
  }
  a.reorder_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
  a.wide = collapse8(a.bin);
  a.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return a;
}

std::size_t Accel::bytes_prims() const {
  std::size_t b = tri.bytes() + sph.bytes() + cyl.bytes() + cone.bytes() + poly.bytes() + poly_slot.size() * 4;
  for (const CsgTree* t : csg) b += t->bytes() + sizeof(void*);
  for (const auto& v : id) b += v.size() * sizeof(std::uint32_t);
  return b;
}

BruteForce::BruteForce(const scene::Scene& s) {
  auto fill = [](auto& batch, std::vector<std::uint32_t>& ids) { ids = batch.id; ids.resize(batch.prims.size(), UINT32_MAX); };
  auto t = scene::triangle_verts_batch(s);
  fill(t, id[0]);
  tri = std::move(t.prims);
  auto sp = scene::sphere_batch(s);
  fill(sp, id[1]);
  sph = std::move(sp.prims);
  auto cy = scene::cylinder_batch(s);
  fill(cy, id[2]);
  cyl = std::move(cy.prims);
  auto co = scene::cone_batch(s);
  fill(co, id[3]);
  cone = std::move(co.prims);
  poly = scene::polygon_batch(s);
  id[5].clear();
  for (std::size_t i = 0; i < s.csgs.size(); ++i) {
    csg_owner.push_back(s.csgs[i].tree);
    csg.push_back(s.csgs[i].tree.get());
    id[5].push_back(std::uint32_t(i));
  }
  id[5].resize((id[5].size() + 7) / 8 * 8, UINT32_MAX);
}

}  // namespace rb::bvh
