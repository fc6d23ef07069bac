// The work of each subcommand, a plain function of its parsed options. The command line itself
// (CLI11) is registered in apps/cli/ (one file per subcommand) and parsed in apps/raybench.cpp,
// compiled as one unit: CLI11 is header-only and costs about 6 s of compile time in every file
// that includes it. The conventions of every subcommand (apps/cli.hpp): the exit status says how
// it went (0 done, 1 a parse or input error, 2 nothing to do), and each error is one line on stderr
// that names the input (file, scene, line) it is about and the reason.
#pragma once

#include "apps/query.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <functional>
#include <iostream>
#include <string>

namespace rb::acc {
struct Options;
}

namespace rb::app {

struct TraceRunOptions;   // apps/trace_options.hpp
struct RenderRunOptions;  // apps/render_options.hpp

// Where a subcommand's --json goes: `json` false without --json (the text table on stdout); with
// --json, `file` empty or "-" means stdout. `record`, when set, receives the result document
// once it is written (the results history, apps/history.hpp).
struct JsonOut {
  bool json = false;
  std::string file;
  std::function<void(const nlohmann::json&)> record;
  bool table_to_stderr = false;  // standard output carries something else (render -o -: the PNG)
};

struct CompareOptions;  // apps/compare.hpp

struct HistoryOptions {
  std::string path;    // --history ("" : $RAYBENCH_HISTORY, else results/history.sqlite)
  std::string filter;  // regex on "section/name"
  std::string metric;  // follow this metric across the runs
  std::string plot;    // PNG to draw the metric into
};

int run_info_command(const std::string& scene, const JsonOut& out);
// `raybench info SCENE --dump-json [FILE|-]`: the scene in the JSON scene format (cmd_info.cpp).
int run_dump_scene_command(const std::string& scene, const std::string& file);               // cmd_info.cpp:  raybench info SCENE
// `model_given`: --model was on the command line (a ray file otherwise brings its own)
int run_trace_command(const TraceRunOptions& o, const JsonOut& out, bool model_given = true);  // cmd_trace.cpp: raybench trace SCENE
int run_render_command(const RenderRunOptions& o, const JsonOut& out);            // cmd_render.cpp: raybench render SCENE
int run_accuracy_command(const acc::Options& o, bool list, const JsonOut& out);   // cmd_accuracy.cpp: raybench accuracy
int run_csg_command(int repetitions, std::size_t rays, bool markdown, const std::string& filter, const JsonOut& out);  // report_csg.cpp: raybench csg
int run_compare_command(const std::string& a, const std::string& b, const CompareOptions& o, bool markdown,
                        const JsonOut& out);                                        // cmd_compare.cpp: raybench compare A B
int run_history_command(const HistoryOptions& o, const JsonOut& out);              // cmd_history.cpp: raybench history
int run_ops_command(bool notes, const std::string& filter, const JsonOut& out);                               // cmd_ops.cpp: raybench ops
struct BenchOptions;                                                                // apps/report.hpp
int run_bench_command(const BenchOptions& o, bool list, const JsonOut& out);      // cmd_bench.cpp: raybench bench
int run_machine_command(const JsonOut& out);                                       // cmd_ops.cpp: raybench machine
int run_plan_command(const std::string& scene, const std::string& model, bool verify, const JsonOut& out);  // cmd_plan.cpp: raybench plan
// raybench query: run_query (apps/query.hpp, cmd_query.cpp) on stdin/stdout/stderr.

// A subcommand's result: the text table on stdout, unless --json without FILE (or "-") puts the
// JSON on stdout instead; with --json FILE the JSON goes to FILE ("wrote WROTE to FILE" on stderr
// when `wrote` is not empty) and the table still to stdout. 0, or 1 with one line on stderr naming
// the file and the system's reason when it cannot be written.
int write_result(const std::string& command, bool json, const std::string& file, const std::function<std::string()>& text,
                 const std::function<nlohmann::json()>& to_json, const std::string& wrote = "", std::ostream& table = std::cout);
// When `path`, the value of `option`, is standard output ("-", /dev/stdout), the command's table
// moves to stderr; with --json to standard output as well, one error line (when `talk`) and false.
bool stdout_for_one_output(const std::string& command, const std::string& option, const std::string& path, JsonOut& out, bool talk = true);
// The same, then out.record(the document) when it is set and the result was written.
int write_result(const std::string& command, const JsonOut& out, const std::function<std::string()>& text,
                 const std::function<nlohmann::json()>& to_json, const std::string& wrote = "");

}  // namespace rb::app
