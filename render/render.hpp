// The lecture's recursive ray tracer (RT_trace / RT_shade) over the scene tracer, with Haines' SPD
// statistics.
//
// RT_trace: the closest hit through the BVH; the background colour on a miss. RT_shade: an ambient
// term; per light a shadow ray, not spawned when the normal faces away from the light, whose
// opaque occluders block the light and whose transmitting occluders scale it by their T (once per
// surface crossed); Lambert diffuse and Phong specular; below the depth limit a reflection ray
// for reflective surfaces (Ks > 0) and a refraction ray by Snell's law for transmitting ones
// (T > 0), with the reflection ray taking the transmitted share on total internal reflection.
//
// The image is a grid of samples cut into square tiles; a tile is traced generation by
// generation (eye rays, then all their reflection and refraction rays, ...), each generation as
// one SoA ray batch through the BVH in 8-ray packets (an incoherent packet falls back to single
// rays), its shadow rays as another batch. Every ray carries the weight its colour has in the
// pixel (the product of Ks and T along its path), so the sum equals the recursion's result. A
// tile's result depends on nothing but the tile, which makes the image the same for any thread
// count or any split of the tiles between processes.
//
// The tracer's plan (tracer/plan.hpp) decides the frame rays are traced in and where secondary rays
// start (its spawn offset); shading works on world points in double, so a scene far from the
// origin shades as it does at the origin.
#pragma once

#include "scene/camera.hpp"
#include "scene/scene.hpp"
#include "tracer/accel.hpp"
#include "tracer/ray_file.hpp"
#include "tracer/ray_order.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rb::render {

struct RenderOptions {
  int width = 512, height = 512;
  int depth = 5;        // maximum ray tree depth, the eye ray being depth 1
  // Haines' protocol: rays through the (width+1) x (height+1) pixel corners, each pixel the mean
  // of its four corners; every ray hitting a reflector or a transmitter spawns a reflection ray.
  bool spd = false;
  // Two-sided opaque surfaces (the normal turned towards the incoming ray before the light test).
  // SPD protocol: one-sided except the teapot. Otherwise two-sided.
  bool two_sided = true;
  int tile = 16;        // tile side in samples
  float ambient = 0.1f; // ambient light: the ambient term is ambient * Kd * surface colour
  // Count box and primitive tests (the counting traversal, its own instantiation; off: the plain
  // one, which is what `raybench trace` times). Ray counts are always kept. On with Haines'
  // protocol (spd_options), where the counts are compared with his.
  bool count_tests = false;
  // Reflection, refraction and shadow rays: 1 traces them one by one; 8 traces each batch in
  // direction-octant order, 8 rays of one octant as a packet (the hits go back to the batch's
  // order, so the image is the same bit for bit in every mode).
  int secondary_packet = 1;
  // The shadow rays of the eye rays' hits (the first generation's): 1, 8 or 16 (16 in octant order
  // as 8; a triangle mesh's packets of 16 walk in 16 AVX-512 lanes where the CPU has them); 0: as
  // secondary_packet. A tile's eye hits lie side by side and their shadow rays to one light
  // converge, so these are coherent where later generations' rays, from scattered hit points, may
  // not be: each kind can take its own size.
  int eye_shadow_packet = 0;
  // The packet size of a generation's shadow rays (gen 0: the eye rays') or other secondary rays.
  int packet_for(std::size_t gen, bool shadow) const {
    const int p = shadow && gen == 0 && eye_shadow_packet != 0 ? eye_shadow_packet : secondary_packet;
    return p == 8 || p == 16 ? p : 1;
  }
  // The order of a batch traced in packets of 8: by direction octant, shadow rays then by their
  // light (stable: the batch's order within, which for a tile follows its image rows), or by the ray
  // sort's key (octant, then the Morton codes of origin, in the scene's box, and direction:
  // tracer/ray_order.hpp).
  // Either way the hits go back to the batch's order: the image is the same.
  enum class Order { octant, sfc };
  Order secondary_order = Order::octant;
  // Eye rays: rays per packet (1, 8, 16 or 64; a tile's rows of neighbouring pixels, so a
  // 64-ray packet is a 16x4 block of the image traced with a frustum test of the node's children).
  int eye_packet = 64;
  // Keep every ray traced, per generation and in the order traced (GenerationStats::kept): what
  // `raybench render --rays-out` writes and what the render's same-rays figure traces alone.
  bool keep_rays = false;
};

// The lanes per group a render asks its packets to walk in (tracer::TraceOptions::lanes): eye
// packets of 16 or more rays of a triangle mesh walk in 16 AVX-512 lanes where the binary and the
// CPU have them, as `raybench trace` does by default (the same hits: the image is unchanged).
inline constexpr int kRenderLanes = 16;

// One generation of a render's rays (0: the eye rays; 1: their reflection and refraction rays; ...):
// its rays, how many hit, its shadow rays, and where its time went, in thread seconds (summed
// over threads; under MPI, this rank's own).
struct GenerationStats {
  std::uint64_t rays = 0, hits = 0, shadow_rays = 0;
  // Coherence: of its rays' 8-ray groups (in the order they are traced), those whose valid rays
  // share a direction octant, which the traversal takes as one packet when the packet size is 8 or
  // more; the same for its shadow rays.
  std::uint64_t groups = 0, coherent_groups = 0, shadow_groups = 0, shadow_coherent_groups = 0;
  double pack_s = 0;             // rays sorted into packet order and copied into SoA (its rays and its shadow rays)
  double traverse_s = 0;         // its rays through the BVH
  double shadow_traverse_s = 0;  // its shadow rays through the BVH (every round past transmitting occluders)
  double shade_s = 0;            // RT_shade: local light, the next generation's rays and the shadow rays made
  double shadow_light_s = 0;     // the shadow rays' light added, rays past transmitting occluders made
  // With RenderOptions::keep_rays: its rays and its shadow rays (every round past transmitting
  // occluders included) as traced, tile after tile.
  std::vector<Ray<float>> kept, kept_shadow;
  double seconds() const { return pack_s + traverse_s + shadow_traverse_s + shade_s + shadow_light_s; }
  void add(const GenerationStats& o) {
    rays += o.rays; hits += o.hits; shadow_rays += o.shadow_rays;
    groups += o.groups; coherent_groups += o.coherent_groups;
    shadow_groups += o.shadow_groups; shadow_coherent_groups += o.shadow_coherent_groups;
    pack_s += o.pack_s; traverse_s += o.traverse_s; shadow_traverse_s += o.shadow_traverse_s;
    shade_s += o.shade_s; shadow_light_s += o.shadow_light_s;
    kept.insert(kept.end(), o.kept.begin(), o.kept.end());
    kept_shadow.insert(kept_shadow.end(), o.kept_shadow.begin(), o.kept_shadow.end());
  }
};

// Ray and test counts. Box and primitive tests are those of every traversal (eye, reflection,
// refraction, shadow and its continuations through transmitting occluders).
// The seconds spent in the BVH (summed over threads; under MPI, this rank's own) for eye rays, for
// their shadow rays and for the other rays, by which a run can choose each kind's packet size, and
// the time split by generation and step.
struct RenderStats {
  std::uint64_t eye = 0, eye_hit = 0, reflect = 0, refract = 0, shadow = 0;
  bvh::TraceCounters cost;
  // eye_shadow_trace_s: the eye rays' shadow rays; secondary_trace_s: every other ray but the eye rays.
  double eye_trace_s = 0, eye_shadow_trace_s = 0, secondary_trace_s = 0;
  double generate_s = 0;  // eye rays made
  std::vector<GenerationStats> generations;
  std::uint64_t rays() const { return eye + reflect + refract + shadow; }
  GenerationStats& generation(std::size_t g) {
    if (generations.size() <= g) generations.resize(g + 1);
    return generations[g];
  }
  void add(const RenderStats& o) {
    eye += o.eye; eye_hit += o.eye_hit; reflect += o.reflect; refract += o.refract; shadow += o.shadow;
    cost.add(o.cost);
    eye_trace_s += o.eye_trace_s; eye_shadow_trace_s += o.eye_shadow_trace_s; secondary_trace_s += o.secondary_trace_s;
    generate_s += o.generate_s;
    for (std::size_t g = 0; g < o.generations.size(); ++g) generation(g).add(o.generations[g]);
  }
};

// Options for a scene under Haines' protocol (512 x 512 unless given, depth 5, one-sided opaque
// primitives except for the teapot).
RenderOptions spd_options(const scene::Scene& s, int width = 512, int height = 512, int depth = 5);

class Renderer {
 public:
  // Throws std::invalid_argument on absurd sizes (width/height outside [1, 16384], depth < 1).
  Renderer(const scene::Scene& s, const tracer::SceneAccel& a, const RenderOptions& o);

  int grid_w() const { return gw_; }  // sample grid (SPD: pixel corners)
  int grid_h() const { return gh_; }
  std::size_t tiles() const { return std::size_t(tx_) * std::size_t(ty_); }
  std::size_t samples() const { return std::size_t(gw_) * std::size_t(gh_); }

  // Traces tile `t` into samples[3 * (y * grid_w + x) ...] (linear RGB) and adds its counts.
  void render_tile(std::size_t t, float* samples, RenderStats& st) const;
  // The image (width x height x 3, linear RGB) from the sample grid.
  std::vector<float> resolve(const std::vector<float>& samples) const;

  const RenderOptions& options() const { return o_; }
  // The rays a render kept (RenderOptions::keep_rays) as a ray file's sections, each with the query
  // and packet size it was traced with (scene, model and origin left to the caller).
  tracer::RayFile kept_rays(const RenderStats& st) const;

  struct Work;  // a tile's rays and payloads (render.cpp)

 private:
  const scene::Scene& s_;
  const tracer::SceneAccel& a_;
  RenderOptions o_;
  int gw_, gh_, tx_, ty_;
  scene::View view_;
  double step_;             // image-plane distance between samples, in units of view_.half
  double x0_, y0_;          // image-plane coordinate of sample (0, 0), in samples
  bool transparent_;        // the scene has a transmitting material (shadow rays see through)
  std::vector<scene::Material> mats_;
  std::vector<Vec3d> light_pos_;  // world
  std::vector<Vec3f> light_frame_;  // the same in the tracer's frame
  std::vector<Vec3f> light_col_;
  tracer::RayKey key_;  // RenderOptions::Order::sfc: the key, origins quantised in the scene's box

  // The steps of one generation (RT_trace / RT_shade), in the order render_tile runs them.
  void eye_rays(int x0, int y0, int x1, int y1, Work& w) const;                                // spawn the first generation
  void hit_rays(Work& w) const;                                                                // its hits' rays, for shading
  void trace(Work& w, const std::vector<Ray<float>>& rays, bool any, bool secondary, bool shadow, RenderStats& st,
             GenerationStats& g) const;                                                        // RT_trace
  void shade(float* samples, Work& w, RenderStats& st) const;                                  // RT_shade: local light, next generation
  void shadows(float* samples, Work& w, RenderStats& st, GenerationStats& g) const;            // the shadow rays of this generation
};

// Renders the tiles t with t % parts == part (all tiles: part 0 of 1) on `threads` TBB threads
// into `samples` (grid size x 3, zero where another part's tiles are) and returns their counts.
// `progress(done, total)` is called from the calling thread's tiles now and then.
RenderStats render_tiles(const Renderer& r, std::vector<float>& samples, int threads, int part = 0, int parts = 1,
                         const std::function<void(std::size_t, std::size_t)>& progress = {});

// The surface colour at p (world): Material::color, or the checkerboard's two colours by cell parity.
Vec3f surface_color(const scene::Material& m, const Vec3d& p);

// 8-bit sRGB-less PNG (values clamped to [0, 1], x 255, rounded). Throws on a write failure.
void write_png(const std::string& path, int width, int height, const std::vector<float>& rgb);
std::vector<std::uint8_t> to_rgb8(const std::vector<float>& rgb);

// The scene rendered under a model (its plan made and the scene built for it), size x size pixels on
// `threads` TBB threads, as 8-bit RGB: what the plan's invariance checks compare (the report's far
// and scaled copies, the tests).
std::vector<std::uint8_t> render_rgb8(const scene::Scene& s, tracer::Model m, int size, int threads = 1);
// The share of pixels whose largest channel difference is above `tolerance` (of 255).
double differing_pixels(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, int tolerance = 4);

}  // namespace rb::render
