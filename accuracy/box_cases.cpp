// Box cases: the origin exactly on a slab plane with +0 and -0 direction components, flat boxes
// (lo == hi on one axis), grazing rays along faces (in the face plane, and 1 ulp off it), origins
// inside. Reference: exact rational slab intervals.
#include "accuracy/exact.hpp"
#include "kernels/box.hpp"

#include <cmath>

namespace rb::acc {

std::vector<CaseInfo> box_cases() {
  return {
      {"box", "origin_on_slab_plane", "origin exactly on a face plane, one direction component +0 or -0, others random"},
      {"box", "flat_box", "boxes with lo == hi on one axis (rectangles), rays at random points near them"},
      {"box", "grazing_faces", "rays in a face plane (or 1 ulp off it) along the face"},
      {"box", "inside", "origins inside the box: the exit"},
  };
}

void run_boxes(Ctx& x) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  x.each_case(box_cases(), [&](const auto& ci) {
    Case<Box> c;
    c.family = "box", c.name = ci.name, c.what = ci.what;
    for (std::size_t i = 0; i < n; ++i) {
      Vec3f lo{float(urand(g, -2, -0.5)), float(urand(g, -2, -0.5)), float(urand(g, -2, -0.5))};
      Vec3f hi{float(urand(g, 0.5, 2)), float(urand(g, 0.5, 2)), float(urand(g, 0.5, 2))};
      const int a = int(urand(g, 0, 3 - 1e-9));
      float* L = &lo.x;
      float* H = &hi.x;
      Vec3f o, d;
      auto rnd_in = [&](float l, float h) { return float(urand(g, double(l) - 0.3, double(h) + 0.3)); };
      if (ci.name == "origin_on_slab_plane" || ci.name == "grazing_faces") {
        float* O = &o.x;
        float* D = &d.x;
        for (int k = 0; k < 3; ++k) O[k] = rnd_in(L[k], H[k]), D[k] = float(urand(g, -1, 1));
        O[a] = i % 2 ? L[a] : H[a];
        D[a] = i % 4 < 2 ? 0.0f : -0.0f;
        if (ci.name == "grazing_faces") {
          const int b = (a + 1) % 3;
          O[b] = D[b] > 0 ? L[b] - 1.0f : H[b] + 1.0f;  // start outside, run along the face
          if (i % 8 >= 4) O[a] = std::nextafter(O[a], i % 16 >= 8 ? 1e30f : -1e30f);
        }
      } else if (ci.name == "flat_box") {
        H[a] = L[a];
        const Vec3d P{rnd_in(lo.x, hi.x), rnd_in(lo.y, hi.y), rnd_in(lo.z, hi.z)};
        const Vec3d O = P + unit_rand(g) * 4.0;
        o = to_float(O), d = to_float(P - O);
      } else {
        o = {float(urand(g, lo.x, hi.x)), float(urand(g, lo.y, hi.y)), float(urand(g, lo.z, hi.z))};
        d = to_float(unit_rand(g));
        if (i % 4 == 0) (&d.x)[a] = i % 8 == 0 ? 0.0f : -0.0f;
      }
      const Box<float> b = make_box(lo, hi);
      c.prims.push(b);
      c.rays.push(make_ray(o, d));
      const Ray<float> r = c.rays.get(c.rays.count - 1);
      c.ref.push_back(box_ref(r.o, r.d, r.tmin, r.tmax, b.lo, b.hi));
    }
    measure(x, c, "slab", [](const auto& r, const auto& b, IterCount*) { return intersect_box(r, b); });
  });
}

}  // namespace rb::acc
