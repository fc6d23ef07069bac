// Statistics of repeated measurements: median, range, coefficient of variation, geometric mean,
// the Mann-Whitney U test, and the ratio intervals built on it and on the sign test.
#pragma once

#include "core/median.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace rb::stats {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using rb::median;  // core/median.hpp: NaN when empty
double mean(const std::vector<double>& v);            // NaN when empty
double stddev(const std::vector<double>& v);          // sample standard deviation (n - 1); NaN for n < 2
double cv(const std::vector<double>& v);              // stddev / mean; NaN for n < 2 or a zero mean
double geometric_mean(const std::vector<double>& v);  // of the positive finite values; NaN when there are none

struct Summary {
  std::size_t n = 0;
  double median = kNaN, min = kNaN, max = kNaN, cv = kNaN;
};
Summary summarize(const std::vector<double>& v);
// The indices of the values above Tukey's upper fence, Q3 + 1.5 (Q3 - Q1) (quartiles by linear
// interpolation): the runs a busy moment slowed, reported beside the median (which they barely
// move), never dropped. Fewer than 4 values: none.
std::vector<std::size_t> tukey_outliers(const std::vector<double>& v);

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

// A ratio measured in paired rounds (round i timed both sides back to back, so that a change of the
// machine's load falls on both): the median of the per-round ratios a_i / b_i with its
// distribution-free confidence interval, the order statistics r_(k) and r_(n+1-k) of the sorted
// ratios for the largest k with P(Binomial(n, 1/2) < k) <= (1 - level) / 2: the sign test's
// interval for a median, exact for any continuous distribution of the ratios. `coverage` is the
// interval's own confidence, 1 - 2 P(Binomial(n, 1/2) < k), at least `level` from 6 rounds on
// (96.9 % at 6); with 2..5 rounds no k reaches it, the interval is [min, max] and `coverage` says
// what that holds (93.75 % at 5). Pairs with a non-positive or non-finite side are dropped.
struct RatioInterval {
  std::size_t n = 0;  // rounds used (unpaired: the smaller sample's size)
  double ratio = kNaN, lo = kNaN, hi = kNaN, coverage = kNaN;
  bool paired = true;  // false: unpaired_ratio's
  bool valid() const { return n >= 2 && std::isfinite(lo) && std::isfinite(hi); }
};
RatioInterval paired_ratio(const std::vector<double>& a, const std::vector<double>& b, double level = 0.95);

// A ratio of two samples measured apart (not in paired rounds): median(a) / median(b), and the
// distribution-free confidence interval for the factor between the two distributions obtained by
// inverting the Mann-Whitney test on logarithms (the Hodges-Lehmann interval): every ratio a_i / b_j
// sorted, r_(k) and r_(N+1-k), N = n1 n2, for the largest k with P(U < k) <= (1 - level) / 2 under
// the exact null distribution of U; `coverage` = 1 - 2 P(U < k) (7 and 7 values: k = 9, 96.2 %).
// Exact when b's distribution is a's scaled by a factor; the load drifts that paired rounds cancel
// widen it instead. Below the level (2 and 2 values), the range of the ratios and what it holds.
RatioInterval unpaired_ratio(const std::vector<double>& a, const std::vector<double>& b, double level = 0.95);

// As JSON: {"ratio", "lo", "hi", "coverage", "rounds", "method"} (null figures where there are none),
// and back (a missing or null object gives an interval that is not valid).
nlohmann::json interval_json(const RatioInterval& r);
RatioInterval interval_from_json(const nlohmann::json& j);
// "1.12x [1.08-1.15]" ("1.12x [range of 5: 1.05-1.18]" below the level's rounds; "-" when none);
// `unit` replaces the "x" of a ratio (a rate's median over rounds: " G/s").
std::string interval_text(const RatioInterval& r, const char* unit = "x");

// A goal on a ratio: met when the whole interval clears the target (lo >= target), not met when
// it lies below (hi < target), undecided when it straddles it; not measured without an interval.
enum class Verdict { met, not_met, undecided, not_measured };
Verdict verdict(const RatioInterval& r, double target);

// An interval's half-width relative to its ratio, (hi - lo) / 2 / ratio (NaN without an interval),
// and whether it is wider than `precision` (0.05: +-5 %): the rule by which `bench` gives a ratio's
// rows more rounds (apps/bench_run.cpp, --extra-rounds). Extending only the wide rows is a
// sequential rule, which costs about a point of the stated coverage (Stats.ExtraRoundsKeepCoverage
// measures it on a synthetic workload).
double half_width(const RatioInterval& r);
bool too_wide(const RatioInterval& r, double precision);


}  // namespace rb::stats
