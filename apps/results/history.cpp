#include "apps/results/history.hpp"

#include "core/output_file.hpp"

#include "apps/cli.hpp"
#include "apps/results/stats.hpp"

#include <fmt/format.h>
#include <sqlite3.h>

#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <map>

namespace rb::app {

using nlohmann::json;

std::string history_path(const std::string& option, const std::string& fallback) {
  if (!option.empty()) return option;
  if (const char* e = std::getenv(kHistoryEnv); e && *e) return e;
  return fallback;
}

namespace {

// The schema (docs/DESIGN.md section 16). user_version 1.
const char* const kSchema = R"(
CREATE TABLE IF NOT EXISTS runs (
  id           INTEGER PRIMARY KEY AUTOINCREMENT,
  time         TEXT    NOT NULL,  -- when the run was stored: UTC, ISO 8601
  kind         TEXT    NOT NULL,  -- bench, trace, render, accuracy, report
  command      TEXT    NOT NULL,  -- the command line
  version      TEXT    NOT NULL,
  git_revision TEXT    NOT NULL,  -- recorded when the binary was built
  git_dirty    INTEGER NOT NULL,  -- 1: tracked files differed from that revision when it was built
  git_time     TEXT    NOT NULL,  -- the revision's commit date ('' when unknown)
  build_type   TEXT    NOT NULL,
  build_flags  TEXT    NOT NULL,
  fp_contract  TEXT    NOT NULL,
  pgo          TEXT    NOT NULL,  -- PGO phase: none, generate, use (training)
  compiler     TEXT    NOT NULL,
  cpu          TEXT    NOT NULL,  -- CPU model
  isa          TEXT    NOT NULL,  -- the host's SIMD extensions (avx2 fma avx512f)
  cores        INTEGER NOT NULL,  -- hardware threads
  machine      TEXT    NOT NULL   -- the whole machine and build block (JSON)
);
CREATE TABLE IF NOT EXISTS figures (
  run       INTEGER NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
  section   TEXT    NOT NULL,  -- bench, trace, render, accuracy, csg, scenes
  name      TEXT    NOT NULL,  -- the row: benchmark, scene and configuration, accuracy case
  metric    TEXT    NOT NULL,  -- tests_per_s, mrays_per_s, false_hit_ppm, ...
  unit      TEXT    NOT NULL,  -- as shown (value * scale): Mtests/s, Mrays/s, ppm, ...
  scale     REAL    NOT NULL,
  direction INTEGER NOT NULL,  -- 1 higher is better, -1 lower is better, 0 neither
  timing    INTEGER NOT NULL,  -- 1 a measurement (noisy), 0 a seeded figure
  value     REAL,              -- median of the repetitions, or the one figure; NULL if not finite
  n         INTEGER NOT NULL,  -- repetitions (0: one figure)
  cv        REAL,              -- coefficient of variation of the repetitions
  samples   TEXT    NOT NULL,  -- the repetitions, a JSON array
  PRIMARY KEY (run, section, name, metric)
);
CREATE INDEX IF NOT EXISTS figures_by_metric ON figures(metric, section, name);
PRAGMA user_version = 1;
)";

struct Stmt {
  sqlite3_stmt* s = nullptr;
  Stmt(sqlite3* db, const char* sql, const std::string& path) {
    if (sqlite3_prepare_v2(db, sql, -1, &s, nullptr) != SQLITE_OK) throw std::runtime_error(path + ": " + sqlite3_errmsg(db));
  }
  ~Stmt() { sqlite3_finalize(s); }
  Stmt(const Stmt&) = delete;
  Stmt& operator=(const Stmt&) = delete;
  void text(int i, const std::string& v) { sqlite3_bind_text(s, i, v.c_str(), int(v.size()), SQLITE_TRANSIENT); }
  void integer(int i, long long v) { sqlite3_bind_int64(s, i, v); }
  void real(int i, double v) {
    if (std::isfinite(v)) sqlite3_bind_double(s, i, v);
    else sqlite3_bind_null(s, i);
  }
  std::string col_text(int i) const {
    const unsigned char* t = sqlite3_column_text(s, i);
    return t ? reinterpret_cast<const char*>(t) : "";
  }
};

std::string now_utc() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

std::string jstr(const json& m, const char* k) { return m.is_object() && m.contains(k) && m[k].is_string() ? m[k].get<std::string>() : ""; }

}  // namespace

History::History(const std::string& path, bool create) : path_(path) {
  if (!create) {
    if (const std::string why = check_input_file(path); !why.empty()) throw std::runtime_error(path + ": " + why);
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
      const std::string why = db_ ? sqlite3_errmsg(db_) : "cannot open";
      sqlite3_close(db_);
      db_ = nullptr;
      throw std::runtime_error(path + ": " + why);
    }
    sqlite3_busy_timeout(db_, 10000);
    bool ok = false;
    try {
      Stmt q(db_, "SELECT COUNT(*) FROM sqlite_master WHERE type = 'table' AND name IN ('runs', 'figures')", path_);
      ok = sqlite3_step(q.s) == SQLITE_ROW && sqlite3_column_int(q.s, 0) == 2;
    } catch (const std::exception& e) {
      sqlite3_close(db_);
      db_ = nullptr;
      std::string why = e.what();
      if (why.find("file is not a database") != std::string::npos) throw std::runtime_error(path + ": not a raybench history (not an SQLite file)");
      throw;
    }
    if (!ok) {
      sqlite3_close(db_);
      db_ = nullptr;
      throw std::runtime_error(path + ": not a raybench history (no runs and figures tables)");
    }
    return;
  }
  const std::filesystem::path p(path);
  if (p.has_parent_path()) {
    if (const std::string why = check_output_dir(p.parent_path().string()); !why.empty())
      throw std::runtime_error(p.parent_path().string() + ": " + why);
  }
  if (const std::string why = check_output_file(path); !why.empty()) throw std::runtime_error(path + ": " + why);
  // SQLite keeps a journal beside the database and rewrites it in place: a FIFO, a device or a
  // descriptor cannot hold one (a symlink to a file is followed, as for every output).
  if (const OutputTarget t = output_target(path); t.kind != OutputTarget::kNewFile && t.kind != OutputTarget::kRegular)
    throw std::runtime_error(path + ": a results history is an SQLite database and must be a regular file, not " +
                             (t.kind == OutputTarget::kDescriptor ? std::string("a file descriptor") : "a FIFO or a device"));
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "cannot open";
    sqlite3_close(db_);
    db_ = nullptr;
    throw std::runtime_error(path + ": " + why);
  }
  sqlite3_busy_timeout(db_, 10000);  // another raybench storing a run at the same time
  try {
    exec("PRAGMA foreign_keys = ON");
    exec(kSchema);
  } catch (...) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw;
  }
}

History::~History() { sqlite3_close(db_); }

void History::exec(const char* sql) const {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    std::string why = err ? err : sqlite3_errmsg(db_);
    sqlite3_free(err);
    if (why == "file is not a database") why = "not a raybench history (" + why + ")";
    throw std::runtime_error(path_ + ": " + why);
  }
}

long long History::store(const std::string& kind, const std::string& command, const json& m, const std::vector<Figure>& figures) {
  exec("BEGIN IMMEDIATE");
  try {
    {
      Stmt s(db_,
             "INSERT INTO runs (time, kind, command, version, git_revision, git_dirty, git_time, build_type, build_flags, fp_contract, "
             "pgo, compiler, cpu, isa, cores, machine) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)",
             path_);
      s.text(1, now_utc());
      s.text(2, kind);
      s.text(3, command);
      s.text(4, jstr(m, "version"));
      s.text(5, jstr(m, "git_revision"));
      s.integer(6, m.is_object() && m.value("git_dirty", false) ? 1 : 0);
      s.text(7, jstr(m, "git_time"));
      s.text(8, jstr(m, "build_type"));
      s.text(9, jstr(m, "build_flags"));
      s.text(10, jstr(m, "fp_contract"));
      s.text(11, jstr(m, "pgo"));
      s.text(12, jstr(m, "compiler"));
      s.text(13, jstr(m, "cpu"));
      s.text(14, jstr(m, "host_simd"));
      s.integer(15, m.is_object() ? m.value("cores", 0) : 0);
      s.text(16, m.dump());
      if (sqlite3_step(s.s) != SQLITE_DONE) throw std::runtime_error(path_ + ": " + sqlite3_errmsg(db_));
    }
    const long long run = sqlite3_last_insert_rowid(db_);
    Stmt f(db_,
           "INSERT OR REPLACE INTO figures (run, section, name, metric, unit, scale, direction, timing, value, n, cv, samples) "
           "VALUES (?,?,?,?,?,?,?,?,?,?,?,?)",
           path_);
    for (const Figure& x : figures) {
      sqlite3_reset(f.s);
      f.integer(1, run);
      f.text(2, x.section);
      f.text(3, x.name);
      f.text(4, x.metric);
      f.text(5, x.unit);
      f.real(6, x.scale);
      f.integer(7, x.direction);
      f.integer(8, x.timing ? 1 : 0);
      f.real(9, x.value);
      f.integer(10, (long long)x.samples.size());
      f.real(11, stats::cv(x.samples));
      f.text(12, json(x.samples).dump());
      if (sqlite3_step(f.s) != SQLITE_DONE) throw std::runtime_error(path_ + ": " + sqlite3_errmsg(db_));
    }
    exec("COMMIT");
    return run;
  } catch (...) {
    sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::vector<History::Run> History::runs(const std::string& filter) const {
  std::map<long long, long long> matching;  // run -> figures whose name matches
  const bool filtered = !filter.empty();
  if (filtered) {
    const std::regex re = filter_regex(filter);
    Stmt q(db_, "SELECT run, section, name FROM figures", path_);
    while (sqlite3_step(q.s) == SQLITE_ROW)
      if (filter_matches(re, q.col_text(1) + "/" + q.col_text(2))) ++matching[sqlite3_column_int64(q.s, 0)];
  }
  std::vector<Run> out;
  Stmt q(db_,
         "SELECT id, time, kind, command, version, git_revision, git_dirty, git_time, build_type, build_flags, fp_contract, pgo, "
         "compiler, cpu, isa, cores, (SELECT COUNT(*) FROM figures WHERE run = runs.id) FROM runs ORDER BY id",
         path_);
  while (sqlite3_step(q.s) == SQLITE_ROW) {
    Run r;
    r.id = sqlite3_column_int64(q.s, 0);
    if (filtered && !matching.count(r.id)) continue;
    r.time = q.col_text(1);
    r.kind = q.col_text(2);
    r.command = q.col_text(3);
    r.version = q.col_text(4);
    r.git_revision = q.col_text(5);
    r.git_dirty = sqlite3_column_int(q.s, 6) != 0;
    r.git_time = q.col_text(7);
    r.build_type = q.col_text(8);
    r.build_flags = q.col_text(9);
    r.fp_contract = q.col_text(10);
    r.pgo = q.col_text(11);
    r.compiler = q.col_text(12);
    r.cpu = q.col_text(13);
    r.isa = q.col_text(14);
    r.cores = sqlite3_column_int(q.s, 15);
    r.figures = filtered ? matching[r.id] : sqlite3_column_int64(q.s, 16);
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<History::Point> History::series(const std::string& metric, const std::string& filter) const {
  std::vector<Point> out;
  const bool filtered = !filter.empty();
  std::regex re;
  if (filtered) re = filter_regex(filter);
  Stmt q(db_,
         "SELECT run, section, name, metric, unit, direction, timing, value, scale, cv, n FROM figures WHERE metric = ? "
         "ORDER BY run, section, name",
         path_);
  Stmt& s = q;
  s.text(1, metric);
  while (sqlite3_step(q.s) == SQLITE_ROW) {
    Point p;
    p.run = sqlite3_column_int64(q.s, 0);
    p.section = q.col_text(1);
    p.name = q.col_text(2);
    if (filtered && !filter_matches(re, p.section + "/" + p.name)) continue;
    p.metric = q.col_text(3);
    p.unit = q.col_text(4);
    p.direction = sqlite3_column_int(q.s, 5);
    p.timing = sqlite3_column_int(q.s, 6) != 0;
    p.value = sqlite3_column_type(q.s, 7) == SQLITE_NULL ? stats::kNaN : sqlite3_column_double(q.s, 7);
    p.scale = sqlite3_column_double(q.s, 8);
    p.cv = sqlite3_column_type(q.s, 9) == SQLITE_NULL ? stats::kNaN : sqlite3_column_double(q.s, 9);
    p.n = sqlite3_column_int64(q.s, 10);
    out.push_back(std::move(p));
  }
  return out;
}

ResultSet History::load_run(long long id) const {
  ResultSet r;
  {
    Stmt q(db_, "SELECT kind, machine FROM runs WHERE id = ?", path_);
    q.integer(1, id);
    if (sqlite3_step(q.s) != SQLITE_ROW) throw std::runtime_error(fmt::format("{}: no run {} (raybench history lists them)", path_, id));
    r.kind = q.col_text(0);
    r.machine = json::parse(q.col_text(1), nullptr, false);
    if (r.machine.is_discarded()) r.machine = nullptr;
  }
  r.source = fmt::format("{} run {}", path_, id);
  Stmt q(db_, "SELECT section, name, metric, unit, scale, direction, timing, value, samples FROM figures WHERE run = ? ORDER BY rowid", path_);
  q.integer(1, id);
  while (sqlite3_step(q.s) == SQLITE_ROW) {
    Figure f;
    f.section = q.col_text(0);
    f.name = q.col_text(1);
    f.metric = q.col_text(2);
    f.unit = q.col_text(3);
    f.scale = sqlite3_column_double(q.s, 4);
    f.direction = sqlite3_column_int(q.s, 5);
    f.timing = sqlite3_column_int(q.s, 6) != 0;
    f.value = sqlite3_column_type(q.s, 7) == SQLITE_NULL ? stats::kNaN : sqlite3_column_double(q.s, 7);
    const json samples = json::parse(q.col_text(8), nullptr, false);
    if (samples.is_array())
      for (const auto& x : samples)
        if (x.is_number()) f.samples.push_back(x.get<double>());
    f.judged = judged_metric(f.metric);
    r.figures.push_back(std::move(f));
  }
  return r;
}

std::vector<std::pair<std::string, long long>> History::metrics() const {
  std::vector<std::pair<std::string, long long>> out;
  Stmt q(db_, "SELECT metric, COUNT(*) FROM figures GROUP BY metric ORDER BY metric", path_);
  while (sqlite3_step(q.s) == SQLITE_ROW) out.push_back({q.col_text(0), sqlite3_column_int64(q.s, 1)});
  return out;
}

}  // namespace rb::app
