// `raybench accuracy`: the accuracy lab: where each method fails.
#include "apps/cli/command.hpp"
#include "apps/accuracy_run.hpp"

namespace rb::app::cli {
namespace {

class AccuracyCommand final : public Command {
  rb::acc::Options ao;
  bool accuracy_list = false;
 public:
  explicit AccuracyCommand(CLI::App& root) : Command(root, "accuracy", "The accuracy lab: where each method fails") {
    sub_->add_flag("--full", ao.full, "Every case with 100000 rays (default: 10000)");
    sub_->add_option("--seed", ao.seed, "Seed of every case generator")->capture_default_str();
    sub_->add_option("--rays", ao.rays, "Rays per case (overrides the mode's count)")->check(CLI::Range(std::size_t(8), std::size_t(1) << 24));
    sub_->add_option("--filter", ao.filter, "Only the cases whose family/case matches this\nregex (e.g. triangle/octa, ^torus/)");
    sub_->add_flag("!--no-timing", ao.timing, "Skip the ns-per-test timing");
    sub_->add_flag("--list", accuracy_list, "List the cases the filter selects and exit");
    json_option("Write the rows as JSON to FILE\n(no FILE: stdout instead of the table)");
    history_option();
    sub_->footer(
        "Adversarial, seeded rays per primitive family (edges and vertices of closed\n"
        "meshes, far and grazing rays, planets, apexes, tangents, slab planes, spawned\n"
        "rays) against exact references from the same float inputs: false hits and\n"
        "misses, leaks, t error in ulps, self-hits and ns per test, per method in float,\n"
        "double and 8-lane SIMD.");
  }
  int run(Context& c) override {
    if (!accuracy_list && !open_history(c)) return kExitError;
    const JsonOut out = recorded_json_out(c);
    return run_accuracy_command(ao, accuracy_list, out);
  }
};

}  // namespace

std::unique_ptr<Command> make_accuracy(CLI::App& root) { return std::make_unique<AccuracyCommand>(root); }

}  // namespace rb::app::cli
