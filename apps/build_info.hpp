// What this binary was built from, recorded when it was built (cmake/build_info.cmake writes the
// revision and the dirty flag at build time): an old binary keeps naming its own source, whatever
// is checked out when it runs.
#pragma once

#include <string>

namespace rb::app {

struct BuildInfo {
  std::string version;       // the project's version (CMakeLists.txt)
  std::string git_revision;  // short commit id, "unknown" outside a git checkout
  bool git_dirty = false;    // tracked files differed from that commit when it was built
  std::string git_time;      // the commit's date (ISO 8601), "" when unknown
  std::string build_type, build_flags, fp_contract, pgo, compiler;
  std::string git() const { return git_revision + (git_dirty ? "-dirty" : ""); }
};

const BuildInfo& build_info();

// `raybench --version`: version, revision, build type and flags, compiler, each line <= 80 columns.
std::string version_text();

}  // namespace rb::app
