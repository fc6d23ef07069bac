// Triangle cases: rays through the shared edges and vertices of closed meshes (an octahedron, a
// jittered sphere mesh, a square refined into a random triangle fan as the Vulkan conformance
// watertightness test does), the mesh far from the origin and the camera far from the mesh,
// grazing rays, needle and tiny triangles.
#include "accuracy/exact.hpp"
#include "kernels/triangle.hpp"
#include "kernels/triangle_cramer.hpp"
#include "kernels/triangle_woop.hpp"

#include <array>
#include <cmath>

namespace rb::acc {

namespace {

using Tri = std::array<Vec3f, 3>;

struct Mesh {
  std::vector<Vec3f> v;
  std::vector<std::array<int, 3>> f;
  Vec3d centre{0, 0, 0};
  std::vector<Tri> tris() const {
    std::vector<Tri> t;
    for (const auto& i : f) t.push_back({v[std::size_t(i[0])], v[std::size_t(i[1])], v[std::size_t(i[2])]});
    return t;
  }
  // Unique edges (vertex index pairs).
  std::vector<std::array<int, 2>> edges() const {
    std::vector<std::array<int, 2>> e;
    for (const auto& i : f)
      for (int k = 0; k < 3; ++k) {
        int a = i[std::size_t(k)], b = i[std::size_t((k + 1) % 3)];
        if (a > b) std::swap(a, b);
        if (std::find(e.begin(), e.end(), std::array<int, 2>{a, b}) == e.end()) e.push_back({a, b});
      }
    return e;
  }
};

Vec3f f3(const Vec3d& v) { return to_float(v); }

// An octahedron about `c` with half-diagonal s, each vertex jittered by up to `jit` (relative).
Mesh octahedron(const Vec3d& c, double s, double jit, std::mt19937_64& g) {
  Mesh m;
  const Vec3d ax[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const Vec3d& a : ax) m.v.push_back(f3(c + a * (s * (1 + urand(g, -jit, jit)))));
  // Faces outward (counter-clockwise seen from outside).
  const int xs[2] = {0, 1}, ys[2] = {2, 3}, zs[2] = {4, 5};
  for (int i : xs)
    for (int j : ys)
      for (int k : zs) {
        const bool flip = ((i == 1) + (j == 3) + (k == 5)) % 2 == 1;
        m.f.push_back(flip ? std::array<int, 3>{i, k, j} : std::array<int, 3>{i, j, k});
      }
  m.centre = c;
  return m;
}

// A UV sphere mesh (nlat bands, nlon segments) with radially jittered vertices.
Mesh sphere_mesh(const Vec3d& c, double R, int nlat, int nlon, double jit, std::mt19937_64& g) {
  Mesh m;
  m.v.push_back(f3(c + Vec3d{0, 0, R}));
  for (int i = 1; i < nlat; ++i) {
    const double th = M_PI * double(i) / double(nlat);
    for (int j = 0; j < nlon; ++j) {
      const double ph = 2 * M_PI * double(j) / double(nlon);
      const double rr = R * (1 + urand(g, -jit, jit));
      m.v.push_back(f3(c + Vec3d{rr * std::sin(th) * std::cos(ph), rr * std::sin(th) * std::sin(ph), rr * std::cos(th)}));
    }
  }
  m.v.push_back(f3(c + Vec3d{0, 0, -R}));
  const int S = int(m.v.size()) - 1;
  auto id = [&](int i, int j) { return 1 + (i - 1) * nlon + (j % nlon); };
  for (int j = 0; j < nlon; ++j) m.f.push_back({0, id(1, j), id(1, j + 1)});
  for (int i = 1; i < nlat - 1; ++i)
    for (int j = 0; j < nlon; ++j) {
      m.f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  for (int j = 0; j < nlon; ++j) m.f.push_back({S, id(nlat - 1, j + 1), id(nlat - 1, j)});
  m.centre = c;
  return m;
}

// The square [-1, 1]^2 (z = 0) as a fan of triangles about a random inner point, with random
// extra points on the sides (the Vulkan conformance watertightness construction).
Mesh square_fan(std::mt19937_64& g, int extra) {
  Mesh m;
  m.v.push_back(f3({urand(g, -0.5, 0.5), urand(g, -0.5, 0.5), 0}));
  std::vector<double> ang;  // perimeter parameter in [0, 8)
  for (int k = 0; k < 4; ++k) ang.push_back(2.0 * k);
  for (int k = 0; k < extra; ++k) ang.push_back(urand(g, 0, 8));
  std::sort(ang.begin(), ang.end());
  for (double p : ang) {
    const int side = int(p / 2);
    const double u = p - 2 * side - 1;
    const Vec3d q = side == 0 ? Vec3d{1, u, 0} : side == 1 ? Vec3d{-u, 1, 0} : side == 2 ? Vec3d{-1, -u, 0} : Vec3d{u, -1, 0};
    m.v.push_back(f3(q));
  }
  const int n = int(ang.size());
  for (int k = 0; k < n; ++k) m.f.push_back({0, 1 + k, 1 + (k + 1) % n});
  return m;
}

// Targets on the mesh: points on shared edges (vertices == false) or vertices.
Vec3d mesh_target(const Mesh& m, bool vertices, bool inner_only, std::mt19937_64& g) {
  if (vertices) {
    const std::size_t k = inner_only ? 0 : std::size_t(urand(g, 0, double(m.v.size()) - 1e-9));
    return to_double(m.v[k]);
  }
  const auto e = m.edges();
  for (;;) {
    const auto& ab = e[std::size_t(urand(g, 0, double(e.size()) - 1e-9))];
    if (inner_only && ab[0] != 0 && ab[1] != 0) continue;  // the fan's inner edges start at vertex 0
    const Vec3d a = to_double(m.v[std::size_t(ab[0])]), b = to_double(m.v[std::size_t(ab[1])]);
    return a + (b - a) * urand(g, 0.02, 0.98);
  }
}

// A case of rays x every triangle of a mesh; reference and must-hit from the exact tests.
struct TriCase {
  Case<TriVerts> woop;
  Case<Triangle> mt;
  // One-to-one cases: ray i against its own triangle, in both batches, with the exact reference of
  // the ray as stored (the float ray the kernels see).
  void add_pair(const Tri& t, const Ray<float>& r) {
    woop.prims.push(make_tri_verts(t[0], t[1], t[2]));
    mt.prims.push(make_triangle(t[0], t[1], t[2]));
    woop.rays.push(r);
    mt.rays.push(r);
    const Ray<float> q = woop.rays.get(woop.rays.count - 1);
    woop.ref.push_back(triangle_ref(q.o, q.d, q.tmin, q.tmax, t[0], t[1], t[2]));
  }
};

// closed: 0 open surface (no leak figure), 1 a closed solid (a ray must hit when it passes through
// the solid: a chord longer than 1e-4 of the mesh size; a graze along a silhouette edge may miss),
// 2 a planar patch (a ray must hit when it crosses the patch's inside, at a face or an inner edge).
TriCase build(const std::string& name, const std::string& what, const std::vector<Tri>& tris, const std::vector<Ray<float>>& rays,
              int closed) {
  TriCase c;
  for (auto* k : {&c.woop.family, &c.mt.family}) *k = "triangle";
  c.woop.name = c.mt.name = name;
  c.woop.what = c.mt.what = what;
  c.woop.one_to_one = c.mt.one_to_one = false;
  for (const Tri& t : tris) {
    c.woop.prims.push(make_tri_verts(t[0], t[1], t[2]));
    c.mt.prims.push(make_triangle(t[0], t[1], t[2]));
  }
  for (const Ray<float>& r : rays) {
    c.woop.rays.push(r);
    c.mt.rays.push(r);
  }
  const std::size_t nr = rays.size();
  c.woop.ref.resize(nr * tris.size());
  if (closed) c.woop.must_hit.assign(nr, 0);
  for (std::size_t i = 0; i < nr; ++i) {
    const Ray<float> r = c.woop.rays.get(i);
    bool interior = false;
    int bpos = 0, bneg = 0;
    long double t0 = 1e300L, t1 = -1e300L, size = 0;
    for (std::size_t j = 0; j < tris.size(); ++j) {
      const Tri& t = tris[j];
      const Ref f = triangle_ref(r.o, r.d, r.tmin, r.tmax, t[0], t[1], t[2]);
      c.woop.ref[j * nr + i] = f;
      if (f.cls == Cls::hit) interior = true;
      if (f.cls == Cls::either && f.has_t) (triangle_facing(r.d, t[0], t[1], t[2]) > 0 ? bpos : bneg)++;
      if (f.has_t) t0 = std::min(t0, f.t), t1 = std::max(t1, f.t);
      for (const Vec3f& v : t) size = std::max<long double>(size, norm(to_double(v - t[0])));
    }
    if (closed == 1) c.woop.must_hit[i] = t1 - t0 > 1e-4L * size;
    // A planar patch: through a face's inside, or through an inner edge or vertex (>= 2 faces).
    if (closed == 2) c.woop.must_hit[i] = interior || (bpos + bneg >= 2 && (bpos == 0 || bneg == 0));
  }
  c.mt.ref = c.woop.ref;
  c.mt.must_hit = c.woop.must_hit;
  return c;
}

// Rays from outside through edge/vertex targets P of a closed mesh towards a point Q well inside
// (the centre moved by up to `inner` of the size), the origin at distance `dist` before P: every
// such ray passes through the solid, entering at the edge or vertex (up to the rounding of the
// stored ray, which the exact reference sees).
std::vector<Ray<float>> aimed_rays(const Mesh& m, bool vertices, std::size_t n, double dist, std::mt19937_64& g, double inner = 0.3) {
  std::vector<Ray<float>> rs;
  double size = 0;
  for (const Vec3f& v : m.v) size = std::max(size, norm(to_double(v) - m.centre));
  while (rs.size() < n) {
    const Vec3d P = mesh_target(m, vertices, false, g);
    const Vec3d aim = m.centre + unit_rand(g) * (size * inner * urand(g, 0, 1));
    Vec3d d = aim - P;
    d = d * (1.0 / norm(d));
    const Vec3d O = P - d * dist;
    rs.push_back(make_ray(O, d));
  }
  return rs;
}

// The probe's construction: an integer direction d, a dyadic point P on an edge, O = P - k d.
std::vector<Ray<float>> integer_dir_rays(const Mesh& m, std::size_t n, std::mt19937_64& g) {
  std::vector<Ray<float>> rs;
  const auto e = m.edges();
  while (rs.size() < n) {
    const auto& ab = e[std::size_t(urand(g, 0, double(e.size()) - 1e-9))];
    const Vec3d a = to_double(m.v[std::size_t(ab[0])]), b = to_double(m.v[std::size_t(ab[1])]);
    const double u = std::floor(urand(g, 1, 16)) / 16.0;
    const Vec3d P = a + (b - a) * u;
    const Vec3d d{std::floor(urand(g, -4, 5)), std::floor(urand(g, -4, 5)), std::floor(urand(g, -4, 5))};
    if (dot(d, d) == 0) continue;
    const Vec3d out = P - m.centre;
    if (dot(d, out) >= -0.3 * norm(d) * norm(out)) continue;  // must come from outside towards the inside
    const Vec3d O = P - d * std::ldexp(1.0, int(urand(g, 0, 3)));
    rs.push_back(make_ray(O, d));
  }
  return rs;
}

template <class K>
void measure_all(Ctx& x, const TriCase& c) {
  measure(x, c.mt, "moller_trumbore", [](const auto& r, const auto& p, IterCount*) { return intersect_triangle_mt(r, p); });
  measure(x, c.mt, "cramer", [](const auto& r, const auto& p, IterCount*) { return intersect_triangle_cramer(r, p); });
  measure(x, c.woop, "woop", [](const auto& r, const auto& p, IterCount*) { return intersect_triangle_woop(r, p); });
}

// The closed-mesh cases through the whole tracer (family "bvh"), where the lab runs with the
// tracer's cases (Options::tracer, accuracy/bvh_cases.cpp).
void bvh_rows(Ctx& x, const TriCase& c, const Mesh& m) {
  if (x.o->tracer) x.o->tracer->mesh_rows(x, c.woop, m.v, m.f);
}

void triangle_grazing(Ctx& x, const std::string& what) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  x.reseed("triangle", "grazing");
  const Tri t{Vec3f{-1.f, -1.f, 0.25f}, Vec3f{1.5f, -0.75f, -0.125f}, Vec3f{0.125f, 1.25f, 0.5f}};
  const Vec3d A = to_double(t[0]), B = to_double(t[1]), C = to_double(t[2]);
  Vec3d nrm = cross(B - A, C - A);
  nrm = nrm * (1.0 / norm(nrm));
  std::vector<Ray<float>> rays;
  while (rays.size() < n) {
    double u = urand(g, -0.1, 1.1), v = urand(g, -0.1, 1.1);
    const Vec3d P = A + (B - A) * u + (C - A) * v * 0.5;
    Vec3d inpl = unit_rand(g);
    inpl = inpl - nrm * dot(inpl, nrm);
    inpl = inpl * (1.0 / norm(inpl));
    const double delta = lurand(g, 1e-12, 1e-1) * (urand(g, 0, 1) < 0.5 ? -1 : 1);
    const Vec3d d = inpl + nrm * delta;
    rays.push_back(make_ray(P - d * 3.0, d));
  }
  measure_all<void>(x, build("grazing", what, {t}, rays, 0));
}

void triangle_pbrt_bad_triangle(Ctx& x, const std::string& what) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  x.reseed("triangle", "pbrt_bad_triangle");
  // The vertices share x and z: the triangle is a segment. No method may report a hit.
  const Tri t{Vec3f{-1113.45459f, -79.049614f, -56.2431908f}, Vec3f{-1113.45459f, -87.0922699f, -56.2431908f},
              Vec3f{-1113.45459f, -79.2090149f, -56.2431908f}};
  TriCase c;
  c.woop.family = c.mt.family = "triangle";
  c.woop.name = c.mt.name = "pbrt_bad_triangle";
  c.woop.what = c.mt.what = what;
  const Vec3d O0{-1081.47925, 99.9999542, 87.7701111}, D{-32.1072998, -183.355865, -144.607635};
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3d O = i == 0 ? O0 : O0 + unit_rand(g) * lurand(g, 1e-7, 1e-3);
    c.add_pair(t, make_ray(O, D, 0.0, 0.9999));
  }
  c.mt.ref = c.woop.ref;
  measure_all<void>(x, c);
}

void triangle_needle(Ctx& x, const std::string& what) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  x.reseed("triangle", "needle");
  // One-to-one: each ray its own needle or tiny triangle.
  TriCase c;
  c.woop.family = c.mt.family = "triangle";
  c.woop.name = c.mt.name = "needle";
  c.woop.what = c.mt.what = what;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3d A = unit_rand(g) * 0.5;
    const bool tiny = i % 4 == 0;
    const Vec3d L = unit_rand(g) * (tiny ? 1e-6 : 1.0);
    const Vec3d W = any_perp(L) * (tiny ? 1e-6 : lurand(g, 1e-7, 1e-3));
    const Tri t{f3(A), f3(A + L), f3(A + L * 0.5 + W)};
    const Vec3d tA = to_double(t[0]), tB = to_double(t[1]), tC = to_double(t[2]);
    const Vec3d P = tA + (tB - tA) * urand(g, -0.05, 1.05) + (tC - tA) * urand(g, -0.3, 0.6);
    Vec3d u = unit_rand(g);
    const Vec3d O = P + u * 2.0;
    c.add_pair(t, make_ray(O, P - O));
  }
  c.mt.ref = c.woop.ref;
  measure_all<void>(x, c);
}

}  // namespace

std::vector<CaseInfo> triangle_cases() {
  return {
      {"triangle", "octahedron_edges", "rays from outside aimed at points on the 12 shared edges of a jittered octahedron"},
      {"triangle", "octahedron_vertices", "rays from outside aimed at the 6 vertices of a jittered octahedron"},
      {"triangle", "octahedron_integer_dirs", "integer directions through dyadic edge points, origin = P - 2^k d (the probe's construction)"},
      {"triangle", "sphere_mesh_edges", "rays aimed at shared edges of a jittered UV sphere mesh (8 x 12)"},
      {"triangle", "sphere_mesh_vertices", "rays aimed at vertices of a jittered UV sphere mesh (8 x 12)"},
      {"triangle", "fan_square", "a square refined into a random triangle fan; rays through inner edges and the fan centre"},
      {"triangle", "far_mesh_1e3", "octahedron edges with the mesh (and camera) 1e3 from the origin"},
      {"triangle", "far_mesh_1e6", "octahedron edges with the mesh (and camera) 1e6 from the origin"},
      {"triangle", "far_camera_1e4", "octahedron edges seen from 1e4 mesh sizes away"},
      {"triangle", "grazing", "in-plane direction + delta n (delta 1e-1..1e-12) at random points of one triangle"},
      {"triangle", "needle", "needle triangles (aspect 1e3..1e7) and tiny ones (size 1e-6), rays at random points near them"},
      {"triangle", "pbrt_bad_triangle", "pbrt-v4's known bad case (a zero-area triangle at x = -1113.45, its ray with tmax 0.9999 |d|), "
                                        "and the ray moved by up to 1e-3"},
  };
}

void run_triangles(Ctx& x) {
  auto& g = x.rng;
  const std::size_t n = x.rays;
  auto sel = [&](const char* name) { return x.selected("triangle", name); };
  auto mesh_case = [&](const char* name, const char* what, const Mesh& m, const std::vector<Ray<float>>& rays) {
    const TriCase c = build(name, what, m.tris(), rays, 1);
    measure_all<void>(x, c);
    bvh_rows(x, c, m);
  };
  const auto infos = triangle_cases();
  auto what = [&](const char* name) {
    for (const auto& i : infos)
      if (i.name == name) return i.what;
    return std::string();
  };
  {
    x.reseed("triangle", "octahedron");
    const Mesh m = octahedron({0.5, -0.25, 0.125}, 2.0, 0.1, g);
    if (sel("octahedron_edges")) mesh_case("octahedron_edges", what("octahedron_edges").c_str(), m, aimed_rays(m, false, n, 8.0, g));
    if (sel("octahedron_vertices")) mesh_case("octahedron_vertices", what("octahedron_vertices").c_str(), m, aimed_rays(m, true, n, 8.0, g));
  }
  if (sel("octahedron_integer_dirs")) {
    x.reseed("triangle", "octahedron_integer_dirs");
    const Mesh m = octahedron({0.5, -0.25, 0.125}, 2.0, 0.0, g);
    mesh_case("octahedron_integer_dirs", what("octahedron_integer_dirs").c_str(), m, integer_dir_rays(m, n, g));
  }
  if (sel("sphere_mesh_edges") || sel("sphere_mesh_vertices")) {
    x.reseed("triangle", "sphere_mesh");
    const Mesh m = sphere_mesh({0.3, -0.2, 0.1}, 1.0, 8, 12, 0.05, g);
    const std::size_t nm = std::max<std::size_t>(n / 4, 64);  // 168 triangles per ray
    if (sel("sphere_mesh_edges")) mesh_case("sphere_mesh_edges", what("sphere_mesh_edges").c_str(), m, aimed_rays(m, false, nm, 4.0, g));
    if (sel("sphere_mesh_vertices"))
      mesh_case("sphere_mesh_vertices", what("sphere_mesh_vertices").c_str(), m, aimed_rays(m, true, nm, 4.0, g));
  }
  if (sel("fan_square")) {
    x.reseed("triangle", "fan_square");
    const Mesh m = square_fan(g, 12);
    std::vector<Ray<float>> rays;
    while (rays.size() < n) {
      const Vec3d P = mesh_target(m, rays.size() % 8 == 0, true, g);
      Vec3d u = unit_rand(g);
      if (std::fabs(u.z) < 0.2) continue;
      const Vec3d O = P + u * 3.0;
      rays.push_back(make_ray(O, P - O));
    }
    const TriCase c = build("fan_square", what("fan_square").c_str(), m.tris(), rays, 2);
    measure_all<void>(x, c);
    bvh_rows(x, c, m);
  }
  for (double off : {1e3, 1e6}) {
    const std::string name = off < 1e4 ? "far_mesh_1e3" : "far_mesh_1e6";
    if (!sel(name.c_str())) continue;
    x.reseed("triangle", name);
    const Vec3d ctr = unit_rand(g) * off;
    const Mesh m = octahedron(ctr, 2.0, 0.1, g);
    const TriCase c = build(name, what(name.c_str()), m.tris(), aimed_rays(m, false, n, 8.0, g), 1);
    measure_all<void>(x, c);
    bvh_rows(x, c, m);
  }
  if (sel("far_camera_1e4")) {
    x.reseed("triangle", "far_camera_1e4");
    const Mesh m = octahedron({0.5, -0.25, 0.125}, 2.0, 0.1, g);
    const TriCase c = build("far_camera_1e4", what("far_camera_1e4"), m.tris(), aimed_rays(m, false, n, 2e4, g), 1);
    measure_all<void>(x, c);
    bvh_rows(x, c, m);
  }
  if (sel("grazing")) triangle_grazing(x, what("grazing"));
  if (sel("pbrt_bad_triangle")) triangle_pbrt_bad_triangle(x, what("pbrt_bad_triangle"));
  if (sel("needle")) triangle_needle(x, what("needle"));
}

}  // namespace rb::acc
