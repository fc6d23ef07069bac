// The median of repeated measurements (the mean of the middle two for an even count; NaN for
// none): the one definition every figure quoted as a median uses.
#pragma once

#include <algorithm>
#include <limits>
#include <vector>

namespace rb {

inline double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace rb
