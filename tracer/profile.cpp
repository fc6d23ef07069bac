#include "tracer/profile.hpp"

#include "scene/camera.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <vector>

namespace rb::tracer {

double float_step(double x) {
  x = std::fabs(x);
  if (!(x >= 0x1p-126)) return 0x1p-149;
  if (!std::isfinite(x)) return std::numeric_limits<double>::infinity();
  int e = 0;
  std::frexp(x, &e);  // x = m 2^e, m in [0.5, 1): floats there are 2^(e - 24) apart
  return std::ldexp(1.0, e - 24);
}

namespace {
double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return 0;
  const std::size_t k = std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}
double max_abs(const Vec3d& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }
// The largest distance from p to a point of box b.
double far_dist(const scene::Bounds& b, const Vec3d& p) {
  const Vec3d d{std::max(std::fabs(p.x - b.lo.x), std::fabs(p.x - b.hi.x)), std::max(std::fabs(p.y - b.lo.y), std::fabs(p.y - b.hi.y)),
                std::max(std::fabs(p.z - b.lo.z), std::fabs(p.z - b.hi.z))};
  return std::sqrt(dot(d, d));
}
// The distance from p to the nearest point of box b (0 inside).
double near_dist(const scene::Bounds& b, const Vec3d& p) {
  const Vec3d d{std::max({b.lo.x - p.x, 0.0, p.x - b.hi.x}), std::max({b.lo.y - p.y, 0.0, p.y - b.hi.y}),
                std::max({b.lo.z - p.z, 0.0, p.z - b.hi.z})};
  return std::sqrt(dot(d, d));
}
// The float step at a primitive's largest coordinate in the frame at `origin`.
double step_at(const scene::Bounds& b, const Vec3d& origin) {
  return b.empty() ? 0 : float_step(std::max(max_abs(b.lo - origin), max_abs(b.hi - origin)));
}
// No area or no size: degenerate in every frame.
bool no_area(const scene::Bounds& b, const kinds::Feature& f) { return b.empty() || !(f.size > 0) || !(f.extent > 0) || f.flat; }
// No area or no size, or smaller than one float step where it lies in the frame at `origin` (`step`:
// step_at there): left out of the profile's figures.
bool degenerate_at(const scene::Bounds& b, const kinds::Feature& f, const Vec3d& origin, double& step) {
  step = step_at(b, origin);
  return no_area(b, f) || !(f.extent > step);
}

// The significant digits of x's shortest decimal form and the place of its last one: x's text
// resolution is half a unit there.
double text_resolution(double x, int& digits) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific);  // shortest: d.ddde+XX
  const char* e = std::find(buf, r.ptr, 'e');
  digits = 0;
  for (const char* c = buf; c < e; ++c) digits += *c >= '0' && *c <= '9';
  int exp10 = 0;
  if (e < r.ptr) std::from_chars(e + 1 + (e[1] == '+'), r.ptr, exp10);
  return 0.5 * std::pow(10.0, exp10 - digits + 1);
}

// What the mesh coordinates hold, and which vertices float storage in world coordinates keeps.
void measure_input(const scene::Scene& s, Profile& p) {
  InputPrecision& in = p.input;
  p.vertex_as_input.assign(s.verts.size(), 0);
  for (std::size_t v = 0; v < s.verts.size(); ++v) {
    bool kept = true;
    for (const double c : {s.verts[v].x, s.verts[v].y, s.verts[v].z}) {
      ++in.coords;
      const double f = double(float(c));
      if (f == c) {
        ++in.floats;
        continue;
      }
      int digits = 0;
      const double res = text_resolution(c, digits);
      in.digits_max = std::max(in.digits_max, digits);
      if (std::fabs(f - c) <= res * (1 + 0x1p-20)) {  // the tie at exactly half a unit, computed in binary
        ++in.decimal;
      } else {
        ++in.finer;
        kept = false;
      }
    }
    p.vertex_as_input[v] = kept;
  }
}

}  // namespace

std::string InputPrecision::summary() const {
  if (!coords) return "no mesh vertices";
  if (floats == coords) return "float: every mesh coordinate is a float (float storage keeps the input as it is)";
  if (!finer)
    return fmt::format("decimal text of up to {} significant digits: float reproduces every mesh coordinate within the text's own "
                       "resolution ({} exact floats)",
                       digits_max, floats);
  return fmt::format("finer than float: {} of {} mesh coordinates hold more than a float ({} exact floats, {} decimals float keeps; "
                     "up to {} significant digits)",
                     finer, coords, floats, decimal, digits_max);
}

Profile make_profile(const scene::Scene& s) {
  Profile p;
  p.scene = s.name;
  measure_input(s, p);
  const scene::View v = scene::view_of(s);
  p.camera = v.from;
  p.stated_camera = v.stated;
  std::vector<double> extents_all, extents_represented;
  struct Acc {
    std::vector<double> size, extent;
  };
  std::array<Acc, kKinds> acc;
  kinds::AllKinds::each([&]<class K>() {
    KindProfile& kp = p.kinds[std::size_t(K::id)];
    Acc& a = acc[std::size_t(K::id)];
    K::each(s, [&](std::uint32_t i) {
      ++kp.count;
      const scene::Bounds b = K::bounds(s, i);
      if (b.empty()) return;
      p.bounds.grow(b);
      kp.coord_max = std::max({kp.coord_max, max_abs(b.lo), max_abs(b.hi)});
      const kinds::Feature f = K::feature(s, i);
      double step = 0;
      if (degenerate_at(b, f, {0, 0, 0}, step)) {
        ++kp.degenerate;
        return;
      }
      a.size.push_back(f.size);
      a.extent.push_back(f.extent);
      extents_all.push_back(f.extent);
      if (step <= kFloatTolerance * f.extent) extents_represented.push_back(f.extent);
      kp.aspect_max = std::max(kp.aspect_max, f.extent / f.size);
    });
    p.primitives += kp.count;
  });
  p.extent = p.bounds.empty() ? 0 : p.bounds.max_extent();
  p.coord_max = p.bounds.empty() ? 0 : std::max(max_abs(p.bounds.lo), max_abs(p.bounds.hi));
  // Slivers (a few percent of a scanned mesh, smaller than 4096 float steps where they lie) do not
  // set the scene's scale: the percentile is over the primitives float represents, unless those
  // are not nine in ten (a whole scene far from the origin).
  p.object_min = quantile(extents_represented.size() * 10 >= extents_all.size() * 9 ? extents_represented : extents_all, 0.01);
  const scene::Camera& cam = s.camera;
  p.pixel_angle = v.angle * M_PI / 180.0 / double(std::max({cam.width, cam.height, 1}));
  // Ray origins: the eye and every primitive that is not huge; the eye's distance to the nearest box.
  p.origins.grow(p.camera);
  double near = 1e300;
  kinds::AllKinds::each([&]<class K>() {
    K::each(s, [&](std::uint32_t i) {
      const scene::Bounds b = K::bounds(s, i);
      if (b.empty()) return;
      near = std::min(near, near_dist(b, p.camera));
      if (K::feature(s, i).extent > 1e3 * p.object_min) {
        ++p.huge;
        return;
      }
      p.origins.grow(b);
    });
  });
  p.camera_distance = near < 1e300 ? near : 0;
  for (const auto& L : s.lights)
    if (!p.bounds.empty()) p.light_distance_max = std::max(p.light_distance_max, std::sqrt(dot(L.pos - p.bounds.centre(), L.pos - p.bounds.centre())));

  kinds::AllKinds::each([&]<class K>() {
    KindProfile& kp = p.kinds[std::size_t(K::id)];
    Acc& a = acc[std::size_t(K::id)];
    if (a.size.empty()) return;
    std::vector<double> sz = a.size, ex = a.extent;
    kp.size_min = *std::min_element(sz.begin(), sz.end());
    kp.size_max = *std::max_element(sz.begin(), sz.end());
    kp.size_median = quantile(sz, 0.5);
    kp.extent_min = *std::min_element(ex.begin(), ex.end());
    kp.extent_max = *std::max_element(ex.begin(), ex.end());
    kp.extent_p01 = quantile(ex, 0.01);
    // How far the kind is seen from: the farthest ray origin (a corner of the origins' box) from
    // each primitive's centre, over its size.
    double far = 0;
    K::each(s, [&](std::uint32_t i) {
      const kinds::Feature f = K::feature(s, i);
      double step = 0;
      if (!degenerate_at(K::bounds(s, i), f, {0, 0, 0}, step)) far = std::max(far, far_dist(p.origins, f.centre) / f.size);
    });
    kp.far_ratio = far;
    kp.scale_ratio = p.object_min > 0 ? kp.extent_max / p.object_min : 0;
    kp.world_step_ratio = kp.size_min > 0 ? float_step(kp.coord_max) / kp.size_min : 0;
  });
  return p;
}

double FrameError::worst(const std::array<bool, kKinds>& ignore) const {
  double w = 0;
  for (int k = 0; k < kKinds; ++k)
    if (!ignore[std::size_t(k)]) w = std::max(w, contact[std::size_t(k)]);
  return w;
}

double smallest_object(const Profile& p) { return p.object_min > 0 ? p.object_min : (p.extent > 0 ? p.extent : 1.0); }

double float_step_ratio(const scene::Bounds& b, const kinds::Feature& f, const Vec3d& origin, double small) {
  // Its float step against its own extent; a primitive over a thousand times the smallest object (a
  // planet, a vast floor) against that object: small objects rest on it.
  return step_at(b, origin) / (f.extent > 1e3 * small ? small : f.extent);
}

FrameError frame_error(const scene::Scene& s, const Profile& p, const Vec3d& origin) {
  FrameError e;
  const double small = smallest_object(p);
  const bool world = origin.x == 0 && origin.y == 0 && origin.z == 0;
  kinds::AllKinds::each([&]<class K>() {
    double worst = 0, worst_fine = 0;
    // The area float storage may move (the coarse primitives' perimeters times their float step)
    // against the kind's area (each primitive's smallest times largest length over 2: an
    // underestimate for fat primitives, which makes the share larger; huge ones left out).
    double moved = 0, area = 0;
    KindClasses& c = e.classes[std::size_t(K::id)];
    K::each(s, [&](std::uint32_t i) {
      const scene::Bounds b = K::bounds(s, i);
      const kinds::Feature f = K::feature(s, i);
      // The float step at the largest coordinate the primitive stores in this frame. A primitive with
      // no area or no size is degenerate; one smaller than that step but with an area in the input
      // is not: float would collapse it, double keeps it (coarse, unless the input held it as float).
      const double step = step_at(b, origin);
      if (no_area(b, f)) {
        if (c.degenerate++ == 0 || f.extent < c.worst_degenerate_extent) c.worst_degenerate = i, c.worst_degenerate_extent = f.extent;
        return;
      }
      if constexpr (requires { K::mesh_vertices(s, i); }) {
        if (world && !p.vertex_as_input.empty()) {
          bool kept = true;
          for (const auto v : K::mesh_vertices(s, i)) kept = kept && p.vertex_as_input[v];
          if (kept) {
            ++c.as_input;
            return;
          }
        }
      }
      const bool huge = f.extent > 1e3 * small;
      const double r = float_step_ratio(b, f, origin, small);
      worst = std::max(worst, r);
      if (!huge) area += 0.5 * f.size * f.extent;
      if (r <= kFloatTolerance) {
        ++c.fine;
        worst_fine = std::max(worst_fine, r);
      } else {
        if (r > c.worst_coarse_ratio) c.worst_coarse = i, c.worst_coarse_ratio = r;
        ++c.coarse;
        c.coarse_huge += huge;
        e.coarse_ids[std::size_t(K::id)].push_back(i);
        moved += 3.0 * f.extent * step;
      }
    });
    // Coarse primitives whose rounding can change at most kNegligibleShare of the hits on the kind
    // (slivers among a mesh's triangles) do not decide its storage: judged by effect, not by size.
    c.moved_share = area > 0 ? moved / area : (c.coarse ? 1.0 : 0.0);
    c.negligible = c.coarse > 0 && c.moved_share <= kNegligibleShare;
    e.contact[std::size_t(K::id)] = c.negligible ? worst_fine : worst;
    e.contact_fine[std::size_t(K::id)] = worst_fine;
  });
  const double dist = std::max(p.camera_distance, small);
  e.eye = p.pixel_angle > 0 ? float_step(max_abs(p.camera - origin)) * std::sqrt(3.0) / dist / p.pixel_angle : 0;
  return e;
}

nlohmann::json Profile::json() const {
  using nlohmann::json;
  auto v3 = [](const Vec3d& v) { return json::array({v.x, v.y, v.z}); };
  json k = json::object();
  for (int i = 0; i < kKinds; ++i) {
    const KindProfile& q = kinds[std::size_t(i)];
    if (!q.count) continue;
    k[kinds::kind_name(Kind(i))] = {{"count", q.count},
                                    {"size_min", q.size_min},
                                    {"size_median", q.size_median},
                                    {"size_max", q.size_max},
                                    {"extent_min", q.extent_min},
                                    {"extent_max", q.extent_max},
                                    {"aspect_max", q.aspect_max},
                                    {"coord_max", q.coord_max},
                                    {"far_ratio", q.far_ratio},
                                    {"scale_ratio", q.scale_ratio},
                                    {"world_float_step_over_size", q.world_step_ratio}};
  }
  return {{"scene", scene},
          {"primitives", primitives},
          {"bounds_lo", bounds.empty() ? json(nullptr) : v3(bounds.lo)},
          {"bounds_hi", bounds.empty() ? json(nullptr) : v3(bounds.hi)},
          {"extent", extent},
          {"coord_max", coord_max},
          {"world_float_step", float_step(coord_max)},
          {"camera", v3(camera)},
          {"camera_stated", stated_camera},
          {"camera_distance", camera_distance},
          {"pixel_angle", pixel_angle},
          {"huge_primitives", huge},
          {"light_distance_max", light_distance_max},
          {"object_min", object_min},
          {"input_precision",
           {{"summary", input.summary()},
            {"coordinates", input.coords},
            {"floats", input.floats},
            {"decimal_kept_by_float", input.decimal},
            {"finer_than_float", input.finer},
            {"digits_max", input.digits_max}}},
          {"kinds", k}};
}

}  // namespace rb::tracer
