// Binned SAH builder (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"),
// parallel with TBB: subtrees are tasks, and large nodes bin and bound their primitives with
// parallel reductions.
#include "bvh/bvh.hpp"

#include "core/box4.hpp"
#include "core/lanes.hpp"
#include "core/memory.hpp"
#include "core/par.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>

namespace rb::bvh {

namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();
constexpr std::size_t kParallelNode = 16384;  // primitives above which a node bins in parallel
constexpr std::size_t kTaskNode = 4096;       // primitives above which a child subtree is a task
constexpr int kMaxBins = 64;

// Boxes as two SSE registers (core/box4.hpp): binning grows 3 bins per primitive with 2 min/max
// instructions each.
using Box = Box4;

struct Bin {
  Box box;
  std::uint32_t n = 0;
};
// The bins of the three axes. Only the first nb of each axis are made (by the constructor) and
// used: most nodes are small and use few of the 64, and making all of them (9 KB per node) took
// about a seventh of the builder's time.
struct Bins {
  alignas(Bin) unsigned char raw[3 * kMaxBins * sizeof(Bin)];
  explicit Bins(int nb) {
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < nb; ++i) new (raw + std::size_t(a * kMaxBins + i) * sizeof(Bin)) Bin{};
  }
  Bin& at(int a, int i) { return *std::launder(reinterpret_cast<Bin*>(raw + std::size_t(a * kMaxBins + i) * sizeof(Bin))); }
  const Bin& at(int a, int i) const {
    return *std::launder(reinterpret_cast<const Bin*>(raw + std::size_t(a * kMaxBins + i) * sizeof(Bin)));
  }
  void merge(const Bins& o, int nb) {
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < nb; ++i) { at(a, i).box.grow(o.at(a, i).box); at(a, i).n += o.at(a, i).n; }
  }
};

// One primitive as the builder moves it: its box (x, y, z in lanes 0-2) with the primitive's index
// in the low box's fourth lane. Partitions move these 32 bytes in place, so binning and
// partitioning read memory front to back instead of through an index array.
struct alignas(16) PrimRef {
  Box box;
  std::uint32_t id() const { return box.tag(); }
  // Twice the box centre (the halving cancels in every use: bins and centroid bounds alike).
  __m128 centre2() const { return box.centre2(); }
};

struct Builder {
  const BuildOptions& opt;
  std::span<PrimRef> refs;
  const std::uint8_t* kind;
  BNode* nodes;  // room for 2 n nodes, each written once when the build claims it
  std::atomic<std::uint32_t> next{1};

  std::uint8_t kind_of(std::size_t i) const { return kind[refs[i].id()]; }
  // Box and (doubled) centroid box of refs[begin, end).
  std::pair<Box, Box> bounds(std::size_t begin, std::size_t end) const {
    auto body = [&](std::size_t b, std::size_t e, std::pair<Box, Box> acc) {
      for (std::size_t i = b; i < e; ++i) {
        acc.first.grow(refs[i].box);
        acc.second.grow(refs[i].centre2());
      }
      return acc;
    };
    if (!opt.parallel || end - begin < kParallelNode) return body(begin, end, {});
    return par::reduce(begin, end, 4096, std::pair<Box, Box>{}, body, [](std::pair<Box, Box> a, const std::pair<Box, Box>& b) {
      a.first.grow(b.first);
      a.second.grow(b.second);
      return a;
    });
  }

  // SAH counts primitives in blocks of the leaf's lane group: a leaf of up to `leaf_block`
  // primitives is one kernel call.
  float blocks(std::size_t n) const {
    const std::size_t b = std::size_t(std::max(1, opt.leaf_block));
    return float((n + b - 1) / b);
  }
  static int bin_of(const PrimRef& r, int axis, float clo, float scale, int nb) {
    const int b = int((lane4(r.centre2(), axis) - clo) * scale);
    return std::clamp(b, 0, nb - 1);
  }

  void make_leaf(BNode& n, std::size_t begin, std::size_t end) {
    n.first = std::uint32_t(begin);
    n.count = std::uint16_t(end - begin);
    n.kind = kind_of(begin);
  }

  struct Split {
    float cost = kInfF;
    int axis = -1, bin = 0;  // axis -1: none
  };
  // The cheapest binned SAH split of refs[begin, end) (box `box`, centroid box `cbox` of extent
  // `ext`) over nb bins per axis.
  Split best_split(std::size_t begin, std::size_t end, const Box& box, const Box& cbox, const float ext[3], int nb) const {
    const std::size_t n = end - begin;
    Split best;
    Bins bins(nb);
    float scale[3];
    for (int k = 0; k < 3; ++k) scale[k] = ext[k] > 0 ? float(nb) * (1.f - 1e-6f) / ext[k] : 0.f;
    // Copies: the bins' stores could alias the box behind a reference, which would be read again
    // for every primitive.
    const __m128 vclo = cbox.lo, vscale = f4(scale[0], scale[1], scale[2]);
    auto body = [&](std::size_t b, std::size_t e, Bins& acc) {
      for (std::size_t i = b; i < e; ++i) {
        const Box& pb = refs[i].box;
        const std::array<int, 4> b3 = bins4(refs[i].centre2(), vclo, vscale, nb);
        for (int k = 0; k < 3; ++k) {
          Bin& bin = acc.at(k, b3[k]);
          bin.box.grow(pb);
          ++bin.n;
        }
      }
    };
    if (opt.parallel && n >= kParallelNode) {
      bins = par::reduce(
          begin, end, 4096, Bins(nb), [&](std::size_t b, std::size_t e, Bins acc) { body(b, e, acc); return acc; },
          [nb](Bins a, const Bins& b) { a.merge(b, nb); return a; });
    } else {
      body(begin, end, bins);
    }
    const float inv_area = box.area() > 0 ? 1.f / box.area() : 0.f;
    for (int k = 0; k < 3; ++k) {
      if (!(ext[k] > 0)) continue;
      std::array<float, kMaxBins> right_cost{};
      Box acc;
      std::uint32_t cnt = 0;
      for (int i = nb - 1; i > 0; --i) {
        acc.grow(bins.at(k, i).box);
        cnt += bins.at(k, i).n;
        right_cost[i] = acc.area() * blocks(cnt);
      }
      acc = Box{};
      cnt = 0;
      for (int i = 0; i < nb - 1; ++i) {
        acc.grow(bins.at(k, i).box);
        cnt += bins.at(k, i).n;
        if (cnt == 0 || cnt == n) continue;
        const float c = opt.traversal_cost + opt.intersection_cost * inv_area * (acc.area() * blocks(cnt) + right_cost[i + 1]);
        if (c < best.cost) best = {c, k, i};
      }
    }
    return best;
  }

  // Moves the refs of [begin, end) in bins <= s.bin on axis s.axis before the others and returns
  // where they end; both sides' boxes and centroid boxes are grown in the same pass.
  std::size_t partition(std::size_t begin, std::size_t end, const Split& s, float clo, float extent, int nb, std::pair<Box, Box>& lb,
                        std::pair<Box, Box>& rb) {
    const float scale = float(nb) * (1.f - 1e-6f) / extent;
    std::size_t i = begin, j = end;
    for (;;) {
      while (i < j && bin_of(refs[i], s.axis, clo, scale, nb) <= s.bin) { lb.first.grow(refs[i].box); lb.second.grow(refs[i].centre2()); ++i; }
      while (i < j && bin_of(refs[j - 1], s.axis, clo, scale, nb) > s.bin) { rb.first.grow(refs[j - 1].box); rb.second.grow(refs[j - 1].centre2()); --j; }
      if (i >= j) break;
      std::swap(refs[i], refs[j - 1]);
    }
    return i;
  }

  // Builds node `ni` over refs[begin, end) whose box is `box`. `may_mix`: the range may hold more
  // than one kind (false below a node that held one: its kinds are not scanned again).
  void build(std::uint32_t ni, std::size_t begin, std::size_t end, const Box& box, const Box& cbox, int depth, bool may_mix) {
    const std::size_t n = end - begin;
    BNode& node = nodes[ni];
    for (int k = 0; k < 3; ++k) { node.lo[k] = box.l(k); node.hi[k] = box.h(k); }
    node.pad_ = 0;
    bool mixed = false;
    const std::uint8_t k0 = kind_of(begin);
    if (may_mix)
      for (std::size_t i = begin + 1; i < end && !mixed; ++i) mixed = kind_of(i) != k0;
    const std::size_t max_leaf = std::size_t(std::max(1, std::min(opt.max_leaf, 8)));
    // With a visit cost at least one leaf call, a split of at most one lane group never beats a
    // leaf (split cost Ct + Ci (AL + AR) / A > Ci): no binning needed.
    const bool small = n <= max_leaf && n <= std::size_t(std::max(1, opt.leaf_block)) && opt.traversal_cost >= opt.intersection_cost;
    if (n == 1 || (small && !mixed)) { make_leaf(node, begin, end); return; }

    std::size_t mid = begin;
    std::pair<Box, Box> lb, rb;  // children's boxes and centroid boxes when the partition made them
    bool have_bounds = false;
    // Fewer bins for small nodes: their few centroids fill few bins anyway (docs/DESIGN.md section 12).
    const int nb = std::clamp(std::min(opt.bins, 8 + int(std::min<std::size_t>(n / 16, kMaxBins))), 2, kMaxBins);
    float ext[3];
    int axis = 0;
    for (int k = 0; k < 3; ++k) ext[k] = cbox.h(k) - cbox.l(k);
    if (ext[1] > ext[axis]) axis = 1;
    if (ext[2] > ext[axis]) axis = 2;
    const bool flat = !(ext[axis] > 0);
    Split best;
    if (!flat && depth < std::min(opt.max_depth, kMaxSahDepth)) best = best_split(begin, end, box, cbox, ext, nb);
    const float leaf_cost = opt.intersection_cost * blocks(n);
    if (n <= max_leaf && !mixed && (best.axis < 0 || leaf_cost <= best.cost)) { make_leaf(node, begin, end); return; }

    if (best.axis >= 0 && !(n <= max_leaf && mixed)) {
      mid = partition(begin, end, best, cbox.l(best.axis), ext[best.axis], nb, lb, rb);
      have_bounds = true;
    } else if (mixed) {
      // Split off the first primitive's kind (a leaf holds one kind).
      mid = std::size_t(std::stable_partition(refs.begin() + std::ptrdiff_t(begin), refs.begin() + std::ptrdiff_t(end),
                                              [&](const PrimRef& r) { return kind[r.id()] == k0; }) -
                        refs.begin());
    }
    if (mid <= begin || mid >= end) {
      // No usable split (coincident centroids, or too deep): the object median on the widest axis.
      mid = begin + n / 2;
      have_bounds = false;
      if (!flat)
        std::nth_element(refs.begin() + std::ptrdiff_t(begin), refs.begin() + std::ptrdiff_t(mid), refs.begin() + std::ptrdiff_t(end),
                         [&](const PrimRef& a, const PrimRef& b) { return lane4(a.centre2(), axis) < lane4(b.centre2(), axis); });
    }
    const std::uint32_t c = next.fetch_add(2);
    node.first = c;
    node.count = 0;
    node.kind = 0;
    if (!have_bounds) {
      lb = bounds(begin, mid);
      rb = bounds(mid, end);
    }
    auto left = [&, c, begin, mid, depth, lb, mixed] { build(c, begin, mid, lb.first, lb.second, depth + 1, mixed); };
    auto right = [&, c, mid, end, depth, rb, mixed] { build(c + 1, mid, end, rb.first, rb.second, depth + 1, mixed); };
    if (opt.parallel && n >= kTaskNode) {
      par::invoke(left, right);
    } else {
      left();
      right();
    }
  }
};

}  // namespace

Bvh2 build_sah(std::size_t n, const BoxFill& boxes, const std::vector<std::uint8_t>& kind, const BuildOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  Bvh2 out;
  // One pass makes every primitive's reference at its own index from the boxes it is given (no
  // array of input boxes in between: on the 1M-triangle height field 24 MB less fresh memory and
  // one pass fewer), counts the unusable ones (an empty or non-finite box: left out, they never
  // hit) and finds the kinds of the usable ones (one kind: no node scans kinds). The pages of the
  // references are first written here, in parallel.
  uninit_array<PrimRef> refs_a(std::max<std::size_t>(n, 1));
  PrimRef* const rs = refs_a.data();
  struct Scan {
    std::size_t bad = 0;
    int kmin = 256, kmax = -1;
  };
  auto scan = [&](std::size_t b, std::size_t e, Scan acc) {
    alignas(16) float lo[3 * kBoxChunk], hi[3 * kBoxChunk];
    for (std::size_t c = b; c < e; c += kBoxChunk) {
      const std::size_t ce = std::min(e, c + kBoxChunk);
      boxes(c, ce, lo, hi);
      for (std::size_t i = c; i < ce; ++i) {
        const float* l = lo + 3 * (i - c);
        const float* h = hi + 3 * (i - c);
        PrimRef& r = rs[i];
        r.box = Box::of(l, h, std::uint32_t(i));
        if (r.box.usable()) {
          acc.kmin = std::min(acc.kmin, int(kind[i]));
          acc.kmax = std::max(acc.kmax, int(kind[i]));
        } else {
          ++acc.bad;
        }
      }
    }
    return acc;
  };
  const Scan sc = opt.parallel && n >= kParallelNode
                      ? par::reduce(std::size_t(0), n, 4096, Scan{}, scan,
                                    [](Scan a, const Scan& b) {
                                      a.bad += b.bad;
                                      a.kmin = std::min(a.kmin, b.kmin);
                                      a.kmax = std::max(a.kmax, b.kmax);
                                      return a;
                                    })
                      : scan(0, n, Scan{});
  std::size_t m = n;
  if (sc.bad) {  // rare: the usable references moved to the front, in order
    m = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (rs[i].box.usable()) rs[m++] = rs[i];
  }
  if (m == 0) {
    out.stats.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }
  const bool mixed = sc.kmin != sc.kmax;  // more than one kind among the kept primitives
  const std::span<PrimRef> refs(rs, m);
  // A binary tree over n leaves has 2 n - 1 nodes: the node array is sized to that without being
  // written (Bvh2::nodes), the build writes the nodes it claims, and the array is cut to them
  // (no copy; the pages past them are never touched).
  out.nodes.resize(2 * refs.size());
  Builder b{opt, refs, kind.data(), out.nodes.data()};
  const auto [box, cbox] = b.bounds(0, refs.size());
  b.build(0, 0, refs.size(), box, cbox, 0, mixed);
  out.nodes.resize(b.next.load());
  out.order.resize(m);
  auto ids = [&](std::size_t from, std::size_t to) {
    for (std::size_t j = from; j < to; ++j) out.order[j] = refs[j].id();
  };
  if (opt.parallel && m >= kParallelNode)
    par::for_range(0, m, 4096, ids);
  else
    ids(0, m);
  out.stats.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (opt.stats) tree_stats(out, opt);
  return out;
}

Bvh2 build_sah(std::span<const float> lo, std::span<const float> hi, const std::vector<std::uint8_t>& kind,
               const BuildOptions& opt) {
  const BoxFill copy = [&](std::size_t b, std::size_t e, float* l, float* h) {
    std::copy(lo.begin() + std::ptrdiff_t(3 * b), lo.begin() + std::ptrdiff_t(3 * e), l);
    std::copy(hi.begin() + std::ptrdiff_t(3 * b), hi.begin() + std::ptrdiff_t(3 * e), h);
  };
  return build_sah(kind.size(), copy, kind, opt);
}

void tree_stats(Bvh2& b, const BuildOptions& opt) {
  BuildStats& s = b.stats;
  s.nodes = b.nodes.size();
  s.leaves = 0;
  s.prims = b.order.size();
  s.depth = 0;
  s.sah_cost = 0;
  s.leaf_hist.assign(9, 0);
  if (b.nodes.empty()) return;
  auto area = [](const BNode& n) {
    const float dx = n.hi[0] - n.lo[0], dy = n.hi[1] - n.lo[1], dz = n.hi[2] - n.lo[2];
    return 2.0 * (double(dx) * double(dy) + double(dy) * double(dz) + double(dz) * double(dx));
  };
  const double root = area(b.nodes[0]);
  std::vector<std::pair<std::uint32_t, int>> st{{0u, 1}};
  while (!st.empty()) {
    const auto [i, d] = st.back();
    st.pop_back();
    const BNode& n = b.nodes[i];
    s.depth = std::max(s.depth, d);
    const double rel = root > 0 ? area(n) / root : 1.0;
    if (n.leaf()) {
      ++s.leaves;
      if (n.count >= s.leaf_hist.size()) s.leaf_hist.resize(n.count + 1u, 0);
      ++s.leaf_hist[n.count];
      s.sah_cost += rel * double(opt.intersection_cost) * double((n.count + std::max(1, opt.leaf_block) - 1) / std::max(1, opt.leaf_block));
    } else {
      s.sah_cost += rel * double(opt.traversal_cost);
      st.push_back({n.first, d + 1});
      st.push_back({n.first + 1, d + 1});
    }
  }
}

Bvh8 collapse8(const Bvh2& b) {
  const auto t0 = std::chrono::steady_clock::now();
  Bvh8 w;
  if (b.nodes.empty()) return w;
  auto ref_of_leaf = [](const BNode& n) { return make_leaf_ref(n.kind, n.first); };
  if (b.nodes[0].leaf()) {
    w.root = ref_of_leaf(b.nodes[0]);
    // A one-leaf tree still gets a wide root holding that leaf, so traversal has one entry point.
  }
  auto area = [](const BNode& n) {
    const float dx = n.hi[0] - n.lo[0], dy = n.hi[1] - n.lo[1], dz = n.hi[2] - n.lo[2];
    return dx * dy + dy * dz + dz * dx;
  };
  // Work list: (binary node, wide node index to fill, its depth).
  struct Work {
    std::uint32_t bi, wi;
    int depth;
  };
  std::vector<Work> work;
  w.nodes.reserve(b.nodes.size() / 4 + 1);
  w.nodes.emplace_back();
  work.push_back({0u, 0u, 1});
  while (!work.empty()) {
    const auto [bi, wi, depth] = work.back();
    work.pop_back();
    w.depth = std::max(w.depth, depth);
    std::uint32_t kids[8];
    int nk = 0;
    if (b.nodes[bi].leaf()) {
      kids[nk++] = bi;
    } else {
      kids[nk++] = b.nodes[bi].first;
      kids[nk++] = b.nodes[bi].first + 1;
      while (nk < 8) {
        int best = -1;
        float ba = -1;
        for (int k = 0; k < nk; ++k)
          if (!b.nodes[kids[k]].leaf() && area(b.nodes[kids[k]]) > ba) { ba = area(b.nodes[kids[k]]); best = k; }
        if (best < 0) break;
        const std::uint32_t open = kids[best];
        kids[best] = b.nodes[open].first;
        kids[nk++] = b.nodes[open].first + 1;
      }
    }
    WNode node;
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 8; ++c) { node.b[2 * a][c] = kInfF; node.b[2 * a + 1][c] = -kInfF; }
    for (int c = 0; c < 8; ++c) node.child[c] = kEmpty;
    for (int k = 0; k < nk; ++k) {
      const BNode& n = b.nodes[kids[k]];
      for (int a = 0; a < 3; ++a) { node.b[2 * a][k] = n.lo[a]; node.b[2 * a + 1][k] = n.hi[a]; }
      if (n.leaf()) {
        node.child[k] = ref_of_leaf(n);
      } else {
        const auto ci = std::uint32_t(w.nodes.size());
        w.nodes.emplace_back();
        node.child[k] = ci;
        work.push_back({kids[k], ci, depth + 1});
      }
    }
    w.nodes[wi] = node;
  }
  if (w.depth > kMaxTreeDepth)
    throw std::length_error("the BVH is " + std::to_string(w.depth) + " wide levels deep; the traversal serves at most " +
                            std::to_string(kMaxTreeDepth));
  w.root = 0;
  w.collapse_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return w;
}

void make_conservative(Bvh8& t, float origin_bound) {
  // Every child box rounded outward, a row of 8 coordinates at a time (lanes::round_outward: 48 at
  // once per node instead of 48 nextafter calls).
  auto widen = [&](WNode& n) {
    // Empty slots keep their inverted boxes (lo = +inf, hi = -inf).
    const f8_mask empty = lanes::of(lanes::equal_bits(n.child, kEmpty));
    for (int a = 0; a < 3; ++a) {
      float* lo = n.b[2 * a];
      float* hi = n.b[2 * a + 1];
      const f8 l = f8::load_unaligned(lo), h = f8::load_unaligned(hi);
      xsimd::select(empty, l, lanes::round_outward<false>(l, double(origin_bound))).store_unaligned(lo);
      xsimd::select(empty, h, lanes::round_outward<true>(h, double(origin_bound))).store_unaligned(hi);
    }
  };
  par::for_range(0, t.nodes.size(), 1024, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) widen(t.nodes[i]);
  });
  t.origin_bound = origin_bound;
}

}  // namespace rb::bvh
