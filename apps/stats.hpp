// Statistics of repeated measurements: median, range, coefficient of variation, geometric mean,
// and the Mann-Whitney U test that `raybench compare` applies to two sets of repetitions.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

namespace rb::stats {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double median(std::vector<double> v);                 // NaN when empty
double mean(const std::vector<double>& v);            // NaN when empty
double stddev(const std::vector<double>& v);          // sample standard deviation (n - 1); NaN for n < 2
double cv(const std::vector<double>& v);              // stddev / mean; NaN for n < 2 or a zero mean
double geometric_mean(const std::vector<double>& v);  // of the positive finite values; NaN when there are none

struct Summary {
  std::size_t n = 0;
  double median = kNaN, min = kNaN, max = kNaN, cv = kNaN;
};
Summary summarize(const std::vector<double>& v);

// Two-sided Mann-Whitney U test of the samples a and b, computed as SciPy's
// scipy.stats.mannwhitneyu(a, b, alternative="two-sided") with its defaults (method "auto",
// continuity correction), which Google Benchmark's compare.py reports:
//   U1 = R1 - n1 (n1 + 1) / 2 from the midranks of the pooled samples, U = max(U1, n1 n2 - U1);
//   exact when n1 <= 8 or n2 <= 8 and no value is tied: p = 2 P(U' >= U) under the null
//   distribution of U (every ordering of the pooled samples equally likely);
//   otherwise the normal approximation with tie correction and continuity correction:
//   z = (U - n1 n2 / 2 - 0.5) / sqrt(n1 n2 / 12 ((n + 1) - sum(t^3 - t) / (n (n - 1)))), p = 2 P(Z >= z).
// p is clipped to [0, 1]. Empty samples give NaN.
struct UTest {
  double u = kNaN;  // max(U1, U2)
  double u1 = kNaN;  // U of the first sample
  double p = kNaN;
  bool exact = false;
};
UTest mann_whitney_u(const std::vector<double>& a, const std::vector<double>& b);

// The smallest two-sided p-value the test can give for samples of sizes n1 and n2 without ties
// (every value of one sample above every value of the other): with 3 and 3 repetitions it is 0.1,
// so no difference can reach p < 0.05.
double smallest_p(std::size_t n1, std::size_t n2);

}  // namespace rb::stats
