// SceneAccel::build: boxes in the frame -> binned SAH -> batches in leaf order -> 8-wide collapse
// -> conservative boxes; the leaf sources; surfaces and spawn points.
#include "tracer/accel.hpp"

#include "core/spawn.hpp"
#include "tracer/simd16.hpp"

#include "core/par.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <stdexcept>
#include <string>

namespace rb::tracer {

namespace {

// The batch in leaf order: slot j holds scene primitive ids[j] (a padding slot, UINT32_MAX, the
// kind's never-hit filler). Written slot by slot in parallel chunks of whole groups, so that one
// thread fills each group's block: made in scene order and scattered to their slots, the
// primitives of one group came from different chunks and two threads wrote into the same cache
// lines (at two threads this pass took longer than at one). Read in leaf order, a mesh's
// triangles and vertices are fetched ahead (the kind's prefetch_input, when it has one), 16 and 8
// slots before they are made: without that the slot order cost a tenth of the build on a scanned
// mesh whose vertex order is not the leaves'.
template <class K>
void build_std(StdBatch<K>& b, const scene::Scene& s, kinds::SlotIds ids, const Vec3d& origin, bool store64, bool parallel) {
  b.id = std::move(ids);
  const std::size_t n = b.id.size();
  auto fill = [&](auto& soa, auto tag) {
    using S = decltype(tag);
    soa.allocate(n);  // every slot written once below
    const auto never = K::template Prim<S>::never();
    const std::uint32_t* const id = b.id.data();
    auto write = [&](std::size_t lo, std::size_t hi) {
      for (std::size_t j = lo; j < hi; ++j) {
        if constexpr (requires { K::prefetch_input(s, 0u, 0); }) {
          if (j + 16 < hi && id[j + 16] != UINT32_MAX) K::prefetch_input(s, id[j + 16], 0);
          if (j + 8 < hi && id[j + 8] != UINT32_MAX) K::prefetch_input(s, id[j + 8], 1);
        }
        soa.set(j, id[j] == UINT32_MAX ? never : K::template make<S>(s, id[j], origin));
      }
    };
    if (parallel && n > 4096)
      par::for_range(0, n / kPadLanes, 256, [&](std::size_t lo, std::size_t hi) { write(lo * kPadLanes, hi * kPadLanes); });
    else
      write(0, n);
  };
  bool s64 = false;
  if constexpr (K::methods[0].f64_storage) s64 = store64;
  if (s64) {
    if constexpr (K::methods[0].f64_storage) fill(b.f64, double{});
  } else {
    fill(b.f32, float{});
  }
}

// The primitives stored apart, in local frames (KindPlan::split_local): each group's origin is the
// centre of its primitives' box snapped to a grid of the box's size rounded up to a power of two
// (neighbouring groups of one size share it, and with it the rounding of their shared vertices and
// of the re-based ray: a mesh stays watertight across their leaves). A group is stored in float
// relative to it when every primitive's float step over its size there is within the plan's
// tolerance (tracer/profile.hpp, float_step_ratio), else in double (LocalFrame::deep).
template <class K>
void build_local(StdBatch<K>& b, const scene::Scene& s, kinds::SlotIds ids, const Plan& plan) {
  b.id = std::move(ids);
  const std::size_t n = b.id.size(), groups = n / 8;
  b.local.assign(groups, LocalFrame{});
  std::uint32_t deep = 0;
  for (std::size_t g = 0; g < groups; ++g) {
    scene::Bounds box;
    for (std::size_t j = 8 * g; j < 8 * g + 8; ++j)
      if (b.id[j] != UINT32_MAX) box.grow(K::bounds(s, b.id[j]));
    LocalFrame& f = b.local[g];
    if (box.empty() || !std::isfinite(box.lo.x + box.lo.y + box.lo.z + box.hi.x + box.hi.y + box.hi.z)) {
      f.deep = deep++;
      continue;
    }
    const Vec3d c = box.centre() - plan.origin, e = box.hi - box.lo;
    const double cell = std::ldexp(1.0, std::ilogb(std::max({e.x, e.y, e.z, 0x1p-1000})) + 1);
    f.origin = {std::nearbyint(c.x / cell) * cell, std::nearbyint(c.y / cell) * cell, std::nearbyint(c.z / cell) * cell};
    bool holds = true;
    for (std::size_t j = 8 * g; j < 8 * g + 8 && holds; ++j)
      if (b.id[j] != UINT32_MAX)
        holds = float_step_ratio(K::bounds(s, b.id[j]), K::feature(s, b.id[j]), plan.origin + f.origin, plan.object_min) <=
                kFloatTolerance;
    if (!holds) {
      f.deep = deep++;
      continue;
    }
    const Vec3d lo = box.lo - plan.origin - f.origin, hi = box.hi - plan.origin - f.origin;
    b.local_reach = std::max({b.local_reach, std::fabs(lo.x), std::fabs(lo.y), std::fabs(lo.z), std::fabs(hi.x), std::fabs(hi.y),
                              std::fabs(hi.z)});
  }
  b.f32.allocate(n);
  b.f64.allocate(std::size_t(deep) * 8);
  const auto never32 = K::template Prim<float>::never();
  const auto never64 = K::template Prim<double>::never();
  for (std::size_t g = 0; g < groups; ++g) {
    const LocalFrame& f = b.local[g];
    for (std::size_t l = 0; l < 8; ++l) {
      const std::uint32_t id = b.id[8 * g + l];
      if (f.deep == UINT32_MAX) {
        b.f32.set(8 * g + l, id == UINT32_MAX ? never32 : K::template make<float>(s, id, plan.origin + f.origin));
      } else {
        b.f32.set(8 * g + l, never32);
        b.f64.set(8 * std::size_t(f.deep) + l, id == UINT32_MAX ? never64 : K::template make<double>(s, id, plan.origin));
      }
    }
  }
}

}  // namespace

SceneAccel::SceneAccel(SceneAccel&& o) noexcept { *this = std::move(o); }
SceneAccel& SceneAccel::operator=(SceneAccel&& o) noexcept {
  bin = std::move(o.bin);
  wide = std::move(o.wide);
  options = o.options;
  build_ms = o.build_ms;
  reorder_ms = o.reorder_ms;
  scene_ = o.scene_;
  plan_ = std::move(o.plan_);
  scene_prims_ = o.scene_prims_;
  batches_ = std::move(o.batches_);
  apart_ = std::move(o.apart_);
  fns_ = o.fns_;
  mesh_only_ = o.mesh_only_;
  wire();
  return *this;
}

void SceneAccel::wire() {
  table_ = {};
  table_.fns = fns_.data();
  AllKinds::each([&]<class K>() {
    auto slots = [](const void* p, std::size_t base) { return real_slots(*static_cast<const Batch<K>*>(p), base); };
    table_.batch[std::size_t(K::id)] = &std::get<Batch<K>>(batches_);
    table_.batch[std::size_t(apart_tag(K::id))] = &std::get<Batch<K>>(apart_);
    table_.slots_fn[std::size_t(K::id)] = table_.slots_fn[std::size_t(apart_tag(K::id))] = slots;
  });
  mesh_.tri = &std::get<Batch<kinds::TriangleKind>>(batches_);
  mesh_.apart = &std::get<Batch<kinds::TriangleKind>>(apart_);
}

void SceneAccel::check_size(const scene::Scene& s, const bvh::BuildOptions& opt) {
  // A leaf reference holds 27 bits of group number, a hit 28 bits of index within its kind.
  if (s.primitive_count() > bvh::kLeafGroupMask)
    throw std::length_error("the scene has " + std::to_string(s.primitive_count()) + " primitives; the tracer takes at most " +
                            std::to_string(bvh::kLeafGroupMask));
  const std::size_t need = s.primitive_count() * bvh::kBuildBytesPerPrim;
  if (opt.max_bytes && need > opt.max_bytes)
    throw std::length_error("the BVH of " + std::to_string(s.primitive_count()) + " primitives needs about " +
                            std::to_string(need >> 20) + " MiB, above the limit of " + std::to_string(opt.max_bytes >> 20) + " MiB");
}

namespace {

// Every primitive: its leaf tag (its kind, or apart_tag(kind) when the plan stores it apart) and
// scene index, kinds in Kind order, each in scene order.
struct LeafTags {
  std::vector<std::uint8_t> kind;
  std::vector<std::uint32_t> index;
};
LeafTags leaf_tags(const scene::Scene& s, const Plan& plan) {
  LeafTags t;
  t.kind.reserve(s.primitive_count());
  t.index.reserve(s.primitive_count());
  AllKinds::each([&]<class K>() {
    const std::vector<std::uint32_t>& apart = plan.kinds[std::size_t(K::id)].split;  // ascending, as K::each
    std::size_t next = 0;
    K::each(s, [&](std::uint32_t i) {
      const bool away = next < apart.size() && apart[next] == i;
      next += away;
      t.kind.push_back(std::uint8_t(away ? apart_tag(K::id) : int(K::id)));
      t.index.push_back(i);
    });
  });
  return t;
}

// The binary tree over the primitives' boxes in the frame (rounded outward to float), made as the
// builder asks for them; another builder (Embree's) takes them as arrays.
bvh::Bvh2 build_binary(const scene::Scene& s, const LeafTags& t, const Vec3d& origin, const bvh::BuildOptions& opt,
                       const BinaryBuilder& builder) {
  const bvh::BoxFill boxes = [&](std::size_t b, std::size_t e, float* lo, float* hi) {
    for (std::size_t i = b; i < e; ++i) {
      const scene::Bounds wb = AllKinds::at<scene::Bounds>(tag_kind(t.kind[i]), [&]<class K>() { return K::bounds(s, t.index[i]); });
      kinds::frame_box(wb, origin, &lo[3 * (i - b)], &hi[3 * (i - b)]);
    }
  };
  bvh::BuildOptions bopt = opt;
  bopt.stats = false;  // made once the build is timed
  if (!builder) return bvh::build_sah(t.kind.size(), boxes, t.kind, bopt);
  std::vector<float> lo(3 * t.kind.size()), hi(3 * t.kind.size());
  auto fill = [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; c += bvh::kBoxChunk) boxes(c, std::min(e, c + bvh::kBoxChunk), &lo[3 * c], &hi[3 * c]);
  };
  if (opt.parallel) par::for_range(0, t.kind.size(), 4096, fill);
  else fill(0, t.kind.size());
  return builder(lo, hi, t.kind, bopt);
}

// Every leaf becomes one 8-slot group of its kind's batch, groups numbered in node order; the
// result's [kind][slot] is the scene index of each slot. In parallel: each chunk of nodes counts
// its leaves per kind, a prefix over the chunks gives each chunk its first group per kind, and the
// chunks then number their leaves (the same numbers as one pass in node order).
std::array<kinds::SlotIds, kLeafKinds> number_leaves(bvh::Bvh2& bin, const std::vector<std::uint32_t>& index, bool parallel) {
  constexpr std::size_t kNodeChunk = 8192;
  const std::size_t nn = bin.nodes.size(), chunks = (nn + kNodeChunk - 1) / kNodeChunk;
  using Counts = std::array<std::uint32_t, kLeafKinds>;
  std::vector<Counts> first(chunks + 1, Counts{});  // first[c][k]: groups of kind k before chunk c
  auto by_chunk = [&](auto&& f) {
    auto body = [&](std::size_t c0, std::size_t c1) {
      for (std::size_t c = c0; c < c1; ++c) f(c, c * kNodeChunk, std::min(nn, (c + 1) * kNodeChunk));
    };
    if (parallel) par::for_range(0, chunks, 1, body);
    else body(0, chunks);
  };
  by_chunk([&](std::size_t c, std::size_t b, std::size_t e) {  // (internal nodes have kind 0 and add 0)
    for (std::size_t i = b; i < e; ++i) first[c + 1][bin.nodes[i].kind] += bin.nodes[i].leaf();
  });
  for (std::size_t c = 0; c < chunks; ++c)
    for (std::size_t k = 0; k < kLeafKinds; ++k) first[c + 1][k] += first[c][k];
  std::array<kinds::SlotIds, kLeafKinds> ids;
  for (std::size_t k = 0; k < kLeafKinds; ++k) ids[k].assign(std::size_t(first[chunks][k]) * 8, UINT32_MAX);  // sized once
  by_chunk([&](std::size_t c, std::size_t b, std::size_t e) {
    Counts g = first[c];
    for (std::size_t i = b; i < e; ++i) {
      bvh::BNode& n = bin.nodes[i];
      if (!n.leaf()) continue;
      const std::uint32_t from = n.first;
      n.first = g[n.kind]++;
      n.pad_ = 0;
      std::uint32_t* v = ids[n.kind].data() + std::size_t(n.first) * 8;
      for (std::uint32_t j = 0; j < n.count; ++j) v[j] = index[bin.order[from + j]];
    }
  });
  return ids;
}

}  // namespace

SceneAccel SceneAccel::build(const scene::Scene& s, const Plan& plan, const bvh::BuildOptions& opt, const BinaryBuilder& builder) {
  const auto t0 = std::chrono::steady_clock::now();
  SceneAccel a;
  a.scene_ = &s;
  a.plan_ = plan;
  a.options = opt;
  check_size(s, opt);
  const LeafTags tags = leaf_tags(s, plan);
  a.scene_prims_ = tags.kind.size();
  const Vec3d origin = plan.origin;
  a.bin = build_binary(s, tags, origin, opt, builder);
  const auto t1 = std::chrono::steady_clock::now();
  std::array<kinds::SlotIds, kLeafKinds> ids = number_leaves(a.bin, tags.index, opt.parallel);
  // The batches, and the 8-wide tree with its conservative boxes: independent (both read the
  // renumbered binary tree), side by side.
  std::array<LeafChoice, kKinds> choice{};
  std::array<int, kKinds> apart{};
  auto batches = [&] {
    AllKinds::each([&]<class K>() {
      const KindPlan& kp = plan.kinds[std::size_t(K::id)];
      choice[std::size_t(K::id)] = {kp.method, kp.f64, kp.f64_storage};
      apart[std::size_t(K::id)] = kp.split_method;
      auto& b = std::get<Batch<K>>(a.batches_);
      auto& v = ids[std::size_t(K::id)];
      if constexpr (K::custom) {
        K::build(b, s, std::move(v), origin, kp.method, kp.f64, kp.f64_storage);
      } else {
        build_std<K>(b, s, std::move(v), origin, kp.f64_storage, opt.parallel);
        auto& apart_b = std::get<Batch<K>>(a.apart_);
        auto& apart_ids = ids[std::size_t(apart_tag(K::id))];
        if constexpr (K::methods[0].f64_storage)  // (only kinds that store double have primitives apart)
          if (kp.split_local) return build_local<K>(apart_b, s, std::move(apart_ids), plan);
        build_std<K>(apart_b, s, std::move(apart_ids), origin, true, opt.parallel);
      }
    });
    a.reorder_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
  };
  auto wide = [&] {
    a.wide = bvh::collapse8(a.bin);
    bvh::make_conservative(a.wide, plan.origin_bound);
  };
  if (opt.parallel) {
    par::invoke(batches, wide);
  } else {
    batches();
    wide();
  }
  const auto main_fns = leaf_table(choice), apart_fns = apart_table(apart);
  std::copy(main_fns.begin(), main_fns.end(), a.fns_.begin());
  std::copy(apart_fns.begin(), apart_fns.end(), a.fns_.begin() + kKinds);
  std::size_t present = 0;
  AllKinds::each([&]<class K>() { present += K::count(s) > 0; });
  const KindPlan& tri = plan.kinds[std::size_t(Kind::triangle)];
  a.mesh_only_ = present == 1 && kinds::TriangleKind::count(s) > 0 && tri.method == 0 && !tri.f64 && !tri.f64_storage &&
                 (tri.split.empty() || tri.split_method == 0);
  a.wire();
  a.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  // The binary tree's statistics (SAH cost, depth, leaf sizes) describe the build and are not part
  // of it: made after the clock stops, as for Embree's tree (bench/embree_build.cpp).
  if (opt.stats) bvh::tree_stats(a.bin, opt);
  return a;
}

std::size_t SceneAccel::kind_bytes(Kind k) const {
  return AllKinds::at<std::size_t>(k, [&]<class K>() { return std::get<Batch<K>>(batches_).bytes() + std::get<Batch<K>>(apart_).bytes(); });
}
double SceneAccel::apart_reach(Kind k) const {
  return AllKinds::at<double>(k, [&]<class K>() {
    if constexpr (K::custom) return 0.0;
    else return std::get<Batch<K>>(apart_).local_reach;
  });
}
std::size_t SceneAccel::apart_deep(Kind k) const {
  return AllKinds::at<std::size_t>(k, [&]<class K>() {
    std::size_t n = 0;
    if constexpr (!K::custom) {
      const auto& b = std::get<Batch<K>>(apart_);
      if (b.local.empty()) return b.id.size() - std::size_t(std::count(b.id.begin(), b.id.end(), UINT32_MAX));
      for (std::size_t g = 0; g < b.local.size(); ++g)
        if (b.local[g].deep != UINT32_MAX) n += real_slots(b, 8 * g);
    }
    return n;
  });
}
std::size_t SceneAccel::apart_bytes(Kind k) const {
  return AllKinds::at<std::size_t>(k, [&]<class K>() { return std::get<Batch<K>>(apart_).bytes(); });
}
std::uint32_t SceneAccel::slot_id(int tag, std::size_t slot) const {
  if (tag < 0 || tag >= kLeafKinds) return UINT32_MAX;
  return AllKinds::at<std::uint32_t>(tag_kind(tag), [&]<class K>() {
    const auto& b = std::get<Batch<K>>(tag < kKinds ? batches_ : apart_);
    return slot < b.id.size() ? b.id[slot] : UINT32_MAX;
  });
}
bool SceneAccel::stored_apart(Kind k, std::uint32_t index) const {
  const auto& v = plan_.kinds[std::size_t(k)].split;
  return std::binary_search(v.begin(), v.end(), index);
}

std::size_t SceneAccel::bytes_prims() const {
  std::size_t b = 0;
  for (int k = 0; k < kKinds; ++k) b += kind_bytes(Kind(k));
  return b;
}

Ray<float> SceneAccel::frame_ray(const Vec3d& o, const Vec3d& d, double tmin, double tmax) const {
  return make_ray(o - plan_.origin, d, tmin, tmax);
}

namespace {
// Each kind's surface rule by Kind, called so that the Surface is built in place where the caller
// keeps it (a rule picked in a fold over the kinds was built in a temporary and copied whole: wide
// loads of fields just written one by one, a store-forwarding stall per hit).
using SurfaceRule = kinds::Surface (*)(const kinds::HitQuery&, std::uint32_t);
template <class... K>
constexpr std::array<SurfaceRule, sizeof...(K)> surface_rules(const kinds::KindList<K...>*) {
  return {&K::surface...};
}
constexpr auto kSurfaceRules = surface_rules(static_cast<const AllKinds*>(nullptr));

// What a kind's rule is given of hit h of the frame ray r (the world point p, the kind's batch),
// written field by field into the caller's query rather than built and returned, so that no copy of
// the whole struct follows the stores (wide loads of fields just stored one by one stall, as the
// Surface's copy did). surface() compiles to the same instructions as with the fields set inline.
RB_INLINE void fill_query(kinds::HitQuery& q, const scene::Scene* s, const Vec3d& origin, const void* batch, const bvh::HitRec& h,
                          const Ray<float>& r, const Vec3d& p) {
  q.scene = s;
  q.origin = origin;
  q.ray = r;
  q.t = h.t;
  q.p = p;
  q.aux = h.aux;
  q.batch = batch;
}
}  // namespace

kinds::Surface SceneAccel::surface(const bvh::HitRec& h, const Ray<float>& r) const {
  const std::uint32_t prim = h.prim;
  const Kind k = kinds::kind_of(prim);
  if (std::size_t(k) >= kSurfaceRules.size()) return {};  // a miss, or a code of no kind
  // The hit's surface, built where the caller keeps it: one named Surface returned from a body with
  // no other return, so that the rule writes it in place (with the miss's return beside it, the
  // compiler built it in a temporary and copied it whole: wide loads of fields the rule had just
  // written one by one, a store-forwarding stall per hit).
  return [&] {
    kinds::HitQuery q;
    fill_query(q, scene_, plan_.origin, table_.batch[std::size_t(k)], h, r, world_point(r, h.t));
    kinds::Surface sf = kSurfaceRules[std::size_t(k)](q, kinds::index_of(prim));
    // A primitive stored in float lies within a few roundings of its coordinates (and, for placed
    // ones, of its map's) from the double surface sf.p is on: 8 u (|p| + its extent), frame units,
    // u = 2^-24; one stored in double within as many double roundings (u = 2^-53).
    // The primitive's extent: the kind's own shortcut where it has one (kept in its batch, or fewer
    // square roots), else its feature's.
    const double ext = AllKinds::at<double>(k, [&]<class K>() {
      if constexpr (requires { K::extent(q, 0u); }) return K::extent(q, kinds::index_of(prim));
      else return K::feature(*scene_, kinds::index_of(prim)).extent;
    });
    const Vec3d pf = sf.p - plan_.origin;
    const bool apart = stored_apart(k, kinds::index_of(prim));
    const double u = plan_.kinds[std::size_t(k)].f64_storage || (apart && !plan_.kinds[std::size_t(k)].split_local) ? 0x1p-53 : 0x1p-24;
    // In a local frame, the coordinates rounded are those relative to the leaf's origin (at most
    // the batch's reach): the double error of its deep leaves is far below that bound.
    const double mag = apart && plan_.kinds[std::size_t(k)].split_local ? apart_reach(k)
                                                                         : std::max({std::fabs(pf.x), std::fabs(pf.y), std::fabs(pf.z)});
    sf.err = 8 * u * (mag + (std::isfinite(ext) ? ext : 0.0));
    return sf;
  }();
}

std::uint32_t SceneAccel::material(const bvh::HitRec& h, const Ray<float>& r) const {
  const Kind k = kinds::kind_of(h.prim);
  if (std::size_t(k) >= kSurfaceRules.size()) return 0;
  const std::uint32_t i = kinds::index_of(h.prim);
  return AllKinds::at<std::uint32_t>(k, [&]<class K>() -> std::uint32_t {
    if constexpr (requires(const kinds::HitQuery& q) { K::hit_material(q, 0u); }) {
      kinds::HitQuery q;
      fill_query(q, scene_, plan_.origin, table_.batch[std::size_t(k)], h, r, world_point(r, h.t));
      return K::hit_material(q, i);
    } else {
      return K::material(*scene_, i);
    }
  });
}

SceneAccel::SpawnBase SceneAccel::spawn_base(const kinds::Surface& sf) const {
  SpawnBase b;
  b.p = to_frame(sf.p);
  b.ng = sf.ng;
  const Vec3f& p = b.p;
  if (plan_.spawn == SpawnScheme::error_bound) {
    // sf.p is the hit point projected onto the surface in double (tracer/kinds.hpp: within a few
    // double roundings of it), so the error of the float point is its rounding to float plus the
    // double error, bounded here by 2^-40 of the coordinate, plus how far the traced primitive may
    // lie from that surface (sf.err: its storage's rounding at this hit). All of this hit's own:
    // a ball resting on a planet keeps its offsets at the ball's scale.
    const Vec3d pd = sf.p - plan_.origin;
    auto err = [&](double x, float f) { return float(std::fabs(x - double(f)) + std::fabs(x) * 0x1p-40 + sf.err); };
    b.err = {err(pd.x, p.x), err(pd.y, p.y), err(pd.z, p.z)};
  }
  return b;
}

Vec3f SceneAccel::spawn_point(const SpawnBase& b, const Vec3f& dir) const {
  const Vec3f n = dot_fma(b.ng, dir) < 0.0f ? -b.ng : b.ng;
  switch (plan_.spawn) {
    case SpawnScheme::extent_eps: return spawn::eps_offset(b.p, n, plan_.spawn_eps);
    case SpawnScheme::error_bound: return spawn::bound_offset(b.p, b.err, n);
  }
  return b.p;
}

Vec3<f8> SceneAccel::spawn_point(const Vec3<f8>& p, const Vec3<f8>& err, const Vec3<f8>& ng, const Vec3<f8>& dir) const {
  const Vec3<f8> n = vselect3(dot_fma(ng, dir) < f8(0.0f), -ng, ng);
  switch (plan_.spawn) {
    case SpawnScheme::extent_eps: return spawn::eps_offset(p, n, f8(plan_.spawn_eps));
    case SpawnScheme::error_bound: return spawn::bound_offset(p, err, n);
  }
  return p;
}

Vec3f SceneAccel::spawn_point(const kinds::Surface& sf, const Vec3f& dir) const { return spawn_point(spawn_base(sf), dir); }

int SceneAccel::group_lanes(const TraceOptions& o) const {
  if (o.packet == 1) return 1;
  return o.lanes == 16 && simd16_traversal_runs() && mesh_only_ && o.packet >= 16 ? 16 : 8;
}

HitRec SceneAccel::brute_force(const Ray<float>& r, bool any) const {
  bvh::Closest h{r.tmax, kNoPrim};
  if (!(r.tmin <= r.tmax)) return {std::numeric_limits<float>::infinity(), kNoPrim};
  RayCache cache(r);
  for (int tag = 0; tag < kLeafKinds; ++tag) {
    const std::size_t slots = AllKinds::at<std::size_t>(tag_kind(tag), [&]<class K>() {
      return std::get<Batch<K>>(tag < kKinds ? batches_ : apart_).id.size();
    });
    for (std::size_t g = 0; g < slots; g += 8)
      if (fns_[std::size_t(tag)].single(table_.batch[tag], g, r, cache, h) && any) return bvh::finished(h, cache);
  }
  return bvh::finished(h, cache);
}

}  // namespace rb::tracer
