#include "apps/machine.hpp"

#include <fmt/format.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <memory>
#include <thread>

#ifndef RB_SOURCE_DIR
#define RB_SOURCE_DIR "."
#endif

namespace rb::app {

std::string run_capture(const std::string& cmd) {
  std::string out;
  std::unique_ptr<FILE, int (*)(FILE*)> p(popen((cmd + " 2>/dev/null").c_str(), "r"), pclose);
  if (!p) return out;
  std::array<char, 256> buf;
  while (fgets(buf.data(), int(buf.size()), p.get())) out += buf.data();
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  return out;
}

Machine machine() {
  Machine m;
  std::ifstream ci("/proc/cpuinfo");
  std::string line;
  while (std::getline(ci, line)) {
    auto val = [&] { auto p = line.find(':'); return p == std::string::npos ? std::string() : line.substr(p + 2); };
    if (m.cpu.empty() && line.rfind("model name", 0) == 0) m.cpu = val();
    if (m.host_flags.empty() && line.rfind("flags", 0) == 0) {
      const std::string f = " " + val() + " ";
      for (const char* k : {"avx2", "fma", "avx512f"})
        if (f.find(std::string(" ") + k + " ") != std::string::npos) m.host_flags += std::string(m.host_flags.empty() ? "" : " ") + k;
    }
  }
  m.cores = int(std::thread::hardware_concurrency());
  m.compiler = "g++ " __VERSION__;
  m.build_type = RB_BUILD_TYPE;
  m.build_flags = RB_BUILD_FLAGS;
  m.fp_contract = RB_FP_CONTRACT_NAME;
  m.pgo = RB_PGO_PHASE[0] ? RB_PGO_PHASE : "none";
  m.git = run_capture(std::string("git -C '") + RB_SOURCE_DIR + "' rev-parse --short HEAD");
  if (!m.git.empty() && !run_capture(std::string("git -C '") + RB_SOURCE_DIR + "' status --porcelain --untracked-files=no").empty())
    m.git += "-dirty";
  if (m.git.empty()) m.git = "unknown";
  const std::time_t t = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&t));
  m.date = buf;
  return m;
}

nlohmann::json Machine::json() const {
  return {{"cpu", cpu}, {"cores", cores}, {"host_simd", host_flags}, {"compiler", compiler}, {"build_type", build_type},
          {"build_flags", build_flags}, {"fp_contract", fp_contract}, {"pgo", pgo}, {"git", git}, {"date", date},
          {"simd_arch", "xsimd 8.1 fma3<avx2>, 8 x float"}};
}

std::string Machine::markdown() const {
  return fmt::format(
      "| | |\n|---|---|\n| CPU | {} ({} logical cores; host has {}) |\n| compiler | {} |\n| build | {} `{}` |\n"
      "| FP contraction | `-ffp-contract={}` |\n| PGO | {} |\n| SIMD | xsimd 8.1, `fma3<avx2>`, 8 x float |\n"
      "| git | {} |\n| date | {} |\n",
      cpu, cores, host_flags, compiler, build_type, build_flags, fp_contract, pgo, git, date);
}

}  // namespace rb::app
