// raybench: the command-line front end. `raybench --help` lists the subcommands.
#include "apps/commands.hpp"
#include "apps/machine.hpp"
#include "apps/report.hpp"
#include "bench/ops_table.hpp"

#include <CLI/CLI.hpp>

#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{
      "raybench: a data-oriented SIMD benchmark engine for ray x scene intersection.\n"
      "Every intersection method is one kernel template run as scalar float/double, as 8-lane AVX2 SIMD\n"
      "and as an operation-counting number. Start with `raybench report`."};
  app.require_subcommand(1);

  rb::app::ReportOptions ro;
  auto* report = app.add_subcommand("report", "The main job: ops table, scalar-vs-SIMD benchmarks and charts on the embedded "
                                              "defaults; writes OUT/index.md with JSON and PNG beside it");
  report->add_option("-o,--out", ro.out, "Output folder")->capture_default_str();
  report->add_option("-r,--repetitions", ro.repetitions, "Benchmark repetitions (the report quotes medians)")
      ->capture_default_str()->check(CLI::Range(1, 100));
  report->add_option("--min-time", ro.min_time, "Seconds per benchmark repetition")->capture_default_str()->check(CLI::Range(0.001, 10.0));
  report->add_option("--filter", ro.filter, "Only benchmarks whose name (kernel/method/variant/case) matches this regex")
      ->capture_default_str();
  report->add_flag("!--no-charts", ro.charts, "Skip the matplotlib charts");

  std::string ops_json;
  auto* ops = app.add_subcommand("ops", "Operations per intersection: the lecture's counts beside Counted<float> and per-lane "
                                        "Counted<simd8> measurements, with the reason for every difference");
  ops->add_option("--json", ops_json, "Write the rows as a JSON array to this file instead of the table (no FILE or '-': stdout)")
      ->expected(0, 1)
      ->default_str("-");

  rb::app::BenchOptions bo;
  auto* bench = app.add_subcommand("bench", "Run the kernel benchmarks (Google Benchmark) and write their JSON, every repetition "
                                            "and its aggregates (what Google Benchmark's compare.py reads)");
  bench->add_option("-o,--out", bo.json_out, "JSON output file")->capture_default_str();
  bench->add_option("--filter", bo.filter, "Regex on kernel/method/variant/case")->capture_default_str();
  bench->add_option("-r,--repetitions", bo.repetitions, "Repetitions")->capture_default_str()->check(CLI::Range(1, 100));
  bench->add_option("--min-time", bo.min_time, "Seconds per repetition")->capture_default_str()->check(CLI::Range(0.001, 10.0));
  bench->add_option("--seed", bo.seed, "Seed of the benchmark rays and primitives (0: the report's data)")->capture_default_str();

  const rb::app::Command info = rb::app::add_info_command(app);
  const rb::app::Command query = rb::app::add_query_command(app);
  const rb::app::Command trace = rb::app::add_trace_command(app);
  const rb::app::Command render = rb::app::add_render_command(app);
  const rb::app::Command accuracy = rb::app::add_accuracy_command(app);
  const rb::app::Command csg = rb::app::add_csg_command(app);

  auto* mach = app.add_subcommand("machine", "Print the machine and build description recorded with every result (JSON)");

  CLI11_PARSE(app, argc, argv);
  try {
    if (*report) return rb::app::run_report(ro);
    if (*ops) {
      const auto rows = rb::opstable::build();
      return rb::app::write_result("ops", !ops_json.empty(), ops_json, [&] { return rb::opstable::to_text(rows); },
                                   [&] { return rb::opstable::to_json(rows); }, std::to_string(rows.size()) + " rows");
    }
    if (*bench) {
      const int rc = rb::app::run_benchmarks(bo);
      if (rc == 0) std::cerr << "wrote " << bo.json_out << "\n";
      return rc;
    }
    if (*info.cli) return info.run();
    if (*query.cli) return query.run();
    if (*trace.cli) return trace.run();
    if (*render.cli) return render.run();
    if (*accuracy.cli) return accuracy.run();
    if (*csg.cli) return csg.run();
    if (*mach) { std::cout << rb::app::machine().json().dump(2) << "\n"; return 0; }
  } catch (const std::exception& e) {
    std::cerr << "raybench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
