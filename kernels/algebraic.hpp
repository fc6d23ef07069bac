// Ray x algebraic surface of degree D (seed 000 "Algebraic surface"):
//   A(x, y, z) = sum_{i+j+k <= D} a_ijk x^i y^j z^k = 0,  A*(t) = A(P0 + t p1), degree <= D.
//
// Placement and conditioning: a surface is stored with a bounding sphere (centre b, radius rb)
// that says which part of it is wanted (algebraic surfaces are often unbounded), and its
// coefficients are re-expanded about b at construction, in double (A(b + u) as a polynomial in
// u), then scaled so the largest |a_ijk| is 1. The kernel clips the ray to the bounding sphere
// and moves the origin to the entry point, so every coordinate it forms is <= rb in size.
//
// Expansion of A* (why this way): nested Horner in x, then y, then z, on polynomials in t:
//   A* = sum_i X^i ( sum_j Y^j ( sum_k a_ijk Z^k ) ),  X = x0 + s x1, Y, Z likewise linear,
// each Horner step a multiplication of a polynomial of degree e by a linear factor (2e + 2
// operations). That is O(terms * D) operations with no power tables, no binomial coefficients
// and no division. Sampling D + 1 points and interpolating costs the same number of trivariate
// evaluations and then a Vandermonde-type solve whose conditioning grows quickly with D.
//
// Roots: all real roots of A*(s) on [0, t1 - t0], by derivative isolation and safeguarded
// Newton (core/poly.hpp), reported ascending as Roots<F, D>.
#pragma once

#include "core/poly.hpp"
#include "core/ray.hpp"
#include "core/roots.hpp"
#include "core/why.hpp"
#include "kernels/bounding_sphere.hpp"

#include <array>
#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

namespace rb {

// Number of monomials x^i y^j z^k with i + j + k <= D.
inline constexpr int alg_terms(int D) { return (D + 1) * (D + 2) * (D + 3) / 6; }
// Storage index of (i, j, k): i-major, then j, then k (the order of the Horner nesting).
inline constexpr int alg_index(int D, int i, int j, int k) {
  int n = 0;
  for (int a = 0; a <= D; ++a)
    for (int b = 0; b <= D - a; ++b)
      for (int c = 0; c <= D - a - b; ++c) {
        if (a == i && b == j && c == k) return n;
        ++n;
      }
  return -1;
}

template <class F, int D>
struct Algebraic {
  static constexpr int kDegree = D;
  static constexpr int kTerms = alg_terms(D);
  F a[kTerms];   // coefficients about the bounding-sphere centre, alg_index order
  Vec3<F> bc;    // bounding-sphere centre
  F br2;         // bounding-sphere radius^2 (-inf: never hits)
  auto fields() {
    return [this]<std::size_t... I>(std::index_sequence<I...>) {
      return std::tie(a[I]..., bc.x, bc.y, bc.z, br2);
    }(std::make_index_sequence<kTerms>{});
  }
  static Algebraic never() {
    Algebraic s;
    for (auto& x : s.a) x = F(0);
    s.bc = {F(0), F(0), F(0)};
    s.br2 = F(-kInf<F>);
    return s;
  }
};
// One-parameter kinds for PrimSoA, prim_cast and the test helpers (a template template parameter
// cannot be deduced through an alias template): Algebraic4<float>{make_algebraic<4>(...)}.
template <class F> struct Algebraic2 : Algebraic<F, 2> { static Algebraic2 never() { return {Algebraic<F, 2>::never()}; } };
template <class F> struct Algebraic4 : Algebraic<F, 4> { static Algebraic4 never() { return {Algebraic<F, 4>::never()}; } };
template <class F> struct Algebraic6 : Algebraic<F, 6> { static Algebraic6 never() { return {Algebraic<F, 6>::never()}; } };

// ---- construction (double, any allocation allowed) --------------------------------------------

// A trivariate polynomial of degree <= D, dense over i + j + k <= D (construction only).
struct TriPoly {
  int D = 0;
  std::vector<double> a;  // alg_index order
  explicit TriPoly(int deg = 0) : D(deg), a(std::size_t(alg_terms(deg)), 0.0) {}
  double& at(int i, int j, int k) { return a[std::size_t(alg_index(D, i, j, k))]; }
  double get(int i, int j, int k) const { return i + j + k > D ? 0.0 : a[std::size_t(alg_index(D, i, j, k))]; }
  static TriPoly constant(double c) { TriPoly p(0); p.at(0, 0, 0) = c; return p; }
  // c0 + cx x + cy y + cz z
  static TriPoly linear(double c0, double cx, double cy, double cz) {
    TriPoly p(1);
    p.at(0, 0, 0) = c0; p.at(1, 0, 0) = cx; p.at(0, 1, 0) = cy; p.at(0, 0, 1) = cz;
    return p;
  }
  friend TriPoly operator+(const TriPoly& p, const TriPoly& q) {
    TriPoly r(std::max(p.D, q.D));
    for (int i = 0; i <= r.D; ++i)
      for (int j = 0; j <= r.D - i; ++j)
        for (int k = 0; k <= r.D - i - j; ++k) r.at(i, j, k) = p.get(i, j, k) + q.get(i, j, k);
    return r;
  }
  friend TriPoly operator*(const TriPoly& p, const TriPoly& q) {
    TriPoly r(p.D + q.D);
    for (int i = 0; i <= p.D; ++i)
      for (int j = 0; j <= p.D - i; ++j)
        for (int k = 0; k <= p.D - i - j; ++k)
          for (int a = 0; a <= q.D; ++a)
            for (int b = 0; b <= q.D - a; ++b)
              for (int c = 0; c <= q.D - a - b; ++c) r.at(i + a, j + b, k + c) += p.get(i, j, k) * q.get(a, b, c);
    return r;
  }
  friend TriPoly operator*(double s, TriPoly p) {
    for (auto& x : p.a) x *= s;
    return p;
  }
  double eval(double x, double y, double z) const {
    double s = 0;
    for (int i = 0; i <= D; ++i)
      for (int j = 0; j <= D - i; ++j)
        for (int k = 0; k <= D - i - j; ++k) s += get(i, j, k) * std::pow(x, i) * std::pow(y, j) * std::pow(z, k);
    return s;
  }
  // p(x + cx, y + cy, z + cz): the same surface in coordinates about (cx, cy, cz).
  TriPoly shifted(double cx, double cy, double cz) const {
    TriPoly r = constant(0.0);
    const TriPoly X = linear(cx, 1, 0, 0), Y = linear(cy, 0, 1, 0), Z = linear(cz, 0, 0, 1);
    for (int i = 0; i <= D; ++i)
      for (int j = 0; j <= D - i; ++j)
        for (int k = 0; k <= D - i - j; ++k) {
          if (get(i, j, k) == 0.0) continue;
          TriPoly m = constant(get(i, j, k));
          for (int n = 0; n < i; ++n) m = m * X;
          for (int n = 0; n < j; ++n) m = m * Y;
          for (int n = 0; n < k; ++n) m = m * Z;
          r = r + m;
        }
    return r;
  }
};

// Common surfaces (world coordinates).
inline TriPoly tri_sphere(Vec3d c, double r) {
  const TriPoly X = TriPoly::linear(-c.x, 1, 0, 0), Y = TriPoly::linear(-c.y, 0, 1, 0), Z = TriPoly::linear(-c.z, 0, 0, 1);
  return X * X + Y * Y + Z * Z + TriPoly::constant(-r * r);
}
// Seed 000's T_ab, axis z, centred at c.
inline TriPoly tri_torus(Vec3d c, double R, double r) {
  const TriPoly X = TriPoly::linear(-c.x, 1, 0, 0), Y = TriPoly::linear(-c.y, 0, 1, 0), Z = TriPoly::linear(-c.z, 0, 0, 1);
  const TriPoly G = X * X + Y * Y + Z * Z + TriPoly::constant(-R * R - r * r);
  return G * G + (4.0 * R * R) * (Z * Z + TriPoly::constant(-r * r));
}

// From world-coordinate coefficients and a bounding sphere. never() (the reason in *why) when the
// degree exceeds D, a coefficient or the sphere is not finite, the radius is not positive, or
// every coefficient is 0 (A == 0 is all of space, not a surface).
template <int D>
inline Algebraic<float, D> make_algebraic(const TriPoly& p, Vec3d bc, double radius, std::string* why = nullptr) {
  using P = Algebraic<float, D>;
  if (p.D > D) return never_because<P>(why, "algebraic: polynomial degree " + std::to_string(p.D) + " exceeds " + std::to_string(D));
  for (double x : p.a)
    if (!std::isfinite(x)) return never_because<P>(why, "algebraic: non-finite coefficient");
  if (!finite3(bc) || !std::isfinite(radius)) return never_because<P>(why, "algebraic: non-finite bounding sphere");
  if (!(radius > 0.0)) return never_because<P>(why, "algebraic: bounding radius is not positive");
  const TriPoly q = p.shifted(bc.x, bc.y, bc.z);
  double big = 0;
  for (double x : q.a) big = std::max(big, std::fabs(x));
  if (!(big > 0.0)) return never_because<P>(why, "algebraic: all coefficients are zero (A == 0 is not a surface)");
  Algebraic<float, D> s;
  for (int i = 0; i <= D; ++i)
    for (int j = 0; j <= D - i; ++j)
      for (int k = 0; k <= D - i - j; ++k) s.a[alg_index(D, i, j, k)] = float(q.get(i, j, k) / big);
  s.bc = to_float(bc);
  s.br2 = float(radius * radius);
  return s;
}

// ---- kernel -----------------------------------------------------------------------------------

// Coefficients c[0..D] of A(q + s d) in s (q, d in the surface's frame about bc).
template <int D, class F>
RB_INLINE void algebraic_on_ray(const Algebraic<F, D>& A, const Vec3<F>& q, const Vec3<F>& d, F (&c)[D + 1]) {
  F outer[D + 1];
  for (int i = D; i >= 0; --i) {
    F mid[D + 1];
    for (int j = D - i; j >= 0; --j) {
      F inner[D + 1];
      const int K = D - i - j;
      inner[0] = A.a[alg_index(D, i, j, K)];
      for (int k = K - 1; k >= 0; --k) {  // inner = inner * Z + a_ijk, degree K - 1 - k -> K - k
        poly_mul_linear<D + 1>(inner, K - 1 - k, q.z, d.z);
        inner[0] = inner[0] + A.a[alg_index(D, i, j, k)];
      }
      if (j == D - i) {
        for (int n = 0; n <= K; ++n) mid[n] = inner[n];
      } else {  // mid = mid * Y + inner, degree K - 1 -> K
        poly_mul_linear<D + 1>(mid, K - 1, q.y, d.y);
        for (int n = 0; n <= K; ++n) mid[n] = mid[n] + inner[n];
      }
    }
    if (i == D) {
      outer[0] = mid[0];
    } else {  // outer = outer * X + mid, degree D - i - 1 -> D - i
      poly_mul_linear<D + 1>(outer, D - i - 1, q.x, d.x);
      for (int n = 0; n <= D - i; ++n) outer[n] = outer[n] + mid[n];
    }
  }
  for (int n = 0; n <= D; ++n) c[n] = outer[n];
}

// All roots in [tmin, tmax] inside the bounding sphere, ascending.
template <int D, class F>
RB_INLINE Roots<F, D> algebraic_roots(const Ray<F>& r, const Algebraic<F, D>& A, IterCount* ic = nullptr) {
  const Vec3<F> q = r.o - A.bc;
  const Roots<F, 2> clip = bounding_sphere_span(r, q, A.br2);
  const mask_t<F> m = clip.valid[0];
  if (none_of<F>(m)) return Roots<F, D>::none();
  const F t0 = clip.lo(), t1 = clip.hi();
  const F W = vmax(t1 - t0, F(0));
  const Vec3<F> q0 = q + r.d * t0;
  F c[D + 1];
  algebraic_on_ray<D>(A, q0, r.d, c);
  const F tol = F(4 * std::numeric_limits<scalar_t<F>>::epsilon()) * (W + vsqrt(vmax(A.br2, F(0))));
  F s[D];
  mask_t<F> ok[D];
  poly_roots_in<D, F>(c, F(0), W, tol, s, ok, ic);
  for (int k = 0; k < D; ++k) s[k] = vselect(m & ok[k], t0 + s[k], F(kInf<F>));
  return Roots<F, D>::canonical(s);
}

template <int D, class F>
RB_INLINE Hit<F> intersect_algebraic(const Ray<F>& r, const Algebraic<F, D>& A, IterCount* ic = nullptr) {
  const Roots<F, D> rt = algebraic_roots<D>(r, A, ic);
  return make_hit<F>(rt.valid[0], rt.t[0]);
}

// A and grad A at a world point p (Horner per variable on the stored coefficients).
template <int D, class F>
RB_INLINE F algebraic_eval(const Algebraic<F, D>& A, const Vec3<F>& p, Vec3<F>* grad = nullptr) {
  const Vec3<F> u = p - A.bc;
  F px[D + 1], py[D + 1], pz[D + 1];
  px[0] = py[0] = pz[0] = F(1);
  for (int n = 1; n <= D; ++n) { px[n] = px[n - 1] * u.x; py[n] = py[n - 1] * u.y; pz[n] = pz[n - 1] * u.z; }
  F f = F(0), gx = F(0), gy = F(0), gz = F(0);
  for (int i = 0; i <= D; ++i)
    for (int j = 0; j <= D - i; ++j)
      for (int k = 0; k <= D - i - j; ++k) {
        const F a = A.a[alg_index(D, i, j, k)];
        f = f + a * px[i] * py[j] * pz[k];
        if (grad) {
          if (i > 0) gx = gx + F(scalar_t<F>(i)) * a * px[i - 1] * py[j] * pz[k];
          if (j > 0) gy = gy + F(scalar_t<F>(j)) * a * px[i] * py[j - 1] * pz[k];
          if (k > 0) gz = gz + F(scalar_t<F>(k)) * a * px[i] * py[j] * pz[k - 1];
        }
      }
  if (grad) *grad = {gx, gy, gz};
  return f;
}

// Unit normal grad A / |grad A| at a point on the surface (the side where A grows).
template <int D, class F>
RB_INLINE Vec3<F> algebraic_normal(const Algebraic<F, D>& A, const Vec3<F>& p) {
  Vec3<F> g;
  (void)algebraic_eval<D>(A, p, &g);
  return normalize(g);
}

}  // namespace rb
