// Ray files (tracer/ray_file.hpp): the rays a render traced, written, read back bit for bit and
// traced alone to the render's own hits; malformed files refused with the file and what is wrong.
// Ray orders (tracer/ray_order.hpp): a stream sorted into coherent groups and its hits put back.
#include "render/render.hpp"
#include "scene/sources.hpp"
#include "tracer/ray_file.hpp"
#include "tracer/ray_order.hpp"
#include "tracer/ray_sets.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>

namespace {

using namespace rb;

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("raybench_test_" + std::to_string(::getpid()) + "_" + name)).string();
}

bool same_bits(const Ray<float>& a, const Ray<float>& b) {
  return std::memcmp(&a.o, &b.o, sizeof a.o) == 0 && std::memcmp(&a.d, &b.d, sizeof a.d) == 0 &&
         std::memcmp(&a.rd, &b.rd, sizeof a.rd) == 0 && std::memcmp(&a.tmin, &b.tmin, sizeof a.tmin) == 0 &&
         std::memcmp(&a.tmax, &b.tmax, sizeof a.tmax) == 0;
}

// A glass scene (shadow rays followed past transmitting occluders: closest-hit shadow sections)
// and an opaque one (any-hit shadow sections), rendered keeping their rays.
struct Kept {
  scene::Scene s;
  tracer::SceneAccel a;
  render::RenderStats st;
  tracer::RayFile f;
};
Kept render_kept(const char* name, int secondary_packet) {
  Kept k{scene::load_scene(name), {}, {}, {}};
  k.a = tracer::SceneAccel::build(k.s);
  render::RenderOptions o;
  o.width = 40;
  o.height = 36;
  o.secondary_packet = secondary_packet;
  o.keep_rays = true;
  const render::Renderer r(k.s, k.a, o);
  std::vector<float> samples;
  k.st = render::render_tiles(r, samples, 2);
  k.f = r.kept_rays(k.st);
  k.f.scene = name;
  k.f.model = "auto";
  k.f.origin = k.a.plan().origin;
  return k;
}

TEST(RayFile, KeptRaysWrittenAndReadBackBitForBit) {
  const Kept k = render_kept("lecture:five_glass_balls", 8);
  ASSERT_FALSE(k.f.sections.empty());
  EXPECT_EQ(k.f.sections[0].kind, "eye");
  EXPECT_EQ(k.f.sections[0].rays.size(), k.st.eye);
  std::size_t shadow = 0;
  for (const auto& s : k.f.sections)
    if (s.kind == "shadow") {
      shadow += s.rays.size();
      EXPECT_FALSE(s.any) << "a glass scene's shadow rays look past transmitting occluders";
    }
  EXPECT_GE(shadow, k.st.shadow);  // and the rays past each occluder
  const std::string path = temp_path("kept.rays");
  tracer::write_ray_file(path, k.f);
  const tracer::RayFile back = tracer::read_ray_file(path);
  std::filesystem::remove(path);
  EXPECT_EQ(back.scene, k.f.scene);
  ASSERT_EQ(back.sections.size(), k.f.sections.size());
  for (std::size_t i = 0; i < back.sections.size(); ++i) {
    const auto &a = back.sections[i], &b = k.f.sections[i];
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.generation, b.generation);
    EXPECT_EQ(a.any, b.any);
    EXPECT_EQ(a.packet, b.packet);
    ASSERT_EQ(a.rays.size(), b.rays.size());
    std::size_t differ = 0;
    for (std::size_t r = 0; r < a.rays.size(); ++r) differ += !same_bits(a.rays[r], b.rays[r]);
    EXPECT_EQ(differ, 0u) << a.label();
  }
}

// Traced alone, each generation's rays meet what they met in the render: the same hits, for an
// opaque scene (any-hit shadow rays) and two with transmitting surfaces, rays one by one and in
// packets.
TEST(RayFile, KeptRaysTracedAloneHitWhatTheRenderHit) {
  for (const char* name : {"lecture:five_glass_balls", "lecture:nine_red_balls", "spd:gears:1"})
    for (int packet : {1, 8}) {
      const Kept k = render_kept(name, packet);
      for (const auto& s : k.f.sections) {
        RaySoA soa;
        for (const auto& r : s.rays) soa.push(r);
        std::vector<bvh::HitRec> out(soa.size());
        tracer::TraceOptions to;
        to.packet = s.packet;
        to.any = s.any;
        k.a.trace(soa, 0, soa.size(), out.data(), to);
        std::size_t hits = 0;
        for (std::size_t i = 0; i < s.rays.size(); ++i) hits += out[i].prim != bvh::kNoPrim;
        if (s.kind == "shadow") {
          bool glass = false;
          for (const auto& m : k.s.materials) glass = glass || m.t > 0;
          EXPECT_EQ(s.any, !glass) << name;
          continue;  // the render counts no shadow hits
        }
        ASSERT_LT(std::size_t(s.generation - 1), k.st.generations.size());
        EXPECT_EQ(hits, k.st.generations[std::size_t(s.generation - 1)].hits) << name << " " << s.label() << ", packet " << packet;
        EXPECT_EQ(s.rays.size(), k.st.generations[std::size_t(s.generation - 1)].rays) << name << " " << s.label();
      }
    }
}

// A contract-breaking ray in a file (NaN, zero direction, a non-unit direction) is read as a ray
// the contract allows: the invalid ray (a defined miss) or the same ray normalised.
TEST(RayFile, RaysBreakingTheContractAreMadeAgain) {
  tracer::RayFile f;
  f.scene = "x";
  f.model = "auto";
  tracer::RaySection s;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Ray<float> bad{{0, 0, 0}, {nan, 0, 1}, {1, 1, 1}, 0, 1};
  Ray<float> zero{{0, 0, 0}, {0, 0, 0}, {1, 1, 1}, 0, 1};
  Ray<float> longer{{1, 2, 3}, {0, 0, 2}, {1, 1, 1}, 0, 5};
  s.rays = {bad, zero, longer};
  f.sections.push_back(s);
  const std::string path = temp_path("bad.rays");
  tracer::write_ray_file(path, f);
  const tracer::RayFile back = tracer::read_ray_file(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.sections.at(0).rays.size(), 3u);
  EXPECT_GT(back.sections[0].rays[0].tmin, back.sections[0].rays[0].tmax);
  EXPECT_GT(back.sections[0].rays[1].tmin, back.sections[0].rays[1].tmax);
  EXPECT_TRUE(same_bits(back.sections[0].rays[2], make_ray(Vec3f{1, 2, 3}, Vec3f{0, 0, 2}, 0.0f, 5.0f)));
}

// Malformed files: an error naming the file and what is wrong, never a crash or a huge allocation.
TEST(RayFile, MalformedFilesAreRefusedNamingTheFile) {
  tracer::RayFile f;
  f.scene = "x";
  f.model = "auto";
  tracer::RaySection s;
  s.rays.assign(10, make_ray(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}));
  f.sections.push_back(s);
  const std::string good = temp_path("good.rays");
  tracer::write_ray_file(good, f);
  std::string bytes;
  {
    std::ifstream in(good, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::filesystem::remove(good);
  const std::size_t header_end = bytes.find('\n', bytes.find('\n') + 1) + 1;
  const std::string head = bytes.substr(0, header_end);
  const std::string absurd = head.substr(0, head.find("\"rays\":10")) + "\"rays\":18446744073709551615" +
                             head.substr(head.find("\"rays\":10") + 9);
  const struct {
    const char* what;
    std::string text;
    const char* says;
  } cases[] = {
      {"empty", "", "line 1"},
      {"not a ray file", "ply\nformat ascii 1.0\n", "line 1"},
      {"header not JSON", "raybench rays 1\n{\"scene\": \n", "line 2"},
      {"no header end", "raybench rays 1\n{\"scene\": \"x\"", "line 2"},
      {"no sections", "raybench rays 1\n{\"scene\":\"x\",\"model\":\"auto\",\"origin\":[0,0,0],\"sections\":[]}\n", "no sections"},
      {"bad query", std::string(head).replace(head.find("closest"), 7, "nearest") + bytes.substr(header_end), "query"},
      {"truncated", bytes.substr(0, bytes.size() - 5), "promises 10 rays"},
      {"absurd count", absurd + bytes.substr(header_end), "promises"},
      {"bytes after", bytes + "xyz", "3 bytes follow"},
  };
  for (const auto& c : cases) {
    const std::string path = temp_path("malformed.rays");
    {
      std::ofstream out(path, std::ios::binary);
      out << c.text;
    }
    try {
      tracer::read_ray_file(path);
      ADD_FAILURE() << c.what << ": read without an error";
    } catch (const std::runtime_error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(path), std::string::npos) << c.what << ": " << m;
      EXPECT_NE(m.find(c.says), std::string::npos) << c.what << ": " << m;
    }
    std::filesystem::remove(path);
  }
  EXPECT_THROW(tracer::read_ray_file(temp_path("missing.rays")), std::runtime_error);
}

// Rays written in one frame and read under a plan with another origin are moved into it in double:
// the same world rays.
TEST(RayFile, MovedIntoAnotherFrameTheWorldRaysStay) {
  tracer::RayFile f;
  f.origin = {1000, -2000, 0.5};
  tracer::RaySection s;
  s.rays = {make_ray(Vec3f{1, 2, 3}, Vec3f{0.6f, 0.8f, 0}, 0.5f, 10.0f)};
  f.sections.push_back(s);
  tracer::move_frame(f, {0, 0, 0});
  const Ray<float>& r = f.sections[0].rays[0];
  EXPECT_FLOAT_EQ(r.o.x, 1001.0f);
  EXPECT_FLOAT_EQ(r.o.y, -1998.0f);
  EXPECT_FLOAT_EQ(r.o.z, 3.5f);
  EXPECT_NEAR(r.tmax, 10.0f, 1e-5f);
}

// The direction octant of sorted row i (a component below zero sets its bit).
int octant_of(const RaySoA& r, std::size_t i) { return int(r.dx[i] < 0) | int(r.dy[i] < 0) << 1 | int(r.dz[i] < 0) << 2; }

// The sorted stream holds every ray of the stream once (order() is a permutation of 0..n-1).
void expect_sorted_permutation(const tracer::RayOrder& order, std::size_t n) {
  ASSERT_EQ(order.order().size(), n);
  std::vector<std::uint32_t> seen(order.order());
  std::sort(seen.begin(), seen.end());
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(seen[i], i);
}

// How many of the stream's rays get another hit (primitive or t) traced in sorted order and put
// back than traced in the given order.
std::size_t sorted_hits_that_differ(const tracer::SceneAccel& a, const RaySoA& rays, const tracer::RayOrder& order,
                                    const tracer::TraceOptions& to, tracer::ThreadScope& ts) {
  std::vector<bvh::HitRec> given(rays.size()), sorted(rays.size()), back(rays.size());
  a.trace(rays, 0, rays.size(), given.data(), to);
  a.trace(order.sorted(), 0, order.sorted().size(), sorted.data(), to);
  order.unsort(sorted.data(), back.data(), ts);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < rays.count; ++i) differ += back[i].prim != given[i].prim || back[i].t != given[i].t;
  return differ;
}

// A sorted stream is a permutation of the rays, grouped by direction octant, with origins in one
// cell of the key's grid next to each other; traced sorted and put back, its hits are the given
// order's, bit for bit (closest hits), and the order is the same on 1 and 2 threads.
TEST(RayOrder, SortedStreamIsAPermutationWithTheSameHits) {
  const scene::Scene s = scene::load_scene("spd:balls:1");
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  for (const auto set : {tracer::RaySet::diffuse, tracer::RaySet::random}) {
    const RaySoA rays = tracer::make_rays(s, a, set, 5000, 3);
    const scene::Bounds b = s.bounds();
    tracer::RayOrder order, order2;
    {
      tracer::ThreadScope ts(1);
      order.sort(rays, a.to_frame(b.lo), a.to_frame(b.hi), ts);
    }
    tracer::ThreadScope ts(2);
    order2.sort(rays, a.to_frame(b.lo), a.to_frame(b.hi), ts);
    EXPECT_EQ(order.order(), order2.order()) << "the order depends on the rays alone";
    const std::size_t n = rays.count;
    expect_sorted_permutation(order, n);
    const RaySoA& sr = order.sorted();
    ASSERT_EQ(sr.size(), rays.size());
    int octant_changes = 0, last = -1;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t j = order.order()[i];
      ASSERT_EQ(sr.ox[i], rays.ox[j]);
      ASSERT_EQ(sr.dz[i], rays.dz[j]);
      ASSERT_EQ(sr.tmax[i], rays.tmax[j]);
      const int oct = octant_of(sr, i);
      EXPECT_GE(oct, last) << "octants in order";
      octant_changes += oct != last;
      last = oct;
    }
    EXPECT_LE(octant_changes, 8);
    for (std::size_t i = n; i < rays.size(); ++i) EXPECT_GT(sr.tmin[i], sr.tmax[i]) << "padding stays invalid";
    tracer::TraceOptions to;
    to.packet = 8;
    EXPECT_EQ(sorted_hits_that_differ(a, rays, order, to, ts), 0u) << tracer::ray_set_name(set);
  }
  // Origins far outside the key's box (and a huge box) clamp to its cells: sorted, nothing lost.
  RaySoA far;
  for (float x : {1e30f, -1e30f, 3e38f, 0.0f, 1.0f})
    far.push(make_ray(Vec3f{x, -x, x}, Vec3f{0.0f, 1.0f, 0.0f}));
  tracer::RayOrder order;
  tracer::ThreadScope ts(1);
  order.sort(far, Vec3f{-1, -1, -1}, Vec3f{1, 1, 1}, ts);
  EXPECT_EQ(order.order().size(), far.count);
  order.sort(far, Vec3f{-3e38f, -3e38f, -3e38f}, Vec3f{3e38f, 3e38f, 3e38f}, ts);
  EXPECT_EQ(order.order().size(), far.count);
}

// The key of single rays puts the origin first (octants mixed); that of packets the octant. Either
// way the sorted stream is a permutation in key order whose hits, put back, are the given order's.
TEST(RayOrder, SingleRaysSortByOriginFirstAndPacketsByOctant) {
  using Layout = tracer::RayKey::Layout;
  EXPECT_EQ(tracer::RayKey::layout_for(1), Layout::origin_first);
  EXPECT_EQ(tracer::RayKey::layout_for(8), Layout::octant_first);
  EXPECT_EQ(tracer::RayKey::layout_for(16), Layout::octant_first);
  EXPECT_NE(tracer::RayKey::describe(Layout::origin_first), tracer::RayKey::describe(Layout::octant_first));
  // A ray from the box's low corner pointing to -x-y-z (octant 7), and one from the high corner to
  // +x+y+z (octant 0).
  const Vec3f lo{-1, -1, -1}, hi{1, 1, 1};
  const Vec3f o_low{-0.99f, -0.99f, -0.99f}, o_high{0.99f, 0.99f, 0.99f}, up{0.6f, 0.64f, 0.48f};
  const tracer::RayKey origin_first(lo, hi, Layout::origin_first), octant_first(lo, hi, Layout::octant_first);
  EXPECT_LT(origin_first(o_low, -up), origin_first(o_high, up)) << "the origin decides";
  EXPECT_GT(octant_first(o_low, -up), octant_first(o_high, up)) << "the octant decides";
  EXPECT_LT(origin_first(o_low, -up), origin_first(o_low, up)) << "then the direction";

  const scene::Scene s = scene::load_scene("spd:balls:1");
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  const scene::Bounds b = s.bounds();
  const Vec3f flo = a.to_frame(b.lo), fhi = a.to_frame(b.hi);
  const RaySoA rays = tracer::make_rays(s, a, tracer::RaySet::random, 5000, 5);
  tracer::RayOrder order;
  tracer::ThreadScope ts(2);
  order.sort(rays, flo, fhi, ts, Layout::origin_first);
  const std::size_t n = rays.count;
  expect_sorted_permutation(order, n);
  const RaySoA& sr = order.sorted();
  const tracer::RayKey key(flo, fhi, Layout::origin_first);
  int octant_changes = 0, last = -1;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t j = order.order()[i];
    ASSERT_EQ(sr.ox[i], rays.ox[j]);
    ASSERT_EQ(sr.ry[i], rays.ry[j]);
    ASSERT_EQ(sr.tmin[i], rays.tmin[j]);
    if (i > 0) {
      const std::uint64_t k0 = key({sr.ox[i - 1], sr.oy[i - 1], sr.oz[i - 1]}, {sr.dx[i - 1], sr.dy[i - 1], sr.dz[i - 1]});
      const std::uint64_t k1 = key({sr.ox[i], sr.oy[i], sr.oz[i]}, {sr.dx[i], sr.dy[i], sr.dz[i]});
      ASSERT_LE(k0, k1) << "key order at " << i;
      if (k0 == k1) {
        ASSERT_LT(order.order()[i - 1], j) << "equal keys keep the stream's order";
      }
    }
    const int oct = octant_of(sr, i);
    octant_changes += oct != last;
    last = oct;
  }
  EXPECT_GT(octant_changes, 100) << "octants mixed: the origin comes first";
  EXPECT_EQ(sorted_hits_that_differ(a, rays, order, tracer::TraceOptions{}, ts), 0u) << "single rays";
}

}  // namespace
