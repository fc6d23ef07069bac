// Cylinder and cone cases (in their own frame: axis z): rays parallel to the cylinder's axis or
// to a cone generator (also tilted by 10^-k), rays exactly through and near the cone's apex,
// distant cameras, near-tangent rays. Open surfaces and capped solids each have their reference.
// The shell cases are the tracer's own cylinder and cone kinds (NFF shells: the unit quadric placed
// by an affine map, tracer/kinds/cylinder_kind.hpp), at a random place and axis, seen from 10^k of their
// radius: the evidence of the plan's choice between float and double (tracer/plan.cpp).
#include "accuracy/exact.hpp"
#include "kernels/cylinder_cone.hpp"
#include "tracer/kinds.hpp"

#include <cmath>

namespace rb::acc {

namespace {

template <template <class> class P>
struct Pair {
  Case<P> open, solid;  // the same rays; one primitive each (open surface, capped solid)
};

void add_cyl(Pair<Cylinder>& c, const Ray<float>& r0) {
  const Cylinder<float> cy = make_cylinder(0.25, -0.125, 1.0, 0.0, 2.0);
  c.open.prims.push(cy), c.solid.prims.push(cy);
  c.open.rays.push(r0), c.solid.rays.push(r0);
  const Ray<float> r = c.open.rays.get(c.open.rays.count - 1);
  c.open.ref.push_back(quadric_ref(Quad::cylinder, false, r.o, r.d, r.tmin, r.tmax, cy.cx, cy.cy, cy.r2, cy.z0, cy.z1));
  c.solid.ref.push_back(quadric_ref(Quad::cylinder, true, r.o, r.d, r.tmin, r.tmax, cy.cx, cy.cy, cy.r2, cy.z0, cy.z1));
}
// The cone x^2 + y^2 = z^2 about the apex: open, both nappes, -2 <= z <= 2 (the apex inside the
// height range, not on a rim); capped, one nappe 0 <= z <= 2 (the closed frustum with its tip).
const Vec3d kApex{0.0, 0.0, 0.0};
void add_cone(Pair<Cone>& c, const Ray<float>& r0) {
  const Cone<float> open = make_cone(kApex, -2.0, 2.0), solid = make_capped_cone(kApex, 0.0, 2.0);
  c.open.prims.push(open), c.solid.prims.push(solid);
  c.open.rays.push(r0), c.solid.rays.push(r0);
  const Ray<float> r = c.open.rays.get(c.open.rays.count - 1);
  // The reference works in the apex frame (the apex is the origin here, exactly).
  c.open.ref.push_back(quadric_ref(Quad::cone, false, r.o, r.d, r.tmin, r.tmax, 0, 0, 0, open.z0, open.z1));
  c.solid.ref.push_back(quadric_ref(Quad::cone, true, r.o, r.d, r.tmin, r.tmax, 0, 0, 0, solid.z0, solid.z1));
}

template <template <class> class P>
void name(Pair<P>& c, const CaseInfo& ci) {
  c.open.family = c.solid.family = "quadric";
  c.open.name = c.solid.name = ci.name;
  c.open.what = c.solid.what = ci.what;
}

Vec3d tilt(const Vec3d& d, double k, std::mt19937_64& g) {
  Vec3d p = unit_rand(g);
  p = p - d * dot(p, d);
  return d + p * (k / norm(p));
}

}  // namespace

std::vector<CaseInfo> quadric_cases() {
  return {
      {"quadric", "cyl_parallel_axis", "radius-1 cylinder, 0 <= z <= 2: rays along +-z exactly or tilted by 10^-3..10^-9, inside and outside"},
      {"quadric", "cyl_tangent", "rays across the axis passing it at r (1 +- 10^-k), k = 1..7"},
      {"quadric", "cyl_far_camera", "the cylinder seen from 1e4 away, rays at random points of it"},
      {"quadric", "cone_generator_parallel", "rays parallel to a generator of the 45-degree cone (exactly and tilted by 10^-k)"},
      {"quadric", "cone_apex", "steep rays exactly through the apex (integer directions, origin = apex - 2^k d)"},
      {"quadric", "cone_near_apex", "the same rays moved off the apex by 1e-7..1e-4 (the two nappes' roots within rounding of each other)"},
      {"quadric", "cone_far_camera", "the cone seen from 1e4 away"},
      {"quadric", "shell_cyl_far_1e1", "a placed open cylinder (NFF shell; random axis, radius 0.5..2, length 1..4) seen from 10 radii"},
      {"quadric", "shell_cyl_far_1e2", "the same seen from 1e2 radii"},
      {"quadric", "shell_cyl_far_1e3", "the same seen from 1e3 radii"},
      {"quadric", "shell_cyl_far_1e4", "the same seen from 1e4 radii"},
      {"quadric", "shell_cyl_far_1e5", "the same seen from 1e5 radii"},
      {"quadric", "shell_cone_far_1e1", "a placed open cone frustum (NFF shell; random axis, radii 0.5..2 and 0.1..0.9 of it) seen from 10 radii"},
      {"quadric", "shell_cone_far_1e2", "the same seen from 1e2 radii"},
      {"quadric", "shell_cone_far_1e3", "the same seen from 1e3 radii"},
      {"quadric", "shell_cone_far_1e4", "the same seen from 1e4 radii"},
      {"quadric", "shell_cone_far_1e5", "the same seen from 1e5 radii"},
  };
}

namespace {
// Shells seen from D radii: random place (|centre| <= 4) and axis, rays from D radii away aimed at
// random points of the shell's bounding sphere.
void run_shells(Ctx& x, const CaseInfo& ci) {
  auto& g = x.rng;
  const bool cyl = ci.name.rfind("shell_cyl", 0) == 0;
  const double D = std::pow(10.0, std::stod(ci.name.substr(ci.name.size() - 1)));
  auto common = [&](auto& c) {
    c.family = "quadric", c.name = ci.name, c.what = ci.what;
  };
  Case<Transformed<Cylinder>::T> cc;
  Case<Transformed<Cone>::T> kc;
  common(cc), common(kc);
  for (std::size_t i = 0; i < x.rays; ++i) {
    const Vec3d base = unit_rand(g) * urand(g, 0, 4), axis = unit_rand(g) * urand(g, 1, 4);
    const double rb = urand(g, 0.5, 2), ra = cyl ? rb : rb * urand(g, 0.1, 0.9);
    const Vec3d centre = base + axis * 0.5;
    const double bound = std::sqrt(rb * rb + 0.25 * dot(axis, axis));
    const Vec3d eye = centre + unit_rand(g) * (D * rb);
    const Vec3d target = centre + unit_rand(g) * (bound * std::cbrt(urand(g, 0, 1)));
    const Ray<float> r0 = make_ray(eye, target - eye);
    if (cyl) {
      const auto p = place_cylinder(base, base + axis, rb);
      cc.prims.push(p);
      cc.rays.push(r0);
      const Ray<float> r = cc.rays.get(cc.rays.count - 1);
      cc.ref.push_back(placed_quadric_ref(Quad::cylinder, p.inv, r.o, r.d, r.tmin, r.tmax, p.prim.cx, p.prim.cy, p.prim.r2, p.prim.z0,
                                         p.prim.z1, 2 * bound));
    } else {
      const auto p = place_cone(base, rb, base + axis, ra);
      kc.prims.push(p);
      kc.rays.push(r0);
      const Ray<float> r = kc.rays.get(kc.rays.count - 1);
      kc.ref.push_back(placed_quadric_ref(Quad::cone, p.inv, r.o, r.d, r.tmin, r.tmax, 0, 0, 0, p.prim.z0, p.prim.z1, 2 * bound));
    }
  }
  // The tracer's two methods of each kind (tracer/kinds/cylinder_kind.hpp, cone_kind.hpp).
  if (cyl) {
    measure(x, cc, "transformed", [](const auto& r, const auto& p, IterCount*) {
      return kinds::CylinderKind::hit<0>(r, {}, p);
    });
    measure(x, cc, "recentred", [](const auto& r, const auto& p, IterCount*) {
      return kinds::CylinderKind::hit<1>(r, {}, p);
    });
  } else {
    measure(x, kc, "transformed", [](const auto& r, const auto& p, IterCount*) { return kinds::ConeKind::hit<0>(r, {}, p); });
    measure(x, kc, "recentred", [](const auto& r, const auto& p, IterCount*) { return kinds::ConeKind::hit<1>(r, {}, p); });
  }
}
}  // namespace

void run_quadrics(Ctx& x) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  x.each_case(quadric_cases(), [&](const auto& ci) {
    if (ci.name.rfind("shell_", 0) == 0) {
      run_shells(x, ci);
    } else if (ci.name.rfind("cyl", 0) == 0) {
      Pair<Cylinder> c;
      name(c, ci);
      const Vec3d axis{0.25, -0.125, 0};
      for (std::size_t i = 0; i < n; ++i) {
        if (ci.name == "cyl_parallel_axis") {
          const double ph = urand(g, 0, 2 * M_PI), rho = urand(g, 0, 1.3);
          const Vec3d P = axis + Vec3d{std::cos(ph), std::sin(ph), 0} * rho + Vec3d{0, 0, urand(g, -3, 5)};
          Vec3d d{0, 0, i % 2 ? 1.0 : -1.0};
          if (i % 3) d = tilt(d, std::pow(10.0, -std::floor(urand(g, 3, 10))), g);
          add_cyl(c, make_ray(P, d));
        } else if (ci.name == "cyl_tangent") {
          const double ph = urand(g, 0, 2 * M_PI);
          const Vec3d rad{std::cos(ph), std::sin(ph), 0}, tan{-std::sin(ph), std::cos(ph), 0};
          const double b = 1 + (i % 2 ? 1 : -1) * std::pow(10.0, -std::floor(urand(g, 1, 8)));
          const Vec3d P = axis + rad * b + Vec3d{0, 0, urand(g, 0.1, 1.9)};
          add_cyl(c, make_ray(P - tan * 3.0, tan));
        } else {
          const Vec3d target = axis + Vec3d{urand(g, -1, 1), urand(g, -1, 1), urand(g, 0, 2)};
          const Vec3d eye = axis + Vec3d{0, 0, 1} + unit_rand(g) * 1e4;
          add_cyl(c, make_ray(eye, target - eye));
        }
      }
      measure(x, c.open, "cylinder", [](const auto& r, const auto& p, IterCount*) { return intersect_cylinder(r, p); });
      measure(x, c.solid, "cylinder_capped", [](const auto& r, const auto& p, IterCount*) { return intersect_cylinder_capped(r, p); });
    } else {
      Pair<Cone> c;
      name(c, ci);
      for (std::size_t i = 0; i < n; ++i) {
        if (ci.name == "cone_generator_parallel") {
          const double ph = urand(g, 0, 2 * M_PI);
          Vec3d d{std::cos(ph), std::sin(ph), 1.0};
          if (i % 2) d = tilt(d * (1 / std::sqrt(2.0)), std::pow(10.0, -std::floor(urand(g, 2, 9))), g);
          const Vec3d P = Vec3d{urand(g, -1, 1), urand(g, -1, 1), urand(g, 0.2, 1.8)};
          add_cone(c, make_ray(P - d * 4.0, d));
        } else if (ci.name == "cone_apex" || ci.name == "cone_near_apex") {
          Vec3d d{std::floor(urand(g, -3, 4)), std::floor(urand(g, -3, 4)), std::floor(urand(g, 4, 9))};
          if (i % 2) d.z = -d.z;
          Vec3d O = kApex - d * std::ldexp(1.0, int(urand(g, 0, 3)));
          if (ci.name == "cone_near_apex") O = O + unit_rand(g) * lurand(g, 1e-7, 1e-4);  // near, not through
          add_cone(c, make_ray(O, d));
        } else {
          const Vec3d target{urand(g, -1, 1), urand(g, -1, 1), urand(g, 0, 2)};
          const Vec3d eye = Vec3d{0, 0, 1} + unit_rand(g) * 1e4;
          add_cone(c, make_ray(eye, target - eye));
        }
      }
      measure(x, c.open, "cone", [](const auto& r, const auto& p, IterCount*) { return intersect_cone(r, p); });
      measure(x, c.solid, "cone_capped", [](const auto& r, const auto& p, IterCount*) { return intersect_cone_capped(r, p); });
    }
  });
}

}  // namespace rb::acc
