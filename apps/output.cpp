// Where a subcommand's result goes (the one convention of every subcommand with --json).
#include "apps/commands.hpp"

#include <fstream>
#include <iostream>

namespace rb::app {

int write_result(const std::string& command, bool json, const std::string& file, const std::function<std::string()>& text,
                 const std::function<nlohmann::json()>& to_json, const std::string& wrote) {
  if (!json) {
    std::cout << text();
    return 0;
  }
  if (file.empty() || file == "-") {
    std::cout << to_json().dump(2) << "\n";
    return 0;
  }
  std::ofstream f(file);
  f << to_json().dump(2) << "\n";
  if (!f) {
    std::cerr << "raybench " << command << ": " << file << ": cannot write\n";
    return 1;
  }
  if (!wrote.empty()) std::cerr << "wrote " << wrote << " to " << file << "\n";
  return 0;
}

}  // namespace rb::app
