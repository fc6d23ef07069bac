#include "accuracy/common.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rb::acc {

namespace {
double pct(std::vector<double>& v, double p) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t k = std::min(v.size() - 1, std::size_t(p * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}
// One unit in the last place of x in the method's precision (eps = its machine epsilon).
double ulp_at(long double x, double eps) {
  const double ax = std::fabs(double(x));
  if (eps > 1e-10) {  // float
    const float f = float(ax);
    return double(std::nextafter(f, std::numeric_limits<float>::infinity()) - f);
  }
  return std::nextafter(ax, std::numeric_limits<double>::infinity()) - ax;
}
}  // namespace

Row tally(const std::string& family, const std::string& method, const std::string& precision, const std::string& case_name,
          const std::string& what, std::size_t rays, const std::vector<Ref>& ref, const std::vector<Out>& out, double eps,
          bool one_to_one, const std::vector<std::uint8_t>& must_hit, bool wrong_roots) {
  Row r;
  r.family = family, r.method = method, r.precision = precision, r.case_name = case_name, r.what = what;
  r.rays = rays, r.tests = ref.size();
  std::vector<double> ulps, scaled;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    const Ref& f = ref[k];
    const Out& m = out[k];
    if (m.hit && !std::isfinite(m.t)) ++r.nans;
    if (f.cls == Cls::miss && m.hit) ++r.false_hits;
    if (f.cls == Cls::hit && !m.hit) ++r.false_misses;
    if (m.hit && f.has_t && std::isfinite(m.t)) {
      const long double dt = std::fabs((long double)m.t - f.t);
      const double u = double(dt) / ulp_at(f.t, eps);
      const double sc = double(dt) / (eps * f.scale);
      // A wrong root: nearer the next root than the first (when the case knows the next root), else
      // farther than 1e3 scale-normalised units from the first.
      if (wrong_roots && (f.has_next ? std::fabs((long double)m.t - f.t_next) < dt : sc > 1e3)) ++r.wrong_roots;
      ulps.push_back(u);
      scaled.push_back(sc);
    }
  }
  const double n = std::max<double>(1.0, double(ref.size()));
  r.false_hit_ppm = 1e6 * double(r.false_hits) / n;
  r.false_miss_ppm = 1e6 * double(r.false_misses) / n;
  r.nan_ppm = 1e6 * double(r.nans) / n;
  r.wrong_root_ppm = wrong_roots ? 1e6 * double(r.wrong_roots) / n : std::numeric_limits<double>::quiet_NaN();
  r.t_err_ulp_p50 = pct(ulps, 0.5);
  r.t_err_ulp_p99 = pct(ulps, 0.99);
  r.t_err_ulp_max = ulps.empty() ? std::numeric_limits<double>::quiet_NaN() : *std::max_element(ulps.begin(), ulps.end());
  r.scaled_err_p99 = pct(scaled, 0.99);
  r.self_hit_ppm = std::numeric_limits<double>::quiet_NaN();
  r.leak_ppm = r.multi_hit_ppm = std::numeric_limits<double>::quiet_NaN();
  if (!one_to_one && !must_hit.empty()) {
    std::size_t leaks = 0, multi = 0, crossing = 0;
    const std::size_t np = ref.size() / rays;
    for (std::size_t i = 0; i < rays; ++i) {
      std::size_t hits = 0, exact = 0;
      for (std::size_t j = 0; j < np; ++j) {
        hits += out[j * rays + i].hit;
        exact += ref[j * rays + i].cls != Cls::miss;
      }
      if (must_hit[i]) {
        ++crossing;
        leaks += hits == 0;
      }
      multi += hits > std::max<std::size_t>(exact, 1);
    }
    r.leaks = leaks;
    r.leak_ppm = 1e6 * double(leaks) / double(std::max<std::size_t>(crossing, 1));
    r.multi_hit_ppm = 1e6 * double(multi) / double(std::max<std::size_t>(rays, 1));
  }
  return r;
}

nlohmann::json Row::json() const {
  auto v = [](double x) -> nlohmann::json { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  nlohmann::json j = {{"family", family}, {"method", method}, {"precision", precision}, {"case", case_name}, {"rays", rays}, {"tests", tests},
          {"false_hit_ppm", v(false_hit_ppm)}, {"false_miss_ppm", v(false_miss_ppm)}, {"leak_ppm", v(leak_ppm)},
          {"multi_hit_ppm", v(multi_hit_ppm)}, {"nan_ppm", v(nan_ppm)}, {"wrong_root_ppm", v(wrong_root_ppm)},
          {"t_err_ulp_p50", v(t_err_ulp_p50)}, {"t_err_ulp_p99", v(t_err_ulp_p99)}, {"t_err_ulp_max", v(t_err_ulp_max)},
          {"scaled_err_p99", v(scaled_err_p99)}, {"self_hit_ppm", v(self_hit_ppm)}, {"iterations", v(iterations)},
          {"ns_per_test", v(ns_per_test)}, {"failure_ppm", v(failure_ppm())}};
  if (!round_seconds.empty()) j["round_seconds"] = round_seconds;
  j["counts"] = {{"false_hits", false_hits}, {"false_misses", false_misses}, {"leaks", leaks}, {"self_hits", self_hits}, {"nans", nans},
                 {"wrong_roots", wrong_roots}};
  return j;
}

Row Row::from_json(const nlohmann::json& j) {
  auto v = [&](const char* k) { return j.contains(k) && j[k].is_number() ? j[k].get<double>() : std::numeric_limits<double>::quiet_NaN(); };
  Row r;
  r.family = j.at("family").get<std::string>(), r.method = j.at("method").get<std::string>();
  r.precision = j.at("precision").get<std::string>(), r.case_name = j.at("case").get<std::string>();
  r.rays = j.value("rays", std::size_t(0)), r.tests = j.value("tests", std::size_t(0));
  r.false_hit_ppm = v("false_hit_ppm"), r.false_miss_ppm = v("false_miss_ppm"), r.leak_ppm = v("leak_ppm");
  r.multi_hit_ppm = v("multi_hit_ppm"), r.nan_ppm = v("nan_ppm"), r.wrong_root_ppm = v("wrong_root_ppm");
  r.t_err_ulp_p50 = v("t_err_ulp_p50"), r.t_err_ulp_p99 = v("t_err_ulp_p99"), r.t_err_ulp_max = v("t_err_ulp_max");
  r.scaled_err_p99 = v("scaled_err_p99"), r.self_hit_ppm = v("self_hit_ppm"), r.iterations = v("iterations");
  r.ns_per_test = v("ns_per_test");
  if (j.contains("round_seconds")) r.round_seconds = j["round_seconds"].get<std::vector<double>>();
  if (j.contains("counts")) {
    const nlohmann::json& c = j["counts"];
    r.false_hits = c.value("false_hits", std::size_t(0)), r.false_misses = c.value("false_misses", std::size_t(0));
    r.leaks = c.value("leaks", std::size_t(0)), r.self_hits = c.value("self_hits", std::size_t(0));
    r.nans = c.value("nans", std::size_t(0)), r.wrong_roots = c.value("wrong_roots", std::size_t(0));
  }
  return r;
}

double Row::failure_ppm() const {
  auto z = [](double x) { return std::isfinite(x) ? x : 0.0; };
  // A closed mesh: the failure is a leak (or a wrong, farther hit). Which of two faces sharing an
  // edge a ray within rounding of the edge hits is arbitrary for every float method; that one
  // of them is hit is what must hold.
  if (std::isfinite(leak_ppm)) return leak_ppm + z(nan_ppm) + z(wrong_root_ppm);
  return z(false_hit_ppm) + z(false_miss_ppm) + z(self_hit_ppm) + z(nan_ppm) + z(wrong_root_ppm);
}

}  // namespace rb::acc
