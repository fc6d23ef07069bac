// `raybench query`: one-off intersection queries for debugging a case and for checking raybench
// against other tools. JSON lines on stdin, one JSON line per query on stdout:
//   in : {"primitive": {...}, "ray": {"origin": [x,y,z], "direction": [x,y,z], "tmin": 0, "tmax": 1e30},
//         "method": "optional name"}
//   out: {"line": N, "primitive": TYPE, "results": [{"method", "hit", "t", "point", "normal", "uv"}]}
//        or {"line": N, "error": "what is wrong"} (the other lines still run)
// t is in the units of the given direction (the engine works on the unit direction and divides
// by |direction| on output), so a direction of length 2 halves t. A miss has "hit": false and
// no t. Every method that applies to the primitive runs unless "method" names one.
#include "apps/query.hpp"
#include "kernels/box.hpp"
#include "kernels/cylinder_cone.hpp"
#include "kernels/plane.hpp"
#include "kernels/plane_uv.hpp"
#include "kernels/polygon.hpp"
#include "kernels/polyhedron.hpp"
#include "kernels/quadric.hpp"
#include "kernels/sphere.hpp"
#include "kernels/torus.hpp"
#include "kernels/transform.hpp"
#include "kernels/triangle.hpp"
#include "kernels/triangle_cramer.hpp"
#include "kernels/triangle_woop.hpp"
#include "scene/csg_scene.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <functional>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>

namespace rb::app {
namespace {
using nlohmann::json;

struct QueryError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Result {
  bool hit = false;
  double t = 0;  // along the unit direction
  Vec3d p{}, n{};
  double u = 0, v = 0;
  bool has_uv = false;
  std::vector<double> list;  // CSG: every boundary along the whole line (entry, exit, entry, ...)
  bool has_list = false;
};
using Method = std::function<Result(const Ray<float>&)>;
struct Named {
  std::string name;
  Method run;
};

Vec3d vec(const json& j, const char* key) {
  if (!j.contains(key)) throw QueryError(std::string("missing \"") + key + "\"");
  const json& a = j[key];
  if (!a.is_array() || a.size() != 3 || !a[0].is_number() || !a[1].is_number() || !a[2].is_number())
    throw QueryError(std::string("\"") + key + "\" must be an array of three numbers");
  return {a[0].get<double>(), a[1].get<double>(), a[2].get<double>()};
}
double num(const json& j, const char* key) {
  if (!j.contains(key)) throw QueryError(std::string("missing \"") + key + "\"");
  if (!j[key].is_number()) throw QueryError(std::string("\"") + key + "\" must be a number");
  return j[key].get<double>();
}
double num_or(const json& j, const char* key, double def) { return j.contains(key) ? num(j, key) : def; }
bool flag(const json& j, const char* key) {
  if (!j.contains(key)) return false;
  if (!j[key].is_boolean()) throw QueryError(std::string("\"") + key + "\" must be true or false");
  return j[key].get<bool>();
}
Vec3f f3(const Vec3d& v) { return to_float(v); }

// Runs kernel(ray, prim) in number type F on the float inputs; normal(prim, point) -> Vec3<F>.
template <class F, class P, class K, class N>
Result eval(const Ray<float>& r0, const P& prim, K kern, N normal, bool uv = false) {
  const Ray<F> r = Ray<F>::broadcast(r0);
  const auto p = prim_cast<F>(prim);
  const Hit<F> h = kern(r, p);
  Result o;
  o.hit = lane_mask<F>(h.mask, 0);
  if (!o.hit) return o;
  o.t = double(lane(h.t, 0));
  const Vec3<F> pt = r.at(h.t);
  o.p = to_double(lane3(pt, 0));
  Vec3d n = to_double(lane3(normal(p, pt), 0));
  const double l = std::sqrt(dot(n, n));
  o.n = l > 0 ? n * (1.0 / l) : n;
  o.has_uv = uv;
  o.u = double(lane(h.u, 0));
  o.v = double(lane(h.v, 0));
  return o;
}

// A frame taking +z to `axis`, origin at `o`, with the query's error message.
Affine3d frame(const Vec3d& o, const Vec3d& axis) {
  const std::optional<Affine3d> M = Affine3d::frame(o, axis);
  if (!M) throw QueryError("\"axis\" must be a non-zero finite vector");
  return *M;
}

// A builder's result, or the query's error with the builder's reason (docs/DESIGN.md section 7).
template <class P>
P built(P p, const std::string& why) {
  if (!why.empty()) throw QueryError(why);
  return p;
}

// The methods of one primitive, each in number type F.
// The methods a query runs, each in number type F.
template <class F>
struct MethodList {
  std::vector<Named> m;
  void add(std::string name, Method fn) { m.push_back({std::move(name), std::move(fn)}); }
  // A placed instance x: `kernel` and `normal` run in its own frame (kernels/transform.hpp).
  template <class X, class Kernel, class Normal>
  void placed(std::string name, const X& x, Kernel kernel, Normal normal) {
    add(std::move(name), [=](const Ray<float>& r) {
      return eval<F>(
          r, x, [kernel](auto& ray, auto& prim) { return intersect_transformed(ray, prim, kernel); },
          [normal](const auto& prim, const auto& p) { return transformed_normal(prim, p, normal); });
    });
  }
};

template <class F>
void methods_sphere(const json& pj, MethodList<F>& out) {
  const auto s = make_sphere(vec(pj, "center"), num(pj, "radius"));
  auto nrm = [](const auto& p, const auto& x) { return sphere_normal(p, x); };
  out.add("geometric", [=](const Ray<float>& r) { return eval<F>(r, s, [](auto& a, auto& b) { return intersect_sphere_geometric(a, b); }, nrm); });
  out.add("algebraic", [=](const Ray<float>& r) { return eval<F>(r, s, [](auto& a, auto& b) { return intersect_sphere_algebraic(a, b); }, nrm); });
  out.add("stable", [=](const Ray<float>& r) { return eval<F>(r, s, [](auto& a, auto& b) { return intersect_sphere_stable(a, b); }, nrm); });
  out.add("hearn_baker", [=](const Ray<float>& r) { return eval<F>(r, s, [](auto& a, auto& b) { return intersect_sphere_hearn_baker(a, b); }, nrm); });
  out.add("compensated", [=](const Ray<float>& r) { return eval<F>(r, s, [](auto& a, auto& b) { return intersect_sphere_compensated(a, b); }, nrm); });
  const Vec3d pole = pj.contains("pole") ? vec(pj, "pole") : Vec3d{0, 0, 1};
  const Vec3d eq = pj.contains("equator") ? vec(pj, "equator") : Vec3d{1, 0, 0};
  std::string why;
  const auto su = make_sphere_uv(vec(pj, "center"), num(pj, "radius"), pole, eq, &why);
  // A degenerate radius leaves every method to report the miss; a bad pole or equator (with a
  // valid sphere) is the caller's error.
  if (!why.empty() && s.r2 > 0.f) throw QueryError(why);
  out.add("uv", [=](const Ray<float>& r) {
    return eval<F>(r, su, [](auto& a, auto& b) { return intersect_sphere_uv(a, b); },
                   [](const auto& p, const auto& x) { return sphere_normal(p.s, x); }, true);
  });
}

template <class F>
void methods_triangle(const json& pj, MethodList<F>& out) {
  const Vec3d a = vec(pj, "v0"), b = vec(pj, "v1"), c = vec(pj, "v2");
  int axis = 2;
  const auto lec = make_tri_lecture(a, b, c, axis);
  const auto mt = make_triangle(a, b, c);
  const auto tv = make_tri_verts(a, b, c);
  out.add("lecture", [=](const Ray<float>& r) {
    return eval<F>(r, lec, [axis](auto& x, auto& y) { return intersect_triangle_lecture(x, y, axis); },
                   [](const auto& p, const auto&) { return triangle_normal(p); }, true);
  });
  auto nrm = [](const auto& p, const auto&) { return triangle_normal(p); };
  out.add("moller_trumbore", [=](const Ray<float>& r) { return eval<F>(r, mt, [](auto& x, auto& y) { return intersect_triangle_mt(x, y); }, nrm, true); });
  out.add("cramer", [=](const Ray<float>& r) { return eval<F>(r, mt, [](auto& x, auto& y) { return intersect_triangle_cramer(x, y); }, nrm, true); });
  out.add("woop", [=](const Ray<float>& r) { return eval<F>(r, tv, [](auto& x, auto& y) { return intersect_triangle_woop(x, y); }, nrm, true); });
}

template <class F>
void methods_plane(const json& pj, MethodList<F>& out) {
  const auto pl = make_plane(vec(pj, "point"), vec(pj, "normal"));
  out.add("lecture", [=](const Ray<float>& r) {
    return eval<F>(r, pl, [](auto& x, auto& y) { return intersect_plane(x, y); }, [](const auto& p, const auto&) { return plane_normal(p); });
  });
  if (pj.contains("u") && pj.contains("v")) {
    int axis = 2;
    const auto q = make_plane_uv(vec(pj, "point"), vec(pj, "u"), vec(pj, "v"), axis);
    out.add("uv", [=](const Ray<float>& r) {
      return eval<F>(r, q, [axis](auto& x, auto& y) { return intersect_plane_uv(x, y, axis); },
                     [](const auto& p, const auto&) { return triangle_normal(p); }, true);
    });
  }
}

template <class F>
void methods_parallelogram(const json& pj, MethodList<F>& out) {
  int axis = 2;
  const auto q = make_parallelogram(vec(pj, "origin"), vec(pj, "u"), vec(pj, "v"), axis);
  out.add("lecture", [=](const Ray<float>& r) {
    return eval<F>(r, q, [axis](auto& x, auto& y) { return intersect_parallelogram(x, y, axis); },
                   [](const auto& p, const auto&) { return triangle_normal(p); }, true);
  });
}

template <class F>
void methods_polygon(const json& pj, MethodList<F>& out) {
  if (!pj.contains("vertices") || !pj["vertices"].is_array()) throw QueryError("\"vertices\" must be an array of [x,y,z]");
  if (pj["vertices"].size() > 100000) throw QueryError("\"vertices\": more than 100000 vertices");
  std::vector<Vec3d> vs;
  for (const auto& v : pj["vertices"]) {
    json w = {{"v", v}};
    vs.push_back(vec(w, "v"));
  }
  const PolygonInfo info = polygon_info(vs);
  if (!info.valid) throw QueryError(std::string("polygon: ") + info.why);
  auto soa = std::make_shared<PolygonSoA>(PolygonSoA::build(std::vector<std::vector<Vec3d>>{vs}));
  std::size_t slot = 0;
  while (slot < soa->id.size() && soa->id[slot] != 0) ++slot;
  out.add("crossing", [soa, slot](const Ray<float>& r0) {
    const Ray<F> r = Ray<F>::broadcast(r0);
    const auto p = soa->template broadcast<F>(slot);
    const Hit<F> h = intersect_polygon(r, p);
    Result o;
    o.hit = lane_mask<F>(h.mask, 0);
    if (!o.hit) return o;
    o.t = double(lane(h.t, 0));
    o.p = to_double(lane3(r.at(h.t), 0));
    o.n = to_double(lane3(polygon_normal(p), 0));
    return o;
  });
}

template <class F>
void methods_box(const json& pj, MethodList<F>& out) {
  const Vec3d lo = vec(pj, "min"), hi = vec(pj, "max");
  const auto b = make_box(lo, hi);
  auto nrm = [](const auto& p, const auto& x) { return box_normal(p, x); };
  out.add("slab", [=](const Ray<float>& r) { return eval<F>(r, b, [](auto& x, auto& y) { return intersect_box(x, y); }, nrm); });
  const auto h = make_box_halfspaces(f3(lo), f3(hi));
  out.add("halfspaces", [=](const Ray<float>& r) {
    return eval<F>(r, h, [](auto& x, auto& y) { return intersect_polyhedron(x, y); },
                   [](const auto& p, const auto& x) { return polyhedron_normal(p, x); });
  });
}

template <class F>
void methods_cylinder(const json& pj, MethodList<F>& out) {
  const double rad = num(pj, "radius"), ht = num(pj, "height");
  if (!(rad > 0) || !(ht > 0) || !std::isfinite(rad) || !std::isfinite(ht)) throw QueryError("cylinder: radius and height must be positive and finite");
  const bool caps = flag(pj, "caps");
  std::string why;
  const auto c = built(make_transformed(frame(vec(pj, "base"), vec(pj, "axis")), make_cylinder(0.f, 0.f, float(rad), 0.f, float(ht)), &why), why);
  out.placed(caps ? "capped" : "lecture", c,
             [caps](const auto& lr, const auto& p) { return caps ? intersect_cylinder_capped(lr, p) : intersect_cylinder(lr, p); },
             [caps](const auto& q, const auto& l) { return caps ? capped_cylinder_normal(q, l) : cylinder_normal(q, l); });
}

template <class F>
void methods_cone(const json& pj, MethodList<F>& out) {
  double ht, tan_a;
  if (pj.contains("angle")) {
    const double a = num(pj, "angle");
    if (!(a > 0 && a < 90)) throw QueryError("cone: \"angle\" is the half-angle in degrees, in (0, 90)");
    tan_a = std::tan(a * std::numbers::pi / 180.0);
    ht = num_or(pj, "height", std::numeric_limits<double>::infinity());
  } else {
    const double rad = num(pj, "radius");
    ht = num(pj, "height");
    if (!(rad > 0) || !(ht > 0) || !std::isfinite(rad) || !std::isfinite(ht)) throw QueryError("cone: radius and height must be positive and finite");
    tan_a = rad / ht;
  }
  if (!(ht > 0)) throw QueryError("cone: \"height\" must be positive");
  const bool caps = flag(pj, "caps");
  if (caps && !std::isfinite(ht)) throw QueryError("cone: caps need a finite height");
  const Affine3d M = frame(vec(pj, "apex"), vec(pj, "axis")) * Affine3d::scale({tan_a, tan_a, 1});
  const float h1 = std::isfinite(ht) ? float(ht) : std::numeric_limits<float>::infinity();
  std::string why;
  const auto c = built(make_transformed(M, caps ? make_capped_cone(Vec3f{0, 0, 0}, 0.f, h1, &why) : make_cone(Vec3f{0, 0, 0}, 0.f, h1), &why), why);
  out.placed(caps ? "capped" : "lecture", c,
             [caps](const auto& lr, const auto& p) { return caps ? intersect_cone_capped(lr, p) : intersect_cone(lr, p); },
             [caps](const auto& q, const auto& l) { return caps ? capped_cone_normal(q, l) : cone_normal(q, l); });
}

template <class F>
void methods_torus(const json& pj, MethodList<F>& out) {
  std::string why;
  const Torus<float> t =
      built(make_torus(vec(pj, "center"), vec(pj, "axis"), num(pj, "major"), num(pj, "minor"), Vec3d{1, 0, 0}, &why), why);
  auto nrm = [](const auto& p, const auto& x) { return torus_normal(p, x); };
  out.add("ferrari", [=](const Ray<float>& r) { return eval<F>(r, t, [](auto& x, auto& y) { return intersect_torus_ferrari(x, y); }, nrm, true); });
  out.add("robust", [=](const Ray<float>& r) { return eval<F>(r, t, [](auto& x, auto& y) { return intersect_torus_robust(x, y); }, nrm, true); });
}

template <class F>
void methods_quadric(const json& pj, MethodList<F>& out) {
  if (!pj.contains("coefficients") || !pj["coefficients"].is_array() || pj["coefficients"].size() != 10)
    throw QueryError("\"coefficients\" must be [a,b,c,d,e,f,g,h,j,k] (seed 004's order)");
  double k[10];
  for (int i = 0; i < 10; ++i) {
    if (!pj["coefficients"][i].is_number()) throw QueryError("\"coefficients\" must all be numbers");
    k[i] = pj["coefficients"][i].get<double>();
  }
  const Quadric<float> q = make_quadric(QuadricCoeffs{k[0], k[1], k[2], k[3], k[4], k[5], k[6], k[7], k[8], k[9]});
  auto nrm = [](const auto& p, const auto& x) { return quadric_normal(p, x); };
  out.add("matrix", [=](const Ray<float>& r) { return eval<F>(r, q, [](auto& x, auto& y) { return intersect_quadric_matrix(x, y); }, nrm); });
  out.add("coeffs10", [=](const Ray<float>& r) { return eval<F>(r, q, [](auto& x, auto& y) { return intersect_quadric_coeffs10(x, y); }, nrm); });
}

template <class F>
void methods_csg(const json& pj, MethodList<F>& out) {
  // A CSG tree (the JSON scene format's node, scene/csg_scene.hpp); float only: the tree is compiled
  // for float rays and 8-ray packets.
  std::shared_ptr<const CsgTree> tree;
  try {
    tree = std::make_shared<const CsgTree>(scene::csg_from_json_text(pj.dump(), "primitive"));
  } catch (const scene::SceneError& e) {
    throw QueryError(e.what());
  }
  out.add("csg", [tree](const Ray<float>& r) {
    Result o;
    float tag = 0;
    const Hit<float> h = csg_hit(*tree, r, tag);
    Spans<float> L;
    csg_list(*tree, r, L);
    o.has_list = true;
    for (int k = 0; k < L.n; ++k) o.list.push_back(double(L.t[k]));
    o.hit = h.mask;
    if (!o.hit) return o;
    o.t = double(h.t);
    o.p = to_double(r.at(h.t));
    o.n = to_double(csg_normal(*tree, tag, r.at(h.t)));
    return o;
  });
}

// The methods of one primitive, each in number type F: the primitive types and their methods.
template <class F>
std::vector<Named> methods(const json& pj, std::string& type) {
  if (!pj.is_object()) throw QueryError("\"primitive\" must be an object");
  if (!pj.contains("type") || !pj["type"].is_string()) throw QueryError("\"primitive\" needs a string \"type\"");
  type = pj["type"].get<std::string>();
  using Fill = void (*)(const json&, MethodList<F>&);
  static const std::pair<const char*, Fill> kTypes[] = {
      {"sphere", methods_sphere<F>},
      {"triangle", methods_triangle<F>},
      {"plane", methods_plane<F>},
      {"parallelogram", methods_parallelogram<F>},
      {"polygon", methods_polygon<F>},
      {"box", methods_box<F>},
      {"cylinder", methods_cylinder<F>},
      {"cone", methods_cone<F>},
      {"torus", methods_torus<F>},
      {"quadric", methods_quadric<F>},
      {"union", methods_csg<F>},
      {"intersection", methods_csg<F>},
      {"difference", methods_csg<F>},
  };
  MethodList<F> list;
  for (const auto& [name, fill] : kTypes)
    if (type == name) {
      fill(pj, list);
      return list.m;
    }
  std::string known;
  for (const auto& [name, fill] : kTypes) known += (known.empty() ? "" : ", ") + std::string(name);
  throw QueryError("unknown primitive type \"" + type + "\" (" + known + ")");
}

json answer(const json& q, bool dbl) {
  if (!q.is_object()) throw QueryError("a query is a JSON object");
  if (!q.contains("primitive")) throw QueryError("missing \"primitive\"");
  if (!q.contains("ray") || !q["ray"].is_object()) throw QueryError("missing \"ray\" object");
  const json& rj = q["ray"];
  const Vec3d o = vec(rj, "origin"), d = vec(rj, "direction");
  const double tmin = num_or(rj, "tmin", 0.0), tmax = num_or(rj, "tmax", std::numeric_limits<double>::infinity());
  const double len = std::sqrt(dot(d, d));
  std::string type;
  auto ms = dbl ? methods<double>(q["primitive"], type) : methods<float>(q["primitive"], type);
  std::string only;
  if (q.contains("method")) {
    if (!q["method"].is_string()) throw QueryError("\"method\" must be a string");
    only = q["method"].get<std::string>();
    bool found = false;
    for (const auto& m : ms) found = found || m.name == only;
    if (!found) {
      std::string names;
      for (const auto& m : ms) names += (names.empty() ? "" : ", ") + m.name;
      throw QueryError("method \"" + only + "\" does not apply to a " + type + " (" + names + ")");
    }
  }
  const Ray<float> ray = make_ray(o, d, tmin, tmax);
  json res = json::array();
  for (const auto& m : ms) {
    if (!only.empty() && m.name != only) continue;
    const Result r = m.run(ray);
    json j = {{"method", m.name}, {"hit", r.hit}};
    if (r.has_list) {
      json iv = json::array();
      for (std::size_t k = 0; k + 1 < r.list.size(); k += 2) iv.push_back({r.list[k] / len, r.list[k + 1] / len});
      j["intervals"] = iv;
    }
    if (r.hit) {
      j["t"] = r.t / len;
      j["point"] = {r.p.x, r.p.y, r.p.z};
      j["normal"] = {r.n.x, r.n.y, r.n.z};
      if (r.has_uv) j["uv"] = {r.u, r.v};
    }
    res.push_back(j);
  }
  return {{"primitive", type}, {"valid_ray", ray.tmin <= ray.tmax}, {"results", res}};
}

}  // namespace

int run_query(std::istream& in, std::ostream& out, bool dbl) {
  std::ostringstream ignored;
  return run_query(in, out, ignored, dbl);
}

int run_query(std::istream& in, std::ostream& out, std::ostream& err, bool dbl) {
  std::string line;
  long n = 0;
  int errors = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    json o;
    try {
      const json q = json::parse(line);
      o = answer(q, dbl);
      o["line"] = n;
    } catch (const json::exception& e) {
      o = {{"line", n}, {"error", std::string("malformed JSON: ") + e.what()}};
      ++errors;
    } catch (const std::exception& e) {
      o = {{"line", n}, {"error", e.what()}};
      ++errors;
    }
    if (o.contains("error")) err << "raybench query: stdin line " << n << ": " << o["error"].get<std::string>() << "\n";
    out << o.dump() << "\n";
  }
  return errors ? 1 : 0;
}

}  // namespace rb::app
