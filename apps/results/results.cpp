#include "apps/results/results.hpp"

#include "apps/results/stats.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <sys/stat.h>

namespace rb::app {

using nlohmann::json;
namespace fs = std::filesystem;

json read_json_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw std::runtime_error(path + ": " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw std::runtime_error(path + ": " + std::strerror(EISDIR));
  std::ifstream f(path);
  if (!f) throw std::runtime_error(path + ": " + std::strerror(errno));
  std::stringstream ss;
  ss << f.rdbuf();
  return parse_json_text(ss.str(), path);
}

json parse_json_text(const std::string& raw, const std::string& name) {
  // Google Benchmark writes NaN and infinities as bare words, which JSON has not: null instead.
  const std::string text = std::regex_replace(raw, std::regex(R"(:\s*-?(NaN|nan|Infinity|inf)\b)"), ": null");
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    // nlohmann's message: "[json.exception.parse_error.101] parse error at line 3, column 5: ..."
    std::string what = e.what();
    const auto p = what.find("parse error");
    throw std::runtime_error(name + ": not JSON (" + (p == std::string::npos ? what : what.substr(p)) + ")");
  }
}

std::string result_kind(const json& j) {
  if (!j.is_object() && !j.is_array()) return "";
  if (j.is_object() && j.contains("benchmarks") && j["benchmarks"].is_array()) return "bench";
  if (j.is_object() && j.contains("ray_set") && j.contains("mrays_per_s")) return "trace";
  if (j.is_object() && j.contains("eye_rays") && j.contains("total_rays")) return "render";
  if (j.is_object() && j.contains("rows") && j["rows"].is_array() && j.contains("mode") &&
      (j["rows"].empty() || j["rows"][0].contains("false_hit_ppm")))
    return "accuracy";
  const json* rows = j.is_array() ? &j : (j.contains("rows") && j["rows"].is_array() ? &j["rows"] : nullptr);
  if (rows && !rows->empty() && (*rows)[0].is_object() && (*rows)[0].contains("simd8_queries_per_s")) return "csg";
  return "";
}

json machine_of(const json& doc) {
  if (doc.is_object() && doc.contains("machine")) return doc["machine"];
  return nullptr;
}

namespace {

double num(const json& j, const char* key) {
  if (!j.is_object()) return stats::kNaN;
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : stats::kNaN;
}
std::string str(const json& j, const char* key) {
  if (!j.is_object()) return "";
  const auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : "";
}

Figure fig(std::string section, std::string name, std::string metric, std::string unit, double scale, int direction, bool timing,
           double value, std::vector<double> samples = {}) {
  Figure f;
  f.section = std::move(section);
  f.name = std::move(name);
  f.metric = std::move(metric);
  f.unit = std::move(unit);
  f.scale = scale;
  f.direction = direction;
  f.timing = timing;
  f.samples = std::move(samples);
  f.value = f.samples.empty() ? value : stats::median(f.samples);
  f.judged = judged_metric(f.metric);
  return f;
}

// Google Benchmark JSON: every repetition of a benchmark (run_type "iteration") is a sample of its
// tests per second; a file of aggregates only gives the median alone.
void bench_figures(const json& doc, const std::string& section, std::vector<Figure>& out) {
  std::map<std::string, std::vector<double>> reps;
  std::map<std::string, double> med;
  std::map<std::string, std::string> time_unit;
  std::vector<std::string> order;
  const bool rates = [&] {
    for (const auto& b : doc["benchmarks"])
      if (b.contains("tests_per_s")) return true;
    return false;
  }();
  for (const auto& b : doc["benchmarks"]) {
    const std::string name = b.contains("run_name") ? str(b, "run_name") : str(b, "name");
    if (name.empty()) continue;
    if (!reps.count(name) && !med.count(name)) order.push_back(name);
    const double v = rates ? num(b, "tests_per_s") : num(b, "cpu_time");
    time_unit[name] = str(b, "time_unit");
    const std::string type = str(b, "run_type");
    if (type == "aggregate") {
      if (str(b, "aggregate_name") == "median") med[name] = v;
    } else if (std::isfinite(v)) {
      reps[name].push_back(v);
    }
  }
  for (const auto& name : order) {
    const auto it = reps.find(name);
    std::vector<double> s = it != reps.end() ? it->second : std::vector<double>{};
    const double v = med.count(name) ? med[name] : stats::kNaN;
    if (s.empty() && !std::isfinite(v)) continue;
    if (rates) out.push_back(fig(section, name, "tests_per_s", "Mtests/s", 1e-6, 1, true, v, s));
    else out.push_back(fig(section, name, "cpu_time", time_unit[name].empty() ? "time" : time_unit[name], 1, -1, true, v, s));
  }
}

std::string trace_row_name(const json& t) {
  std::string n = fmt::format("{} {} K={} T={}", str(t, "scene"), str(t, "ray_set"), t.value("packet", 0), t.value("threads", 0));
  const std::string model = str(t, "model"), slab = str(t, "slab");
  if (!model.empty() && model != "auto") n += " " + model;
  if (!slab.empty() && slab != "conservative") n += " " + slab;
  return n;
}

// Rays per second of each repetition, in Mrays/s, from its seconds.
std::vector<double> mrays(const json& t, const char* seconds_key) {
  std::vector<double> v;
  const double rays = num(t, "rays");
  if (!t.contains(seconds_key) || !t[seconds_key].is_array() || !std::isfinite(rays)) return v;
  for (const auto& s : t[seconds_key])
    if (s.is_number() && s.get<double>() > 0) v.push_back(rays / s.get<double>() / 1e6);
  return v;
}

void trace_figures(const json& t, const std::string& section, std::vector<Figure>& out) {
  const std::string n = trace_row_name(t);
  out.push_back(fig(section, n, "mrays_per_s", "Mrays/s", 1, 1, true, num(t, "mrays_per_s"), mrays(t, "seconds")));
  if (std::isfinite(num(t, "embree_mrays_per_s")))
    out.push_back(fig(section, n, "embree_mrays_per_s", "Mrays/s", 1, 1, true, num(t, "embree_mrays_per_s"), mrays(t, "embree_seconds")));
  if (std::isfinite(num(t, "build_ms"))) out.push_back(fig(section, n, "build_ms", "ms", 1, -1, true, num(t, "build_ms")));
  if (std::isfinite(num(t, "mismatch_rate"))) out.push_back(fig(section, n, "mismatch_rate", "%", 100, -1, false, num(t, "mismatch_rate")));
  if (std::isfinite(num(t, "box_tests_per_ray")))
    out.push_back(fig(section, n, "box_tests_per_ray", "tests/ray", 1, -1, false, num(t, "box_tests_per_ray")));
  if (std::isfinite(num(t, "prim_tests_per_ray")))
    out.push_back(fig(section, n, "prim_tests_per_ray", "tests/ray", 1, -1, false, num(t, "prim_tests_per_ray")));
}

void render_figures(const json& r, const std::string& section, std::vector<Figure>& out) {
  const std::string n = fmt::format("{} {}x{} depth {}{} T={}", str(r, "scene"), r.value("width", 0), r.value("height", 0),
                                    r.value("depth", 0), r.value("spd", false) ? " spd" : "", r.value("threads", 0));
  std::vector<double> s;
  const double rays = num(r, "total_rays");
  if (r.contains("trace_seconds") && r["trace_seconds"].is_array())
    for (const auto& x : r["trace_seconds"])
      if (x.is_number() && x.get<double>() > 0) s.push_back(rays / x.get<double>() / 1e6);
  out.push_back(fig(section, n, "mrays_per_s", "Mrays/s", 1, 1, true, num(r, "mrays_per_s"), s));
  if (std::isfinite(num(r, "build_ms"))) out.push_back(fig(section, n, "build_ms", "ms", 1, -1, true, num(r, "build_ms")));
  if (std::isfinite(rays)) out.push_back(fig(section, n, "total_rays", "rays", 1, 0, false, rays));
  // The test counts follow the packet sizes, which a render may choose by timing trial renders: a
  // count pairs only with a run that traced in the same packets.
  // (A record without the eye rays' shadow packet traced them as the other secondary rays.)
  if (r.value("tests_counted", false) && std::isfinite(num(r, "box_tests"))) {
    const int sec = r.value("secondary_packet", 0), esh = r.value("eye_shadow_packet", sec);
    const std::string sizes = esh == sec ? fmt::format("{}/{}", r.value("eye_packet", 0), sec)
                                         : fmt::format("{}/{}/{}", r.value("eye_packet", 0), esh, sec);
    out.push_back(fig(section, fmt::format("{} packets {}", n, sizes), "box_tests", "tests", 1, -1, false, num(r, "box_tests")));
  }
}

void accuracy_figures(const json& rows, const std::string& section, std::vector<Figure>& out) {
  struct M { const char* key; const char* unit; };
  static const M kDet[] = {{"false_hit_ppm", "ppm"}, {"false_miss_ppm", "ppm"}, {"leak_ppm", "ppm"},
                           {"self_hit_ppm", "ppm"}, {"t_err_ulp_p99", "ulp"}};
  for (const auto& r : rows) {
    const std::string n = fmt::format("{}/{} {} {}", str(r, "family"), str(r, "case"), str(r, "method"), str(r, "precision"));
    for (const M& m : kDet)
      if (std::isfinite(num(r, m.key))) out.push_back(fig(section, n, m.key, m.unit, 1, -1, false, num(r, m.key)));
    if (std::isfinite(num(r, "ns_per_test"))) out.push_back(fig(section, n, "ns_per_test", "ns/test", 1, -1, true, num(r, "ns_per_test")));
  }
}

void csg_figures(const json& rows, const std::string& section, std::vector<Figure>& out) {
  for (const auto& r : rows) {
    const std::string n = str(r, "scene");
    for (const char* k : {"scalar_queries_per_s", "simd8_queries_per_s", "camera_scalar_queries_per_s", "camera_simd8_queries_per_s"})
      if (std::isfinite(num(r, k))) out.push_back(fig(section, n, k, "Mq/s", 1e-6, 1, true, num(r, k)));
  }
}

json config_of(const std::string& kind, const json& doc) {
  json c = json::object();
  if (kind == "accuracy") {
    for (const char* k : {"mode", "seed", "rays", "filter"})
      if (doc.contains(k)) c[k] = doc[k];
  } else if (kind == "trace" || kind == "render") {
    for (const char* k : {"scene", "rays", "ray_set", "seed", "threads", "packet", "model", "slab", "repetitions", "warmup", "width", "height", "tile", "secondary_order"})
      if (doc.contains(k)) c[k] = doc[k];
  } else if (kind == "bench" && doc.contains("context")) {
    for (const char* k : {"raybench_seed", "raybench_repetitions"})
      if (doc["context"].contains(k)) c[k] = doc["context"][k];
  }
  return c;
}

}  // namespace

bool judged_metric(const std::string& metric) { return metric.rfind("embree_", 0) != 0 && metric != "build_ms"; }

ResultSet figures_of(const std::string& kind, const json& doc) {
  ResultSet r;
  r.kind = kind;
  r.machine = machine_of(doc);
  r.config = config_of(kind, doc);
  if (kind == "bench") bench_figures(doc, kind, r.figures);
  else if (kind == "trace") trace_figures(doc, kind, r.figures);
  else if (kind == "render") render_figures(doc, kind, r.figures);
  else if (kind == "accuracy") accuracy_figures(doc["rows"], kind, r.figures);
  else if (kind == "csg") csg_figures(doc.is_array() ? doc : doc["rows"], kind, r.figures);
  else throw std::runtime_error("not a raybench result (bench, trace, render, accuracy, csg or a report folder)");
  return r;
}

ResultSet load_results(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw std::runtime_error(path + ": " + std::strerror(errno));
  if (!S_ISDIR(st.st_mode)) {
    const json doc = read_json_file(path);
    const std::string kind = result_kind(doc);
    if (kind.empty())
      throw std::runtime_error(path + ": not a raybench result (a JSON file of bench, trace, render, accuracy or csg, or a report folder)");
    ResultSet r = figures_of(kind, doc);
    r.source = path;
    return r;
  }
  // A report folder: summary.json says it is one.
  const fs::path dir(path);
  if (!fs::exists(dir / "summary.json")) throw std::runtime_error(path + ": a folder without summary.json (not a report folder)");
  ResultSet r;
  r.kind = "report";
  r.source = path;
  const json summary = read_json_file((dir / "summary.json").string());
  r.machine = machine_of(summary);
  if (summary.contains("goals") && summary["goals"].is_array()) r.goals = summary["goals"];
  auto add = [&](const ResultSet& part) { r.figures.insert(r.figures.end(), part.figures.begin(), part.figures.end()); };
  if (fs::exists(dir / "bench.json")) add(figures_of("bench", read_json_file((dir / "bench.json").string())));
  if (fs::exists(dir / "tracing.json")) {
    const json t = read_json_file((dir / "tracing.json").string());
    for (const char* key : {"matrix", "bunny"})  // "bunny": reports written before the matrix
      if (t.contains(key))
        for (const auto& row : t[key]) trace_figures(row, "trace", r.figures);
    if (t.contains("by_size"))
      for (const auto& row : t["by_size"]) {
        const std::string n = str(row, "scene");
        for (const char* k : {"ns_per_ray", "embree_ns_per_ray", "build_ms", "embree_build_ms"})
          if (std::isfinite(num(row, k)))
            r.figures.push_back(fig("trace", n, k, std::string(k).find("ns_") != std::string::npos ? "ns/ray" : "ms", 1, -1, true, num(row, k)));
      }
  }
  if (summary.contains("render"))
    for (const auto& row : summary["render"]) render_figures(row, "render", r.figures);
  if (fs::exists(dir / "accuracy.json")) {
    const json a = read_json_file((dir / "accuracy.json").string());
    if (a.contains("rows")) accuracy_figures(a["rows"], "accuracy", r.figures);
    r.config["accuracy"] = config_of("accuracy", a);
  }
  if (fs::exists(dir / "csg.json")) csg_figures(read_json_file((dir / "csg.json").string()), "csg", r.figures);
  if (summary.contains("scenes"))
    for (const auto& row : summary["scenes"])
      if (std::isfinite(num(row, "median_ms"))) r.figures.push_back(fig("scenes", str(row, "source"), "median_ms", "ms", 1, -1, true, num(row, "median_ms")));
  return r;
}

}  // namespace rb::app
