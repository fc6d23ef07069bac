#include "apps/paths.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>

#ifndef RB_SOURCE_DIR
#define RB_SOURCE_DIR "."
#endif

namespace rb::app {

namespace fs = std::filesystem;

std::string executable_path() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? "" : p.string();
}

std::string share_dir() {
  if (const char* e = std::getenv("RAYBENCH_SHARE"); e && *e) return e;
  const std::string exe = executable_path();
  if (!exe.empty()) {
    const fs::path installed = fs::path(exe).parent_path().parent_path() / "share" / "raybench";
    std::error_code ec;
    if (fs::is_directory(installed / "tools", ec)) return installed.lexically_normal().string();
  }
  return RB_SOURCE_DIR;
}

std::string tool_path(const std::string& script) { return (fs::path(share_dir()) / "tools" / script).string(); }
std::string data_dir() { return (fs::path(share_dir()) / "data").string(); }

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace rb::app
