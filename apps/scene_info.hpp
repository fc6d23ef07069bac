// What `raybench info` says about a scene (also used by the report's scenes section):
// primitive counts per kind, bounds, camera/lights/materials, and memory per batch: the
// input-form bytes of each kind and the bytes of the SoA kernel batch it would build.
#pragma once

#include "scene/scene.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace rb::app {

nlohmann::json scene_info(const rb::scene::Scene& s);
std::string scene_info_text(const nlohmann::json& info);  // the plain-text table
std::string scene_info_markdown(const nlohmann::json& info);

// Resident-memory probe for one load: resets the kernel's peak-RSS mark (Linux
// /proc/self/clear_refs "5"), so peak_mib() after the work is the high-water mark it reached
// above the resident size at reset. `ok` is false where the reset is not permitted.
struct PeakRss {
  bool ok = false;
  double base_mib = 0;
  void reset();
  double peak_mib() const;  // VmHWM - base, MiB
};

}  // namespace rb::app
