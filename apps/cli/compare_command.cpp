// `raybench compare`: compare two results: ratios with their intervals.
#include "apps/cli/command.hpp"
#include "apps/results/compare.hpp"

namespace rb::app::cli {
namespace {

class CompareCommand final : public Command {
  CompareOptions co;
  std::string compare_a, compare_b;
  double compare_threshold = -1, compare_noise = 5;
  bool compare_markdown = false;
 public:
  explicit CompareCommand(CLI::App& root) : Command(root, "compare", "Compare two results: ratios with their intervals") {
    positional("A", compare_a, "The baseline: a JSON result or a report folder\n(with --history: a run id)");
    positional("B", compare_b, "The result to compare with it, of the same kind\n(with --history: a run id)");
    sub_->add_option("--history", co.history, "A and B are two runs of this results history,\nby id (`raybench history` lists them)")->type_name("FILE");
    sub_->add_option("--threshold", compare_threshold, "Exit 1 when a row is worse than A beyond noise\nby more than PCT percent")
        ->type_name("PCT")->check(CLI::Range(0.0, 1e6));
    sub_->add_option("--alpha", co.alpha, "1 - the intervals' confidence level")->capture_default_str()->check(CLI::Range(1e-9, 0.5));
    sub_->add_option("--noise", compare_noise, "A single figure (no repetitions) differs when\nit moved by more than PCT percent")
        ->type_name("PCT")->capture_default_str()->check(CLI::Range(0.0, 1e6));
    sub_->add_option("--filter", co.filter, "Only the rows whose section/name matches this\nregex");
    sub_->add_option("--metric", co.metric, "Only this metric (e.g. tests_per_s,\nmrays_per_s, false_hit_ppm)");
    sub_->add_flag("--all", co.all, "Also list the seeded figures that did not change");
    sub_->add_flag("--force", co.force, "Compare two trace or render runs made with other\nsettings (scene, ray set, packet, threads, rays,\nmodel) anyway, matched by metric");
    sub_->add_flag("--markdown", compare_markdown, "Markdown tables instead of the text table");
    json_option("Write the comparison as JSON to FILE\n(no FILE: stdout instead of the table)");
    sub_->footer(
        "A and B: JSON results of one kind (bench, trace, render, accuracy, csg) or two\n"
        "report folders. Per row: both figures, B/A, and for repeated measurements B/A's\n"
        "95 % confidence interval (the ratio of medians; the Mann-Whitney test inverted\n"
        "on logarithms, distribution-free); a timing is faster or slower when the\n"
        "interval excludes 1, or, as a single figure, when it moved by more than\n"
        "--noise. Seeded figures (accuracy rates, test counts) differ\n"
        "when they are not equal. The summary gives the geometric mean of the speed\n"
        "ratios and how many rows are faster or slower. With --threshold, a regression\n"
        "(the whole interval worse by more than PCT) exits 1:\n"
        "`raybench compare base.json new.json --threshold 5` guards CI.\n"
        "Only the subject's own figures are judged (summary, --threshold): Embree's\n"
        "figures and build times measured once are shown in brackets, and judged only\n"
        "when --metric names them. Two trace or render runs of other settings are\n"
        "refused (--force compares them).");
  }
  int run(Context&) override {
    co.threshold = compare_threshold >= 0 ? compare_threshold / 100 : -1;
    co.noise = compare_noise / 100;
    return run_compare_command(compare_a, compare_b, co, compare_markdown, json_out());
  }
};

}  // namespace

std::unique_ptr<Command> make_compare(CLI::App& root) { return std::make_unique<CompareCommand>(root); }

}  // namespace rb::app::cli
