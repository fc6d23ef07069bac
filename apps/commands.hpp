// Subcommands that live in their own files. The command line itself (CLI11) is parsed in one
// translation unit only, apps/raybench.cpp: CLI11 is header-only and costs about 6 s of compile
// time in every file that includes it. Each subcommand here is a plain function of its parsed
// options. The convention of every subcommand: the exit status says how it went (0 done, 1 the
// input was bad or a line failed, 2 usage), and each error is one line on stderr that names the
// input (file, scene, line) it is about.
#pragma once

#include "apps/query.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <functional>
#include <string>

namespace rb::acc {
struct Options;
}

namespace rb::app {

struct TraceRunOptions;   // apps/trace_options.hpp
struct RenderRunOptions;  // apps/render_options.hpp

// Where a subcommand's --json goes: `json` false without --json (the text table on stdout); with
// --json, `file` empty or "-" means stdout.
struct JsonOut {
  bool json = false;
  std::string file;
};

int run_info_command(const std::string& scene, const JsonOut& out);               // cmd_info.cpp:  raybench info SCENE
int run_trace_command(const TraceRunOptions& o, const JsonOut& out);              // cmd_trace.cpp: raybench trace SCENE
int run_render_command(const RenderRunOptions& o, const JsonOut& out);            // cmd_render.cpp: raybench render SCENE
int run_accuracy_command(const acc::Options& o, bool list, const JsonOut& out);   // cmd_accuracy.cpp: raybench accuracy
int run_csg_command(int repetitions, std::size_t rays);                            // report_csg.cpp: raybench csg
int run_plan_command(const std::string& scene, const std::string& model, bool verify, const JsonOut& out);  // cmd_plan.cpp: raybench plan
// raybench query: run_query (apps/query.hpp, cmd_query.cpp) on stdin/stdout/stderr.

// A subcommand's result: without --json (`json` false) the text table on stdout; with --json the
// JSON on stdout (no FILE or "-") or in FILE, then "wrote WROTE to FILE" on stderr when `wrote` is
// not empty. 0, or 1 with one line on stderr naming the file when it cannot be written.
int write_result(const std::string& command, bool json, const std::string& file, const std::function<std::string()>& text,
                 const std::function<nlohmann::json()>& to_json, const std::string& wrote = "");

}  // namespace rb::app
