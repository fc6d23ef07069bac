// Run under `mpirun -n 2` (or more): every rank renders its tiles of a small lecture scene on
// THREADS threads (the first argument, default 1), rank 0 gathers them and compares the image with
// the one it renders alone on one thread, bit for bit, and the counts.
#include "render/mpi.hpp"
#include "scene/sources.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

int main(int argc, char** argv) {
  using namespace rb;
  render::MpiSession mpi(&argc, &argv);
  const int threads = argc > 1 ? std::max(1, std::atoi(argv[1])) : 1;
  if (!mpi.active() || mpi.size() < 2) {
    std::fprintf(stderr, "mpi_render_check: start it with mpirun -n 2 (or more)\n");
    return 1;
  }
  const scene::Scene s = scene::lecture_scene("five_glass_balls");
  const tracer::SceneAccel a = tracer::SceneAccel::build(s);
  render::RenderOptions o;
  o.width = 40;
  o.height = 30;
  o.tile = 8;
  o.count_tests = true;  // the test counts compared too
  const render::Renderer r(s, a, o);
  std::vector<float> split;
  const render::RenderStats st = render::render_tiles_mpi(mpi, r, split, threads);
  if (mpi.rank() != 0) return 0;
  std::vector<float> whole;
  const render::RenderStats ref = render::render_tiles(r, whole, 1);
  const bool same_image = split.size() == whole.size() && std::memcmp(split.data(), whole.data(), split.size() * sizeof(float)) == 0;
  const bool same_counts = st.eye == ref.eye && st.eye_hit == ref.eye_hit && st.reflect == ref.reflect && st.refract == ref.refract &&
                           st.shadow == ref.shadow && st.cost.boxes == ref.cost.boxes && st.cost.prims == ref.cost.prims;
  std::printf("%d ranks x %d threads: image %s, counts %s (eye %llu, reflect %llu, refract %llu, shadow %llu)\n", mpi.size(), threads,
              same_image ? "bit-identical" : "DIFFERS", same_counts ? "equal" : "DIFFER", (unsigned long long)st.eye,
              (unsigned long long)st.reflect, (unsigned long long)st.refract, (unsigned long long)st.shadow);
  return same_image && same_counts && st.refract > 0 ? 0 : 1;
}
