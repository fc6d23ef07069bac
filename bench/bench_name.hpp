// A kernel benchmark's name in its parts, for the code that builds names and the code that reads
// them back (the results and the report), without the benchmark harness.
#pragma once

#include <optional>
#include <string>

namespace rb::bench {

// A kernel benchmark's name, kernel/method/variant/case, in its parts: the one place that builds
// it (register.hpp) and the one that reads it (the results, the report). parse: nullopt for a
// name of another shape (the node test's three parts, an empty part).
struct BenchName {
  std::string kernel, method, variant, kase;
  std::string kernel_method() const { return kernel + "/" + method; }
  std::string str() const { return kernel + "/" + method + "/" + variant + "/" + kase; }
  static std::optional<BenchName> parse(const std::string& name) {
    BenchName b;
    std::string* part[] = {&b.kernel, &b.method, &b.variant, &b.kase};
    std::size_t s = 0;
    for (int i = 0; i < 4; ++i) {
      const std::size_t e = name.find('/', s);
      if ((i < 3) == (e == std::string::npos)) return std::nullopt;  // too few parts, or too many
      *part[i] = name.substr(s, (i < 3 ? e : name.size()) - s);
      if (part[i]->empty()) return std::nullopt;
      s = e + 1;
    }
    return b;
  }
};

}  // namespace rb::bench
