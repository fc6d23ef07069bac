// Whole scenes through the tracer (family "scene"): the scenes of scene/precision_scenes.cpp (small
// objects on a planet, a mesh and spheres 1e3..1e7 from the origin, small spheres seen from far, a
// thin torus from 500 sizes, cylinders seen from 1e4 radii, a scene mixing scales, and a plain one)
// traced under each model (tracer/plan.hpp: fast, auto, exact) and checked ray by ray against an
// exact reference: the scene's own double geometry, every primitive against the ray in long double
// (a brute-force loop over the scene). A model's ray is the float ray it traces, lifted to world
// coordinates exactly (its frame origin plus its float origin, its float direction): the reference
// answers the question the model was asked, so what differs is the model's geometry and arithmetic.
//
// Per ray: a false hit or miss, a wrong hit (another primitive than the reference's first, or the
// same one, at a distance off by more than 1e-5 of (t + the smallest object), the precision a shaded
// point needs, unless the model's hit point lies within 2^-12 of the primitives' size of the
// reference's surface: two surfaces that touch, or a grazing ray); then a secondary ray spawned at the model's own hit point by the model's spawn offset,
// leaving on the side the primary ray came from in a random direction: a self-hit when it hits
// its own primitive within 1e-4 of that primitive's size. Mrays/s: the model's primary rays in
// 8-ray packets on one thread. Method = the model, precision = the frame it chose.
#include "accuracy/common.hpp"
#include "accuracy/exact.hpp"
#include "scene/camera.hpp"
#include "scene/sources.hpp"
#include "tracer/accel.hpp"
#include "tracer/profile.hpp"

#include <chrono>
#include <cmath>
#include <limits>

namespace rb::acc {

namespace {

using LD = long double;
struct V3 {
  LD x, y, z;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(V3 a, LD k) { return {a.x * k, a.y * k, a.z * k}; }
LD dotl(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 crossl(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 vl(const Vec3d& v) { return {LD(v.x), LD(v.y), LD(v.z)}; }
V3 vl(const Vec3f& v) { return {LD(v.x), LD(v.y), LD(v.z)}; }

constexpr LD kNo = std::numeric_limits<LD>::infinity();

// The first t in (lo, hi] among the real roots of a t^2 + 2 b t + c, ascending.
LD quad_first(LD a, LD b, LD c, LD lo, LD hi, LD& second) {
  second = kNo;
  if (a == 0) return kNo;
  const LD disc = b * b - a * c;
  if (disc < 0) return kNo;
  const LD sq = std::sqrt(disc);
  const LD q = -(b + (b < 0 ? -sq : sq));
  LD t0 = q / a, t1 = q != 0 ? c / q : t0;
  if (t0 > t1) std::swap(t0, t1);
  if (t0 >= lo && t0 <= hi) return second = t1, t0;
  if (t1 >= lo && t1 <= hi) return t1;
  return kNo;
}

// One primitive of the scene against a ray, exactly enough: its first t in [lo, hi] (kNo: none).
struct Reference {
  const scene::Scene& s;

  LD sphere(std::uint32_t i, V3 o, V3 d, LD lo, LD hi) const {
    const auto& sp = s.spheres[i];
    const V3 f = o - vl(sp.c);
    LD second;
    return quad_first(dotl(d, d), dotl(f, d), dotl(f, f) - LD(sp.r) * LD(sp.r), lo, hi, second);
  }
  LD triangle(std::uint32_t i, V3 o, V3 d, LD lo, LD hi) const {
    const auto& t = s.triangles[i];
    const V3 a = vl(s.verts[t.v[0]]), e1 = vl(s.verts[t.v[1]]) - a, e2 = vl(s.verts[t.v[2]]) - a;
    const V3 p = crossl(d, e2);
    const LD det = dotl(e1, p);
    if (det == 0) return kNo;
    const V3 tv = o - a;
    const LD u = dotl(tv, p) / det;
    if (u < 0 || u > 1) return kNo;
    const V3 q = crossl(tv, e1);
    const LD v = dotl(d, q) / det;
    if (v < 0 || u + v > 1) return kNo;
    const LD tt = dotl(e2, q) / det;
    return tt >= lo && tt <= hi ? tt : kNo;
  }
  LD polygon(std::uint32_t i, V3 o, V3 d, LD lo, LD hi) const {
    const auto& pg = s.polygons[i];
    const Vec3d* v = s.poly_verts.data() + pg.first;
    const Vec3d n = newell_normal(v, pg.count);
    const V3 nl = vl(n);
    const LD den = dotl(nl, d);
    if (den == 0) return kNo;
    const LD tt = dotl(vl(v[0]) - o, nl) / den;
    if (!(tt >= lo && tt <= hi)) return kNo;
    const V3 p = o + d * tt;
    const int ax = dominant_axis(n), a = (ax + 1) % 3, b = (ax + 2) % 3;
    auto c = [](V3 q, int k) { return k == 0 ? q.x : k == 1 ? q.y : q.z; };
    bool in = false;
    for (std::uint32_t k = 0; k < pg.count; ++k) {
      const V3 p0 = vl(v[k]) - p, p1 = vl(v[(k + 1) % pg.count]) - p;
      const LD y0 = c(p0, b), y1 = c(p1, b), x0 = c(p0, a), x1 = c(p1, a);
      if ((y0 >= 0) != (y1 >= 0) && ((y1 * (x0 - x1) >= x1 * (y0 - y1)) == (y1 >= 0))) in = !in;
    }
    return in ? tt : kNo;
  }
  // An NFF shell (open): |q_perp| = r(s) for 0 <= s <= len, q = p - base, s = q . a.
  LD shell(std::uint32_t i, V3 o, V3 d, LD lo, LD hi) const {
    const auto& c = s.cones[i];
    const V3 b = vl(c.base), ax0 = vl(c.apex) - b;
    const LD len = std::sqrt(dotl(ax0, ax0));
    const V3 a = ax0 * (LD(1) / len);
    const LD r0 = std::fabs(LD(c.base_r)), r1 = std::fabs(LD(c.apex_r)), k = (r1 - r0) / len;
    // |q - (q.a) a|^2 - (r0 + k (q.a))^2 = 0 along q = f + t d.
    const V3 f = o - b;
    const LD fa = dotl(f, a), da = dotl(d, a);
    const V3 fp = f - a * fa, dp = d - a * da;
    const LD A = dotl(dp, dp) - k * k * da * da, B = dotl(fp, dp) - (r0 + k * fa) * k * da, C = dotl(fp, fp) - (r0 + k * fa) * (r0 + k * fa);
    const LD disc = B * B - A * C;
    if (A == 0 || disc < 0) return kNo;
    const LD sq = std::sqrt(disc);
    const LD q = -(B + (B < 0 ? -sq : sq));
    LD ts[2] = {q / A, q != 0 ? C / q : q / A};
    if (ts[0] > ts[1]) std::swap(ts[0], ts[1]);
    for (LD tt : ts) {
      if (!(tt >= lo && tt <= hi)) continue;
      const LD sa = fa + tt * da;
      if (sa >= 0 && sa <= len && r0 + k * sa >= 0) return tt;
    }
    return kNo;
  }
  LD torus(std::uint32_t i, V3 o, V3 d, LD lo, LD hi) const {
    const auto& tr = s.tori[i];
    const Vec3d w0 = tr.axis * (1.0 / std::sqrt(dot(tr.axis, tr.axis)));
    const V3 w = vl(w0), c = vl(tr.c);
    const LD R = LD(tr.R), r = LD(tr.r);
    // Re-centred at the closest approach to the centre (the quartic's coefficients stay small).
    const LD dd = dotl(d, d);
    const LD t0 = -dotl(o - c, d) / dd;
    const V3 q = o + d * t0 - c;
    // T(q + s d) = (|q + s d|^2 - R^2 - r^2)^2 - 4 R^2 (r^2 - ((q + s d) . w)^2), in s.
    const LD qq = dotl(q, q), qd = dotl(q, d), qw = dotl(q, w), dw = dotl(d, w);
    const LD k0 = qq - R * R - r * r, k1 = 2 * qd, k2 = dd;
    const long double cf[5] = {k0 * k0 - 4 * R * R * (r * r - qw * qw), 2 * k0 * k1 + 8 * R * R * qw * dw,
                               k1 * k1 + 2 * k0 * k2 + 4 * R * R * dw * dw, 2 * k1 * k2, k2 * k2};
    const LD ext = (R + r) * 2 + std::sqrt(qq);
    for (LD sroot : poly_roots_ld(cf, 4, -ext / std::sqrt(dd), ext / std::sqrt(dd))) {
      const LD tt = t0 + sroot;
      if (tt >= lo && tt <= hi) return tt;
    }
    return kNo;
  }

  // The first hit of the whole scene: its t and primitive code (bvh::prim_code), brute force.
  bvh::HitRec trace(V3 o, V3 d, LD lo, LD hi, LD& t) const {
    t = kNo;
    std::uint32_t prim = bvh::kNoPrim;
    auto take = [&](LD tt, kinds::Kind k, std::uint32_t i) {
      if (tt < t) t = tt, prim = kinds::code(k, i);
    };
    kinds::AllKinds::each([&]<class K>() {
      K::each(s, [&](std::uint32_t i) {
        LD tt = kNo;
        if constexpr (std::is_same_v<K, kinds::SphereKind>) tt = sphere(i, o, d, lo, hi);
        else if constexpr (std::is_same_v<K, kinds::TriangleKind>) tt = triangle(i, o, d, lo, hi);
        else if constexpr (std::is_same_v<K, kinds::PolygonKind>) tt = polygon(i, o, d, lo, hi);
        else if constexpr (std::is_same_v<K, kinds::CylinderKind> || std::is_same_v<K, kinds::ConeKind>) tt = shell(i, o, d, lo, hi);
        else if constexpr (std::is_same_v<K, kinds::TorusKind>) tt = torus(i, o, d, lo, hi);
        // CSG objects have no reference here (no whole-scene case holds one).
        take(tt, K::id, i);
      });
    });
    return {float(t), prim};
  }
};

double feature_size(const scene::Scene& s, std::uint32_t code) {
  double f = 0;
  const kinds::Kind k = kinds::kind_of(code);
  kinds::AllKinds::each([&]<class K>() {
    if (K::id == k) f = K::feature(s, kinds::index_of(code)).size;
  });
  return f;
}

double feature_extent(const scene::Scene& s, std::uint32_t code) {
  double f = 0;
  const kinds::Kind k = kinds::kind_of(code);
  kinds::AllKinds::each([&]<class K>() {
    if (K::id == k) f = K::feature(s, kinds::index_of(code)).extent;
  });
  return f;
}

// A hit off the reference's first one that is still right within the plan's representation: the
// model's hit point lies within 2^-12 of the smaller primitive's size of the reference's surface
// (where two surfaces touch, such as a ball resting on a floor, or a ray grazes one, the order of
// hits between surfaces that close is decided by the float rounding of the geometry).
bool near_tie(const scene::Scene& s, const tracer::SceneAccel& a, const Ray<float>& fr, const bvh::HitRec& got, std::uint32_t ref) {
  kinds::HitQuery q;
  q.scene = &s;
  q.origin = a.origin();
  q.ray = fr;
  q.t = got.t;
  q.p = a.world_point(fr, got.t);
  const kinds::Kind k = kinds::kind_of(ref);
  Vec3d on = q.p;
  kinds::AllKinds::each([&]<class K>() {
    if constexpr (!K::custom || std::is_same_v<K, kinds::PolygonKind>)
      if (K::id == k) on = K::surface(q, kinds::index_of(ref)).p;
  });
  const Vec3d gap = q.p - on;
  const double tol = 0x1p-12 * std::min(feature_extent(s, got.prim), feature_extent(s, ref));
  return std::sqrt(dot(gap, gap)) <= tol;
}

}  // namespace

std::vector<CaseInfo> scene_cases() {
  std::vector<CaseInfo> v;
  const std::pair<const char*, const char*> cs[] = {
      {"ball_ground", "a ball resting on a floor near the origin, a second ball, one light (needs nothing special)"},
      {"ball_ground_far", "the same scene 6.4e6 from the origin"},
      {"planet", "the balls on a planet of radius 6.4e6, the camera 4 above its surface"},
      {"mesh_spheres_1e3", "a closed mesh (1,280 triangles), four spheres and a floor, 1e3 from the origin"},
      {"mesh_spheres_1e5", "the same 1e5 from the origin"},
      {"mesh_spheres_1e7", "the same 1e7 from the origin"},
      {"far_spheres", "64 small spheres (radius 0.01..0.1) seen from 5e3 away"},
      {"thin_torus", "two tori with tubes 100 times thinner than their rings, seen from 500 sizes"},
      {"far_cylinders", "NFF cylinders and cone frusta seen from 1e4 radii"},
      {"mixed_scales", "a planet, a moon 3.8e8 away, a mesh, spheres and a cylinder on the planet"},
  };
  for (const auto& [n, w] : cs) v.push_back({"scene", n, w});
  return v;
}

void run_scenes(Ctx& x) {
  for (const CaseInfo& ci : scene_cases()) {
    if (!x.selected(ci.family, ci.name)) continue;
    const scene::Scene s = scene::precision_scene(ci.name);
    const tracer::Profile prof = tracer::make_profile(s);
    const Reference ref{s};
    const scene::View view = scene::view_of(s);
    const double small = prof.object_min > 0 ? prof.object_min : 1.0;
    for (tracer::Model m : {tracer::Model::fast, tracer::Model::automatic, tracer::Model::exact}) {
      x.tick(ci.family, ci.name);
      x.reseed(ci.family, ci.name);
      const tracer::SceneAccel a = tracer::SceneAccel::build(s, tracer::make_plan(s, prof, m));
      // Primary rays: jittered through the image, the same directions for every model.
      const int side = std::max(4, int(std::sqrt(double(x.rays))));
      RaySoA rays;
      for (int py = 0; py < side; ++py)
        for (int px = 0; px < side; ++px) {
          const double u = 2 * (px + urand(x.rng, 0, 1)) / side - 1, v = 1 - 2 * (py + urand(x.rng, 0, 1)) / side;
          rays.push(a.frame_ray(view.from, view.dir(u, v)));
        }
      const std::size_t n = rays.count;
      std::vector<bvh::HitRec> hits(rays.size());
      tracer::TraceOptions to;
      to.packet = 8;
      a.trace(rays, 0, rays.size(), hits.data(), to);
      Row r;
      r.family = "scene", r.case_name = ci.name, r.what = ci.what;
      r.method = tracer::model_name(m);
      r.precision = tracer::frame_name(a.plan().frame);
      r.rays = r.tests = n;
      std::vector<double> err;
      std::size_t spawned = 0;
      RaySoA second;
      std::vector<std::uint32_t> source;
      for (std::size_t i = 0; i < n; ++i) {
        const Ray<float> fr = rays.get(i);
        const V3 o = vl(a.origin()) + vl(fr.o), d = vl(fr.d);
        LD tref;
        const bvh::HitRec h = ref.trace(o, d, LD(fr.tmin), LD(fr.tmax), tref);
        const bool got = hits[i].prim != bvh::kNoPrim, want = h.prim != bvh::kNoPrim;
        if (got && !want) ++r.false_hits;
        if (!got && want) ++r.false_misses;
        if (got && want) {
          const double dt = std::fabs(double(hits[i].t) - double(tref));
          const double tol = 1e-5 * (double(tref) + small);
          if (dt > tol && !near_tie(s, a, fr, hits[i], h.prim)) ++r.wrong_roots;
          err.push_back(dt / (double(std::numeric_limits<float>::epsilon()) * (double(tref) + small)));
        }
        if (!got) continue;
        // The secondary ray: from the model's hit point by its spawn offset, into the hemisphere
        // the primary ray came from.
        const kinds::Surface sf = a.surface(hits[i].prim, fr, hits[i].t);
        const Vec3f side_n = dot(sf.ng, fr.d) <= 0.0f ? sf.ng : -sf.ng;
        Vec3d dir = unit_rand(x.rng);
        if (dot(dir, to_double(side_n)) < 0) dir = dir * -1.0;
        second.push(make_ray(a.spawn_point(sf, side_n), to_float(dir)));
        source.push_back(hits[i].prim);
        ++spawned;
      }
      std::vector<bvh::HitRec> sh(second.size());
      tracer::TraceOptions so;
      if (second.count) a.trace(second, 0, second.size(), sh.data(), so);
      for (std::size_t k = 0; k < second.count; ++k)
        if (sh[k].prim == source[k] && double(sh[k].t) < 1e-4 * feature_size(s, source[k])) ++r.self_hits;
      const double N = double(std::max<std::size_t>(n, 1));
      r.false_hit_ppm = 1e6 * double(r.false_hits) / N;
      r.false_miss_ppm = 1e6 * double(r.false_misses) / N;
      r.wrong_root_ppm = 1e6 * double(r.wrong_roots) / N;
      r.self_hit_ppm = spawned ? 1e6 * double(r.self_hits) / double(spawned) : 0.0;
      r.leak_ppm = r.multi_hit_ppm = r.nan_ppm = std::numeric_limits<double>::quiet_NaN();
      r.iterations = std::numeric_limits<double>::quiet_NaN();
      r.t_err_ulp_p50 = r.t_err_ulp_p99 = r.t_err_ulp_max = std::numeric_limits<double>::quiet_NaN();
      if (!err.empty()) {
        std::sort(err.begin(), err.end());
        r.scaled_err_p99 = err[std::min(err.size() - 1, std::size_t(0.99 * double(err.size())))];
      } else {
        r.scaled_err_p99 = std::numeric_limits<double>::quiet_NaN();
      }
      r.ns_per_test = std::numeric_limits<double>::quiet_NaN();
      if (x.o->timing) {
        double best = 1e300;
        for (int rep = 0; rep < 5; ++rep) {
          const auto t0 = std::chrono::steady_clock::now();
          a.trace(rays, 0, rays.size(), hits.data(), to);
          best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        r.ns_per_test = best * 1e9 / N;
      }
      x.rows->push_back(r);
    }
  }
}

}  // namespace rb::acc
