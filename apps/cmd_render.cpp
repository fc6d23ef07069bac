// `raybench render SCENE -o image.png`: the recursive ray tracer, with ray and test statistics.
#include "apps/commands.hpp"
#include "apps/render_run.hpp"
#ifdef RB_HAVE_MPI
#include "render/mpi.hpp"
#endif

#include <fstream>
#include <iostream>
#include <memory>

namespace rb::app {

Command add_render_command(CLI::App& app) {
  auto o = std::make_shared<RenderRunOptions>();
  auto json_out = std::make_shared<std::string>();
  auto* cmd = app.add_subcommand(
      "render",
      "Render a scene with the recursive ray tracer (shadows, Lambert + Phong, reflection, Snell refraction) through the BVH: "
      "a PNG, rays by kind, tests by primitive kind, time and Mrays/s. --spd follows Haines' SPD protocol and shows his "
      "published counts beside ours. Under `mpirun -n N` the tiles are split across the ranks");
  cmd->add_option("scene", o->scene, "A .obj/.ply/.nff file, spd:NAME[:SIZE] or lecture:NAME (as `raybench info`)")->required();
  cmd->add_option("-o,--out", o->out, "PNG file to write");
  cmd->add_option("--width", o->width, "Image width in pixels (default 512, or the NFF file's resolution)")->check(CLI::Range(1, 16384));
  cmd->add_option("--height", o->height, "Image height in pixels (default: the width)")->check(CLI::Range(1, 16384));
  cmd->add_option("--depth", o->depth, "Maximum ray tree depth, the eye ray being depth 1")->check(CLI::Range(1, 64))->capture_default_str();
  cmd->add_option("--threads", o->threads, "TBB threads (per MPI rank)")->check(CLI::Range(1, 256))->capture_default_str();
  cmd->add_flag("--spd", o->spd,
                "Haines' SPD protocol: rays through the 513 x 513 pixel corners of a 512 x 512 image averaged, depth 5, every ray "
                "hitting a reflector or transmitter spawns a reflection ray, one-sided opaque surfaces except the teapot");
  cmd->add_flag("!--no-counts", o->count_tests,
                "Skip counting box and primitive tests (the plain traversal, as `raybench trace` times it); rays are still counted");
  cmd->add_option("--secondary-packet", o->secondary_packet,
                  "Reflection, refraction and shadow rays: 1 one by one, 8 sorted by direction octant and traced as 8-ray packets")
      ->check(CLI::IsMember({1, 8}))->capture_default_str();
  cmd->add_option("--json", *json_out, "Write the result as JSON to this file (no argument or '-': stdout) instead of the summary")
      ->expected(0, 1);
  return {cmd, [o, json_out, cmd]() -> int {
    try {
#ifdef RB_HAVE_MPI
      render::MpiSession mpi(nullptr, nullptr);
      const nlohmann::json j = run_render(*o, mpi.active() ? &mpi : nullptr);
      if (mpi.rank() != 0) return 0;
#else
      const nlohmann::json j = run_render(*o, nullptr);
#endif
      return write_result("render", cmd->count("--json") > 0, *json_out, [&] { return render_text(j); }, [&] { return j; });
    } catch (const std::exception& e) {
      std::cerr << "raybench render: " << o->scene << ": " << e.what() << "\n";
      return 1;
    }
  }};
}

}  // namespace rb::app
