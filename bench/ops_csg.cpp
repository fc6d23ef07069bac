// Operations per CSG query (kernels/csg_ray.hpp) on the embedded CSG scenes: the whole query (leaf
// lists, node boxes, merges) for a ray that hits and one that misses after passing the root's box,
// as Counted<float> and as the per-lane count of an 8-ray packet (Counted<simd8>). For the two
// two-sphere scenes the note splits the float count into the leaves, the boxes and the merge.
#include "bench/ops_detail.hpp"
#include "scene/csg_scene.hpp"

#include <fmt/format.h>

#include <map>

namespace rb::opstable {

namespace {

template <class F>
Ray<F> lanes_of(const Ray<float>& a, const Ray<float>& b) {  // lane 0 from a, the others from b
  if constexpr (lanes_v<F> == 1) {
    (void)b;
    return Ray<F>::broadcast(a);
  } else {
    alignas(32) float v[11][8];
    const float fa[11] = {a.o.x, a.o.y, a.o.z, a.d.x, a.d.y, a.d.z, a.rd.x, a.rd.y, a.rd.z, a.tmin, a.tmax};
    const float fb[11] = {b.o.x, b.o.y, b.o.z, b.d.x, b.d.y, b.d.z, b.rd.x, b.rd.y, b.rd.z, b.tmin, b.tmax};
    for (int k = 0; k < 11; ++k)
      for (int l = 0; l < 8; ++l) v[k][l] = l == 0 ? fa[k] : fb[k];
    using T = typename F::base::type;  // the batch inside Counted
    auto ld = [&](int k) { return F(T::load_aligned(v[k])); };
    return {{ld(0), ld(1), ld(2)}, {ld(3), ld(4), ld(5)}, {ld(6), ld(7), ld(8)}, ld(9), ld(10)};
  }
}

template <class F>
OpCounts count_query(const CsgTree& T, const Ray<float>& a, const Ray<float>& b) {
  const Ray<F> r = lanes_of<F>(a, b);
  const ops::Scope s;
  F tag;
  (void)csg_closest(T, r, tag);
  return s.elapsed();
}

OpCounts count_box(const CsgTree& T, const Ray<float>& r) {
  const ops::Scope s;
  const Ray<cfloat> c = Ray<cfloat>::broadcast(r);
  (void)detail::csg_box_test(T.nodes[T.root], c, c.tmin, c.tmax);
  return s.elapsed();
}
OpCounts count_leaf(const CsgTree& T, std::size_t i, const Ray<float>& r) {
  const ops::Scope s;
  Spans<cfloat> out;
  csg_leaf_spans(T.leaves[i], std::uint32_t(i), Ray<cfloat>::broadcast(r), out);
  return s.elapsed();
}

// A ray along -z that hits: the first of a few targets across the root's box.
bool find_ray(const CsgTree& T, bool want_hit, Ray<float>& out) {
  const CsgNode& n = T.nodes[T.root];
  const float cx = 0.5f * (n.lo[0] + n.hi[0]), cy = 0.5f * (n.lo[1] + n.hi[1]);
  const float ex = 0.5f * (n.hi[0] - n.lo[0]), ey = 0.5f * (n.hi[1] - n.lo[1]);
  for (float f : {0.05f, 0.2f, 0.35f, 0.5f, 0.65f, 0.8f, 0.9f, 0.97f})
    for (float g : {0.11f, -0.3f, 0.5f, 0.93f}) {
      // Misses: near the box's corner (inside the box, outside the solid); hits: near the centre.
      const float u = want_hit ? f * 0.5f : 0.97f, v = want_hit ? g * 0.5f : 0.97f * (g < 0 ? -1.0f : 1.0f);
      const Ray<float> r = make_ray(Vec3f{cx + u * ex, cy + v * ey, n.hi[2] + 5.0f}, Vec3f{0, 0, -1});
      float tag;
      if (csg_hit(T, r, tag).mask == want_hit) {
        out = r;
        return true;
      }
    }
  return false;
}

std::string leaf_mix(const CsgTree& T) {
  int placed = 0;
  std::map<std::string, int> kinds;
  for (const auto& l : T.leaves) {
    placed += l.placed;
    ++kinds[csg_leaf_name(l.kind)];
  }
  std::string s;
  for (const auto& [k, n] : kinds) s += fmt::format("{}{} {}", s.empty() ? "" : ", ", n, k);
  return fmt::format("{} leaves ({}), {} transformed: 15+- 18* per transformed leaf the query reaches (the slide's count for "
                     "1 transformation)", T.leaves.size(), s, placed);
}

}  // namespace

void add_csg_rows(std::vector<Row>& rows) {
  for (const std::string& name : scene::csg_scene_names()) {
    const scene::Scene sc = scene::csg_scene(name);
    const CsgTree& T = *sc.csgs[0].tree;
    Ray<float> hit, miss;
    if (!find_ray(T, true, hit) || !find_ray(T, false, miss)) continue;
    for (const bool h : {true, false}) {
      const Ray<float>& r = h ? hit : miss;
      const Ray<float>& other = h ? miss : hit;
      Row row;
      row.kernel = "csg";
      row.method = name;
      row.kase = h ? "hit" : "miss";
      row.number = "float";
      row.measured = count_query<cfloat>(T, r, r);
      std::string note = leaf_mix(T) + (h ? "; ray through the solid" : "; ray inside the root's box, missing the solid");
      if (T.leaves.size() == 2 && T.leaves[0].kind == CsgLeafKind::sphere && T.leaves[1].kind == CsgLeafKind::sphere) {
        OpCounts leaves = count_leaf(T, 0, r);
        if (h || T.nodes[T.root].op == CsgOp::unite) leaves += count_leaf(T, 1, r);
        const OpCounts box = count_box(T, r);
        const int boxes = h ? 3 : 2;  // root + each leaf evaluated
        OpCounts boxes_all;
        for (int k = 0; k < boxes; ++k) boxes_all += box;
        const OpCounts merge = row.measured - leaves - boxes_all;
        note += fmt::format("; = leaf lists {} + {} node box tests {} + merge {}", leaves.str(), boxes, boxes_all.str(), merge.str());
        if (h) note += fmt::format(" ({:.2g} cmp per interval end, 4 ends, the merge stopping at the answer)", double(merge.cmp) / 4.0);
        else note += " (the left leaf is empty: the right one is never evaluated, no merge)";
      }
      row.note = note;
      rows.push_back(row);
      Row s8 = row;
      s8.number = "simd8";
      s8.measured = count_query<cf8>(T, r, other);
      s8.uniform = count_query<cf8>(T, r, r);
      s8.note = "8 rays in lanes: the lanes' lists merged without branches (merge_lanes: parities before and after every "
                "boundary, then a sort of the kept ones), no stop at the answer; a packet skips a subtree only when every lane does";
      rows.push_back(s8);
    }
  }
}

}  // namespace rb::opstable
