// The renderer's shading data (render.cpp, Renderer::shade).
#pragma once

#include "core/num.hpp"
#include "core/vec3.hpp"
#include "scene/scene.hpp"
#include "soa/aligned.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rb::render {

// A generation's hits as SoA lanes, what shading runs on eight at a time. The arrays only grow (a
// thread's tiles reuse them) and are written by index; rows past the hits up to a multiple of 8 are
// zeros.
struct HitLanes {
  // Three float arrays: a vector per row.
  struct V3 {
    avec<float> x, y, z;
    void set(std::size_t k, const Vec3f& v) { x[k] = v.x, y[k] = v.y, z[k] = v.z; }
    Vec3f get(std::size_t k) const { return {x[k], y[k], z[k]}; }
    Vec3<f8> load8(std::size_t k) const { return {load<f8>(&x[k]), load<f8>(&y[k]), load<f8>(&z[k])}; }
    void store8(std::size_t k, const Vec3<f8>& v) { store(&x[k], v.x), store(&y[k], v.y), store(&z[k], v.z); }
  };
  // In, per hit: the generation's ray and the material; the world point and the ray's eta_i / eta_t
  // there (double); the light test's normal, the shading normal towards the ray, the ray's
  // direction, the surface colour, the material's kd, ks and exponent; the spawn base (frame point,
  // its error bound and the geometric normal), the geometric normal towards the ray and the light
  // test's geometric normal.
  std::vector<std::uint32_t> ray;
  std::vector<const scene::Material*> mat;
  avec<double> px, py, pz, eta;
  V3 nl, ns, d, base, bp, err, ng, ng_in, ngl;
  avec<float> kd, ks, shine;
  // Out: per light (light l's rows from l * stride) n.L and the local light; the mirror direction
  // and the refracted one (where tok > 0: no total internal reflection); where the shadow rays, the
  // mirror ray and the refracted ray start.
  avec<float> ndl, tok;
  V3 local, dr, dt, from_shadow, from_mirror, from_refracted;
  std::size_t n = 0, stride = 0;

  // Room for `rays` hits and `lights` lights; no hits yet.
  void reset(std::size_t rays, std::size_t lights) {
    n = 0;
    stride = round_up(std::max<std::size_t>(rays, 1), kPadLanes);
    if (px.size() >= stride && ndl.size() >= lights * stride) return;
    ray.resize(stride);
    mat.resize(stride);
    for (auto* a : doubles()) a->resize(stride);
    for (auto* a : floats()) a->resize(stride);
    for (auto* a : {&ndl, &local.x, &local.y, &local.z}) a->resize(lights * stride);
  }
  // Zero rows from the last hit to the next multiple of 8.
  void pad() {
    for (std::size_t k = n; k < round_up(n, kPadLanes); ++k) {
      for (auto* a : doubles()) (*a)[k] = 0.0;
      for (auto* a : floats()) (*a)[k] = 0.0f;
    }
  }

 private:
  std::array<avec<double>*, 4> doubles() { return {&px, &py, &pz, &eta}; }
  std::array<avec<float>*, 46> floats() {
    std::array<avec<float>*, 46> a{};
    std::size_t i = 0;
    for (V3* v : {&nl, &ns, &d, &base, &bp, &err, &ng, &ng_in, &ngl, &dr, &dt, &from_shadow, &from_mirror, &from_refracted})
      a[i++] = &v->x, a[i++] = &v->y, a[i++] = &v->z;
    for (auto* s : {&kd, &ks, &shine, &tok}) a[i++] = s;
    return a;
  }
};

}  // namespace rb::render
