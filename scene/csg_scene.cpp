// CSG trees from the JSON scene format's nodes (scene/csg_scene.hpp): types, transforms, world boxes;
// the scene file around them is read by scene/json_scene.cpp.
#include "scene/csg_scene.hpp"
#include "scene/json_read.hpp"
#include "scene/parse_util.hpp"
#include "core/suggest.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>

namespace rb::scene {

namespace {
using nlohmann::json;
using namespace json_read;

// "transform": translate * rotate * scale, or a 3x4 matrix.
Affine3d transform(const json& t, const std::string& path) {
  if (!t.is_object()) fail(path, "expected an object with translate, rotate, scale or matrix");
  only_keys(t, path, {"translate", "rotate", "scale", "matrix"});
  Affine3d M;
  if (t.contains("matrix")) {
    if (t.size() != 1) fail(path, "\"matrix\" excludes translate, rotate and scale");
    const json& m = t["matrix"];
    const std::string mp = path + ".matrix";
    if (!m.is_array() || m.size() != 3) fail(mp, "expected three rows of four numbers");
    for (int i = 0; i < 3; ++i) {
      const std::string rp = mp + "[" + std::to_string(i) + "]";
      const json& row = m[std::size_t(i)];
      if (!row.is_array() || row.size() != 4) fail(rp, "expected four numbers");
      for (int k = 0; k < 4; ++k) M.m[i][k] = number(row[std::size_t(k)], rp + "[" + std::to_string(k) + "]");
    }
  } else {
    if (t.contains("translate")) M = Affine3d::translate(vec(t, path, "translate"));
    if (t.contains("rotate")) {
      const std::string rp = path + ".rotate";
      const json& r = t["rotate"];
      if (!r.is_object()) fail(rp, "expected {\"axis\": [x,y,z], \"degrees\": d}");
      only_keys(r, rp, {"axis", "degrees"});
      M = M * Affine3d::rotate(nonzero(r, rp, "axis"), num(r, rp, "degrees") * std::numbers::pi / 180.0);
    }
    if (t.contains("scale")) {
      const json& s = t["scale"];
      const std::string sp = path + ".scale";
      const Vec3d f = s.is_array() ? vec3(s, sp) : Vec3d{number(s, sp), number(s, sp), number(s, sp)};
      if (!(f.x != 0 && f.y != 0 && f.z != 0)) fail(sp, "expected non-zero scale factors");
      M = M * Affine3d::scale(f);
    }
  }
  std::string why;
  if (!M.inverse(&why)) fail(path, why);
  return M;
}

bool is_identity(const Affine3d& M) {
  const Affine3d I;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 4; ++k)
      if (M.m[i][k] != I.m[i][k]) return false;
  return true;
}

// World box of a local box under M (its 8 corners), widened so float rounding stays inside.
void world_box(const Affine3d& M, Vec3d lo, Vec3d hi, CsgNode& n) {
  Vec3d a{1e300, 1e300, 1e300}, b{-1e300, -1e300, -1e300};
  for (int c = 0; c < 8; ++c) {
    const Vec3d p = M.point({c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z});
    a = {std::min(a.x, p.x), std::min(a.y, p.y), std::min(a.z, p.z)};
    b = {std::max(b.x, p.x), std::max(b.y, p.y), std::max(b.z, p.z)};
  }
  const double ext = std::max({b.x - a.x, b.y - a.y, b.z - a.z, std::fabs(a.x), std::fabs(a.y), std::fabs(a.z), std::fabs(b.x),
                               std::fabs(b.y), std::fabs(b.z)});
  const double pad = 1e-5 * ext + 1e-30;
  const double l[3] = {a.x - pad, a.y - pad, a.z - pad}, h[3] = {b.x + pad, b.y + pad, b.z + pad};
  for (int k = 0; k < 3; ++k) {
    n.lo[k] = std::nextafter(float(l[k]), -std::numeric_limits<float>::infinity());
    n.hi[k] = std::nextafter(float(h[k]), std::numeric_limits<float>::infinity());
  }
}

// The vertices' box of a convex polyhedron n_i . x + D_i <= 0; nullopt when unbounded or empty.
std::optional<std::pair<Vec3d, Vec3d>> polyhedron_box(const std::vector<HalfspaceIn>& hs) {
  const std::size_t m = hs.size();
  std::vector<Vec3d> n(m);
  std::vector<double> D(m);
  for (std::size_t i = 0; i < m; ++i) {
    const Vec3d v = to_double(hs[i].normal);
    n[i] = v * (1.0 / std::sqrt(dot(v, v)));
    D[i] = -dot(n[i], to_double(hs[i].point));
  }
  Vec3d lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  int found = 0;
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = i + 1; j < m; ++j)
      for (std::size_t k = j + 1; k < m; ++k) {
        const Vec3d c = cross(n[j], n[k]);
        const double det = dot(n[i], c);
        if (std::fabs(det) < 1e-12) continue;
        const Vec3d p = (c * -D[i] + cross(n[k], n[i]) * -D[j] + cross(n[i], n[j]) * -D[k]) * (1.0 / det);
        bool in = true;
        for (std::size_t q = 0; q < m && in; ++q) in = dot(n[q], p) + D[q] <= 1e-9 * (1 + std::sqrt(dot(p, p)));
        if (!in) continue;
        ++found;
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
      }
  if (found < 4) return std::nullopt;
  // Bounded iff every direction leaves: checked by the six axis directions against the planes
  // (a polyhedron with vertices is bounded iff no recession direction exists; a cheap sufficient
  // test is that the vertices' box, enlarged, contains the set: probe the centre plus far points).
  const Vec3d c = (lo + hi) * 0.5;
  const double far = 1e3 * (1 + std::sqrt(dot(hi - lo, hi - lo)));
  for (int ax = 0; ax < 3; ++ax)
    for (double s : {-1.0, 1.0}) {
      Vec3d d{0, 0, 0};
      (ax == 0 ? d.x : ax == 1 ? d.y : d.z) = s;
      bool any_blocks = false;
      for (std::size_t q = 0; q < m; ++q) any_blocks = any_blocks || dot(n[q], c + d * far) + D[q] > 0;
      if (!any_blocks) return std::nullopt;
    }
  return std::make_pair(lo, hi);
}

struct Builder {
  CsgTree tree;
  int slots = 0;
  const std::map<std::string, std::uint32_t>* materials = nullptr;  // null: names not resolved

  std::uint32_t material(const json& j, const std::string& path, std::uint32_t inherited) const {
    if (!j.contains("material")) return inherited;
    const json& m = j["material"];
    if (!m.is_string()) fail(path + ".material", "expected a material name");
    if (!materials) return inherited;
    const auto it = materials->find(m.get<std::string>());
    if (it == materials->end()) fail(path + ".material", "unknown material \"" + detail::quote(m.get<std::string>()) + "\"");
    return it->second;
  }

  // The keys a node of this type may have (an unknown type is reported by node()).
  static std::vector<std::string> node_keys(const std::string& type) {
    std::vector<std::string> k = {"type", "transform", "material"};
    auto add = [&](std::initializer_list<const char*> more) {
      for (const char* m : more) k.emplace_back(m);
    };
    if (type == "union" || type == "intersection") add({"children", "left", "right"});
    else if (type == "difference") add({"left", "right"});
    else if (type == "sphere") add({"center", "radius"});
    else if (type == "box") add({"min", "max"});
    else if (type == "polyhedron") add({"planes"});
    else if (type == "cylinder") add({"base", "axis", "radius", "height"});
    else if (type == "cone") add({"apex", "axis", "radius", "height"});
    else if (type == "torus") add({"center", "axis", "major", "minor"});
    else if (type == "ellipsoid") add({"center", "radii"});
    else if (type == "quadric") add({"coefficients"});
    else return {};
    return k;
  }

  std::uint32_t add_node(CsgNode n) {
    tree.nodes.push_back(n);
    return std::uint32_t(tree.nodes.size() - 1);
  }

  std::uint32_t combine(CsgOp op, std::uint32_t a, std::uint32_t b) {
    CsgNode n;
    n.op = op;
    n.a = a;
    n.b = b;
    const CsgNode &A = tree.nodes[a], &B = tree.nodes[b];
    for (int k = 0; k < 3; ++k) {
      switch (op) {
        case CsgOp::unite: n.lo[k] = std::min(A.lo[k], B.lo[k]); n.hi[k] = std::max(A.hi[k], B.hi[k]); break;
        case CsgOp::intersect: n.lo[k] = std::max(A.lo[k], B.lo[k]); n.hi[k] = std::min(A.hi[k], B.hi[k]); break;
        default: n.lo[k] = A.lo[k]; n.hi[k] = A.hi[k]; break;
      }
    }
    // An empty child box (lo > hi) of a union is ignored.
    if (op == CsgOp::unite) {
      const bool ea = !(A.lo[0] <= A.hi[0] && A.lo[1] <= A.hi[1] && A.lo[2] <= A.hi[2]);
      const bool eb = !(B.lo[0] <= B.hi[0] && B.lo[1] <= B.hi[1] && B.lo[2] <= B.hi[2]);
      if (ea || eb)
        for (int k = 0; k < 3; ++k) {
          n.lo[k] = ea ? B.lo[k] : A.lo[k];
          n.hi[k] = ea ? B.hi[k] : A.hi[k];
        }
    }
    return add_node(n);
  }

  std::uint32_t leaf(CsgLeaf L, const Affine3d& M, Vec3d lo, Vec3d hi, const std::string& path) {
    if (tree.leaves.size() >= 0x7fffff) fail(path, "too many leaves");
    slots += L.slots();
    if (slots > kSpanCap)
      fail(path, "the CSG tree has more than " + std::to_string(kSpanCap) + " interval ends (2 per leaf, 4 per torus)");
    L.placed = !is_identity(M);
    if (L.placed) {
      std::string why;
      const auto inv = M.inverse(&why);
      if (!inv) fail(path, why);
      float* dst[12] = {&L.inv.m00, &L.inv.m01, &L.inv.m02, &L.inv.m03, &L.inv.m10, &L.inv.m11,
                        &L.inv.m12, &L.inv.m13, &L.inv.m20, &L.inv.m21, &L.inv.m22, &L.inv.m23};
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 4; ++k) {
          *dst[i * 4 + k] = float(inv->m[i][k]);
          if (!std::isfinite(*dst[i * 4 + k])) fail(path, "transform: inverse overflows float");
        }
    }
    CsgNode n;
    n.op = CsgOp::leaf;
    n.a = std::uint32_t(tree.leaves.size());
    world_box(M, lo, hi, n);
    tree.leaves.push_back(L);
    return add_node(n);
  }

  // A union, intersection or difference: "left" and "right", or (not for a difference) "children",
  // folded pairwise.
  std::uint32_t operation(const json& j, const std::string& path, const std::string& type, const Affine3d& M, std::uint32_t mat, int depth) {
    const CsgOp op = type == "union" ? CsgOp::unite : type == "intersection" ? CsgOp::intersect : CsgOp::subtract;
    if (j.contains("children")) {
      if (op == CsgOp::subtract) fail(path + ".children", "a difference has \"left\" and \"right\"");
      const json& c = j["children"];
      if (!c.is_array() || c.size() < 2) fail(path + ".children", "expected an array of at least two nodes");
      std::vector<std::uint32_t> ids;
      for (std::size_t i = 0; i < c.size(); ++i) ids.push_back(node(c[i], path + ".children[" + std::to_string(i) + "]", M, mat, depth + 1));
      // A balanced fold: depth log2(n) instead of n.
      while (ids.size() > 1) {
        std::vector<std::uint32_t> next;
        for (std::size_t i = 0; i + 1 < ids.size(); i += 2) next.push_back(combine(op, ids[i], ids[i + 1]));
        if (ids.size() % 2) next.push_back(ids.back());
        ids = std::move(next);
      }
      return ids[0];
    }
    const std::uint32_t a = node(need(j, path, "left"), key_path(path, "left"), M, mat, depth + 1);
    const std::uint32_t b = node(need(j, path, "right"), key_path(path, "right"), M, mat, depth + 1);
    return combine(op, a, b);
  }

  // An ellipsoid (centre and radii) or a general quadric (its 10 coefficients) that bounds a
  // non-empty solid.
  std::uint32_t quadric_leaf(const json& j, const std::string& path, const std::string& type, CsgLeaf L, const Affine3d& M) {
    QuadricCoeffs q;
    if (type == "ellipsoid") {
      const Vec3d c = vec(j, path, "center"), r = vec(j, path, "radii");
      if (!(r.x > 0 && r.y > 0 && r.z > 0)) fail(key_path(path, "radii"), "expected three positive numbers");
      const double ax = 1 / (r.x * r.x), ay = 1 / (r.y * r.y), az = 1 / (r.z * r.z);
      q = {ax, ay, az, 0, 0, 0, -c.x * ax, -c.y * ay, -c.z * az, c.x * c.x * ax + c.y * c.y * ay + c.z * c.z * az - 1};
    } else {
      const json& cj = need(j, path, "coefficients");
      const std::string cp = key_path(path, "coefficients");
      if (!cj.is_array() || cj.size() != 10) fail(cp, "expected [a,b,c,d,e,f,g,h,j,k]");
      double v[10];
      for (int i = 0; i < 10; ++i) v[i] = number(cj[std::size_t(i)], cp + "[" + std::to_string(i) + "]");
      q = {v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9]};
    }
    // Bounded and non-empty: the 3x3 part positive definite (Sylvester), and F < 0 at the centre.
    const double a = q.a, b = q.b, c = q.c, d = q.d, e = q.e, f = q.f;
    const double m2 = a * b - d * d, m3 = a * (b * c - e * e) - d * (d * c - e * f) + f * (d * e - b * f);
    if (!(a > 0 && m2 > 0 && m3 > 0)) fail(path, "quadric: not bounded (its quadratic part must be positive definite: an ellipsoid)");
    // Inverse of the 3x3 part, centre x0 = -A^-1 g, and rhs = g . A^-1 g - k (> 0 iff non-empty).
    const double inv[3][3] = {{(b * c - e * e) / m3, (f * e - d * c) / m3, (d * e - b * f) / m3},
                              {(f * e - d * c) / m3, (a * c - f * f) / m3, (d * f - a * e) / m3},
                              {(d * e - b * f) / m3, (d * f - a * e) / m3, m2 / m3}};
    const double g[3] = {q.g, q.h, q.j};
    Vec3d ctr{0, 0, 0};
    double rhs = -q.k;
    for (int i = 0; i < 3; ++i) {
      double s = 0;
      for (int k2 = 0; k2 < 3; ++k2) s += inv[i][k2] * g[k2];
      (i == 0 ? ctr.x : i == 1 ? ctr.y : ctr.z) = -s;
      rhs += g[i] * s;
    }
    if (!(rhs > 0)) fail(path, "quadric: empty (no point has F <= 0)");
    L.kind = CsgLeafKind::quadric;
    L.quad = make_quadric(q);
    const Vec3d ext{std::sqrt(rhs * inv[0][0]), std::sqrt(rhs * inv[1][1]), std::sqrt(rhs * inv[2][2])};
    return leaf(L, M, ctr - ext, ctr + ext, path);
  }

  // Builds `j` under the accumulated transform M; returns its node and depth.
  std::uint32_t node(const json& j, const std::string& path, Affine3d M, std::uint32_t mat, int depth) {
    if (depth > kCsgMaxDepth) fail(path, "the CSG tree is deeper than " + std::to_string(kCsgMaxDepth) + " levels");
    if (!j.is_object()) fail(path, "expected an object with a \"type\"");
    if (!j.contains("type") || !j["type"].is_string()) fail(key_path(path, "type"), "expected a string");
    const std::string type = j["type"].get<std::string>();
    if (const auto keys = node_keys(type); !keys.empty()) only_keys(j, path, keys);
    if (j.contains("transform")) M = M * transform(j["transform"], key_path(path, "transform"));
    mat = material(j, path, mat);
    if (type == "union" || type == "intersection" || type == "difference") return operation(j, path, type, M, mat, depth);
    CsgLeaf L;
    L.material = mat;
    std::string why;
    auto check = [&](const std::string& p) {
      if (!why.empty()) fail(p, why);
    };
    if (type == "sphere") {
      const Vec3d c = vec(j, path, "center");
      const double r = positive(j, path, "radius");
      L.kind = CsgLeafKind::sphere;
      L.sphere = make_sphere(c, r);
      if (!(L.sphere.r2 > 0)) fail(key_path(path, "radius"), "expected a positive number representable in float");
      return leaf(L, M, c - Vec3d{r, r, r}, c + Vec3d{r, r, r}, path);
    }
    if (type == "box") {
      const Vec3d lo = vec(j, path, "min"), hi = vec(j, path, "max");
      if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z)) fail(key_path(path, "max"), "expected every coordinate above \"min\"'s");
      L.kind = CsgLeafKind::box;
      L.box = make_box(lo, hi);
      return leaf(L, M, lo, hi, path);
    }
    if (type == "polyhedron") {
      const json& pl = need(j, path, "planes");
      const std::string pp = key_path(path, "planes");
      if (!pl.is_array() || pl.size() < 4 || pl.size() > std::size_t(kCsgPlanes))
        fail(pp, "expected an array of 4 to " + std::to_string(kCsgPlanes) + " planes {\"normal\", \"point\"}");
      std::vector<HalfspaceIn> hs;
      for (std::size_t i = 0; i < pl.size(); ++i) {
        const std::string ip = pp + "[" + std::to_string(i) + "]";
        if (!pl[i].is_object()) fail(ip, "expected {\"normal\": [..], \"point\": [..]}");
        only_keys(pl[i], ip, {"normal", "point"});
        hs.push_back({to_float(nonzero(pl[i], ip, "normal")), to_float(vec(pl[i], ip, "point"))});
      }
      const auto box = polyhedron_box(hs);
      if (!box) fail(pp, "the halfspaces do not bound a non-empty solid");
      L.kind = CsgLeafKind::polyhedron;
      L.poly = make_halfspaces<kCsgPlanes>(hs);
      return leaf(L, M, box->first, box->second, path);
    }
    if (type == "cylinder") {
      const Vec3d base = vec(j, path, "base"), axis = nonzero(j, path, "axis");
      const double r = positive(j, path, "radius"), h = positive(j, path, "height");
      const auto F = Affine3d::frame(base, axis, &why);
      check(key_path(path, "axis"));
      L.kind = CsgLeafKind::cylinder;
      L.cyl = make_cylinder(0.0, 0.0, r, 0.0, h);
      if (!(L.cyl.r2 > 0)) fail(path, "cylinder: radius or height not representable in float");
      return leaf(L, M * *F, {-r, -r, 0}, {r, r, h}, path);
    }
    if (type == "cone") {
      const Vec3d apex = vec(j, path, "apex"), axis = nonzero(j, path, "axis");
      const double r = positive(j, path, "radius"), h = positive(j, path, "height");
      const auto F = Affine3d::frame(apex, axis, &why);
      check(key_path(path, "axis"));
      const double k = r / h;  // tan of the half-angle: local x^2 + y^2 = z^2 scaled by k
      L.kind = CsgLeafKind::cone;
      L.cone = make_capped_cone(Vec3d{0, 0, 0}, 0.0, h, &why);
      check(path);
      return leaf(L, M * *F * Affine3d::scale({k, k, 1}), {-h, -h, 0}, {h, h, h}, path);
    }
    if (type == "torus") {
      const Vec3d c = vec(j, path, "center"), w = nonzero(j, path, "axis");
      const double R = positive(j, path, "major"), r = positive(j, path, "minor");
      if (!(R > r)) fail(key_path(path, "minor"), "expected a number below \"major\" (a ring torus)");
      L.kind = CsgLeafKind::torus;
      L.torus = make_torus(c, w, R, r, Vec3d{1, 0, 0}, &why);
      check(path);
      const Vec3d u = w * (1.0 / std::sqrt(dot(w, w)));
      const Vec3d e{R * std::sqrt(std::max(0.0, 1 - u.x * u.x)) + r, R * std::sqrt(std::max(0.0, 1 - u.y * u.y)) + r,
                    R * std::sqrt(std::max(0.0, 1 - u.z * u.z)) + r};
      return leaf(L, M, c - e, c + e, path);
    }
    if (type == "ellipsoid" || type == "quadric") return quadric_leaf(j, path, type, L, M);
    fail(key_path(path, "type"), "unknown type \"" + detail::quote(type) +
                                      "\" (union, intersection, difference, sphere, box, polyhedron, cylinder, cone, torus, ellipsoid, quadric)" +
                                      did_you_mean(type, {"union", "intersection", "difference", "sphere", "box", "polyhedron", "cylinder", "cone",
                                                          "torus", "ellipsoid", "quadric", "polygon"}));
  }

  // The tree's depth in nodes (a balanced union of n children adds log2 n levels to the JSON's).
  int depth_of(std::uint32_t i) const {
    const CsgNode& n = tree.nodes[i];
    return n.op == CsgOp::leaf ? 1 : 1 + std::max(depth_of(n.a), depth_of(n.b));
  }
  CsgTree finish(std::uint32_t root) {
    tree.root = root;
    tree.depth = depth_of(root);
    return std::move(tree);
  }
};

}  // namespace

std::uint32_t json_read::node_material(const json& node, const std::string& path, const std::map<std::string, std::uint32_t>* materials,
                                       std::uint32_t inherited) {
  Builder b;
  b.materials = materials;
  return b.material(node, path, inherited);
}

CsgTree json_read::csg_tree(const json& node, const std::string& path, const Affine3d& M,
                            const std::map<std::string, std::uint32_t>* materials, std::uint32_t mat) {
  Builder b;
  b.materials = materials;
  const std::uint32_t r = b.node(node, path, M, mat, 1);
  return b.finish(r);
}

CsgTree csg_from_json_text(std::string_view node_json, const std::string& where) {
  json j;
  try {
    j = json::parse(node_json);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number beyond double
    throw SceneError(where + ": malformed JSON: " + e.what());
  }
  try {
    Builder b;
    const std::uint32_t r = b.node(j, where, Affine3d{}, 0, 1);
    return b.finish(r);
  } catch (const PathError& e) {
    throw SceneError(e.what());
  }
}

}  // namespace rb::scene
