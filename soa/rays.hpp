// RaySoA: rays as a structure of arrays, 32-byte aligned, padded to a multiple of 8 lanes with
// invalid rays (empty interval). packet<F>(i) is the K-ray view starting at ray i (K = lanes
// of F, i a multiple of K); broadcast<F>(i) puts ray i in every lane.
#pragma once

#include "core/ray.hpp"
#include "soa/aligned.hpp"

#include <stdexcept>

namespace rb {

struct RaySoA {
  avec<float> ox, oy, oz, dx, dy, dz, rx, ry, rz, tmin, tmax;
  std::size_t count = 0;  // real rays; size() is the padded length

  std::size_t size() const { return ox.size(); }
  void reserve(std::size_t n) {
    for (auto* a : arrays()) a->reserve(round_up(n, kPadLanes));
  }
  void clear() {
    for (auto* a : arrays()) a->clear();
    count = 0;
  }
  // Appends a validated ray (make_ray); keeps the arrays padded.
  void push(const Ray<float>& r) {
    trim_padding();
    put(r);
    ++count;
    pad();
  }
  template <class T>
  void push(Vec3<T> o, Vec3<T> d, T t0 = T(0), T t1 = std::numeric_limits<T>::infinity()) {
    push(make_ray(o, d, t0, t1));
  }

  // RB_INLINE: broadcast() calls it once per ray in the primitives-in-lanes loops; left to GCC's
  // heuristics, it stayed an out-of-line call in the timed loop of the larger kernels (cylinder,
  // cone, quadric, uv sphere, transformed instances; seen in the disassembly), a call per ray
  // that the cheap miss case cannot hide.
  RB_INLINE Ray<float> get(std::size_t i) const {
    return {{ox[i], oy[i], oz[i]}, {dx[i], dy[i], dz[i]}, {rx[i], ry[i], rz[i]}, tmin[i], tmax[i]};
  }
  template <class F>
  RB_INLINE Ray<F> packet(std::size_t i) const {
    return {{load<F>(&ox[i]), load<F>(&oy[i]), load<F>(&oz[i])},
            {load<F>(&dx[i]), load<F>(&dy[i]), load<F>(&dz[i])},
            {load<F>(&rx[i]), load<F>(&ry[i]), load<F>(&rz[i])},
            load<F>(&tmin[i]), load<F>(&tmax[i])};
  }
  template <class F>
  RB_INLINE Ray<F> broadcast(std::size_t i) const { return Ray<F>::broadcast(get(i)); }
  // Room for n rays in one go (push appends one at a time): count n, the arrays padded to whole
  // 8-lane groups with the invalid ray; rows below n are then written with set or store_packet.
  void resize(std::size_t n) {
    for (auto* a : arrays()) a->resize(round_up(std::max<std::size_t>(n, 1), kPadLanes));
    count = n;
    for (std::size_t i = n; i < size(); ++i) set(i, invalid());
  }
  RB_INLINE void set(std::size_t i, const Ray<float>& r) {
    ox[i] = r.o.x, oy[i] = r.o.y, oz[i] = r.o.z;
    dx[i] = r.d.x, dy[i] = r.d.y, dz[i] = r.d.z;
    rx[i] = r.rd.x, ry[i] = r.rd.y, rz[i] = r.rd.z;
    tmin[i] = r.tmin, tmax[i] = r.tmax;
  }
  // Writes the lanes of r into rays i .. i + lanes - 1 (i a multiple of the lanes, below size()).
  template <class F>
  RB_INLINE void store_packet(std::size_t i, const Ray<F>& r) {
    store(&ox[i], r.o.x), store(&oy[i], r.o.y), store(&oz[i], r.o.z);
    store(&dx[i], r.d.x), store(&dy[i], r.d.y), store(&dz[i], r.d.z);
    store(&rx[i], r.rd.x), store(&ry[i], r.rd.y), store(&rz[i], r.rd.z);
    store(&tmin[i], r.tmin), store(&tmax[i], r.tmax);
  }

 private:
  std::vector<avec<float>*> arrays() { return {&ox, &oy, &oz, &dx, &dy, &dz, &rx, &ry, &rz, &tmin, &tmax}; }
  void put(const Ray<float>& r) {
    ox.push_back(r.o.x); oy.push_back(r.o.y); oz.push_back(r.o.z);
    dx.push_back(r.d.x); dy.push_back(r.d.y); dz.push_back(r.d.z);
    rx.push_back(r.rd.x); ry.push_back(r.rd.y); rz.push_back(r.rd.z);
    tmin.push_back(r.tmin); tmax.push_back(r.tmax);
  }
  void trim_padding() {
    for (auto* a : arrays()) a->resize(count);
  }
  // The padding rows' ray: the invalid ray (make_ray of a zero direction), a defined miss.
  static Ray<float> invalid() { return make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 0}); }
  void pad() {
    while (ox.size() % kPadLanes) put(invalid());
  }
};

}  // namespace rb
