#include "apps/results/stats.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>
#include <numeric>

namespace rb::stats {

double mean(const std::vector<double>& v) {
  if (v.empty()) return kNaN;
  return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

double stddev(const std::vector<double>& v) {
  if (v.size() < 2) return kNaN;
  const double m = mean(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / double(v.size() - 1));
}

double cv(const std::vector<double>& v) {
  const double m = mean(v);
  if (v.size() < 2 || m == 0) return kNaN;
  return stddev(v) / std::fabs(m);
}

double geometric_mean(const std::vector<double>& v) {
  double s = 0;
  std::size_t n = 0;
  for (double x : v)
    if (std::isfinite(x) && x > 0) s += std::log(x), ++n;
  return n ? std::exp(s / double(n)) : kNaN;
}

Summary summarize(const std::vector<double>& v) {
  Summary s;
  s.n = v.size();
  if (v.empty()) return s;
  s.median = median(v);
  s.min = *std::min_element(v.begin(), v.end());
  s.max = *std::max_element(v.begin(), v.end());
  s.cv = cv(v);
  return s;
}

std::vector<std::size_t> tukey_outliers(const std::vector<double>& v) {
  std::vector<std::size_t> out;
  if (v.size() < 4) return out;
  std::vector<double> s = v;
  std::sort(s.begin(), s.end());
  auto quantile = [&](double q) {
    const double x = q * double(s.size() - 1);
    const std::size_t i = std::size_t(x);
    return i + 1 < s.size() ? s[i] + (x - double(i)) * (s[i + 1] - s[i]) : s[i];
  };
  const double q1 = quantile(0.25), q3 = quantile(0.75), fence = q3 + 1.5 * (q3 - q1);
  for (std::size_t i = 0; i < v.size(); ++i)
    if (v[i] > fence) out.push_back(i);
  return out;
}

namespace {

// P(U' >= u) for the null distribution of the Mann-Whitney U of samples of sizes m and n (no
// ties): the number of orderings of m x's and n y's with exactly k pairs (x, y) in which x
// follows y, over all C(m + n, m) orderings. Recurrence on the last element of the ordering:
// c(k; i, j) = c(k - j; i - 1, j) (an x, after all j y's) + c(k; i, j - 1) (a y). Only additions,
// so doubles hold the counts with relative rounding error alone.
// The counts c(k), k = 0 .. m n, of the orderings with U = k.
std::vector<double> u_counts(std::size_t m, std::size_t n) {
  if (m > n) std::swap(m, n);  // the distribution is symmetric in the sample sizes
  const std::size_t kmax = m * n;
  // c[i][k] for the current j, i = 0..m.
  std::vector<std::vector<double>> c(m + 1, std::vector<double>(kmax + 1, 0.0));
  for (std::size_t i = 0; i <= m; ++i) c[i][0] = 1;  // j = 0: one ordering, k = 0
  for (std::size_t j = 1; j <= n; ++j)
    // c(k; 0, j) = [k == 0] stays; i increasing, so c[i - 1] already holds column j, while c[i]
    // still holds c(k; i, j - 1).
    for (std::size_t i = 1; i <= m; ++i)
      for (std::size_t k = j; k <= kmax; ++k) c[i][k] += c[i - 1][k - j];
  return c[m];
}

double u_sf(double u, std::size_t m, std::size_t n) {
  const std::vector<double> f = u_counts(m, n);
  const std::size_t kmax = f.size() - 1;
  double total = 0, tail = 0;
  for (std::size_t k = 0; k <= kmax; ++k) {
    total += f[k];
    if (double(k) >= u) tail += f[k];
  }
  return tail / total;
}

}  // namespace

UTest mann_whitney_u(const std::vector<double>& a, const std::vector<double>& b) {
  UTest r;
  const std::size_t n1 = a.size(), n2 = b.size(), n = n1 + n2;
  if (!n1 || !n2) return r;
  // Midranks of the pooled samples (ties share the mean of their ranks) and the tie term.
  std::vector<std::pair<double, int>> all;
  all.reserve(n);
  for (double x : a) all.push_back({x, 0});
  for (double x : b) all.push_back({x, 1});
  std::sort(all.begin(), all.end(), [](const auto& p, const auto& q) { return p.first < q.first; });
  double r1 = 0, tie_term = 0;
  bool ties = false;
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i;
    while (j < n && all[j].first == all[i].first) ++j;
    const double t = double(j - i), rank = 0.5 * (double(i + 1) + double(j));  // ranks i+1 .. j
    if (t > 1) ties = true, tie_term += t * t * t - t;
    for (std::size_t k = i; k < j; ++k)
      if (all[k].second == 0) r1 += rank;
    i = j;
  }
  const double dn1 = double(n1), dn2 = double(n2), dn = double(n);
  r.u1 = r1 - dn1 * (dn1 + 1) / 2;
  r.u = std::max(r.u1, dn1 * dn2 - r.u1);
  double p;
  if ((n1 <= 8 || n2 <= 8) && !ties) {
    r.exact = true;
    p = 2 * u_sf(r.u, n1, n2);
  } else {
    const double mu = dn1 * dn2 / 2;
    const double s = std::sqrt(dn1 * dn2 / 12 * ((dn + 1) - tie_term / (dn * (dn - 1))));
    const double num = r.u - mu - 0.5;
    // All values tied (s = 0): numerator -0.5 / 0 is -inf, P(Z >= -inf) = 1.
    const double z = s > 0 ? num / s : -std::numeric_limits<double>::infinity();
    p = std::erfc(z / std::sqrt(2.0));  // 2 P(Z >= z)
  }
  r.p = std::clamp(p, 0.0, 1.0);
  return r;
}


RatioInterval paired_ratio(const std::vector<double>& a, const std::vector<double>& b, double level) {
  RatioInterval r;
  std::vector<double> q;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    if (a[i] > 0 && b[i] > 0 && std::isfinite(a[i]) && std::isfinite(b[i])) q.push_back(a[i] / b[i]);
  r.n = q.size();
  if (q.empty()) return r;
  std::sort(q.begin(), q.end());
  r.ratio = median(q);
  if (q.size() < 2) return r;
  // P(Binomial(n, 1/2) < k) for k = 1, 2, ...: the largest k whose tail stays within (1 - level) / 2.
  const std::size_t n = q.size();
  const double alpha2 = (1 - level) / 2;
  double tail = 0, c = 1;  // c = C(n, j)
  const double p_one = std::ldexp(1.0, -int(std::min<std::size_t>(n, 1000)));
  std::size_t k = 0;
  for (std::size_t j = 0; j < n / 2; ++j) {
    const double next = tail + c * p_one;  // P(X <= j) = P(X < j + 1)
    if (next > alpha2) break;
    tail = next;
    k = j + 1;
    c = c * double(n - j) / double(j + 1);
  }
  if (k == 0) {  // too few rounds for the level: the whole range, with what it holds
    r.lo = q.front(), r.hi = q.back();
    r.coverage = 1 - 2 * p_one;
  } else {
    r.lo = q[k - 1], r.hi = q[n - k];
    r.coverage = 1 - 2 * tail;
  }
  return r;
}

double half_width(const RatioInterval& r) { return r.valid() && r.ratio > 0 ? (r.hi - r.lo) / 2 / r.ratio : kNaN; }

bool too_wide(const RatioInterval& r, double precision) { return r.valid() && !(half_width(r) <= precision); }

RatioInterval unpaired_ratio(const std::vector<double>& a, const std::vector<double>& b, double level) {
  RatioInterval r;
  r.paired = false;
  auto positive = [](const std::vector<double>& v) {
    std::vector<double> p;
    for (double x : v)
      if (x > 0 && std::isfinite(x)) p.push_back(x);
    return p;
  };
  const std::vector<double> pa = positive(a), pb = positive(b);
  r.n = std::min(pa.size(), pb.size());
  if (pa.empty() || pb.empty()) return r;
  r.ratio = median(pa) / median(pb);
  if (pa.size() < 2 || pb.size() < 2) return r;
  std::vector<double> q;
  for (double x : pa)
    for (double y : pb) q.push_back(x / y);
  std::sort(q.begin(), q.end());
  // P(U <= j) from the exact null distribution; the largest k (at least 1) with P(U <= k - 1) within
  // (1 - level) / 2.
  const std::vector<double> f = u_counts(pa.size(), pb.size());
  double total = 0;
  for (double c : f) total += c;
  const double alpha2 = (1 - level) / 2;
  double below = f[0] / total;  // P(U <= k - 1) for k = 1
  std::size_t k = 1;
  while (k < q.size() / 2 && below + f[k] / total <= alpha2) below += f[k++] / total;
  r.lo = q[k - 1], r.hi = q[q.size() - k];
  r.coverage = 1 - 2 * below;  // below the level when even the range (k = 1) has P(U <= 0) beyond alpha2
  return r;
}

Verdict verdict(const RatioInterval& r, double target) {
  if (!r.valid()) return Verdict::not_measured;
  if (r.lo >= target) return Verdict::met;
  if (r.hi < target) return Verdict::not_met;
  return Verdict::undecided;
}

nlohmann::json interval_json(const RatioInterval& r) {
  auto num = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  return {{"ratio", num(r.ratio)}, {"lo", num(r.lo)}, {"hi", num(r.hi)}, {"coverage", num(r.coverage)}, {"rounds", r.n},
          {"method", r.paired ? "median of the per-round ratios of paired rounds; distribution-free interval (order statistics, as the sign test)"
                              : "ratio of the medians of two unpaired samples; distribution-free interval (the Mann-Whitney test inverted on "
                                "log values, Hodges-Lehmann)"}};
}

RatioInterval interval_from_json(const nlohmann::json& j) {
  RatioInterval r;
  if (!j.is_object()) return r;
  auto num = [&](const char* k) { return j.contains(k) && j[k].is_number() ? j[k].get<double>() : kNaN; };
  r.ratio = num("ratio"), r.lo = num("lo"), r.hi = num("hi"), r.coverage = num("coverage");
  r.n = j.contains("rounds") && j["rounds"].is_number_unsigned() ? j["rounds"].get<std::size_t>() : 0;
  return r;
}

std::string interval_text(const RatioInterval& r, const char* unit) {
  char buf[128];
  if (!std::isfinite(r.ratio)) return "-";
  if (!r.valid()) {
    std::snprintf(buf, sizeof buf, "%.2f%s", r.ratio, unit);
    return buf;
  }
  if (r.coverage < 0.95)
    std::snprintf(buf, sizeof buf, "%.2f%s [range of %zu: %.2f-%.2f]", r.ratio, unit, r.n, r.lo, r.hi);
  else
    std::snprintf(buf, sizeof buf, "%.2f%s [%.2f-%.2f]", r.ratio, unit, r.lo, r.hi);
  return buf;
}

}  // namespace rb::stats
