// `raybench report`: the main job: every measurement, as a report.
#include "apps/cli/command.hpp"
#include "apps/results/machine.hpp"
#include "apps/report/report.hpp"
#include "apps/results/results.hpp"

namespace rb::app::cli {
namespace {

class ReportCommand final : public Command {
  ReportOptions ro;
  std::string report_history;
  bool report_no_history = false;
 public:
  explicit ReportCommand(CLI::App& root) : Command(root, "report", "The main job: every measurement, as a report") {
    sub_->add_option("-o,--out", ro.out, "Output folder")->capture_default_str();
    sub_->add_option("-r,--repetitions", ro.repetitions, "Benchmark rounds (each runs every benchmark\nonce: medians, and SIMD / scalar with a 95 %\ninterval from 6 rounds; from 9 it leaves out\nthe most extreme round on each side)")
        ->capture_default_str()->check(CLI::Range(1, 100));
    sub_->add_option("--min-time", ro.min_time, "Seconds per benchmark repetition")->capture_default_str()->check(CLI::Range(0.001, 10.0));
    sub_->add_option("--extra-rounds", ro.extra_rounds, "Then up to N more rounds of the benchmarks whose\nratio's 95 % interval is wider than --within\n(0: none)")
        ->capture_default_str()->check(CLI::Range(0, 100));
    sub_->add_option_function<double>("--within", [this](double p) { ro.within = p / 100; }, "Half-width in % an interval is held to (the\nrule for extra rounds) [5]")
        ->check(CLI::Range(0.001, 100.0));
    sub_->add_option("--filter", ro.filter, "Only the benchmarks whose name\n(kernel/method/variant/case) matches this regex")
        ->capture_default_str();
    sub_->add_flag("!--no-charts", ro.charts, "Skip the matplotlib charts");
    sub_->add_flag("--quick", ro.quick, "A small report in about a minute, to check its\nlayout and links: 2 repetitions of 0.005 s\n(unless -r, --min-time say otherwise), few\nrays, 128x128 renders, fewer scenes");
    optional_file("--json", ro.json_file, "The summary JSON also to FILE (no FILE: stdout,\nthe terminal summary then to stderr)");
    sub_->add_option("--history", report_history, "Keep the run in this results history\n(default: $RAYBENCH_HISTORY, else\nresults/history.sqlite)")
        ->type_name("FILE");
    sub_->add_flag("--no-history", report_no_history, "Do not keep the run in a results history");
    sub_->add_option("--from", ro.from, "Write the report in DIR again from what it\nmeasured (DIR/measured.json), without\nmeasuring: after a change of the page, not\nof the numbers")
        ->type_name("DIR");
    sub_->footer(
        "Runs the ops table, the scalar-vs-SIMD kernel benchmarks, scene loading, tracing\n"
        "beside Embree, the recursive renderer, the accuracy lab and CSG on the embedded\n"
        "scenes, and writes OUT/index.md with JSON and PNG charts beside it (about 20\n"
        "minutes on a 2-core machine; --quick: a few). Two report folders compare with\n"
        "`raybench compare A B`; each run is kept in results/history.sqlite.\n"
        "Everything measured is kept in OUT/measured.json: `raybench report --from OUT`\n"
        "writes the page again from it in seconds. The profile-guided optimisation\n"
        "section is OUT/pgo.md, which `./run.sh pgo` writes (its own builds, the PGO and\n"
        "the normal binary in paired rounds); `./run.sh report` runs it first.");
  }
  int run(Context& c) override {
    if (!ro.from.empty()) {
      // The figures, and so the options that chose them, are the folder's.
      for (const char* opt : {"--out", "--repetitions", "--min-time", "--extra-rounds", "--within", "--filter", "--quick"})
        if (sub_->count(opt)) {
          std::cerr << error_line("report", ro.from, std::string("--from writes the folder's report from its record: ") + opt +
                                                         " would change what was measured, so it is not taken with --from")
                    << "\n";
          return kExitError;
        }
      if (const std::string why = check_output_dir(ro.from); !why.empty()) {
        std::cerr << error_line("report", ro.from, why) << "\n";
        return kExitError;
      }
      ro.json = sub_->count("--json") > 0;
      return run_report(ro);  // nothing measured: nothing for the history
    }
    if (const std::string why = check_output_dir(ro.out); !why.empty()) {
      std::cerr << error_line("report", ro.out, why) << "\n";
      return kExitError;
    }
    ro.json = sub_->count("--json") > 0;
    if (ro.quick && sub_->count("--repetitions") == 0) ro.repetitions = 2;
    if (ro.quick && sub_->count("--min-time") == 0) ro.min_time = 0.005;
    if (ro.quick && sub_->count("--extra-rounds") == 0) ro.extra_rounds = 0;
    if (!report_no_history && !c.open_history("report", report_history, kReportHistory)) return kExitError;
    const int rc = run_report(ro);
    if (rc == 0 && c.history) {
      const ResultSet r = load_results(ro.out);
      const long long id = c.history->store("report", c.cmdline, r.machine.is_null() ? machine().json() : r.machine, r.figures);
      std::cerr << "kept as run " << id << " in the results history " << c.history->path() << "\n";
    }
    return rc;
  }
};

}  // namespace

std::unique_ptr<Command> make_report(CLI::App& root) { return std::make_unique<ReportCommand>(root); }

}  // namespace rb::app::cli
