#include "render/surface.hpp"

#include "scene/csg.hpp"

#include <cmath>
#include <stdexcept>

namespace rb::render {

using scene::Kind;

namespace {

Vec3f unit_or(const Vec3d& v, const Vec3f& fallback) {
  const double l = std::sqrt(dot(v, v));
  if (!(l > 0.0) || !std::isfinite(l)) return fallback;
  return to_float(v * (1.0 / l));
}

// Barycentric weights of p in triangle (a, b, c), by sub-areas along the triangle's normal.
bool barycentric(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& p, double w[3]) {
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
Vec3f interpolate(const Vec3f* v, const Vec3f* n, std::size_t count, const Vec3d& p, const Vec3f& ng) {
  double best_out = -1e300;
  Vec3d best{0, 0, 0};
  for (std::size_t i = 1; i + 1 < count; ++i) {
    double w[3];
    if (!barycentric(to_double(v[0]), to_double(v[i]), to_double(v[i + 1]), p, w)) continue;
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

}  // namespace

Surface surface_at(const scene::Scene& s, std::uint32_t prim, const Ray<float>& r, float t) {
  const Kind kind = Kind(prim >> bvh::kKindShift);
  const std::uint32_t i = prim & ((1u << bvh::kKindShift) - 1);
  Surface h;
  h.kind = kind;
  h.p = r.o + r.d * t;
  const Vec3d p = to_double(h.p);
  const Vec3f fallback = -r.d;
  switch (kind) {
    case Kind::sphere: {
      const auto& sp = s.spheres.at(i);
      h.ng = unit_or(p - to_double(sp.c), fallback);
      h.ns = h.ng;
      h.mat = sp.mat;
      break;
    }
    case Kind::cylinder:
    case Kind::cone: {
      // F = |q| - r(s) with s along the axis and q the radial part: grad F = q/|q| - (r1 - r0)/h a.
      const auto& c = s.cones.at(i);
      const Vec3d base = to_double(c.base), axis = to_double(c.apex) - base;
      const double len = std::sqrt(dot(axis, axis));
      const Vec3d a = len > 0 ? axis * (1.0 / len) : Vec3d{0, 1, 0};
      const Vec3d q = (p - base) - a * dot(p - base, a);
      const double ql = std::sqrt(dot(q, q));
      const Vec3d radial = ql > 0 ? q * (1.0 / ql) : Vec3d{0, 0, 0};
      const double r0 = std::fabs(double(c.base_r)), r1 = std::fabs(double(c.apex_r));
      Vec3f n = unit_or(radial - a * (len > 0 ? (r1 - r0) / len : 0.0), fallback);
      if (c.base_r < 0 || c.apex_r < 0) n = -n;  // NFF: negative radii show the inside
      h.ng = h.ns = n;
      h.mat = c.mat;
      break;
    }
    case Kind::polygon: {
      const auto& pg = s.polygons.at(i);
      const Vec3f* v = s.poly_verts.data() + pg.first;
      h.ng = unit_or(newell_normal(v, pg.count), fallback);
      h.ns = s.poly_normals.empty() ? h.ng : interpolate(v, s.poly_normals.data() + pg.first, pg.count, p, h.ng);
      h.mat = pg.mat;
      break;
    }
    case Kind::triangle: {
      const auto& tr = s.triangles.at(i);
      const Vec3f v[3] = {s.verts[tr.v[0]], s.verts[tr.v[1]], s.verts[tr.v[2]]};
      h.ng = unit_or(cross(to_double(v[1]) - to_double(v[0]), to_double(v[2]) - to_double(v[0])), fallback);
      if (s.vert_normals.empty()) {
        h.ns = h.ng;
      } else {
        const Vec3f n[3] = {s.vert_normals[tr.v[0]], s.vert_normals[tr.v[1]], s.vert_normals[tr.v[2]]};
        h.ns = interpolate(v, n, 3, p, h.ng);
      }
      h.mat = tr.mat;
      break;
    }
    case Kind::csg: {
      // The tree's own closest-hit query gives the outward normal (flipped on subtracted
      // surfaces) and the material of the leaf surface hit, for the same ray.
      const auto c = scene::csg_surface(*s.csgs.at(i).tree, r);
      h.ng = h.ns = c.hit ? unit_or(to_double(c.normal), fallback) : fallback;
      h.mat = c.material;
      break;
    }
    default: throw std::logic_error("surface_at: a primitive kind without a surface rule");
  }
  return h;
}

Vec3f surface_color(const scene::Material& m, const Vec3f& p) {
  if (!(m.checker > 0)) return m.color;
  const double c = double(m.checker);
  const auto cell = [&](float x) { return static_cast<long long>(std::floor(double(x) / c)); };
  const long long parity = cell(p.x) + cell(p.y) + cell(p.z);
  return (parity & 1) ? m.color2 : m.color;
}

}  // namespace rb::render
