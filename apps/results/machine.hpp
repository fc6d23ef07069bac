// What a number was measured on: recorded next to every result (report, JSON, benchmark context).
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace rb::app {

struct Machine {
  std::string cpu, compiler, build_type, build_flags, fp_contract, pgo, git, date, host_flags;
  int cores = 0;
  nlohmann::json json() const;
  std::string markdown() const;
  std::string text() const;  // `raybench machine`: one "key  value" line each, within 80 columns
};

Machine machine();
std::string run_capture(const std::string& cmd);  // stdout of a shell command ("" on failure)

}  // namespace rb::app
