// Secondary rays: a ray spawned at a computed hit point, leaving the surface on the side it came
// from, must not hit the same (convex) primitive again. Self-hits per million spawned rays, with
// the spawn point as computed and with an offset scheme: Waechter and Binder's integer offset
// (Ray Tracing Gems, chapter 6: move the point along the geometric normal by a number of float
// ulps proportional to the normal, or by a fixed small distance near the origin). ns_per_test is
// the cost of one spawned test including the offset, so the two rows show what the offset costs.
#include "accuracy/common.hpp"
#include "kernels/sphere.hpp"
#include "kernels/triangle.hpp"
#include "kernels/triangle_woop.hpp"

#include <bit>
#include <cmath>

namespace rb::acc {

namespace {

// Waechter-Binder: origin 1/32, float_scale 1/65536, int_scale 256 (the published constants).
inline float wb_one(float p, float n) {
  const int of = int(256.0f * n);
  const float pi = std::bit_cast<float>(std::bit_cast<int>(p) + (p < 0 ? -of : of));
  return std::fabs(p) < 1.0f / 32.0f ? p + (1.0f / 65536.0f) * n : pi;
}
inline Vec3f wb_offset(const Vec3f& p, const Vec3f& n) { return {wb_one(p.x, n.x), wb_one(p.y, n.y), wb_one(p.z, n.z)}; }

// One spawned test: point p, outgoing unit direction d, unit geometric normal n on d's side.
struct Spawn {
  Vec3f p, d, n;
};

template <template <class> class P, class K>
void secondary_rows(Ctx& x, const std::string& family, const std::string& method, const std::vector<P<float>>& prims,
                    const std::vector<Spawn>& sp, const K& kern) {
  for (int offset = 0; offset < 2; ++offset) {
    x.tick(family, offset ? "secondary_wb_offset" : "secondary_no_offset");
    auto pass = [&](std::size_t* self) {
      double sink = 0;
      for (std::size_t i = 0; i < sp.size(); ++i) {
        const Spawn& s = sp[i];
        const Vec3f o = offset ? wb_offset(s.p, s.n) : s.p;
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
    r.case_name = offset ? "secondary_wb_offset" : "secondary_no_offset";
    r.what = offset ? "rays spawned at the computed hit point moved by the Waechter-Binder integer offset"
                    : "rays spawned at the computed hit point, no offset";
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

}  // namespace

std::vector<CaseInfo> secondary_cases() {
  return {
      {"sphere", "secondary_no_offset", "unit spheres 1..1e4 from the origin: rays spawned at the computed hit point, no offset"},
      {"sphere", "secondary_wb_offset", "the same, spawn point moved by the Waechter-Binder integer offset"},
      {"triangle", "secondary_no_offset", "triangles of size 1 at 1..1e4 from the origin: spawned at the hit point, no offset"},
      {"triangle", "secondary_wb_offset", "the same, with the Waechter-Binder offset"},
  };
}

void run_secondary(Ctx& x) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  if (x.selected("sphere", "secondary_no_offset") || x.selected("sphere", "secondary_wb_offset")) {
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
      secondary_rows(x, "sphere", method, prims, sp, kern);
    };
    run("stable", [](const Ray<float>& r, const Sphere<float>& s) { return intersect_sphere_stable(r, s); });
    run("hearn_baker", [](const Ray<float>& r, const Sphere<float>& s) { return intersect_sphere_hearn_baker(r, s); });
    run("compensated", [](const Ray<float>& r, const Sphere<float>& s) { return intersect_sphere_compensated(r, s); });
  }
  if (x.selected("triangle", "secondary_no_offset") || x.selected("triangle", "secondary_wb_offset")) {
    x.reseed("triangle", "secondary");
    auto run = [&](const char* method, auto make, auto kern) {
      using P = decltype(make(Vec3f{}, Vec3f{}, Vec3f{}));
      std::vector<P> prims;
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
        sp.push_back({r.at(h.t), hemi(nn, gg), to_float(nn)});
      }
      secondary_rows(x, "triangle", method, prims, sp, kern);
    };
    run("woop", [](Vec3f a, Vec3f b, Vec3f c) { return make_tri_verts(a, b, c); },
        [](const Ray<float>& r, const TriVerts<float>& t) { return intersect_triangle_woop(r, t); });
    run("moller_trumbore", [](Vec3f a, Vec3f b, Vec3f c) { return make_triangle(a, b, c); },
        [](const Ray<float>& r, const Triangle<float>& t) { return intersect_triangle_mt(r, t); });
  }
}

}  // namespace rb::acc
