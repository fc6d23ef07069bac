// SIGINT and SIGTERM: a long run (report, trace, render, ...) stops at once with one message line
// and the exit status 130 (SIGINT) or 143 (SIGTERM). Every output file is written whole through a
// temporary and a rename (core/output_file.hpp), so stopping at any point leaves each output as the
// previous run left it or as this run finished it: the handler unlinks the temporaries being
// written, terminates a chart script this process is waiting for, and exits.
#pragma once

#include <string>

namespace rb::app {

// Installs the handlers; `command` names the subcommand in the message.
void install_interrupt_handlers(const std::string& command);
// std::system's replacement for child processes (chart scripts): /bin/sh -c cmd, waited for; an
// interrupt terminates the child too. Returns the status as std::system does. With `input`, the
// child reads it as its standard input; with `output`, the child's standard output is collected
// there instead of shown.
int run_command(const std::string& cmd, const std::string* input = nullptr, std::string* output = nullptr);

}  // namespace rb::app
