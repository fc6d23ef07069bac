// Where a subcommand's result goes (the one convention of every subcommand with --json): the text
// table on stdout, unless --json without a file (or "-") puts the JSON there instead; --json FILE
// writes the JSON to FILE and still prints the table.
#include "core/atomic_file.hpp"
#include "apps/commands.hpp"

#include "apps/cli.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>

namespace rb::app {

int write_result(const std::string& command, bool as_json, const std::string& file, const std::function<std::string()>& text,
                 const std::function<nlohmann::json()>& to_json, const std::string& wrote) {
  if (!as_json) {
    std::cout << text();
    return 0;
  }
  if (file.empty() || file == "-") {
    std::cout << to_json().dump(2) << "\n";
    return 0;
  }
  const std::string doc = to_json().dump(2) + "\n";
  // Whole or not at all: a temporary renamed over the file (core/atomic_file.hpp).
  try {
    write_file_atomic(file, doc);
  } catch (const std::exception& e) {
    std::cerr << error_line(command, file, e.what()) << "\n";
    return 1;
  }
  if (!wrote.empty()) std::cerr << "wrote " << wrote << " to " << file << "\n";
  std::cout << text();  // the JSON went to a file: the terminal still gets the table
  return 0;
}

int write_result(const std::string& command, const JsonOut& out, const std::function<std::string()>& text,
                 const std::function<nlohmann::json()>& to_json, const std::string& wrote) {
  if (!out.record) return write_result(command, out.json, out.file, text, to_json, wrote);
  const nlohmann::json doc = to_json();
  const int rc = write_result(command, out.json, out.file, text, [&] { return doc; }, wrote);
  if (rc == 0) out.record(doc);  // after the result is out: a history that fails cannot lose it
  return rc;
}

}  // namespace rb::app
