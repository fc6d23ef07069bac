#include "bench/embree_build.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <new>
#include <stdexcept>

namespace rb::trace {

bool is_builder_name(const std::string& s) { return s == "sah" || s == "embree" || s == "embree-high"; }

namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();

// A node of Embree's tree as its callbacks make it, in memory of Embree's thread-local allocator.
// A leaf holds references: indices into the reference arrays of Ctx.
struct ENode {
  unsigned kids = 0;  // internal: 1..2 children
  ENode* kid[2] = {nullptr, nullptr};
  std::size_t count = 0;  // leaf
  std::uint32_t* ref = nullptr;
};

// Every reference a leaf holds: its primitive (input index) and its box (a spatially split
// primitive has one reference per piece, each with the box of its piece).
struct Ctx {
  std::vector<float> lo, hi;  // 3 per reference
  std::vector<std::uint32_t> prim;
  std::atomic<std::size_t> next{0};
  std::atomic<bool> overflow{false};
  const SplitFn* split = nullptr;
};

void* create_node(RTCThreadLocalAllocator a, unsigned count, void*) {
  auto* n = new (rtcThreadLocalAlloc(a, sizeof(ENode), 16)) ENode{};
  n->kids = std::min(count, 2u);
  return n;
}
void set_children(void* np, void** kids, unsigned count, void*) {
  auto* n = static_cast<ENode*>(np);
  n->kids = std::min(count, 2u);
  for (unsigned k = 0; k < n->kids; ++k) n->kid[k] = static_cast<ENode*>(kids[k]);
}
// Child boxes are not kept: the writer recomputes every box from the references' boxes, the boxes
// Embree itself bounded its nodes with.
void set_bounds(void*, const RTCBounds**, unsigned, void*) {}

void* create_leaf(RTCThreadLocalAllocator a, const RTCBuildPrimitive* p, std::size_t n, void* user) {
  auto* ctx = static_cast<Ctx*>(user);
  void* mem = rtcThreadLocalAlloc(a, sizeof(ENode) + n * sizeof(std::uint32_t), 16);
  auto* leaf = new (mem) ENode{};
  leaf->count = n;
  leaf->ref = reinterpret_cast<std::uint32_t*>(static_cast<char*>(mem) + sizeof(ENode));
  const std::size_t base = ctx->next.fetch_add(n);
  if (base + n > ctx->prim.size()) {
    ctx->overflow = true;
    leaf->count = 0;
    return leaf;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t r = base + i;
    leaf->ref[i] = std::uint32_t(r);
    ctx->prim[r] = p[i].primID;
    ctx->lo[3 * r] = p[i].lower_x; ctx->lo[3 * r + 1] = p[i].lower_y; ctx->lo[3 * r + 2] = p[i].lower_z;
    ctx->hi[3 * r] = p[i].upper_x; ctx->hi[3 * r + 1] = p[i].upper_y; ctx->hi[3 * r + 2] = p[i].upper_z;
  }
  return leaf;
}

void split_prim(const RTCBuildPrimitive* p, unsigned dim, float pos, RTCBounds* l, RTCBounds* r, void* user) {
  const auto* ctx = static_cast<const Ctx*>(user);
  const float lo[3] = {p->lower_x, p->lower_y, p->lower_z}, hi[3] = {p->upper_x, p->upper_y, p->upper_z};
  float llo[3], lhi[3], rlo[3], rhi[3];
  (*ctx->split)(p->primID, int(dim), pos, lo, hi, llo, lhi, rlo, rhi);
  l->lower_x = llo[0]; l->lower_y = llo[1]; l->lower_z = llo[2]; l->upper_x = lhi[0]; l->upper_y = lhi[1]; l->upper_z = lhi[2];
  r->lower_x = rlo[0]; r->lower_y = rlo[1]; r->lower_z = rlo[2]; r->upper_x = rhi[0]; r->upper_y = rhi[1]; r->upper_z = rhi[2];
}

// Writes Embree's tree as bvh::Bvh2 nodes: node `at` for e, children appended side by side. A leaf
// of more than max_leaf references or of mixed kinds becomes a small subtree (split off by kind,
// then in halves), so that every leaf is one lane group of one kind.
struct Writer {
  const Ctx& ctx;
  const std::vector<std::uint8_t>& kind;
  std::size_t max_leaf;
  bvh::Bvh2& out;

  void box_of(std::uint32_t at, const std::uint32_t* refs, std::size_t n) {
    bvh::BNode& b = out.nodes[at];
    for (int k = 0; k < 3; ++k) { b.lo[k] = kInfF; b.hi[k] = -kInfF; }
    for (std::size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) {
        b.lo[k] = std::min(b.lo[k], ctx.lo[3 * refs[i] + std::size_t(k)]);
        b.hi[k] = std::max(b.hi[k], ctx.hi[3 * refs[i] + std::size_t(k)]);
      }
  }
  void union_of_children(std::uint32_t at) {
    bvh::BNode& b = out.nodes[at];
    const bvh::BNode &l = out.nodes[b.first], &r = out.nodes[b.first + 1];
    for (int k = 0; k < 3; ++k) { b.lo[k] = std::min(l.lo[k], r.lo[k]); b.hi[k] = std::max(l.hi[k], r.hi[k]); }
  }
  void internal(std::uint32_t at) {
    const auto c = std::uint32_t(out.nodes.size());
    out.nodes.resize(out.nodes.size() + 2);
    out.nodes[at].first = c;
    out.nodes[at].count = 0;
    out.nodes[at].kind = 0;
  }
  void leaf(std::uint32_t at, std::uint32_t* refs, std::size_t n) {
    bool mixed = false;
    for (std::size_t i = 1; i < n; ++i) mixed = mixed || kind[ctx.prim[refs[i]]] != kind[ctx.prim[refs[0]]];
    if (!mixed && n <= max_leaf) {
      box_of(at, refs, n);
      bvh::BNode& b = out.nodes[at];
      b.first = std::uint32_t(out.order.size());
      b.count = std::uint16_t(n);
      b.kind = kind[ctx.prim[refs[0]]];
      for (std::size_t i = 0; i < n; ++i) out.order.push_back(ctx.prim[refs[i]]);
      return;
    }
    std::size_t mid = n / 2;
    if (mixed) {
      const std::uint8_t k0 = kind[ctx.prim[refs[0]]];
      mid = std::size_t(std::stable_partition(refs, refs + n, [&](std::uint32_t r) { return kind[ctx.prim[r]] == k0; }) - refs);
    }
    internal(at);
    const std::uint32_t c = out.nodes[at].first;
    leaf(c, refs, mid);
    leaf(c + 1, refs + mid, n - mid);
    union_of_children(at);
  }
  void node(const ENode* e, std::uint32_t at) {
    if (e->kids == 0) {
      leaf(at, e->ref, e->count);
      return;
    }
    if (e->kids == 1) {
      node(e->kid[0], at);
      return;
    }
    internal(at);
    const std::uint32_t c = out.nodes[at].first;
    node(e->kid[0], c);
    node(e->kid[1], c + 1);
    union_of_children(at);
  }
};

}  // namespace

bvh::Bvh2 embree_binary_tree(std::span<const float> lo, std::span<const float> hi, const std::vector<std::uint8_t>& kind,
                             const bvh::BuildOptions& opt, EmbreeQuality q, int threads, const SplitFn& split) {
  const auto t0 = std::chrono::steady_clock::now();
  bvh::Bvh2 out;
  // The primitives Embree gets: as for build_sah, those with a finite, non-empty box.
  std::vector<RTCBuildPrimitive> prims;
  prims.reserve(kind.size());
  for (std::size_t i = 0; i < kind.size(); ++i) {
    bool ok = true;
    for (int k = 0; k < 3; ++k) {
      const float l = lo[3 * i + std::size_t(k)], h = hi[3 * i + std::size_t(k)];
      ok = ok && std::isfinite(l) && std::isfinite(h) && l <= h;
    }
    if (!ok) continue;
    RTCBuildPrimitive p;
    p.lower_x = lo[3 * i]; p.lower_y = lo[3 * i + 1]; p.lower_z = lo[3 * i + 2];
    p.upper_x = hi[3 * i]; p.upper_y = hi[3 * i + 1]; p.upper_z = hi[3 * i + 2];
    p.geomID = kind[i];
    p.primID = std::uint32_t(i);
    prims.push_back(p);
  }
  if (prims.empty()) {
    out.stats.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }
  const std::size_t n = prims.size();
  // High quality with a split callback: room for twice the references (Embree's spatial splits
  // fill the capacity beyond the primitive count).
  const bool spatial = q == EmbreeQuality::high && split;
  const std::size_t capacity = spatial ? 2 * n : n;
  prims.resize(capacity);
  Ctx ctx;
  ctx.lo.resize(3 * capacity);
  ctx.hi.resize(3 * capacity);
  ctx.prim.resize(capacity);
  ctx.split = spatial ? &split : nullptr;

  const std::string cfg = "threads=" + std::to_string(std::max(1, threads));
  RTCDevice dev = rtcNewDevice(cfg.c_str());
  if (!dev) throw std::runtime_error("Embree's builder: rtcNewDevice failed");
  RTCBVH tree = rtcNewBVH(dev);
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = q == EmbreeQuality::high ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM;
  args.maxBranchingFactor = 2;
  args.maxDepth = unsigned(std::max(opt.max_depth, 32));
  args.sahBlockSize = unsigned(std::max(1, opt.leaf_block));
  args.minLeafSize = 1;
  args.maxLeafSize = unsigned(std::clamp(opt.max_leaf, 1, 8));
  args.traversalCost = opt.traversal_cost;
  args.intersectionCost = opt.intersection_cost;
  args.bvh = tree;
  args.primitives = prims.data();
  args.primitiveCount = n;
  args.primitiveArrayCapacity = capacity;
  args.createNode = create_node;
  args.setNodeChildren = set_children;
  args.setNodeBounds = set_bounds;
  args.createLeaf = create_leaf;
  args.splitPrimitive = spatial ? split_prim : nullptr;
  args.userPtr = &ctx;
  auto* root = static_cast<ENode*>(rtcBuildBVH(&args));
  const bool failed = !root || rtcGetDeviceError(dev) != RTC_ERROR_NONE || ctx.overflow.load();
  if (!failed) {
    out.nodes.reserve(2 * n);
    out.order.reserve(ctx.next.load());
    out.nodes.emplace_back();
    Writer w{ctx, kind, std::size_t(std::clamp(opt.max_leaf, 1, 8)), out};
    w.node(root, 0);
  }
  rtcReleaseBVH(tree);
  rtcReleaseDevice(dev);
  if (failed) throw std::runtime_error("Embree's builder (rtcBuildBVH) reported an error");
  out.nodes.shrink_to_fit();
  out.stats.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (opt.stats) bvh::tree_stats(out, opt);
  return out;
}

tracer::BinaryBuilder embree_builder(const std::string& name, const scene::Scene& s, const tracer::Plan& plan, int threads) {
  if (name == "sah" || name.empty()) return {};
  if (!is_builder_name(name)) throw std::invalid_argument("unknown builder '" + name + "' (sah, embree, embree-high)");
  const EmbreeQuality q = name == "embree-high" ? EmbreeQuality::high : EmbreeQuality::medium;
  // Spatial splits for a scene of triangles only: there the input index is the triangle's index.
  SplitFn split;
  if (q == EmbreeQuality::high && s.primitive_count() == s.triangles.size() && !s.triangles.empty()) {
    const scene::Scene* sp = &s;
    const Vec3d origin = plan.origin;
    split = [sp, origin](std::uint32_t prim, int dim, float pos, const float lo[3], const float hi[3], float llo[3], float lhi[3],
                         float rlo[3], float rhi[3]) {
      // The triangle clipped at the plane, in double in the frame: each side's box is that of its
      // vertices and of the edges' crossings, rounded outward to float and kept within the box the
      // reference had.
      const auto& t = sp->triangles[prim].v;
      double v[3][3];
      for (int i = 0; i < 3; ++i) {
        const Vec3d p = sp->verts[t[std::size_t(i)]] - origin;
        v[i][0] = p.x; v[i][1] = p.y; v[i][2] = p.z;
      }
      double L[2][3], H[2][3];  // side 0 left, 1 right
      for (int sd = 0; sd < 2; ++sd)
        for (int k = 0; k < 3; ++k) { L[sd][k] = std::numeric_limits<double>::infinity(); H[sd][k] = -std::numeric_limits<double>::infinity(); }
      auto grow = [&](int sd, const double* p) {
        for (int k = 0; k < 3; ++k) { L[sd][k] = std::min(L[sd][k], p[k]); H[sd][k] = std::max(H[sd][k], p[k]); }
      };
      const double P = double(pos);
      for (int i = 0; i < 3; ++i) {
        const double* a = v[i];
        const double* b = v[(i + 1) % 3];
        if (a[dim] <= P) grow(0, a);
        if (a[dim] >= P) grow(1, a);
        if ((a[dim] < P && b[dim] > P) || (a[dim] > P && b[dim] < P)) {
          const double f = (P - a[dim]) / (b[dim] - a[dim]);
          double c[3];
          for (int k = 0; k < 3; ++k) c[k] = a[k] + f * (b[k] - a[k]);
          c[dim] = P;
          grow(0, c);
          grow(1, c);
        }
      }
      auto down = [](double x) { float f = float(x); if (double(f) > x) f = std::nextafter(f, -kInfF); return f; };
      auto up = [](double x) { float f = float(x); if (double(f) < x) f = std::nextafter(f, kInfF); return f; };
      for (int sd = 0; sd < 2; ++sd) {
        float* ol = sd ? rlo : llo;
        float* oh = sd ? rhi : lhi;
        const bool some = L[sd][0] <= H[sd][0];
        for (int k = 0; k < 3; ++k) {
          // A side with no part of the triangle (its box only straddled the plane) gets the flat box
          // of the plane within the reference's box: a valid box, tested in vain at worst.
          ol[k] = some ? std::max(lo[k], down(L[sd][k])) : lo[k];
          oh[k] = some ? std::min(hi[k], up(H[sd][k])) : hi[k];
          if (ol[k] > oh[k]) ol[k] = oh[k] = std::min(ol[k], hi[k]);
        }
        if (!some) ol[dim] = oh[dim] = std::clamp(pos, lo[dim], hi[dim]);
      }
      // Within the plane's side: the left box ends at pos, the right begins there.
      lhi[dim] = std::min(lhi[dim], std::max(lo[dim], pos));
      rlo[dim] = std::max(rlo[dim], std::min(hi[dim], pos));
    };
  }
  return [q, threads, split](std::span<const float> lo, std::span<const float> hi, const std::vector<std::uint8_t>& kind,
                             const bvh::BuildOptions& opt) { return embree_binary_tree(lo, hi, kind, opt, q, threads, split); };
}

}  // namespace rb::trace
