// "Did you mean ...?" for a mistyped name: the known name nearest to it by edit distance (letters
// inserted, deleted, replaced or two neighbours swapped), when it is near enough to be a likely
// typo. Used by the command line (commands, options, option values), the scene names and the
// JSON scene format's keys.
#pragma once

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

namespace rb {

// Optimal string alignment distance (insertions, deletions, substitutions, adjacent swaps).
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::size_t> prev2(m + 1), prev(m + 1), cur(m + 1);
  for (std::size_t j = 0; j <= m; ++j) prev[j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= m; ++j) {
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) cur[j] = std::min(cur[j], prev2[j - 2] + 1);
    }
    prev2.swap(prev);
    prev.swap(cur);
  }
  return prev[m];
}

// The name of `names` closest to `word` (the first of equally close ones), or "" when none is
// close enough to be a likely typo: distance at most 1 for words of up to 4 letters, 2 up to 8,
// 3 beyond.
inline std::string closest_name(std::string_view word, const std::vector<std::string>& names) {
  const std::size_t limit = word.size() <= 4 ? 1 : word.size() <= 8 ? 2 : 3;
  std::string best;
  std::size_t best_d = limit + 1;
  for (const auto& n : names) {
    const std::size_t d = edit_distance(word, n);
    if (d < best_d) best_d = d, best = n;
  }
  return best;
}

// "; did you mean 'NAME'?" for the closest name, or nothing: the end of an error message.
inline std::string did_you_mean(std::string_view word, const std::vector<std::string>& names) {
  const std::string n = closest_name(word, names);
  return n.empty() ? std::string() : "; did you mean '" + n + "'?";
}

}  // namespace rb
