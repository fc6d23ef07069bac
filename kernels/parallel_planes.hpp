// Ray x a family of parallel planes (seed 000 "Parallel planes"): one normal n, offsets D_i,
//   t_i = -(n . P0 + D_i) / (n . p1)
// lecture: the first plane 5+- 6* 1/, every next one 1+- 1/ (n . p1 and n . P0 are shared).
// ParallelPlanesK<F, K> holds up to K planes; unused slots have D = NaN (t = NaN fails the
// positive-form range test). intersect_parallel_planes returns the nearest t_i in [tmin, tmax];
// parallel_planes_all returns every t_i (unclipped, in slot order) at the lecture's cost.
// Plain per-primitive data (a PrimSoA), so rays in lanes and primitives in lanes both apply.
#pragma once

#include "core/ray.hpp"
#include "core/why.hpp"

#include <stdexcept>
#include <utility>
#include <vector>

namespace rb {

template <class F, int K>
struct ParallelPlanesK {
  static constexpr int kPlanes = K;
  Vec3<F> n;
  F D[K];
  auto fields() {
    return [this]<std::size_t... I>(std::index_sequence<I...>) { return std::tie(n.x, n.y, n.z, D[I]...); }(
        std::make_index_sequence<K>{});
  }
  // n = 0: parallel to every ray; D = NaN.
  static ParallelPlanesK never() {
    ParallelPlanesK p;
    p.n = {F(0), F(0), F(0)};
    for (auto& d : p.D) d = F(std::numeric_limits<scalar_t<F>>::quiet_NaN());
    return p;
  }
};
template <class F>
using ParallelPlanes4 = ParallelPlanesK<F, 4>;

// Planes n . X + d_i = 0 for the given normal and offsets (scaled by 1/|n| in double, so the
// stored normal is a unit vector). More than K offsets: std::invalid_argument (a programming
// error: K is the caller's choice). A zero or non-finite normal: never() (the reason in *why); a
// non-finite offset: that slot never hits.
template <int K, class T>
inline ParallelPlanesK<float, K> make_parallel_planes(Vec3<T> normal, const std::vector<T>& offsets, std::string* why = nullptr) {
  if (offsets.size() > std::size_t(K)) throw std::invalid_argument("make_parallel_planes: more offsets than slots");
  const Vec3d n = to_double(normal);
  const double len = std::sqrt(dot(n, n));
  if (!std::isfinite(len) || len == 0.0)
    return never_because<ParallelPlanesK<float, K>>(why, "parallel planes: the normal is zero or not finite");
  ParallelPlanesK<float, K> p = ParallelPlanesK<float, K>::never();
  p.n = to_float(n * (1.0 / len));
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    const double d = double(offsets[i]) / len;
    p.D[i] = std::isfinite(d) ? float(d) : std::numeric_limits<float>::quiet_NaN();
  }
  return p;
}

// Every t_i (slot order); returns the parallel mask (n . p1 != 0). 5+- 6* 1/ + (K-1) (1+- 1/).
template <class F, int K>
RB_INLINE mask_t<F> parallel_planes_all(const Ray<F>& r, const ParallelPlanesK<F, K>& p, F (&t)[K]) {
  const F den = dot(p.n, r.d);                      // 2+- 3*
  const F no = dot(p.n, r.o);                       // 2+- 3*
  for (int i = 0; i < K; ++i) t[i] = -(no + p.D[i]) / den;  // 1+- 1/ each
  return den != F(0);                               // 1 cmp
}

// The nearest plane in [tmin, tmax]. Per plane beyond the lecture's arithmetic: 2 cmp (range),
// 1 select and 1 min (nearest).
template <class F, int K>
RB_INLINE Hit<F> intersect_parallel_planes(const Ray<F>& r, const ParallelPlanesK<F, K>& p) {
  const F den = dot(p.n, r.d);                      // 2+- 3*
  mask_t<F> m = den != F(0);                        // 1 cmp  (negative case: parallel ray)
  if (none_of<F>(m)) return miss_hit<F>();
  const F no = dot(p.n, r.o);                       // 2+- 3*
  const F inf = F(kInf<F>);
  F best = inf;
  mask_t<F> any = mask_false<F>();
  for (int i = 0; i < K; ++i) {
    const F t = -(no + p.D[i]) / den;               // 1+- 1/
    const mask_t<F> ok = (t >= r.tmin) & (t <= r.tmax);  // 2 cmp
    best = vmin(vselect(ok, t, inf), best);         // 1 select 1 min
    any = any | ok;
  }
  return make_hit<F>(m & any, best);                // 1 select
}

template <class F, int K>
RB_INLINE Vec3<F> parallel_planes_normal(const ParallelPlanesK<F, K>& p) { return p.n; }

}  // namespace rb
