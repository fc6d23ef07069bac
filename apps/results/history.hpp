// The results history: every bench, trace, render, accuracy and report run can be kept in one
// SQLite file (--history FILE, or the environment variable RAYBENCH_HISTORY; `raybench report`
// keeps its runs in results/history.sqlite unless told otherwise), keyed by the git revision and
// dirty flag the binary was built from, its build flags and PGO phase, the machine (CPU model, ISA,
// hardware threads) and the time. `raybench history` lists the runs and follows a metric across
// revisions. Schema: docs/DESIGN.md section 16.
#pragma once

#include "apps/results/results.hpp"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

struct sqlite3;

namespace rb::app {

inline constexpr const char* kHistoryEnv = "RAYBENCH_HISTORY";
inline constexpr const char* kReportHistory = "results/history.sqlite";

// Which file a command keeps its run in: --history FILE, else $RAYBENCH_HISTORY, else `fallback`
// ("" : none).
std::string history_path(const std::string& option, const std::string& fallback = "");

class History {
 public:
  // Opens for storing runs (create: the file, its folder and the schema are made when missing) or
  // for reading (the file must exist and be a history). Throws std::runtime_error naming the file
  // and the reason.
  explicit History(const std::string& path, bool create = true);
  ~History();
  History(const History&) = delete;
  History& operator=(const History&) = delete;
  const std::string& path() const { return path_; }

  // Stores one run: the machine block (apps/machine.cpp), the command line and every figure.
  // Returns the run's id.
  long long store(const std::string& kind, const std::string& command, const nlohmann::json& machine, const std::vector<Figure>& figures);

  struct Run {
    long long id = 0;
    std::string time, kind, command, version, git_revision, git_time, build_type, build_flags, fp_contract, pgo, compiler, cpu, isa;
    bool git_dirty = false;
    int cores = 0;
    long long figures = 0;  // figures stored (that match the filter, when one is given)
  };
  // Runs in the order they were stored; with a filter, only runs with a figure whose
  // "section/name" matches it (Run::figures counts those).
  std::vector<Run> runs(const std::string& filter = "") const;

  struct Point {
    long long run = 0;
    std::string section, name, metric, unit;
    int direction = 1;
    bool timing = true;
    double value = 0, scale = 1, cv = 0;
    long long n = 0;
  };
  // Every stored figure of `metric` whose "section/name" matches the filter, by run.
  std::vector<Point> series(const std::string& metric, const std::string& filter = "") const;
  // One stored run as a result (kind, machine block, every figure with its repetitions; source
  // "FILE run ID"), for `raybench compare --history`. Throws std::runtime_error when there is none.
  ResultSet load_run(long long id) const;
  // The metrics stored, with how many figures each.
  std::vector<std::pair<std::string, long long>> metrics() const;

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
  void exec(const char* sql) const;
};

}  // namespace rb::app
