#include "apps/report.hpp"
#include "apps/report_sections.hpp"

namespace rb::app {
std::string report_section_scenes(const ReportOptions&, const std::filesystem::path&, nlohmann::json&) { return ""; }
}  // namespace rb::app
