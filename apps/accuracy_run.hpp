// The accuracy lab as the command line and the report run it (apps/cmd_accuracy.cpp).
#pragma once

#include "accuracy/lab.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rb::app {
// Runs the lab with a progress bar on stderr labelled `label`.
std::vector<acc::Row> run_accuracy(acc::Options o, const std::string& label);
// The JSON document (machine, mode, seed, rows, case descriptions) and the terminal table.
nlohmann::json accuracy_json(const acc::Options& o, const std::vector<acc::Row>& rows);
std::string accuracy_text(const std::vector<acc::Row>& rows);
}  // namespace rb::app
