// The operations table: for every kernel and method, the lecture's counts (where the slides
// give them) next to the counts Counted<float> measures on a ray that hits and a ray that
// misses, and the per-lane count of the 8-lane SIMD instantiation.
#pragma once

#include "core/counted.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rb::opstable {

// A slide's count: +- (add), * (mul), / (div), comparisons (< and <=), sqrt.
struct Lecture {
  int add = 0, mul = 0, div = 0, cmp = 0, sqrt = 0;
};

struct Row {
  std::string kernel, method, kase;   // kase: "hit" or "miss"
  std::string number;                 // "float" or "simd8"
  std::optional<Lecture> lecture;
  OpCounts measured;                  // simd8: a packet whose other lanes take the other case
  std::optional<OpCounts> uniform;    // simd8: a packet whose lanes all take this case
  std::string note;                   // why measured differs from the lecture (or what it counts)
  bool note_sums = false;             // the counts in the note add up to the float row
  // Iterative solvers: loop trips per ray (mean, max) over the spec's rays, scalar float.
  std::optional<std::pair<double, double>> iterations;
};

// Every row, measured now.
std::vector<Row> build();

// Differences measured - lecture on the five lecture kinds (FMA counted as 1 mul + 1 add).
struct Diff {
  long add, mul, div, cmp, sqrt;
  bool zero() const { return !add && !mul && !div && !cmp && !sqrt; }
};
Diff diff(const Row& r);

nlohmann::json to_json(const std::vector<Row>& rows);
// The rows back from to_json (a report's record: `raybench report --from`); throws on a missing key.
std::vector<Row> from_json(const nlohmann::json& rows);
std::string to_markdown(const std::vector<Row>& rows);
// The terminal table within 80 columns; `notes`: the reason for every difference under its row.
std::string to_text(const std::vector<Row>& rows, bool notes = false);

}  // namespace rb::opstable
