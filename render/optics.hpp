// The two directions of recursive ray tracing (the lecture's RT_shade): the mirror reflection and
// the refraction by Snell's law, sin(theta_I) / sin(theta_T) = eta_T / eta_I, with total internal
// reflection when no transmitted direction exists.
#pragma once

#include "core/vec3.hpp"

#include <cmath>
#include <optional>

namespace rb::render {

// d (unit, towards the surface) mirrored about the unit normal n (either side): d - 2 (d.n) n.
inline Vec3f reflect(const Vec3f& d, const Vec3f& n) { return d - n * (2.0f * dot(d, n)); }

// The transmitted direction of the unit incident direction d at a surface with unit normal n
// facing the incident side (d.n <= 0), going from index eta_i into eta_t. Computed in double:
// cos_i = -d.n, eta = eta_i / eta_t, k = 1 - eta^2 (1 - cos_i^2);
// k < 0 is total internal reflection (no direction); else t = eta d + (eta cos_i - sqrt(k)) n,
// a unit vector.
inline std::optional<Vec3f> refract(const Vec3f& d, const Vec3f& n, float eta_i, float eta_t) {
  const Vec3d dd = to_double(d), nn = to_double(n);
  const double cos_i = -dot(dd, nn);
  const double eta = double(eta_i) / double(eta_t);
  const double k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
  if (!(k >= 0.0)) return std::nullopt;
  return to_float(dd * eta + nn * (eta * cos_i - std::sqrt(k)));
}

}  // namespace rb::render
