// The command line's conventions, shared by every subcommand (README "Command-line conventions",
// docs/DESIGN.md section 15): exit statuses, one error line naming the input and the reason,
// output paths checked before the work starts, --threads 0, --filter as a regex, the closest name
// for a misspelling, and the warnings that go with a timed run (busy machine, noisy repetitions).
// No CLI11 here: apps/cli/ registers the options, these are plain functions (and tested as such).
#pragma once

#include "core/suggest.hpp"
#include "core/text.hpp"

#include <nlohmann/json.hpp>

#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

namespace rb::app {

// Exit statuses: 0 done, 1 a parse or input error (or, for `compare --threshold`, a regression),
// 2 nothing to do (an empty scene, a filter that selects nothing).
inline constexpr int kExitOk = 0;
inline constexpr int kExitError = 1;
inline constexpr int kExitNothing = 2;

// Thrown where the input is valid but selects nothing to do; the command exits 2.
struct NothingToDo : std::runtime_error {
  using std::runtime_error::runtime_error;
};


// "raybench COMMAND: INPUT: REASON", naming the input once even when REASON already starts with it
// (the scene loaders' messages name the file and line themselves). Newlines become "; ".
std::string error_line(const std::string& command, const std::string& input, const std::string& reason);

// An output, checked before the work starts by the rule of core/output_file.hpp: "" when it can be
// written ("" and "-" are standard output), else the reason (a directory, a socket, a block
// device, an unwritable folder, ...). Nothing is created, opened or truncated.
std::string check_output_file(const std::string& path);
// An output folder: created if missing; "" or the system's reason.
std::string check_output_dir(const std::string& path);

// Scene sources that are not files: spd:NAME[:SIZE], lecture:NAME, csg:NAME, precision:NAME,
// heightfield[:NXxNY].
bool is_generated_scene(const std::string& source);
// An input file: "" when it is a readable regular file, else the system's reason.
std::string check_input_file(const std::string& path);

// --threads: 0 means every hardware thread. Returns the count to run with; `warning` receives a
// line when more threads are asked for than the machine has hardware threads.
unsigned hardware_threads();
int resolve_threads(int requested, std::string* warning);

// The 1-minute load average (/proc/loadavg), or -1 when unknown.
double load_average();
// The machine's CPU time so far (/proc/stat, all CPUs, in clock ticks): in total, and stolen by the
// hypervisor (time a virtual CPU was ready but another guest ran). Zeros when unknown.
struct CpuTimes {
  unsigned long long total = 0, steal = 0;
};
CpuTimes cpu_times();
// The share of CPU time stolen between two readings (NaN when unknown or no time passed).
double steal_share(const CpuTimes& before, const CpuTimes& after);
// The machine's load around timed runs, as every timed result records it ("machine_load"): made
// before the runs; json() after them gives the 1-minute load average before and after, and the share
// of CPU time the hypervisor stole in between (null where unknown). load_text: one line of it.
struct LoadWatch {
  double load_before = load_average();
  CpuTimes cpu_before = cpu_times();
  nlohmann::json json() const;
};
std::string load_text(const nlohmann::json& machine_load);
// A warning when other work ran beside a run that used `threads` threads: the load average
// (read after the run, so that it covers it) exceeded those threads by more than 0.75. "" else.
std::string busy_warning(double load, int threads);
// A warning when the repetitions' coefficient of variation exceeds 5 %. "" else.
std::string noise_warning(double cv, const std::string& what);


// --filter: a POSIX extended regular expression searched in the name (as Google Benchmark's
// --benchmark_filter). Throws std::invalid_argument("--filter 'X': invalid regular expression").
std::regex filter_regex(const std::string& filter);
bool filter_matches(const std::regex& re, const std::string& name);

}  // namespace rb::app
