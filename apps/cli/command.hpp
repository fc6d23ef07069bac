// A subcommand of `raybench`, one file each in apps/cli/: it registers its own options on its
// CLI11 subcommand and, once the line is parsed, runs the subcommand's work (the plain functions
// of apps/commands.hpp). apps/raybench.cpp only assembles them. The registration helpers here give
// every subcommand the same conventions (apps/cli.hpp): --json [FILE|-], outputs checked before
// the work, positionals an optional FILE may not swallow, values refused with the closest one named.
//
// Only apps/raybench.cpp and apps/cli/*.cpp include CLI11 (header-only, about 6 s of compile time
// per file): they are compiled as one unity unit.
#pragma once

#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "apps/results/history.hpp"

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace rb::app::cli {

// What a command may use when it runs: the command line as typed, the results history.
struct Context {
  std::string cmdline;
  std::unique_ptr<History> history;
  // Opens the history named by the option (or the environment, or `fallback`; none: no history);
  // false, with the error printed, when it cannot be opened.
  bool open_history(const std::string& command, const std::string& option, const std::string& fallback);
  // Stores a result document in the opened history (nothing without one).
  std::function<void(const nlohmann::json&)> recorder(const std::string& kind);
};

class Command {
 public:
  Command(CLI::App& root, const std::string& name, const std::string& description);
  virtual ~Command() = default;
  Command(const Command&) = delete;
  Command& operator=(const Command&) = delete;

  virtual int run(Context& c) = 0;

  CLI::App& app() const { return *sub_; }
  const std::string& name() const { return sub_->get_name(); }
  bool chosen() const { return bool(*sub_); }
  // After the parse: the positionals an optional FILE took back ("" or the error), then every
  // output path checked ("" or the error line).
  std::string complete_positionals();
  std::string check_outputs() const;

 protected:
  CLI::App* sub_;
  std::string json_file_, history_file_;

  // A positional argument, required (checked after the parse: see complete_positionals).
  CLI::Option* positional(const std::string& name, std::string& value, const std::string& what);
  // --json [FILE|-]; an output path checked before the work.
  CLI::Option* json_option(const std::string& what);
  // Another option whose FILE is optional (info --dump-json), likewise.
  CLI::Option* optional_file(const std::string& name, std::string& file, const std::string& what);
  // An output path given by an option (-o, --plot), checked before the work.
  CLI::Option* output(const std::string& names, std::string& file, const std::string& what);
  JsonOut json_out() const { return {sub_->count("--json") > 0, json_file_, {}, false}; }
  // --history FILE: keep the run in this results history (default: $RAYBENCH_HISTORY).
  CLI::Option* history_option();
  // Opens that history (false, the error printed, when it cannot be); then the JSON output that
  // also keeps the result there.
  bool open_history(Context& c) const { return c.open_history(name(), history_file_, ""); }
  JsonOut recorded_json_out(Context& c) const {
    JsonOut o = json_out();
    o.record = c.recorder(name());
    return o;
  }

 private:
  std::vector<std::pair<std::string, std::string*>> args_, optional_files_;
  std::vector<const std::string*> outputs_;
};

// Help as CLI11 writes it, but the usage line names the positionals as required (they are: the
// parser is only told otherwise so that an optional FILE can give a swallowed one back).
class Formatter : public CLI::Formatter {
 public:
  std::string make_usage(const CLI::App* app, std::string name) const override;
};

// A value from a fixed set of names; anything else is refused with the names and the closest one.
CLI::Validator one_of(std::vector<std::string> names);
// A count given as an integer or in scientific notation (4e9, 1e6), refused outside 1..max with the
// bound named before anything is allocated; passed on as the integer.
CLI::Validator count_up_to(std::size_t max, const std::string& what);
// A packet size given as one of `allowed` ("auto" or a number), passed on as the number (auto: 0).
CLI::Validator packet_size_choice(std::vector<std::string> allowed);

// Every subcommand, in the order `raybench --help` lists them.
std::vector<std::unique_ptr<Command>> make_commands(CLI::App& root);

// The command line as typed, quoted for a shell (for the results history).
std::string command_line(int argc, char** argv);
// The one error line of a parse error (with the closest option for an unknown one).
std::string parse_error_line(const CLI::App& root, const CLI::ParseError& e, const std::string& command, int argc, char** argv);

}  // namespace rb::app::cli
