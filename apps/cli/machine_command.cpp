// `raybench machine`: the machine and build recorded with results.
#include "apps/cli/command.hpp"

namespace rb::app::cli {
namespace {

class MachineCommand final : public Command {
 public:
  explicit MachineCommand(CLI::App& root) : Command(root, "machine", "The machine and build recorded with results") {
    json_option("The JSON block every result carries, to FILE\n(no FILE: stdout)");
  }
  int run(Context&) override {
    return run_machine_command(json_out());
  }
};

}  // namespace

std::unique_ptr<Command> make_machine(CLI::App& root) { return std::make_unique<MachineCommand>(root); }

}  // namespace rb::app::cli
