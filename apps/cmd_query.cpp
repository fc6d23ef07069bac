#include "apps/commands.hpp"

namespace rb::app {
void add_query_command(CLI::App& app) { (void)app; }
}  // namespace rb::app
