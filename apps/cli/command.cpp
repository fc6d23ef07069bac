// The conventions every subcommand registers its options with (apps/cli/command.hpp).
#include "apps/cli/command.hpp"

#include "apps/results/machine.hpp"
#include "apps/results/results.hpp"
#include "core/suggest.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>

namespace rb::app::cli {

bool Context::open_history(const std::string& command, const std::string& option, const std::string& fallback) {
  const std::string path = history_path(option, fallback);
  if (path.empty()) return true;
  try {
    history = std::make_unique<History>(path);
  } catch (const std::exception& e) {
    std::cerr << error_line(command, "", e.what()) << "\n";
    return false;
  }
  return true;
}

std::function<void(const nlohmann::json&)> Context::recorder(const std::string& kind) {
  if (!history) return {};
  return [this, kind](const nlohmann::json& doc) {
    nlohmann::json m = machine_of(doc);
    if (m.is_null()) m = machine().json();
    const long long id = history->store(kind, cmdline, m, figures_of(kind, doc).figures);
    std::cerr << "kept as run " << id << " in the results history " << history->path() << "\n";
  };
}

Command::Command(CLI::App& root, const std::string& name, const std::string& description)
    : sub_(root.add_subcommand(name, description)) {}

CLI::Option* Command::positional(const std::string& name, std::string& value, const std::string& what) {
  args_.emplace_back(name, &value);
  return sub_->add_option(name, value, what)->type_name("TEXT REQUIRED");
}

CLI::Option* Command::json_option(const std::string& what) { return optional_file("--json", json_file_, what); }

CLI::Option* Command::optional_file(const std::string& name, std::string& file, const std::string& what) {
  optional_files_.emplace_back(name, &file);
  outputs_.push_back(&file);
  return sub_->add_option(name, file, what)->expected(0, 1)->type_name("[FILE|-]");
}

CLI::Option* Command::history_option() {
  return sub_->add_option("--history", history_file_, "Keep the run in this results history\n(default: $RAYBENCH_HISTORY)")->type_name("FILE");
}

CLI::Option* Command::output(const std::string& names, std::string& file, const std::string& what) {
  outputs_.push_back(&file);
  return sub_->add_option(names, file, what)->type_name("FILE");
}

// The parser gives an option whose FILE is optional the next word, so `trace --json csg:die` would
// read the scene as the JSON file and then miss the scene. The positionals are therefore not
// required by the parser: when some are missing and such an option took a word, that word was the
// positional given at its place (the option then writes to stdout); what is still missing is an
// error.
std::string Command::complete_positionals() {
  std::vector<std::string> given;
  for (const auto& [name, v] : args_)
    if (!v->empty()) given.push_back(*v);
  for (const auto& [opt, file] : optional_files_) {
    if (given.size() == args_.size()) break;
    if (!sub_->count(opt) || file->empty() || *file == "-") continue;
    std::size_t before = 0;  // positional words parsed before the option
    for (const CLI::Option* o : sub_->parse_order()) {
      if (o->check_name(opt)) break;
      before += o->get_positional();
    }
    given.insert(given.begin() + std::ptrdiff_t(std::min(before, given.size())), *file);
    file->clear();
  }
  for (std::size_t i = 0; i < args_.size(); ++i) {
    if (i >= given.size()) return error_line(name(), "", args_[i].first + " is required") + " (raybench " + name() + " --help)";
    *args_[i].second = given[i];
  }
  return "";
}

std::string Command::check_outputs() const {
  for (const std::string* path : outputs_) {
    if (path->empty() || *path == "-") continue;
    if (const std::string why = check_output_file(*path); !why.empty()) return error_line(name(), *path, why);
  }
  return "";
}

std::string Formatter::make_usage(const CLI::App* app, std::string name) const {
  std::string u = CLI::Formatter::make_usage(app, std::move(name));
  for (const CLI::Option* o : app->get_options())
    if (o->get_positional())
      if (const auto p = u.find("[" + o->get_name() + "]"); p != std::string::npos) u.replace(p, o->get_name().size() + 2, o->get_name());
  return u;
}

CLI::Validator one_of(std::vector<std::string> names) {
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ",") + n;
  return CLI::Validator(
      [names, list](std::string& s) -> std::string {
        if (std::find(names.begin(), names.end(), s) != names.end()) return "";
        return "'" + s + "' is not one of " + list + rb::did_you_mean(s, names);
      },
      "{" + list + "}");
}

CLI::Validator count_up_to(std::size_t max, const std::string& what) {
  return CLI::Validator(
      [max, what](std::string& s) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v)) return "expected a number, got '" + s + "'";
        if (!(v >= 1 && v <= double(max))) return s + " is outside 1.." + std::to_string(max) + " (the most " + what + " one run takes)";
        if (v != std::floor(v)) return "expected a whole number, got '" + s + "'";
        s = std::to_string(static_cast<unsigned long long>(v));
        return "";
      },
      "1.." + std::to_string(max));
}

CLI::Validator packet_size_choice(std::vector<std::string> allowed) {
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  return CLI::Validator(
      [allowed, list](std::string& s) -> std::string {
        if (std::find(allowed.begin(), allowed.end(), s) == allowed.end()) return "'" + s + "' is not a packet size here; choose " + list;
        if (s == "auto") s = "0";
        return "";
      },
      "");
}

std::string command_line(int argc, char** argv) {
  std::string s;
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    if (i == 0) a = "raybench";
    const bool plain = !a.empty() && a.find_first_of(" \t\n'\"\\$`*?[]{}()<>|&;#~") == std::string::npos;
    if (!plain) {
      std::string q = "'";
      for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
      a = q + "'";
    }
    s += (i ? " " : "") + a;
  }
  return s;
}

std::string parse_error_line(const CLI::App& root, const CLI::ParseError& e, const std::string& command, int argc, char** argv) {
  std::string msg = e.what();
  // An unknown option: name the closest option of the command.
  if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
    const CLI::App* sub = command.empty() ? &root : root.get_subcommand(command);
    std::vector<std::string> opts;
    for (const auto* o : sub->get_options())
      for (const auto& l : o->get_lnames()) opts.push_back("--" + l);
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a.rfind("--", 0) == 0 && msg.find(a) != std::string::npos) {
        msg += rb::did_you_mean(a.substr(0, a.find('=')), opts);
        break;
      }
    }
  }
  return error_line(command, "", msg) + " (raybench " + (command.empty() ? "" : command + " ") + "--help)";
}

std::unique_ptr<Command> make_report(CLI::App&);
std::unique_ptr<Command> make_ops(CLI::App&);
std::unique_ptr<Command> make_bench(CLI::App&);
std::unique_ptr<Command> make_info(CLI::App&);
std::unique_ptr<Command> make_query(CLI::App&);
std::unique_ptr<Command> make_trace(CLI::App&);
std::unique_ptr<Command> make_render(CLI::App&);
std::unique_ptr<Command> make_accuracy(CLI::App&);
std::unique_ptr<Command> make_csg(CLI::App&);
std::unique_ptr<Command> make_compare(CLI::App&);
std::unique_ptr<Command> make_history(CLI::App&);
std::unique_ptr<Command> make_plan(CLI::App&);
std::unique_ptr<Command> make_machine(CLI::App&);

std::vector<std::unique_ptr<Command>> make_commands(CLI::App& root) {
  std::vector<std::unique_ptr<Command>> c;
  for (auto make : {make_report, make_ops, make_bench, make_info, make_query, make_trace, make_render, make_accuracy, make_csg, make_compare,
                    make_history, make_plan, make_machine})
    c.push_back(make(root));
  return c;
}

}  // namespace rb::app::cli
