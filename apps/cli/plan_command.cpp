// `raybench plan`: how a scene is modelled for tracing, and why.
#include "apps/cli/command.hpp"

namespace rb::app::cli {
namespace {

class PlanCommand final : public Command {
  std::string plan_scene, plan_model = "auto";
  bool plan_verify = false;
 public:
  explicit PlanCommand(CLI::App& root) : Command(root, "plan", "How a scene is modelled for tracing, and why") {
    positional("scene", plan_scene, "A scene, as `raybench info` takes it");
    sub_->add_option("--model", plan_model, "auto (what the scene needs), fast or exact")
        ->check(one_of({"auto", "fast", "exact"}))->capture_default_str();
    sub_->add_flag("--verify", plan_verify, "Run the lab cases every choice rests on and\nshow their failure figures (a few seconds)");
    json_option("Write the profile and the plan as JSON to\nFILE (no FILE: stdout instead of the text)");
    sub_->footer(
        "Model no more than a scene needs. The scene's numerical profile per primitive\n"
        "kind (sizes, coordinates against them, how far away each kind is seen), then\n"
        "the plan: the frame of reference coordinates are taken in before they are\n"
        "rounded to float, each kind's method, precision and storage, the slab test\n"
        "and where secondary rays start, each with its reason and the accuracy lab's\n"
        "cases it rests on. `trace` and `render` follow the plan (--model auto).");
  }
  int run(Context&) override {
    return run_plan_command(plan_scene, plan_model, plan_verify, json_out());
  }
};

}  // namespace

std::unique_ptr<Command> make_plan(CLI::App& root) { return std::make_unique<PlanCommand>(root); }

}  // namespace rb::app::cli
