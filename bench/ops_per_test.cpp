// bench::ops_per_test: the benchmarks' operations per test, looked up by (kernel, method) in the
// table the families fill (bench/ops_<family>.cpp), computed once per (spec, case, variant) and
// remembered (Google Benchmark runs a benchmark's function once per repetition).
#include "bench/ops_detail.hpp"

#include <cstring>
#include <limits>
#include <map>
#include <mutex>
#include <tuple>

namespace rb::bench {

double ops_per_test(const char* kernel, const char* method, Case c, Variant v) {
  static const std::vector<opstable::OpsPerTest> table = [] {
    std::vector<opstable::OpsPerTest> t;
    opstable::add_basic_ops_per_test(t);
    opstable::add_planar_ops_per_test(t);
    opstable::add_quadric_ops_per_test(t);
    opstable::add_solver_ops_per_test(t);
    return t;
  }();
  static std::mutex mu;
  static std::map<std::tuple<std::string, std::string, int, int>, double> memo;
  const auto key = std::make_tuple(std::string(kernel), std::string(method), int(c), int(v));
  {
    const std::lock_guard<std::mutex> lock(mu);
    if (const auto it = memo.find(key); it != memo.end()) return it->second;
  }
  for (const auto& e : table)
    if (std::strcmp(e.kernel, kernel) == 0 && std::strcmp(e.method, method) == 0) {
      const double x = e.fn(c, v);
      const std::lock_guard<std::mutex> lock(mu);
      memo[key] = x;
      return x;
    }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace rb::bench
