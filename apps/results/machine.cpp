#include "apps/results/machine.hpp"

#include "apps/build_info.hpp"
#include "apps/cli.hpp"
#include "bench/simd16.hpp"
#include "tracer/simd16.hpp"

#include <fmt/format.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <memory>
#include <thread>

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

namespace {
// The SIMD the binary runs: the AVX2 kernels everywhere, and the kernel benchmarks' 16-lane AVX-512
// loops and the tracer's 16-lane packet walk where this build has them (bench/simd16.hpp,
// tracer/simd16.hpp) and the host supports them (`raybench bench --isa` and `raybench trace --isa`
// choose; their results name the choice).
std::string simd_text() {
  std::string s = "xsimd 8.1 fma3<avx2>, 8 x float";
  if (!bench::simd16_built()) return s + "; this build has no AVX-512 code";
  const std::string what = tracer::simd16_traversal_built() ? "kernel benchmarks and mesh packets of 16+ rays" : "kernel benchmarks";
  return s + (bench::simd16_cpu() ? "; " + what + " also avx512dq, 16 x float"
                                  : "; " + what + ": avx512dq 16 x float built, not run (host lacks it)");
}
}  // namespace

Machine machine() {
  Machine m;
  std::ifstream ci("/proc/cpuinfo");
  std::string line;
  while (std::getline(ci, line)) {
    auto val = [&] { auto p = line.find(':'); return p == std::string::npos ? std::string() : line.substr(p + 2); };
    if (m.cpu.empty() && line.rfind("model name", 0) == 0) m.cpu = val();
    if (m.host_flags.empty() && line.rfind("flags", 0) == 0) {
      const std::string f = " " + val() + " ";
      for (const char* k : {"avx2", "fma", "avx512f", "avx512cd", "avx512dq", "avx512bw", "avx512vl"})
        if (f.find(std::string(" ") + k + " ") != std::string::npos) m.host_flags += std::string(m.host_flags.empty() ? "" : " ") + k;
    }
  }
  m.cores = int(std::thread::hardware_concurrency());
  // The build's description and revision were recorded when this binary was built
  // (apps/build_info.hpp), not read from whatever source tree is checked out now.
  const BuildInfo& b = build_info();
  m.compiler = b.compiler;
  m.build_type = b.build_type;
  m.build_flags = b.build_flags;
  m.fp_contract = b.fp_contract;
  m.pgo = b.pgo;
  m.git = b.git();
  const std::time_t t = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&t));
  m.date = buf;
  return m;
}

nlohmann::json Machine::json() const {
  const BuildInfo& b = build_info();
  return {{"cpu", cpu}, {"cores", cores}, {"host_simd", host_flags}, {"compiler", compiler}, {"build_type", build_type},
          {"build_flags", build_flags}, {"fp_contract", fp_contract}, {"pgo", pgo}, {"git", git}, {"date", date},
          {"simd_arch", simd_text()}, {"version", b.version}, {"git_revision", b.git_revision},
          {"git_dirty", b.git_dirty}, {"git_time", b.git_time}};
}

std::string Machine::text() const {
  const BuildInfo& b = build_info();
  std::string t;
  auto row = [&](const char* key, const std::string& value) { t += wrap_words(fmt::format("{:<13} {}", key, value), 80, std::string(14, ' ')); };
  row("cpu", cpu);
  row("isa", host_flags + " (" + simd_text() + ")");
  row("threads", std::to_string(cores) + " hardware threads");
  row("version", b.version);
  row("git", git + (b.git_time.empty() ? "" : " (" + b.git_time + ")") + ", recorded at build time");
  row("build", build_type + ", -ffp-contract=" + fp_contract + ", PGO " + pgo);
  row("build flags", build_flags);
  row("compiler", compiler);
  row("date", date);
  return t;
}

std::string Machine::markdown() const {
  return fmt::format(
      "| | |\n|---|---|\n| CPU | {} ({} logical cores; host has {}) |\n| compiler | {} |\n| build | {} `{}` |\n"
      "| FP contraction | `-ffp-contract={}` |\n| PGO | {} |\n| SIMD | {} |\n"
      "| git | {} |\n| date | {} |\n",
      cpu, cores, host_flags, compiler, build_type, build_flags, fp_contract, pgo, simd_text(), git, date);
}

}  // namespace rb::app
