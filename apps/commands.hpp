// Subcommands that live in their own files. Each adds itself to the CLI and returns the function
// that runs it. The convention of every subcommand: the exit status says how it went (0 done,
// 1 the input was bad or a line failed, 2 usage), and each error is one line on stderr that names
// the input (file, scene, line) it is about.
#pragma once

#include "apps/query.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <iosfwd>
#include <string>

namespace rb::app {

struct Command {
  CLI::App* cli;
  std::function<int()> run;  // called after parsing when this subcommand was given
};

Command add_info_command(CLI::App& app);   // cmd_info.cpp:  raybench info SCENE
Command add_query_command(CLI::App& app);  // cmd_query.cpp: raybench query
Command add_trace_command(CLI::App& app);  // cmd_trace.cpp: raybench trace SCENE
Command add_render_command(CLI::App& app); // cmd_render.cpp: raybench render SCENE
Command add_accuracy_command(CLI::App& app);  // cmd_accuracy.cpp: raybench accuracy
Command add_csg_command(CLI::App& app);    // report_csg.cpp: raybench csg

// A subcommand's result: without --json (`json` false) the text table on stdout; with --json the
// JSON on stdout (no FILE or "-") or in FILE, then "wrote WROTE to FILE" on stderr when `wrote` is
// not empty. 0, or 1 with one line on stderr naming the file when it cannot be written.
int write_result(const std::string& command, bool json, const std::string& file, const std::function<std::string()>& text,
                 const std::function<nlohmann::json()>& to_json, const std::string& wrote = "");

// The query loop itself: apps/query.hpp (tests include that, not this header and CLI11).

}  // namespace rb::app
