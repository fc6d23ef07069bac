// raybench: the command-line front end. `raybench --help` lists the subcommands; each is one file
// of apps/cli/ that registers its own options (apps/cli/command.hpp). The conventions every
// subcommand follows (README "Command-line conventions", apps/cli.hpp): exit status 0 done, 1 a
// parse or input error, 2 nothing to do; one error line naming the input and the reason; every
// output path checked before the work starts; --json [FILE|-] everywhere; --filter a regex
// everywhere; --threads 0 all hardware threads; help within 80 columns.
#include "apps/build_info.hpp"
#include "apps/cli/command.hpp"
#include "apps/interrupt.hpp"

#include <algorithm>
#include <iostream>

int main(int argc, char** argv) {
  using namespace rb::app;
  CLI::App app{
      "raybench: a data-oriented SIMD benchmark engine for ray x scene intersection.\n"
      "Every intersection method is one kernel template run as scalar float/double,\n"
      "as 8-lane AVX2 SIMD and as an operation-counting number.\n"
      "Start with `raybench report`; `raybench COMMAND --help` explains each command."};
  app.name("raybench");
  app.formatter(std::make_shared<cli::Formatter>());
  app.set_version_flag("--version", version_text(), "Version, git revision and build flags");
  app.require_subcommand(1);
  app.footer(
      "Conventions: exit status 0 done, 1 a parse or input error, 2 nothing to do;\n"
      "--json [FILE|-] (no FILE or '-': stdout) and --filter REGEX on every command\n"
      "that has results or names; --threads 0 uses every hardware thread;\n"
      "--history FILE (or RAYBENCH_HISTORY) keeps a run in the results history.\n"
      "Outputs: a file is replaced whole (a temporary renamed over it), a symlink's\n"
      "target likewise (the link stays); a FIFO or a device is written as it is\n"
      "(--json /dev/null discards, /dev/full fails with exit 1); '-', /dev/stdout,\n"
      "/dev/stderr and /dev/fd/N are this process's own descriptors; a directory,\n"
      "a socket or a block device is refused before the work.");
  const auto commands = cli::make_commands(app);

  // A misspelled command gets the closest one's name, before CLI11 would answer "A subcommand is
  // required" or reject the argument.
  std::vector<std::string> names;
  for (const auto& c : commands) names.push_back(c->name());
  const std::string sub_name = argc > 1 && argv[1][0] != '-' ? argv[1] : "";
  if (!sub_name.empty() && std::find(names.begin(), names.end(), sub_name) == names.end()) {
    std::cerr << "raybench: '" << sub_name << "' is not a command" << rb::did_you_mean(sub_name, names) << " (raybench --help lists them)\n";
    return kExitError;
  }
  if (argc == 1) {
    std::cerr << app.help() << "\nraybench: a command is required\n";
    return kExitError;
  }
  install_interrupt_handlers(sub_name);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::cerr << cli::parse_error_line(app, e, sub_name, argc, argv) << "\n";
    return kExitError;
  }
  const auto chosen = std::find_if(commands.begin(), commands.end(), [](const auto& c) { return c->chosen(); });
  if (chosen == commands.end()) return kExitError;  // require_subcommand(1) makes the parser refuse this first
  cli::Command& cmd = **chosen;
  // Every output is checked before the work starts: a long run must not end in "cannot write".
  for (const std::string& why : {cmd.complete_positionals(), cmd.check_outputs()})
    if (!why.empty()) {
      std::cerr << why << "\n";
      return kExitError;
    }

  cli::Context context{cli::command_line(argc, argv), nullptr};
  int rc = kExitOk;
  try {
    rc = cmd.run(context);
  } catch (const NothingToDo& e) {
    std::cerr << error_line(sub_name, "", e.what()) << "\n";
    rc = kExitNothing;
  } catch (const std::exception& e) {
    std::cerr << error_line(sub_name, "", e.what()) << "\n";
    rc = kExitError;
  }
  // The table or JSON printed on standard output must have got there too (a full disk, /dev/full).
  std::cout.flush();
  if (!std::cout && rc == kExitOk) {
    std::cerr << error_line(sub_name, "", "cannot write standard output") << "\n";
    rc = kExitError;
  }
  return rc;
}
