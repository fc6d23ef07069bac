// Bench specs of the quadric kernel family (see bench/specs.hpp for the shape of a spec).
// Class-c rays hit exactly the class-c primitives, which sit around (10 c, 0, .):
//   spheres, quadrics, quadrics of revolution and transformed instances: the default rays (from
//   z = -50 towards +z) and primitives at z = 3k;
//   cylinders and cones (axis z, as in the lecture's basic position): rays from y = -50 towards
//   +y, primitives at y = 3k, so the rays cross the lateral surface rather than run along it.
#pragma once

#include "bench/specs.hpp"
#include "kernels/cylinder_cone.hpp"
#include "kernels/quadric.hpp"
#include "kernels/sphere.hpp"
#include "kernels/transform.hpp"

namespace rb::bench {

// uni() as a double (for the double-precision placement matrices).
inline double unid(Rng& g, float a, float b) { return double(uni(g, a, b)); }

struct SphereStableSpec : SphereGeometricSpec {
  static constexpr const char* method = "stable";
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Sphere<F>& s, const Soa&, std::size_t) { return intersect_sphere_stable(r, s); }
};

struct SphereHearnBakerSpec : SphereGeometricSpec {
  static constexpr const char* method = "hearn_baker";
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Sphere<F>& s, const Soa&, std::size_t) { return intersect_sphere_hearn_baker(r, s); }
};

// Compensated (error-free transformations; exact to about double precision on the discriminant):
// the float method for grazing rays on a planet. Its speed beside stable is the price of that.
struct SphereCompensatedSpec : SphereGeometricSpec {
  static constexpr const char* method = "compensated";
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Sphere<F>& s, const Soa&, std::size_t) { return intersect_sphere_compensated(r, s); }
};

// Stable intersection plus the lecture's [u,v] (pole and equator vary per sphere).
struct SphereUVSpec : PlainSoaSpec<SphereUV> {
  static constexpr const char* kernel = "sphere";
  static constexpr const char* method = "uv";
  static Input make(int cls, int k, Rng& g) {
    const Vec3f c{10.f * float(cls) + uni(g, -0.1f, 0.1f), uni(g, -0.1f, 0.1f), 3.f * float(k)};
    const Vec3f pole{uni(g, -0.3f, 0.3f), 1.f, uni(g, -0.3f, 0.3f)};
    const Vec3f eq{1.f, uni(g, -0.3f, 0.3f), uni(g, -0.3f, 0.3f)};
    return make_sphere_uv(c, uni(g, 0.8f, 1.2f), pole, eq);
  }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const SphereUV<F>& s, const Soa&, std::size_t) { return intersect_sphere_uv(r, s); }
};

// A rotated ellipsoid in general position, written as a general quadric (all ten coefficients
// nonzero).
inline QuadricCoeffs bench_ellipsoid(int cls, int k, Rng& g) {
  const Affine3d M = Affine3d::translate({10.0 * double(cls) + unid(g, -0.1f, 0.1f), unid(g, -0.1f, 0.1f), 3.0 * double(k)}) *
                     Affine3d::rotate({unid(g, -1.f, 1.f), unid(g, -1.f, 1.f), 1.0}, unid(g, 0.f, 3.f));
  return quadrics::ellipsoid(unid(g, 0.8f, 1.2f), unid(g, 0.8f, 1.2f), unid(g, 0.6f, 1.f)).placed(M);
}

struct QuadricMatrixSpec : PlainSoaSpec<Quadric> {
  static constexpr const char* kernel = "quadric";
  static constexpr const char* method = "matrix";
  static Input make(int cls, int k, Rng& g) { return make_quadric(bench_ellipsoid(cls, k, g)); }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Quadric<F>& q, const Soa&, std::size_t) { return intersect_quadric_matrix(r, q); }
};

struct QuadricCoeffs10Spec : QuadricMatrixSpec {
  static constexpr const char* method = "coeffs10";
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Quadric<F>& q, const Soa&, std::size_t) { return intersect_quadric_coeffs10(r, q); }
};

// x^2 + y^2 + a z^2 + b z + c = 0: spheroids (a in [0.6, 1.5]) slightly shifted along z (b).
struct QuadricRevSpec : PlainSoaSpec<QuadricRev> {
  static constexpr const char* kernel = "quadric_rev";
  static constexpr const char* method = "lecture";
  static Input make(int cls, int k, Rng& g) {
    const Vec3f c{10.f * float(cls) + uni(g, -0.1f, 0.1f), uni(g, -0.1f, 0.1f), 3.f * float(k)};
    return make_quadric_rev(c, uni(g, 0.6f, 1.5f), uni(g, -0.2f, 0.2f), -uni(g, 0.7f, 1.3f));
  }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const QuadricRev<F>& q, const Soa&, std::size_t) { return intersect_quadric_rev(r, q); }
};

// Rays along +y for the z-axis cylinders and cones.
inline Ray<float> y_ray(int cls, Rng& g) {
  const Vec3f o{10.f * float(cls) + uni(g, -0.3f, 0.3f), -50.f, uni(g, -0.3f, 0.3f)};
  const Vec3f d{uni(g, -0.002f, 0.002f), 1.f, uni(g, -0.002f, 0.002f)};
  return make_ray(o, d);
}

struct CylinderSpec : PlainSoaSpec<Cylinder> {
  static constexpr const char* kernel = "cylinder";
  static constexpr const char* method = "lecture";
  static Input make(int cls, int k, Rng& g) {
    return make_cylinder(10.f * float(cls) + uni(g, -0.1f, 0.1f), 3.f * float(k), uni(g, 0.8f, 1.2f), -uni(g, 0.8f, 1.2f),
                         uni(g, 0.8f, 1.2f));
  }
  static Ray<float> ray(int cls, Rng& g) { return y_ray(cls, g); }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Cylinder<F>& c, const Soa&, std::size_t) { return intersect_cylinder(r, c); }
};

struct CylinderCappedSpec : CylinderSpec {
  static constexpr const char* method = "capped";
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Cylinder<F>& c, const Soa&, std::size_t) { return intersect_cylinder_capped(r, c); }
};

// Single-nappe frustums: apex 2 below the rays, height range [1, 3] (radius 2 where the rays pass).
struct ConeSpec : PlainSoaSpec<Cone> {
  static constexpr const char* kernel = "cone";
  static constexpr const char* method = "lecture";
  static Input make(int cls, int k, Rng& g) {
    const Vec3f apex{10.f * float(cls) + uni(g, -0.1f, 0.1f), 3.f * float(k), -2.f + uni(g, -0.1f, 0.1f)};
    return make_capped_cone(apex, uni(g, 0.9f, 1.1f), uni(g, 2.9f, 3.1f));
  }
  static Ray<float> ray(int cls, Rng& g) { return y_ray(cls, g); }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Cone<F>& c, const Soa&, std::size_t) { return intersect_cone(r, c); }
};

struct ConeCappedSpec : ConeSpec {
  static constexpr const char* method = "capped";
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const Cone<F>& c, const Soa&, std::size_t) { return intersect_cone_capped(r, c); }
};

// ---- transformed instances: a primitive in its own frame placed by an affine matrix ------------
// Unit sphere -> a rotated ellipsoid (non-uniform scale), intersected by the stable kernel.
struct TransformedSphereSpec : PlainSoaSpec<Transformed<Sphere>::T> {
  static constexpr const char* kernel = "transformed";
  static constexpr const char* method = "sphere";
  static Input make(int cls, int k, Rng& g) {
    const Affine3d M = Affine3d::translate({10.0 * double(cls) + unid(g, -0.1f, 0.1f), unid(g, -0.1f, 0.1f), 3.0 * double(k)}) *
                       Affine3d::rotate({unid(g, -1.f, 1.f), 1.0, unid(g, -1.f, 1.f)}, unid(g, 0.f, 3.f)) *
                       Affine3d::scale({unid(g, 0.8f, 1.2f), unid(g, 0.8f, 1.2f), unid(g, 0.6f, 1.f)});
    return make_transformed(M, make_sphere(Vec3f{0, 0, 0}, 1.f));
  }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const typename Transformed<Sphere>::template T<F>& x, const Soa&, std::size_t) {
    return intersect_transformed(r, x, [](const auto& lr, const auto& p) { return intersect_sphere_stable(lr, p); });
  }
};

// Capped unit cylinder (z in [-1, 1]) laid along x (rotated about y), scaled and placed.
struct TransformedCylinderSpec : PlainSoaSpec<Transformed<Cylinder>::T> {
  static constexpr const char* kernel = "transformed";
  static constexpr const char* method = "cylinder";
  static Input make(int cls, int k, Rng& g) {
    const Affine3d M = Affine3d::translate({10.0 * double(cls) + unid(g, -0.1f, 0.1f), unid(g, -0.1f, 0.1f), 3.0 * double(k)}) *
                       Affine3d::rotate({0, 1, 0}, 1.5707963 + unid(g, -0.2f, 0.2f)) *
                       Affine3d::scale({unid(g, 0.8f, 1.2f), unid(g, 0.8f, 1.2f), 1.0});
    return make_transformed(M, make_cylinder(0.f, 0.f, 1.f, -1.f, 1.f));
  }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const typename Transformed<Cylinder>::template T<F>& x, const Soa&, std::size_t) {
    return intersect_transformed(r, x, [](const auto& lr, const auto& p) { return intersect_cylinder_capped(lr, p); });
  }
};

// Capped unit cone frustum (z in [1, 2]) laid along x, the rays crossing it at local z ~ 1.5.
struct TransformedConeSpec : PlainSoaSpec<Transformed<Cone>::T> {
  static constexpr const char* kernel = "transformed";
  static constexpr const char* method = "cone";
  static Input make(int cls, int k, Rng& g) {
    const Affine3d M = Affine3d::translate({10.0 * double(cls) - 1.5 + unid(g, -0.1f, 0.1f), unid(g, -0.1f, 0.1f), 3.0 * double(k)}) *
                       Affine3d::rotate({0, 1, 0}, 1.5707963 + unid(g, -0.1f, 0.1f));
    return make_transformed(M, make_capped_cone(Vec3f{0, 0, 0}, 1.f, 2.f));
  }
  template <class F>
  static RB_INLINE Hit<F> run(const Ray<F>& r, const typename Transformed<Cone>::template T<F>& x, const Soa&, std::size_t) {
    return intersect_transformed(r, x, [](const auto& lr, const auto& p) { return intersect_cone_capped(lr, p); });
  }
};

// Every benchmarked (kernel, method) of this family.
template <class V>
void for_each_spec_quadric(V&& v) {
  v.template operator()<SphereStableSpec>();
  v.template operator()<SphereHearnBakerSpec>();
  v.template operator()<SphereCompensatedSpec>();
  v.template operator()<SphereUVSpec>();
  v.template operator()<QuadricMatrixSpec>();
  v.template operator()<QuadricCoeffs10Spec>();
  v.template operator()<QuadricRevSpec>();
  v.template operator()<CylinderSpec>();
  v.template operator()<CylinderCappedSpec>();
  v.template operator()<ConeSpec>();
  v.template operator()<ConeCappedSpec>();
  v.template operator()<TransformedSphereSpec>();
  v.template operator()<TransformedCylinderSpec>();
  v.template operator()<TransformedConeSpec>();
}

}  // namespace rb::bench
