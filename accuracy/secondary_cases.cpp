// Secondary rays: a ray spawned at a computed hit point, leaving the surface on the side it came
// from, must not hit the same primitive again. Self-hits per million spawned rays, with the spawn
// point as computed and with two offset schemes (core/spawn.hpp, which the tracer uses too):
//   - Waechter and Binder's integer offset (Ray Tracing Gems, chapter 6): move the point along the
//     geometric normal by a number of float ulps proportional to the normal, or by a fixed small
//     distance near the origin;
//   - a pbrt-style error-bound offset (as pbrt-v4 spawns rays): recompute the hit point in a form
//     whose rounding error has a known bound (projected back onto the sphere, cylinder or torus;
//     interpolated from the barycentrics on a triangle; snapped to the face plane on a box), bound
//     that error per coordinate (gamma_n |terms|, gamma_n = n u / (1 - n u)), move the point
//     along the normal by |n| . bound, and round each moved coordinate one more float away.
// The primitives are convex, or (torus) the spawn points lie on its outer half, where the tangent
// plane supports the whole torus, so every hit of a spawned ray leaving outward is a self-hit.
// ns_per_test is the cost of one spawned test including the scheme's work, so the rows show what
// each scheme costs.
#include "accuracy/common.hpp"
#include "core/spawn.hpp"
#include "kernels/box.hpp"
#include "kernels/cylinder_cone.hpp"
#include "kernels/sphere.hpp"
#include "kernels/torus.hpp"
#include "kernels/triangle.hpp"
#include "kernels/triangle_woop.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <utility>

namespace rb::acc {

namespace {

using spawn::bound_offset;
using spawn::gamma_f;
using spawn::vabs3;
using spawn::wb_offset;

// One spawned test: point p, outgoing unit direction d, unit geometric normal n on d's side;
// u, v: the primary hit's barycentrics (triangles).
struct Spawn {
  Vec3f p, d, n;
  float u = 0, v = 0;
};
// A recomputed hit point and the bound of its rounding error per coordinate.
struct Refined {
  Vec3f p, err;
};

constexpr std::array<const char*, 3> kScheme = {"secondary_no_offset", "secondary_wb_offset", "secondary_bound_offset"};

bool any_secondary(const Ctx& x, const std::string& family) {
  for (const char* s : kScheme)
    if (x.selected(family, s)) return true;
  return false;
}

// refine(prim, spawn) -> Refined: the scheme's recomputed point and error bound.
template <class P, class K, class R>
void secondary_rows(Ctx& x, const std::string& family, const std::string& method, const std::vector<P>& prims,
                    const std::vector<Spawn>& sp, const K& kern, const R& refine) {
  for (int scheme = 0; scheme < 3; ++scheme) {
    x.tick(family, kScheme[std::size_t(scheme)]);
    auto pass = [&](std::size_t* self) {
      double sink = 0;
      for (std::size_t i = 0; i < sp.size(); ++i) {
        const Spawn& s = sp[i];
        Vec3f o = s.p;
        if (scheme == 1) {
          o = wb_offset(s.p, s.n);
        } else if (scheme == 2) {
          const Refined f = refine(prims[i], s);
          o = bound_offset(f.p, f.err, s.n);
        }
        const Ray<float> r{o, s.d, {1.0f / s.d.x, 1.0f / s.d.y, 1.0f / s.d.z}, 0.0f, std::numeric_limits<float>::max()};
        const Hit<float> h = kern(r, prims[i]);
        if (self) *self += h.mask;
        sink += double(h.t);
      }
      g_sink = g_sink + sink;
    };
    std::size_t self = 0;
    pass(&self);
    Row r;
    r.family = family, r.method = method, r.precision = "float";
    r.case_name = kScheme[std::size_t(scheme)];
    r.what = scheme == 0   ? "rays spawned at the computed hit point, no offset"
             : scheme == 1 ? "rays spawned at the computed hit point moved by the Waechter-Binder integer offset"
                           : "rays spawned at the recomputed hit point moved along the normal by its rounding-error bound (pbrt-style)";
    r.rays = r.tests = sp.size();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    r.false_hit_ppm = r.false_miss_ppm = r.leak_ppm = r.multi_hit_ppm = r.wrong_root_ppm = nan;
    r.t_err_ulp_p50 = r.t_err_ulp_p99 = r.t_err_ulp_max = r.scaled_err_p99 = r.iterations = nan;
    r.self_hits = self;
    r.self_hit_ppm = 1e6 * double(self) / double(std::max<std::size_t>(sp.size(), 1));
    r.ns_per_test = nan;
    if (x.o->timing) {
      double best = 1e300;
      for (int k = 0; k < 20; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        pass(nullptr);
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      r.ns_per_test = best * 1e9 / double(std::max<std::size_t>(sp.size(), 1));
    }
    x.rows->push_back(r);
  }
}

Vec3f hemi(const Vec3d& n, std::mt19937_64& g) {
  Vec3d u = unit_rand(g);
  if (dot(u, n) < 0) u = u * -1.0;
  return to_float(u);
}

// A primary ray from outside onto the surface point `target` with outward normal n: the eye lies
// 3 units off in the open halfspace beyond the tangent plane, which supports the convex primitive.
Ray<float> primary(const Vec3d& target, const Vec3d& n, std::mt19937_64& g) {
  const Vec3d eye = target + to_double(hemi(n, g)) * 3.0;
  return make_ray(eye, target - eye);
}

// ---- recomputed points and their error bounds -------------------------------------------------
// Sphere (pbrt's reprojection): q = p - c scaled to the radius sqrt(r2): <= 6 roundings of |q|
// (sqrt(r2), the length, the ratio, the scaling), one more adding c back.
Refined refine_sphere(const Sphere<float>& s, const Spawn& sp) {
  Vec3f q = sp.p - s.c;
  q = q * (std::sqrt(s.r2) / std::sqrt(dot(q, q)));
  const Vec3f p = s.c + q;
  return {p, vabs3(q) * gamma_f(6) + vabs3(p) * gamma_f(1)};
}
// Cylinder (pbrt's reprojection): the offset from the axis scaled to the radius; z is not moved
// (the lateral normal has no z component).
Refined refine_cylinder(const Cylinder<float>& c, const Spawn& sp) {
  float x = sp.p.x - c.cx, y = sp.p.y - c.cy;
  const float k = std::sqrt(c.r2) / std::sqrt(x * x + y * y);
  x *= k, y *= k;
  const Vec3f p{c.cx + x, c.cy + y, sp.p.z};
  return {p, Vec3f{std::fabs(x), std::fabs(y), 0.0f} * gamma_f(5) + vabs3(p) * gamma_f(1)};
}
// Torus: projected onto the tube's circle in the meridian plane (ring point m = radial part
// scaled to R, then the tube vector scaled to r). Every term is at most R + r in size; 16
// roundings (including |w| = 1 within a few ulps) bound the chain, one more adding c back.
Refined refine_torus(const Torus<float>& T, const Spawn& sp) {
  const Vec3f q = sp.p - T.c;
  const Vec3f rad = q - T.w * dot(q, T.w);
  const Vec3f m = rad * (T.R / std::sqrt(dot(rad, rad)));
  Vec3f v = q - m;
  v = v * (T.r / std::sqrt(dot(v, v)));
  const Vec3f p = T.c + (m + v);
  const float e = gamma_f(16) * (T.R + T.r);
  return {p, Vec3f{e, e, e} + vabs3(p) * gamma_f(1)};
}
// Box: the coordinate of the face the point lies on (the largest offset from the centre relative
// to the half size) snapped to the face plane exactly; the bound is one rounding of each
// coordinate, so the offset still leaves the plane.
Refined refine_box(const Box<float>& b, const Spawn& sp) {
  Vec3f p = sp.p;
  float best = -1;
  int k = 0;
  for (int a = 0; a < 3; ++a) {
    const float lo = a == 0 ? b.lo.x : a == 1 ? b.lo.y : b.lo.z, hi = a == 0 ? b.hi.x : a == 1 ? b.hi.y : b.hi.z;
    const float pa = a == 0 ? p.x : a == 1 ? p.y : p.z;
    const float rel = std::fabs(pa - 0.5f * (lo + hi)) / (0.5f * (hi - lo));
    if (rel > best) best = rel, k = a;
  }
  const float face = [&] {
    const float lo = k == 0 ? b.lo.x : k == 1 ? b.lo.y : b.lo.z, hi = k == 0 ? b.hi.x : k == 1 ? b.hi.y : b.hi.z;
    const float pa = k == 0 ? p.x : k == 1 ? p.y : p.z;
    return std::fabs(pa - lo) < std::fabs(pa - hi) ? lo : hi;
  }();
  (k == 0 ? p.x : k == 1 ? p.y : p.z) = face;
  return {p, vabs3(p) * gamma_f(1)};
}
// Triangle (pbrt's interpolation): b0 a + b1 b + b2 c from the primary hit's barycentrics, error
// <= gamma_7 sum |b_i v_i| per coordinate.
template <class Verts>
Refined refine_triangle(const Verts& v, const Spawn& sp) {
  const float b1 = sp.u, b2 = sp.v, b0 = 1.0f - b1 - b2;
  const Vec3f p = v[0] * b0 + v[1] * b1 + v[2] * b2;
  return {p, (vabs3(v[0] * b0) + vabs3(v[1] * b1) + vabs3(v[2] * b2)) * gamma_f(7)};
}

}  // namespace

std::vector<CaseInfo> secondary_cases() {
  std::vector<CaseInfo> v;
  const char* fams[][2] = {{"sphere", "unit spheres 1..1e4 from the origin"},
                           {"triangle", "triangles of size 1 at 1..1e4 from the origin"},
                           {"box", "boxes of half size 0.5..1.5 at 1..1e4 from the origin"},
                           {"quadric", "radius-1 cylinders (open, axis z) at 1..1e4 from the origin"},
                           {"torus", "tori R = 1, r = 0.25 (random axis) at 1..1e4 from the origin, spawned on the outer half"}};
  for (const auto& f : fams) {
    v.push_back({f[0], kScheme[0], std::string(f[1]) + ": rays spawned at the computed hit point, no offset"});
    v.push_back({f[0], kScheme[1], "the same, spawn point moved by the Waechter-Binder integer offset"});
    v.push_back({f[0], kScheme[2], "the same, recomputed point moved along the normal by its rounding-error bound (pbrt-style)"});
  }
  return v;
}

namespace {

void secondary_sphere(Ctx& x) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  x.reseed("sphere", "secondary");
  auto run = [&](const char* method, auto kern) {
    std::vector<Sphere<float>> prims;
    std::vector<Spawn> sp;
    std::mt19937_64 gg(g());
    while (sp.size() < n) {
      const Vec3d ctr = unit_rand(gg) * lurand(gg, 1, 1e4);
      const Sphere<float> s = make_sphere(ctr, 1.0);
      const Vec3d eye = ctr + unit_rand(gg) * 4.0;
      const Vec3d target = ctr + unit_rand(gg) * 0.9;
      const Ray<float> r = make_ray(eye, target - eye);
      const Hit<float> h = kern(r, s);
      if (!h.mask) continue;
      const Vec3f p = r.at(h.t);
      Vec3d nn = to_double(p) - to_double(s.c);
      nn = nn * (1.0 / norm(nn));
      prims.push_back(s);
      sp.push_back({p, hemi(nn, gg), to_float(nn)});
    }
    secondary_rows(x, "sphere", method, prims, sp, kern, refine_sphere);
  };
  run("stable", [](const Ray<float>& r, const Sphere<float>& s) { return intersect_sphere_stable(r, s); });
  run("hearn_baker", [](const Ray<float>& r, const Sphere<float>& s) { return intersect_sphere_hearn_baker(r, s); });
  run("compensated", [](const Ray<float>& r, const Sphere<float>& s) { return intersect_sphere_compensated(r, s); });
}

void secondary_triangle(Ctx& x) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  x.reseed("triangle", "secondary");
  auto run = [&](const char* method, auto make, auto kern) {
    using P = decltype(make(Vec3f{}, Vec3f{}, Vec3f{}));
    std::vector<P> prims;
    std::vector<std::array<Vec3f, 3>> verts;
    std::vector<Spawn> sp;
    std::mt19937_64 gg(g());
    while (sp.size() < n) {
      const Vec3d c = unit_rand(gg) * lurand(gg, 1, 1e4);
      const Vec3f a = to_float(c + unit_rand(gg)), b = to_float(c + unit_rand(gg)), cc = to_float(c + unit_rand(gg));
      const P t = make(a, b, cc);
      Vec3d nn = cross(to_double(b) - to_double(a), to_double(cc) - to_double(a));
      if (norm(nn) < 1e-3) continue;
      nn = nn * (1.0 / norm(nn));
      const Vec3d target = to_double(a) * 0.3 + to_double(b) * 0.3 + to_double(cc) * 0.4;
      const Vec3d eye = target + to_double(hemi(nn, gg)) * 3.0;
      const Ray<float> r = make_ray(eye, target - eye);
      const Hit<float> h = kern(r, t);
      if (!h.mask) continue;
      if (dot(to_double(r.d), nn) > 0) nn = nn * -1.0;  // the side the ray came from
      prims.push_back(t);
      verts.push_back({a, b, cc});
      sp.push_back({r.at(h.t), hemi(nn, gg), to_float(nn), h.u, h.v});
    }
    // The scheme reads the vertices of spawn i (prims and spawns are parallel arrays).
    const Spawn* base = sp.data();
    secondary_rows(x, "triangle", method, prims, sp, kern,
                   [&](const P&, const Spawn& s) { return refine_triangle(verts[std::size_t(&s - base)], s); });
  };
  run("woop", [](Vec3f a, Vec3f b, Vec3f c) { return make_tri_verts(a, b, c); },
      [](const Ray<float>& r, const TriVerts<float>& t) { return intersect_triangle_woop(r, t); });
  run("moller_trumbore", [](Vec3f a, Vec3f b, Vec3f c) { return make_triangle(a, b, c); },
      [](const Ray<float>& r, const Triangle<float>& t) { return intersect_triangle_mt(r, t); });
}

void secondary_box(Ctx& x) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  x.reseed("box", "secondary");
  std::vector<Box<float>> prims;
  std::vector<Spawn> sp;
  while (sp.size() < n) {
    const Vec3d ctr = unit_rand(g) * lurand(g, 1, 1e4);
    const Vec3d half{urand(g, 0.5, 1.5), urand(g, 0.5, 1.5), urand(g, 0.5, 1.5)};
    const Box<float> b = make_box(ctr - half, ctr + half);
    const int ax = int(urand(g, 0, 3)) % 3;
    const double side = urand(g, 0, 1) < 0.5 ? -1.0 : 1.0;
    Vec3d nn{0, 0, 0}, off{urand(g, -0.9, 0.9) * half.x, urand(g, -0.9, 0.9) * half.y, urand(g, -0.9, 0.9) * half.z};
    (ax == 0 ? nn.x : ax == 1 ? nn.y : nn.z) = side;
    (ax == 0 ? off.x : ax == 1 ? off.y : off.z) = side * (ax == 0 ? half.x : ax == 1 ? half.y : half.z);
    const Ray<float> r = primary(ctr + off, nn, g);
    const Hit<float> h = intersect_box(r, b);
    if (!h.mask) continue;
    prims.push_back(b);
    sp.push_back({r.at(h.t), hemi(nn, g), to_float(nn)});
  }
  secondary_rows(x, "box", "slab", prims, sp, [](const Ray<float>& r, const Box<float>& b) { return intersect_box(r, b); }, refine_box);
}

void secondary_quadric(Ctx& x) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  x.reseed("quadric", "secondary");
  std::vector<Cylinder<float>> prims;
  std::vector<Spawn> sp;
  while (sp.size() < n) {
    const Vec3d ctr = unit_rand(g) * lurand(g, 1, 1e4);
    const Cylinder<float> cy = make_cylinder(ctr.x, ctr.y, 1.0, ctr.z - 1.0, ctr.z + 1.0);
    const double ph = urand(g, 0, 2 * M_PI);
    const Vec3d nn{std::cos(ph), std::sin(ph), 0};
    const Vec3d target = Vec3d{double(cy.cx), double(cy.cy), ctr.z + urand(g, -0.9, 0.9)} + nn;
    const Ray<float> r = primary(target, nn, g);
    const Hit<float> h = intersect_cylinder(r, cy);
    if (!h.mask) continue;
    const Vec3f p = r.at(h.t);
    Vec3d m{double(p.x) - double(cy.cx), double(p.y) - double(cy.cy), 0};
    m = m * (1.0 / norm(m));
    prims.push_back(cy);
    sp.push_back({p, hemi(m, g), to_float(m)});
  }
  secondary_rows(x, "quadric", "cylinder", prims, sp, [](const Ray<float>& r, const Cylinder<float>& c) { return intersect_cylinder(r, c); },
                 refine_cylinder);
}

void secondary_torus(Ctx& x) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  x.reseed("torus", "secondary");
  std::vector<Torus<float>> prims;
  std::vector<Spawn> sp;
  while (sp.size() < n) {
    const Vec3d ctr = unit_rand(g) * lurand(g, 1, 1e4);
    const Torus<float> T = make_torus(ctr, unit_rand(g), 1.0, 0.25);
    const Vec3d c = to_double(T.c), w = to_double(T.w) * (1.0 / norm(to_double(T.w)));
    const Vec3d e1 = any_perp(w), e2 = cross(w, e1);
    const double ph = urand(g, 0, 2 * M_PI), th = urand(g, -1.4, 1.4);
    const Vec3d rad = e1 * std::cos(ph) + e2 * std::sin(ph);
    const Vec3d nn = rad * std::cos(th) + w * std::sin(th);
    const Vec3d target = c + rad * 1.0 + nn * 0.25;
    const Ray<float> r = primary(target, nn, g);
    const Hit<float> h = intersect_torus_robust(r, T);
    if (!h.mask) continue;
    const Vec3f p = r.at(h.t);
    // The surface normal at the computed point (its nearest tube point), outer half only.
    const Vec3d q = to_double(p) - c;
    const Vec3d qr = q - w * dot(q, w);
    if (norm(qr) <= 1.0) continue;
    Vec3d m = q - qr * (1.0 / norm(qr));
    m = m * (1.0 / norm(m));
    prims.push_back(T);
    sp.push_back({p, hemi(m, g), to_float(m)});
  }
  secondary_rows(x, "torus", "robust", prims, sp, [](const Ray<float>& r, const Torus<float>& T) { return intersect_torus_robust(r, T); },
                 refine_torus);
}
}  // namespace

void run_secondary(Ctx& x) {
  if (any_secondary(x, "sphere")) secondary_sphere(x);
  if (any_secondary(x, "triangle")) secondary_triangle(x);
  if (any_secondary(x, "box")) secondary_box(x);
  if (any_secondary(x, "quadric")) secondary_quadric(x);
  if (any_secondary(x, "torus")) secondary_torus(x);
}

}  // namespace rb::acc
