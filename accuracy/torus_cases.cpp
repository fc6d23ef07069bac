// Torus cases: the camera at 5, 50 and 500 times the torus size, a thin tube (R / r = 100) seen
// from 5 and 500 sizes,
// tangent rays (outer equator and top circle at r (1 +- 10^-k)), rays along the axis through the
// tube. Reference: all real roots of the quartic from the stored floats (long double isolation,
// re-centred at the closest approach); a hit that is not the first root is a wrong root.
#include "accuracy/exact.hpp"
#include "kernels/torus.hpp"

#include <cmath>

namespace rb::acc {

namespace {

struct Placed {
  Torus<float> T;
  Vec3d c, w, e1, e2;
};
Placed place(std::mt19937_64& g, double R, double r) {
  Placed p;
  p.c = {0.5, -0.25, 0.125};
  p.w = unit_rand(g);
  p.T = make_torus(p.c, p.w, R, r);
  p.w = to_double(p.T.w);
  p.e1 = any_perp(p.w);
  p.e2 = cross(p.w, p.e1);
  return p;
}

void add(Case<Torus>& c, const Torus<float>& T, const Ray<float>& r0) {
  c.prims.push(T);
  c.rays.push(r0);
  const Ray<float> r = c.rays.get(c.rays.count - 1);
  const auto roots = torus_ref_roots(r.o, r.d, r.tmin, r.tmax, T.c, T.w, T.R, T.r);
  Ref f;
  f.scale = norm(to_double(r.o)) + norm(to_double(T.c)) + double(T.R) + double(T.r);
  if (!roots.empty()) f.cls = Cls::hit, f.t = roots.front(), f.has_t = true;
  c.ref.push_back(f);
}

}  // namespace

std::vector<CaseInfo> torus_cases() {
  return {
      {"torus", "camera_5x", "R = 1, r = 0.25, random axis; camera at 5 torus sizes, rays at random points of the bounding sphere"},
      {"torus", "camera_50x", "the same at 50 torus sizes"},
      {"torus", "camera_500x", "the same at 500 torus sizes"},
      {"torus", "thin_tube", "R / r = 100, camera at 5 sizes, rays aimed at points of the tube's circle"},
      {"torus", "thin_500x", "the same thin tube seen from 500 sizes"},
      {"torus", "tangent", "rays touching the outer equator or the top circle at r (1 +- 10^-k), k = 1..7"},
      {"torus", "along_axis", "rays parallel to the axis through the tube (and through the hole)"},
  };
}

void run_torus(Ctx& x) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  x.each_case(torus_cases(), [&](const auto& ci) {
    Case<Torus> c;
    c.family = "torus", c.name = ci.name, c.what = ci.what;
    for (std::size_t i = 0; i < n; ++i) {
      if (ci.name.rfind("camera_", 0) == 0) {
        const double K = ci.name == "camera_5x" ? 5 : ci.name == "camera_50x" ? 50 : 500;
        const Placed p = place(g, 1.0, 0.25);
        const Vec3d eye = p.c + unit_rand(g) * (K * 1.25);
        const Vec3d target = p.c + unit_rand(g) * (1.25 * std::cbrt(urand(g, 0, 1)));
        add(c, p.T, make_ray(eye, target - eye));
      } else if (ci.name == "thin_tube" || ci.name == "thin_500x") {
        const Placed p = place(g, 1.0, 0.01);
        const double ph = urand(g, 0, 2 * M_PI);
        const Vec3d ring = p.c + (p.e1 * std::cos(ph) + p.e2 * std::sin(ph));
        const Vec3d target = ring + unit_rand(g) * (0.012 * urand(g, 0, 1));
        const Vec3d eye = p.c + unit_rand(g) * (ci.name == "thin_tube" ? 5.05 : 505.0);
        add(c, p.T, make_ray(eye, target - eye));
      } else if (ci.name == "tangent") {
        const Placed p = place(g, 1.0, 0.25);
        const double ph = urand(g, 0, 2 * M_PI);
        const Vec3d rad = p.e1 * std::cos(ph) + p.e2 * std::sin(ph), tan = cross(p.w, rad);
        const double eps = (i % 2 ? 1 : -1) * std::pow(10.0, -std::floor(urand(g, 1, 8)));
        Vec3d P, d;
        if (i % 4 < 2) {  // outer equator: in the ring's plane, along the tangent
          P = p.c + rad * (1.0 + 0.25 * (1 + eps));
          d = tan;
        } else {  // top circle: at height r (1 + eps) over the ring, along the tangent
          P = p.c + rad * 1.0 + p.w * (0.25 * (1 + eps));
          d = tan;
        }
        add(c, p.T, make_ray(P - d * 3.0, d));
      } else {  // along_axis
        const Placed p = place(g, 1.0, 0.25);
        const double ph = urand(g, 0, 2 * M_PI);
        const double rho = i % 8 == 0 ? urand(g, 0, 0.7) : urand(g, 0.7, 1.3);
        const Vec3d P = p.c + (p.e1 * std::cos(ph) + p.e2 * std::sin(ph)) * rho;
        const Vec3d d = p.w * (i % 2 ? 1.0 : -1.0);
        add(c, p.T, make_ray(P - d * 3.0, d));
      }
    }
    measure(x, c, "ferrari", [](const auto& r, const auto& T, IterCount*) { return intersect_torus_ferrari(r, T); }, true);
    measure(x, c, "robust", [](const auto& r, const auto& T, IterCount* ic) { return intersect_torus_robust(r, T, ic); }, true, true);
  });
}

}  // namespace rb::acc
