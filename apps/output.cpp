// Where a subcommand's result goes (the one convention of every subcommand with --json): the text
// table on stdout, unless --json without a file (or "-", or /dev/stdout) puts the JSON there
// instead; --json FILE writes the JSON to FILE (by the rule of core/output_file.hpp: a FIFO or a
// device as it is, a symlink's target whole) and still prints the table.
#include "core/output_file.hpp"
#include "apps/commands.hpp"

#include "apps/cli.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>

namespace rb::app {

int write_result(const std::string& command, bool as_json, const std::string& file, const std::function<std::string()>& text,
                 const std::function<nlohmann::json()>& to_json, const std::string& wrote, std::ostream& table) {
  if (!as_json) {
    table << text();
    return 0;
  }
  const std::string doc = to_json().dump(2) + "\n";
  const bool to_stdout = file.empty() || is_standard_output(file);
  try {
    write_output(to_stdout ? "-" : file, doc);
  } catch (const std::exception& e) {
    std::cerr << error_line(command, "", e.what()) << "\n";  // the message names the file
    return 1;
  }
  if (to_stdout) return 0;  // the JSON is the output: no table after it
  if (!wrote.empty()) std::cerr << "wrote " << wrote << " to " << file << "\n";
  table << text();  // the JSON went to a file: the terminal still gets the table
  return 0;
}

int write_result(const std::string& command, const JsonOut& out, const std::function<std::string()>& text,
                 const std::function<nlohmann::json()>& to_json, const std::string& wrote) {
  std::ostream& table = out.table_to_stderr ? std::cerr : std::cout;
  if (!out.record) return write_result(command, out.json, out.file, text, to_json, wrote, table);
  const nlohmann::json doc = to_json();
  const int rc = write_result(command, out.json, out.file, text, [&] { return doc; }, wrote, table);
  if (rc == 0) out.record(doc);  // after the result is out: a history that fails cannot lose it
  return rc;
}

bool stdout_for_one_output(const std::string& command, const std::string& option, const std::string& path, JsonOut& out, bool talk) {
  if (path.empty() || !is_standard_output(path)) return true;
  if (out.json && (out.file.empty() || is_standard_output(out.file))) {
    if (talk)
      std::cerr << error_line(command, "", fmt::format("{} {} and --json cannot both go to standard output: give --json a FILE", option, path))
                << "\n";
    return false;
  }
  out.table_to_stderr = true;
  return true;
}

}  // namespace rb::app
