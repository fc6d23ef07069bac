// SIGINT and SIGTERM: a long run (report, trace, render, ...) stops at once with one message line
// and the exit status 130 (SIGINT) or 143 (SIGTERM). Every output file is written whole through a
// temporary and a rename (core/atomic_file.hpp), so stopping at any point leaves each output as the
// previous run left it or as this run finished it: the handler unlinks the temporaries being
// written and the still-empty files the command line created to check that it may write them,
// terminates a chart script this process is waiting for, and exits.
#pragma once

#include <string>

namespace rb::app {

// Installs the handlers; `command` names the subcommand in the message.
void install_interrupt_handlers(const std::string& command);
// An output file the command line created empty (apps/cli.cpp check_output_file): removed on an
// interrupt while still empty.
void note_placeholder(const std::string& path);
// std::system's replacement for child processes (chart scripts): /bin/sh -c cmd, waited for; an
// interrupt terminates the child too. Returns the status as std::system does.
int run_command(const std::string& cmd);

}  // namespace rb::app
