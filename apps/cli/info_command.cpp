// `raybench info`: describe a scene: counts, bounds, memory.
#include "apps/cli/command.hpp"

namespace rb::app::cli {
namespace {

class InfoCommand final : public Command {
  std::string info_scene, info_dump;
 public:
  explicit InfoCommand(CLI::App& root) : Command(root, "info", "Describe a scene: counts, bounds, memory") {
    positional("scene", info_scene, "A scene (see below)");
    json_option("Write the description as JSON to FILE\n(no FILE: stdout)");
    optional_file("--dump-json", info_dump,
                  "Write the scene itself in the JSON scene\nformat to FILE (no FILE: stdout), a start\nfor a scene of your own (docs/SCENE_FORMAT.md)");
    sub_->footer(
        "Scenes: a .obj, .ply or .nff file, a .json scene (CSG trees),\n"
        "spd:NAME[:SIZE] (balls gears mount rings teapot tetra tree), lecture:NAME,\n"
        "csg:NAME (spheres_minus lens die torus_box ellipsoid_minus_cylinder), or\n"
        "precision:NAME (scenes that test a tracer's precision: ball_ground,\n"
        "ball_ground_far, planet, mesh_spheres[_1e3|_1e5|_1e7], far_spheres,\n"
        "thin_torus, far_cylinders, mixed_scales, scanned, scanned_double,\n"
        "scattered, pipes), or\n"
        "heightfield[:NXxNY] (a wavy height field of NX x NY quads; default 708x707,\n"
        "about a million triangles).\n"
        "Shows primitive counts per kind, bounds, camera, lights, materials, the\n"
        "memory of the input form and of each SoA kernel batch, and the tracer's plan.");
  }
  int run(Context&) override {
    return sub_->count("--dump-json") ? run_dump_scene_command(info_scene, info_dump) : run_info_command(info_scene, json_out());
  }
};

}  // namespace

std::unique_ptr<Command> make_info(CLI::App& root) { return std::make_unique<InfoCommand>(root); }

}  // namespace rb::app::cli
