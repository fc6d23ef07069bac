#include "apps/commands.hpp"

namespace rb::app {
void add_info_command(CLI::App& app) { (void)app; }
}  // namespace rb::app
