#include "apps/build_info.hpp"

#include "apps/cli.hpp"
#include "apps/paths.hpp"

#include "rb_build_info.h"  // generated at build time (cmake/build_info.cmake)

#include <fmt/format.h>

namespace rb::app {

const BuildInfo& build_info() {
  static const BuildInfo b = [] {
    BuildInfo i;
    i.version = RB_VERSION;
    i.git_revision = RB_GIT_REVISION;
    i.git_dirty = RB_GIT_DIRTY != 0;
    i.git_time = RB_GIT_TIME;
    i.build_type = RB_BUILD_TYPE;
    // One space between flags (the flags are assembled from possibly empty CMake variables).
    for (const char* c = RB_BUILD_FLAGS; *c; ++c)
      if (*c != ' ' || (!i.build_flags.empty() && i.build_flags.back() != ' ')) i.build_flags += *c;
    while (!i.build_flags.empty() && i.build_flags.back() == ' ') i.build_flags.pop_back();
    i.fp_contract = RB_FP_CONTRACT_NAME;
    i.pgo = RB_PGO_PHASE[0] ? RB_PGO_PHASE : "none";
    i.compiler = "g++ " __VERSION__;
    return i;
  }();
  return b;
}

std::string version_text() {
  const BuildInfo& b = build_info();
  std::string t = fmt::format("raybench {}\n", b.version);
  t += fmt::format("git revision  {}{}\n", b.git_revision, b.git_dirty ? " (dirty: tracked files differed when built)" : "");
  if (!b.git_time.empty()) t += fmt::format("commit date   {}\n", b.git_time);
  t += fmt::format("build         {}, -ffp-contract={}, PGO {}\n", b.build_type, b.fp_contract, b.pgo);
  t += wrap_words("build flags   " + b.build_flags, 80, "              ");
  t += wrap_words("compiler      " + b.compiler, 80, "              ");
  t += wrap_words("data and tools " + share_dir(), 80, "              ");
  return t;
}

}  // namespace rb::app
