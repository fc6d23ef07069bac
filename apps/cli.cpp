#include "apps/cli.hpp"

#include "core/output_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <limits>
#include <sstream>
#include <sys/stat.h>
#include <thread>
#include <unistd.h>

namespace rb::app {

std::string error_line(const std::string& command, const std::string& input, const std::string& reason) {
  std::string r = reason;
  for (std::size_t p; (p = r.find('\n')) != std::string::npos;) r.replace(p, 1, "; ");
  while (!r.empty() && (r.back() == ' ' || r.back() == ';')) r.pop_back();
  std::string line = command.empty() ? "raybench: " : "raybench " + command + ": ";
  if (!input.empty() && r.rfind(input, 0) != 0) line += input + ": ";
  return line + r;
}

std::string check_output_file(const std::string& path) {
  if (path.empty()) return "";
  return output_problem(path);  // the rule of core/output_file.hpp; nothing is created or opened
}

std::string check_output_dir(const std::string& path) {
  if (path.empty()) return std::strerror(ENOENT);
  std::string prefix;
  // Create the folder and its missing parents, with the system's reason on failure.
  std::size_t pos = 0;
  while (pos != std::string::npos) {
    pos = path.find('/', pos + 1);
    prefix = path.substr(0, pos);
    if (prefix.empty()) continue;
    struct stat st {};
    if (::stat(prefix.c_str(), &st) == 0) {
      if (!S_ISDIR(st.st_mode)) return std::strerror(ENOTDIR);
      continue;
    }
    if (::mkdir(prefix.c_str(), 0777) != 0 && errno != EEXIST) return std::strerror(errno);
  }
  if (::access(path.c_str(), W_OK | X_OK) != 0) return std::strerror(errno);
  return "";
}

bool is_generated_scene(const std::string& source) {
  for (const char* p : {"spd:", "lecture:", "csg:", "precision:", "heightfield:"})
    if (source.rfind(p, 0) == 0) return true;
  return source == "heightfield";
}

std::string check_input_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::strerror(errno);
  if (S_ISDIR(st.st_mode)) return std::strerror(EISDIR);
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) return std::strerror(errno);
  ::close(fd);
  return "";
}

unsigned hardware_threads() { return std::max(1u, std::thread::hardware_concurrency()); }

int resolve_threads(int requested, std::string* warning) {
  const int hw = int(hardware_threads());
  const int n = requested <= 0 ? hw : requested;
  if (warning && n > hw)
    *warning = fmt::format("warning: {} threads asked for, the machine has {} hardware threads: they share cores, "
                           "so the timings do not show how the code scales",
                           n, hw);
  return n;
}

double load_average() {
  std::ifstream f("/proc/loadavg");
  double l = -1;
  if (!(f >> l)) return -1;
  return l;
}

CpuTimes cpu_times() {
  std::ifstream f("/proc/stat");
  std::string cpu;
  CpuTimes t;
  if (!(f >> cpu) || cpu != "cpu") return t;
  // user nice system idle iowait irq softirq steal (guest and guest_nice are inside user and nice)
  unsigned long long v[8] = {};
  for (auto& x : v)
    if (!(f >> x)) return {};
  for (auto x : v) t.total += x;
  t.steal = v[7];
  return t;
}

double steal_share(const CpuTimes& before, const CpuTimes& after) {
  if (after.total <= before.total || after.steal < before.steal) return std::numeric_limits<double>::quiet_NaN();
  return double(after.steal - before.steal) / double(after.total - before.total);
}

nlohmann::json LoadWatch::json() const {
  using nlohmann::json;
  const double after = load_average(), stolen = steal_share(cpu_before, cpu_times());
  return {{"load_average_before", load_before >= 0 ? json(load_before) : json(nullptr)},
          {"load_average_after", after >= 0 ? json(after) : json(nullptr)},
          {"steal_share", std::isfinite(stolen) ? json(stolen) : json(nullptr)}};
}

std::string load_text(const nlohmann::json& m) {
  auto f2 = [](const nlohmann::json& v) { return v.is_number() ? fmt::format("{:.2f}", v.get<double>()) : std::string("-"); };
  return fmt::format("load average {} before the runs, {} after; CPU time stolen by the hypervisor during them: {}",
                     f2(m.value("load_average_before", nlohmann::json())), f2(m.value("load_average_after", nlohmann::json())),
                     m.value("steal_share", nlohmann::json()).is_number() ? fmt::format("{:.1f} %", 100 * m["steal_share"].get<double>())
                                                                          : std::string("-"));
}

std::string busy_warning(double load, int threads) {
  if (load < 0 || load <= double(threads) + 0.75) return "";
  return fmt::format("warning: the machine was busy (1-minute load average {:.2f} with {} thread(s) of ours on {} hardware "
                     "threads): other work shared the cores, the figures may be low and noisy",
                     load, threads, hardware_threads());
}

std::string noise_warning(double cv, const std::string& what) {
  if (!(cv > 0.05)) return "";
  return fmt::format("warning: {} varied by {:.1f} % (coefficient of variation over 5 %): more --repetitions, or a quieter "
                     "machine, give a firmer median",
                     what, 100 * cv);
}

std::regex filter_regex(const std::string& filter) {
  try {
    return std::regex(filter, std::regex::extended | std::regex::nosubs);
  } catch (const std::regex_error& e) {
    throw std::invalid_argument(fmt::format("--filter '{}': invalid regular expression ({})", filter, e.what()));
  }
}

bool filter_matches(const std::regex& re, const std::string& name) { return std::regex_search(name, re); }

}  // namespace rb::app
