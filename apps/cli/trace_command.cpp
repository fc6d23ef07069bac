// `raybench trace`: trace a scene through the BVH beside Embree.
#include "apps/cli/command.hpp"
#include "apps/trace_options.hpp"
#include "core/suggest.hpp"
#include "tracer/ray_sets.hpp"

#include <filesystem>

namespace rb::app::cli {
namespace {

// A ray set's name, or a file (read, and told apart from a misspelt name, when the run starts).
CLI::Validator ray_set_or_file() {
  const std::vector<std::string> names(std::begin(tracer::kRaySetNames), std::end(tracer::kRaySetNames));
  return CLI::Validator(
      [names](std::string& s) -> std::string {
        if (std::find(names.begin(), names.end(), s) != names.end() || std::filesystem::is_regular_file(s)) return "";
        return "'" + s + "' is not one of primary,shadow,diffuse,random nor a ray file" + rb::did_you_mean(s, names);
      },
      "{primary,shadow,diffuse,random}|FILE");
}

class TraceCommand final : public Command {
  TraceRunOptions to;
 public:
  explicit TraceCommand(CLI::App& root) : Command(root, "trace", "Trace a scene through the BVH beside Embree") {
    positional("scene", to.scene, "A scene, as `raybench info` takes it");
    sub_->add_option("--rays", to.ray_set,
                     "Ray set: primary, shadow, diffuse or random, or\na ray file (`raybench render --rays-out FILE`):\n"
                     "its rays traced alone, each section with the\npacket size and query the render used")
        ->check(ray_set_or_file())
        ->capture_default_str();
    sub_->add_option("--threads", to.threads, "Threads for tracing and both builds\n(0: every hardware thread)")
        ->check(CLI::Range(0, 256))->capture_default_str();
    sub_->add_option("--threads-beside", to.threads_beside,
                     "Thread scaling: raybench also on N threads, in\nthe same rounds, and N threads over --threads\n"
                     "as a paired ratio with its interval (0: off;\nthe builds then run on the larger count).\n"
                     "With --threads 1 the one-thread engines take\nturns on the first N CPUs, pinned, and the\n"
                     "ratio is over one thread's rate averaged over\nthem (a guest's CPUs may differ in speed).\n"
                     "Embree's fastest mode is timed alike, as the\nmachine's control")
        ->check(CLI::Range(0, 256))->capture_default_str();
    sub_->add_option("--packet", to.packet, "Rays per packet: 1 (single rays), 8, 16,\n64 or 256 (coherent packets)")
        ->check(CLI::IsMember({1, 8, 16, 64, 256}))
        ->capture_default_str();
    sub_->add_option("--count", to.count, "About this many rays (primary: the nearest\nsquare image of 16x16 blocks)")
        ->transform(count_up_to(std::size_t(1) << 28, "rays"))->capture_default_str();
    sub_->add_option("--seed", to.seed, "Seed of the ray set")->capture_default_str();
    sub_->add_option("--order", to.order,
                     "given: the ray set's order; sorted: every pass\nsorts the rays into coherent groups first (single\n"
                     "rays by origin, then direction; packets by\noctant first) and puts the hits back, both\ntimed; Embree then "
                     "traces both orders")
        ->check(one_of({"given", "sorted"}))
        ->capture_default_str();
    sub_->add_option("--isa", to.isa,
                     "Lanes per group of a packet's rays (packets of\n16 or more, triangle meshes): auto: 16 AVX-512\n"
                     "lanes where the CPU and the build have them;\navx2: 8 lanes; avx512: fail where 16 cannot run;\n"
                     "both: auto, and where that is 16 lanes the\n8-lane walk timed beside it in the same rounds")
        ->check(one_of({"auto", "avx2", "avx512", "both"}))->capture_default_str();
    sub_->add_option("--model", to.model, "How the scene is modelled: auto (what it\nneeds: `raybench plan`), fast or exact")
        ->check(one_of({"auto", "fast", "exact"}))->capture_default_str();
    sub_->add_option("--slab", to.slab, "Slab test: plan (the model's), conservative,\nfast or robust")
        ->check(one_of({"plan", "conservative", "fast", "robust"}))->capture_default_str();
    sub_->add_option("-r,--repetitions", to.repetitions, "Timed rounds, engines alternating (the median is\nquoted; from 6 rounds raybench / Embree has a\n95 % interval)")
        ->check(CLI::Range(1, 100))->capture_default_str();
    sub_->add_option("--warmup", to.warmup, "Untimed runs per engine before the timed ones,\nat least: more while a run still moves by over\n5 % (up to 6)")->check(CLI::Range(0, 100))->capture_default_str();
    sub_->add_option("--min-time", to.min_time, "Seconds a timed repetition lasts at least: the\nray set traced that many times over (the\nfigures are per pass)")
        ->check(CLI::Range(0.0, 60.0))->capture_default_str();
    sub_->add_option("--brute", to.brute_rays, "Rays checked against the brute-force loop\n(-1: a budget by scene size, 0: none)")
        ->capture_default_str();
    sub_->add_flag("!--no-embree", to.embree, "Skip Embree");
    sub_->add_option("--builds", to.builds,
                      "Builds per engine to time: above 1, the build\ntimes quoted are the medians of this many\n"
                      "builds after an untimed one (as the report)")
        ->check(CLI::Range(1, 100))->capture_default_str();
    sub_->add_option("--builder", to.builder,
                      "The tree raybench traces: sah (its own) or\nEmbree's builder (embree: medium quality,\n"
                      "embree-high: high, with spatial splits of\ntriangles); with Embree's the SAH tree is\ntimed beside it")
        ->check(one_of({"sah", "embree", "embree-high"}))->capture_default_str();
    json_option("Write the result as JSON to FILE\n(no FILE: stdout instead of the table)");
    history_option();
    sub_->footer(
        "One binned-SAH build gives a binary and an 8-wide BVH; the rays (primary,\n"
        "shadow, diffuse or random, from one seed) are traced as single rays or\n"
        "packets on TBB threads, and Embree 3 traces the same float triangles and rays in\n"
        "the same process, on a device with its native ISA and one limited to AVX2, with\n"
        "the call for the packet size (rtcIntersect1/8/16, rtcIntersect1M streams for 64\n"
        "and 256; rtcOccluded* for shadow rays); the fastest is the yardstick. After\n"
        "untimed runs until the times settle (at least --warmup), the engines alternate\n"
        "repetition by repetition, each repetition tracing the rays as often as makes\n"
        "it last --min-time (Embree's modes clearly slower in the warm-up are left out\n"
        "of the rounds); the table gives the\n"
        "median Mrays/s with its range and coefficient of variation, build time, memory,\n"
        "traversal cost and the rate of rays the engines disagree on. A warning follows\n"
        "when the runs varied by over 5 % or the machine was busy. Arrays of 2 MiB and\n"
        "more are advised for transparent huge pages, as Embree does for its own;\n"
        "RAYBENCH_NO_HUGE_PAGES=1 turns that off.");
  }
  int run(Context& c) override {
    if (!open_history(c)) return kExitError;
    const JsonOut out = recorded_json_out(c);
    return run_trace_command(to, out, sub_->get_option("--model")->count() > 0);
  }
};

}  // namespace

std::unique_ptr<Command> make_trace(CLI::App& root) { return std::make_unique<TraceCommand>(root); }

}  // namespace rb::app::cli
