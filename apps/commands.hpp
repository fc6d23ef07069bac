// Subcommands that live in their own files. Each adds itself to the CLI and runs from a CLI11
// final callback; a non-zero exit status is thrown as CLI::RuntimeError(code).
#pragma once

#include <CLI/CLI.hpp>

namespace rb::app {
void add_info_command(CLI::App& app);   // cmd_info.cpp  (issue 4: raybench info SCENE)
void add_query_command(CLI::App& app);  // cmd_query.cpp (issue 3: raybench query)
void add_trace_command(CLI::App& app);  // cmd_trace.cpp (raybench trace SCENE)
// The query loop itself (tests call it): one JSON line out per line in; 1 if any line failed.
int run_query(std::istream& in, std::ostream& out, bool dbl);
}  // namespace rb::app
