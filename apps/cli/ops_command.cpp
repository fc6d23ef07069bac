// `raybench ops`: operations per intersection, lecture vs measured.
#include "apps/cli/command.hpp"

namespace rb::app::cli {
namespace {

class OpsCommand final : public Command {
  std::string ops_filter;
  bool ops_notes = false;
 public:
  explicit OpsCommand(CLI::App& root) : Command(root, "ops", "Operations per intersection, lecture vs measured") {
    sub_->add_flag("--notes", ops_notes, "Under every row, the reason for each difference");
    sub_->add_option("--filter", ops_filter, "Only the rows whose kernel/method/case matches\nthis regex (e.g. sphere/, /miss$)");
    json_option("Write the rows as JSON to FILE (no FILE: stdout)");
    sub_->footer(
        "For every kernel and method: the lecture's operation counts beside those\n"
        "measured by running the kernel with Counted<float> on a ray that hits and one\n"
        "that misses, and the per-lane count of the 8-lane SIMD instantiation.");
  }
  int run(Context&) override {
    return run_ops_command(ops_notes, ops_filter, json_out());
  }
};

}  // namespace

std::unique_ptr<Command> make_ops(CLI::App& root) { return std::make_unique<OpsCommand>(root); }

}  // namespace rb::app::cli
