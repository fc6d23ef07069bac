// Binned SAH builder (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"),
// parallel with TBB: subtrees are tasks, and large nodes bin and bound their primitives with
// parallel reductions.
#include "bvh/bvh.hpp"

#include "core/memory.hpp"
#include "core/par.hpp"
#include "core/spawn.hpp"

#include <immintrin.h>

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

// Boxes as two SSE registers (x, y, z, unused): binning grows 3 bins per primitive with 2
// min/max instructions each.
struct Box {
  __m128 lo = _mm_set1_ps(kInfF), hi = _mm_set1_ps(-kInfF);
  void grow(const Box& b) { lo = _mm_min_ps(lo, b.lo); hi = _mm_max_ps(hi, b.hi); }
  void grow(__m128 p) { lo = _mm_min_ps(lo, p); hi = _mm_max_ps(hi, p); }
  float l(int k) const { alignas(16) float v[4]; _mm_store_ps(v, lo); return v[k]; }
  float h(int k) const { alignas(16) float v[4]; _mm_store_ps(v, hi); return v[k]; }
  float area() const {
    alignas(16) float d[4];
    _mm_store_ps(d, _mm_sub_ps(hi, lo));
    if (!(d[0] >= 0)) return 0.f;
    return 2.f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
  }
};

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
  std::uint32_t id() const { return std::uint32_t(_mm_cvtsi128_si32(_mm_castps_si128(_mm_shuffle_ps(box.lo, box.lo, 3)))); }
  // Twice the box centre (the halving cancels in every use: bins and centroid bounds alike).
  __m128 centre2() const { return _mm_add_ps(box.lo, box.hi); }
};

struct Builder {
  const BuildOptions& opt;
  std::span<PrimRef> refs;
  const std::uint8_t* kind;
  BNode* nodes;  // room for 2 n nodes, each written once when the build claims it
  std::atomic<std::uint32_t> next{1};

  // Lane `axis` of v by a variable permute (through memory it waited on a store each time: the
  // partition asks twice per primitive).
  static float lane(__m128 v, int axis) { return _mm_cvtss_f32(_mm_permutevar_ps(v, _mm_set1_epi32(axis))); }
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
    const int b = int((lane(r.centre2(), axis) - clo) * scale);
    return std::clamp(b, 0, nb - 1);
  }

  void make_leaf(BNode& n, std::size_t begin, std::size_t end) {
    n.first = std::uint32_t(begin);
    n.count = std::uint16_t(end - begin);
    n.kind = kind_of(begin);
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
    float best_cost = kInfF;
    int best_axis = -1, best_bin = 0;
    if (!flat && depth < std::min(opt.max_depth, kMaxSahDepth)) {
      Bins bins(nb);
      float scale[3];
      for (int k = 0; k < 3; ++k) scale[k] = ext[k] > 0 ? float(nb) * (1.f - 1e-6f) / ext[k] : 0.f;
      const __m128 vclo = cbox.lo;
      const __m128 vscale = _mm_setr_ps(scale[0], scale[1], scale[2], 0.f);
      const __m128i vmax = _mm_set1_epi32(nb - 1), vzero = _mm_setzero_si128();
      auto body = [&](std::size_t b, std::size_t e, Bins& acc) {
        for (std::size_t i = b; i < e; ++i) {
          const Box& pb = refs[i].box;
          const __m128i bi = _mm_min_epi32(_mm_max_epi32(_mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(refs[i].centre2(), vclo), vscale)), vzero), vmax);
          alignas(16) int b3[4];
          _mm_store_si128(reinterpret_cast<__m128i*>(b3), bi);
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
          if (c < best_cost) { best_cost = c; best_axis = k; best_bin = i; }
        }
      }
    }
    const float leaf_cost = opt.intersection_cost * blocks(n);
    if (n <= max_leaf && !mixed && (best_axis < 0 || leaf_cost <= best_cost)) { make_leaf(node, begin, end); return; }

    if (best_axis >= 0 && !(n <= max_leaf && mixed)) {
      const float scale = float(nb) * (1.f - 1e-6f) / ext[best_axis];
      const float clo = cbox.l(best_axis);
      // Partition and bound both sides in the same pass.
      std::size_t i = begin, j = end;
      for (;;) {
        while (i < j && bin_of(refs[i], best_axis, clo, scale, nb) <= best_bin) { lb.first.grow(refs[i].box); lb.second.grow(refs[i].centre2()); ++i; }
        while (i < j && bin_of(refs[j - 1], best_axis, clo, scale, nb) > best_bin) { rb.first.grow(refs[j - 1].box); rb.second.grow(refs[j - 1].centre2()); --j; }
        if (i >= j) break;
        std::swap(refs[i], refs[j - 1]);
      }
      mid = i;
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
                         [&](const PrimRef& a, const PrimRef& b) { return lane(a.centre2(), axis) < lane(b.centre2(), axis); });
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
  auto usable = [](const PrimRef& r) {
    const __m128 lo = r.box.lo, hi = r.box.hi;
    // lanes 0-2: finite (x - x == 0 fails for inf and NaN) and lo <= hi
    const __m128 ok = _mm_and_ps(_mm_and_ps(_mm_cmpeq_ps(_mm_sub_ps(lo, lo), _mm_setzero_ps()), _mm_cmpeq_ps(_mm_sub_ps(hi, hi), _mm_setzero_ps())),
                                 _mm_cmple_ps(lo, hi));
    return (_mm_movemask_ps(ok) & 7) == 7;
  };
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
        r.box.lo = _mm_castsi128_ps(_mm_insert_epi32(_mm_castps_si128(_mm_setr_ps(l[0], l[1], l[2], 0.f)), int(i), 3));
        r.box.hi = _mm_setr_ps(h[0], h[1], h[2], 0.f);
        if (usable(r)) {
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
      if (usable(rs[i])) rs[m++] = rs[i];
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
  // A row of 8 coordinates, moved out by 4 u (|c| + O) in double (4 lanes at a time), rounded to
  // float, and one float further out in the lanes where that rounding went inward (the same
  // arithmetic as one coordinate at a time, 48 at once per node instead of 48 nextafter calls).
  const __m256d k4u = _mm256_set1_pd(4 * 0x1p-24), O = _mm256_set1_pd(double(origin_bound));
  const __m256d abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7FFFFFFFFFFFFFFF));
  const __m256i evens = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
  auto out = [&]<bool Up>(__m256 row) {
    const __m256d c[2] = {_mm256_cvtps_pd(_mm256_castps256_ps128(row)), _mm256_cvtps_pd(_mm256_extractf128_ps(row, 1))};
    __m256d moved[2];
    __m128 f[2];
    __m128i inward[2];
    for (int h = 0; h < 2; ++h) {
      const __m256d d = _mm256_mul_pd(k4u, _mm256_add_pd(_mm256_and_pd(c[h], abs_mask), O));
      moved[h] = Up ? _mm256_add_pd(c[h], d) : _mm256_sub_pd(c[h], d);
      f[h] = _mm256_cvtpd_ps(moved[h]);
      const __m256d back = _mm256_cvtps_pd(f[h]);
      const __m256d in = Up ? _mm256_cmp_pd(back, moved[h], _CMP_LT_OQ) : _mm256_cmp_pd(back, moved[h], _CMP_GT_OQ);
      inward[h] = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(in), evens));  // -1 where inward
    }
    const __m256i in8 = _mm256_set_m128i(inward[1], inward[0]);
    const __m256 rounded = _mm256_set_m128(f[1], f[0]);
    // (Only those lanes: stepping by 0 would also turn -0 into +0.)
    return _mm256_blendv_ps(rounded, spawn::step_floats8(rounded, Up ? _mm256_sub_epi32(_mm256_setzero_si256(), in8) : in8),
                            _mm256_castsi256_ps(in8));
  };
  auto widen = [&](WNode& n) {
    // Empty slots keep their inverted boxes (lo = +inf, hi = -inf).
    const __m256 empty = _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(n.child)),
                                                                _mm256_set1_epi32(int(kEmpty))));
    for (int a = 0; a < 3; ++a) {
      float* lo = n.b[2 * a];
      float* hi = n.b[2 * a + 1];
      const __m256 l = _mm256_loadu_ps(lo), h = _mm256_loadu_ps(hi);
      _mm256_storeu_ps(lo, _mm256_blendv_ps(out.template operator()<false>(l), l, empty));
      _mm256_storeu_ps(hi, _mm256_blendv_ps(out.template operator()<true>(h), h, empty));
    }
  };
  par::for_range(0, t.nodes.size(), 1024, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) widen(t.nodes[i]);
  });
  t.origin_bound = origin_bound;
}

}  // namespace rb::bvh
