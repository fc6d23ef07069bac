// `raybench history`: the results history: runs, a metric over time.
#include "apps/cli/command.hpp"

namespace rb::app::cli {
namespace {

class HistoryCommand final : public Command {
  HistoryOptions ho;
 public:
  explicit HistoryCommand(CLI::App& root) : Command(root, "history", "The results history: runs, a metric over time") {
    sub_->add_option("--history", ho.path, "The history file (default: $RAYBENCH_HISTORY,\nelse results/history.sqlite)")->type_name("FILE");
    sub_->add_option("--filter", ho.filter, "Only figures whose section/name matches this\nregex");
    sub_->add_option("--metric", ho.metric, "Follow this metric across the runs (e.g.\ntests_per_s, mrays_per_s)");
    output("--plot", ho.plot, "Draw the metric across the runs into this PNG\n('-': stdout, the table then to stderr)");
    json_option("Write the runs or the series as JSON to FILE\n(no FILE: stdout instead of the table)");
    sub_->footer(
        "Runs of bench, trace, render, accuracy and report are kept with --history FILE\n"
        "or RAYBENCH_HISTORY (report: results/history.sqlite by default), keyed by the\n"
        "git revision and dirty flag the binary was built from, its build flags and\n"
        "PGO phase, the machine and the time. Without --metric: the runs. With --metric:\n"
        "its value in every run (several figures: their geometric mean and range).");
  }
  int run(Context&) override {
    return run_history_command(ho, json_out());
  }
};

}  // namespace

std::unique_ptr<Command> make_history(CLI::App& root) { return std::make_unique<HistoryCommand>(root); }

}  // namespace rb::app::cli
