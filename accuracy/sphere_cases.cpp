// Sphere cases: a small sphere far away (distance / radius 1e1..1e7), the planet (radius 6.4e6,
// eye 1..100 above it, at the pole and at 45 degrees latitude, rays at the horizon's dip angle), a
// viewer 1..10 above spheres of radius 1e2..1e6 looking in every direction, tangent rays at
// r (1 +- 10^-k).
#include "accuracy/exact.hpp"
#include "kernels/sphere.hpp"

#include <cmath>

namespace rb::acc {

namespace {

Case<Sphere> new_case(const std::string& name, const std::string& what) {
  Case<Sphere> c;
  c.family = "sphere", c.name = name, c.what = what;
  return c;
}
void add(Case<Sphere>& c, const Sphere<float>& s, const Ray<float>& r0) {
  c.prims.push(s);
  c.rays.push(r0);
  const Ray<float> r = c.rays.get(c.rays.count - 1);
  c.ref.push_back(sphere_ref(r.o, r.d, r.tmin, r.tmax, s.c, s.r2));
}

void measure_all(Ctx& x, const Case<Sphere>& c) {
  measure(x, c, "geometric", [](const auto& r, const auto& s, IterCount*) { return intersect_sphere_geometric(r, s); });
  measure(x, c, "algebraic", [](const auto& r, const auto& s, IterCount*) { return intersect_sphere_algebraic(r, s); });
  measure(x, c, "stable", [](const auto& r, const auto& s, IterCount*) { return intersect_sphere_stable(r, s); });
  measure(x, c, "hearn_baker", [](const auto& r, const auto& s, IterCount*) { return intersect_sphere_hearn_baker(r, s); });
  measure(x, c, "compensated", [](const auto& r, const auto& s, IterCount*) { return intersect_sphere_compensated(r, s); });
}

// A ray from `eye` passing the centre c at distance b (perpendicular offset along a random
// direction).
Ray<float> aimed(const Vec3d& eye, const Vec3d& c, double b, std::mt19937_64& g) {
  Vec3d d = c - eye;
  d = d * (1.0 / norm(d));
  Vec3d p = unit_rand(g);
  p = p - d * dot(p, d);
  p = p * (1.0 / norm(p));
  return make_ray(eye, (c + p * b) - eye);
}

}  // namespace

std::vector<CaseInfo> sphere_cases() {
  return {
      {"sphere", "far_small_1e1", "unit sphere at distance 1e1, rays passing the centre at 0..0.95 R or 1.05..1.5 R"},
      {"sphere", "far_small_1e2", "the same at distance 1e2"},
      {"sphere", "far_small_1e3", "the same at distance 1e3"},
      {"sphere", "far_small_1e4", "the same at distance 1e4"},
      {"sphere", "far_small_1e5", "the same at distance 1e5"},
      {"sphere", "far_small_1e7", "the same at distance 1e7"},
      {"sphere", "planet_pole", "R = 6.4e6, eye 1..100 above the pole, rays at the dip angle +- 10^-7..10^-1 of it"},
      {"sphere", "planet_45", "the same at 45 degrees latitude"},
      {"sphere", "above_1e2", "R = 1e2, eye 1..10 above it, rays in random directions below the horizon and above it (not only grazing): "
                              "a viewer on a sphere 10..1e2 times its height"},
      {"sphere", "above_1e3", "the same with R = 1e3"},
      {"sphere", "above_1e4", "the same with R = 1e4"},
      {"sphere", "above_1e5", "the same with R = 1e5"},
      {"sphere", "above_1e6", "the same with R = 1e6"},
      {"sphere", "tangent", "rays passing the centre at R (1 +- 10^-k), k = 1..7, distance 4 R"},
  };
}

void run_spheres(Ctx& x) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  const auto infos = sphere_cases();
  x.each_case(infos, [&](const auto& ci) {
    Case<Sphere> c = new_case(ci.name, ci.what);
    if (ci.name.rfind("far_small", 0) == 0) {
      const double D = std::pow(10.0, std::stod(ci.name.substr(std::string("far_small_1e").size())));
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3d ctr = unit_rand(g) * urand(g, 0, 4);
        const double R = urand(g, 0.5, 2);
        const Vec3d eye = ctr + unit_rand(g) * (D * R);
        const double b = (i % 2 ? urand(g, 0, 0.95) : urand(g, 1.05, 1.5)) * R;
        add(c, make_sphere(ctr, R), aimed(eye, ctr, b, g));
      }
    } else if (ci.name.rfind("above_", 0) == 0) {
      // A viewer 1..10 above a sphere of radius R at a random place of it: 90 % of the rays go
      // below the horizon (they hit the sphere near the viewer), 10 % above it.
      const double R = std::pow(10.0, std::stod(ci.name.substr(std::string("above_1e").size())));
      for (std::size_t i = 0; i < n; ++i) {
        const double h = lurand(g, 1, 10);
        const Vec3d up = unit_rand(g);
        const Vec3d eye = up * (R + h);
        Vec3d d = unit_rand(g);
        const bool down = i % 10 != 0;
        if ((dot(d, up) < 0) != down) d = d - up * (2 * dot(d, up));
        add(c, make_sphere(Vec3d{0, 0, 0}, R), make_ray(eye, d));
      }
    } else if (ci.name.rfind("planet", 0) == 0) {
      const bool large = false;
      const double R = 6.4e6;
      const bool pole = ci.name == "planet_pole";
      for (std::size_t i = 0; i < n; ++i) {
        const double h = lurand(g, 1, large ? 10 : 100);
        const Vec3d up = pole ? Vec3d{0, 0, 1} : Vec3d{std::sqrt(0.5), 0, std::sqrt(0.5)};
        const Vec3d eye = up * (R + h);
        const double dip = std::acos(R / (R + h));
        const double a = dip * (1 + (i % 2 ? 1 : -1) * lurand(g, 1e-7, 1e-1));
        const Vec3d e1 = any_perp(up), e2 = cross(up, e1);
        const double az = urand(g, 0, 2 * M_PI);
        const Vec3d hor = e1 * std::cos(az) + e2 * std::sin(az);
        const Vec3d d = hor * std::cos(a) - up * std::sin(a);
        add(c, make_sphere(Vec3d{0, 0, 0}, R), make_ray(eye, d));
      }
    } else {  // tangent
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3d ctr = unit_rand(g) * urand(g, 0, 4);
        const double R = urand(g, 0.5, 2);
        const double k = std::floor(urand(g, 1, 8));
        const double b = R * (1 + (i % 2 ? 1 : -1) * std::pow(10.0, -k));
        add(c, make_sphere(ctr, R), aimed(ctr + unit_rand(g) * (4 * R), ctr, b, g));
      }
    }
    measure_all(x, c);
  });
}

}  // namespace rb::acc
