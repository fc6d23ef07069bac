// `raybench csg`: cSG queries per second, scalar vs 8-ray packets.
#include "apps/cli/command.hpp"

namespace rb::app::cli {
namespace {

class CsgCommand final : public Command {
  int csg_reps = 5;
  std::size_t csg_rays = std::size_t(1) << 15;
  bool csg_markdown = false;
  std::string csg_filter;
 public:
  explicit CsgCommand(CLI::App& root) : Command(root, "csg", "CSG queries per second, scalar vs 8-ray packets") {
    sub_->add_option("-r,--repetitions", csg_reps, "Timed runs (the median is quoted)")->check(CLI::Range(1, 100))->capture_default_str();
    sub_->add_option("--rays", csg_rays, "Rays per scene")->check(CLI::Range(std::size_t(8), std::size_t(1) << 24))->capture_default_str();
    sub_->add_flag("--markdown", csg_markdown, "The report's CSG section (markdown, with the\noperations per query) instead of the table");
    sub_->add_option("--filter", csg_filter, "Only the scenes whose csg:NAME matches this\nregex (e.g. die, ^csg:lens$)");
    json_option("Write the figures as JSON to FILE\n(no FILE: stdout instead of the table)");
  }
  int run(Context&) override {
    return run_csg_command(csg_reps, csg_rays, csg_markdown, csg_filter, json_out());
  }
};

}  // namespace

std::unique_ptr<Command> make_csg(CLI::App& root) { return std::make_unique<CsgCommand>(root); }

}  // namespace rb::app::cli
