// `raybench render`: render a scene with the recursive ray tracer.
#include "apps/cli/command.hpp"
#include "apps/render_options.hpp"

namespace rb::app::cli {
namespace {

class RenderCommand final : public Command {
  RenderRunOptions rdo;
  bool counts = false, no_counts = false;  // neither: count with --spd only
 public:
  explicit RenderCommand(CLI::App& root) : Command(root, "render", "Render a scene with the recursive ray tracer") {
    rdo.warmup = 1;
    rdo.repetitions = 5;  // 4 or more on each side let `compare`'s U test reach p < 0.05
    rdo.min_time = 0.1;
    rdo.trace_alone = true;
    positional("scene", rdo.scene, "A scene, as `raybench info` takes it");
    output("-o,--out", rdo.out, "PNG file to write (default: SCENE.png in the\ncurrent folder; '-': stdout, the table then to\nstderr)");
    sub_->add_option("--width", rdo.width, "Image width in pixels (default 512, or the\nscene camera's resolution)")->check(CLI::Range(1, 16384));
    sub_->add_option("--height", rdo.height, "Image height in pixels (default: from the width\nby the scene camera's aspect ratio, or the width)")->check(CLI::Range(1, 16384));
    sub_->add_option("--depth", rdo.depth, "Maximum ray tree depth (the eye ray is 1)")->check(CLI::Range(1, 64))->capture_default_str();
    sub_->add_option("--threads", rdo.threads, "TBB threads per MPI rank\n(0: every hardware thread)")->check(CLI::Range(0, 256))->capture_default_str();
    sub_->add_flag("--spd", rdo.spd, "Haines' SPD protocol, his counts beside ours");
    auto* c = sub_->add_flag("--counts", counts,
                             "Count box and primitive tests in one more render,\nuntimed (default: with --spd only; the timed\nrenders never count)");
    sub_->add_flag("--no-counts", no_counts, "No test counts, also with --spd")->excludes(c);
    sub_->add_option("--eye-packet", rdo.eye_packet,
                       "Eye rays per packet: 1, 8, 16 or 64 (a 16x4\nblock of the image), or auto: the fastest of\n64, 16 and 8 "
                       "in trial renders before\nthe timed ones")
        ->transform(packet_size_choice({"auto", "1", "8", "16", "64"}))
        ->type_name("auto|1|8|16|64")
        ->default_str("auto");
    sub_->add_option("--secondary-packet", rdo.secondary_packet,
                       "Reflection, refraction and shadow rays: 1 one\nby one, 8 sorted by octant into packets, or\nauto: the "
                       "faster in trial renders")
        ->transform(packet_size_choice({"auto", "1", "8"}))
        ->type_name("auto|1|8")
        ->default_str("auto");
    sub_->add_option("--eye-shadow-packet", rdo.eye_shadow_packet,
                       "The eye rays' shadow rays alone (coherent: a\ntile's hit points towards one light): 1, 8,\n16 "
                       "or auto, chosen apart from the other\nrays' (default: as --secondary-packet)")
        ->transform(packet_size_choice({"auto", "1", "8", "16"}))
        ->type_name("auto|1|8|16");
    sub_->add_option("--secondary-order", rdo.secondary_order,
                     "Order of rays traced in packets of 8: octant\n(by direction octant, shadow rays then by\nlight, else as "
                     "made) or sfc (octant, then\nthe Morton codes of origin and direction; the\nimage does not change)")
        ->check(one_of({"octant", "sfc"}))
        ->capture_default_str();
    sub_->add_option("--tile", rdo.tile,
                     "Tile side in samples: a tile's rays are traced\ngeneration by generation, each generation's\nrays as one "
                     "batch (memory per thread grows\nwith the square of the side; the image does\nnot change)")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    sub_->add_option("--model", rdo.model, "How the scene is modelled: auto (what it\nneeds: `raybench plan`), fast or exact")
        ->check(one_of({"auto", "fast", "exact"}))->capture_default_str();
    sub_->add_option("-r,--repetitions", rdo.repetitions, "Timed renders (the median is quoted)")->check(CLI::Range(1, 100))->capture_default_str();
    sub_->add_option("--warmup", rdo.warmup, "Untimed renders before the timed ones")->check(CLI::Range(0, 100))->capture_default_str();
    sub_->add_option("--min-time", rdo.min_time, "Seconds a timed repetition lasts at least: the\nimage rendered that many times over (at most\n1000; the figures are per render)")
        ->check(CLI::Range(0.0, 10.0))
        ->capture_default_str();
    output("--rays-out", rdo.rays_out,
           "Write the rays one more render traces (each\ngeneration's rays and shadow rays, as traced)\nto FILE, "
           "for `raybench trace SCENE --rays FILE`");
    sub_->add_flag("!--no-trace-alone", rdo.trace_alone,
                   "Skip tracing the render's own rays alone (by\ndefault one more render keeps them and each\ntimed render "
                   "is followed by as long a time\ntracing them alone: the share of the render\nthat is tracing)");
    sub_->add_option("--primary-rays", rdo.primary_rays,
                     "Also trace about N primary rays of the scene\n(8-ray packets, the closest hit) after each\ntimed render, "
                     "as long: the render's rate per\nray against the cheapest rays' (0: not)")
        ->check(CLI::Range(std::size_t(0), std::size_t(1) << 26))
        ->capture_default_str();
    json_option("Write the result as JSON to FILE\n(no FILE: stdout instead of the summary)");
    history_option();
    sub_->footer(
        "The recursive ray tracer through the 8-wide BVH: shadows, Lambert and Phong,\n"
        "reflection, Snell refraction. Writes the image (SCENE.png in the current folder\n"
        "without -o) and prints rays by kind, box and primitive tests by kind (--counts),\n"
        "Mrays/s (median of the timed renders, with range and CV) and where the time\n"
        "went: rays made and packed, the BVH by kind of ray, shading, per generation,\n"
        "and the same rays traced alone (the render's overhead over its tracing).\n"
        "--spd follows Haines' SPD protocol (513 x 513 corner rays averaged, depth 5,\n"
        "one-sided opaque surfaces but the teapot's) and shows his published counts\n"
        "beside ours. Under `mpirun -n N` the tiles are split across the ranks.");
  }
  int run(Context& c) override {
    if (!open_history(c)) return kExitError;
    rdo.count_tests = counts || (rdo.spd && !no_counts);
    const JsonOut out = recorded_json_out(c);
    return run_render_command(rdo, out);
  }
};

}  // namespace

std::unique_ptr<Command> make_render(CLI::App& root) { return std::make_unique<RenderCommand>(root); }

}  // namespace rb::app::cli
