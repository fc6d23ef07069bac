// `raybench compare A B`: two results of one kind, row by row (apps/compare.hpp).
#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "apps/results/compare.hpp"
#include "apps/results/history.hpp"

#include <fmt/format.h>

#include <iostream>

namespace rb::app {

int run_compare_command(const std::string& a, const std::string& b, const CompareOptions& o, bool markdown, const JsonOut& out) {
  Comparison c;
  try {
    ResultSet ra, rb;
    if (!o.history.empty()) {
      // Two runs of a results history, by id.
      auto id = [](const std::string& s) {
        std::size_t used = 0;
        long long v = -1;
        try {
          v = std::stoll(s, &used);
        } catch (const std::exception&) {
        }
        if (used != s.size() || v < 1) throw std::runtime_error("with --history, A and B are run ids (raybench history lists them), not '" + s + "'");
        return v;
      };
      const long long ia = id(a), ib = id(b);
      const History h(o.history, false);
      ra = h.load_run(ia);
      rb = h.load_run(ib);
    } else {
      ra = load_results(a);  // A first: an error names A before B
      rb = load_results(b);
    }
    c = compare_results(std::move(ra), std::move(rb), o);
  } catch (const NothingToDo& e) {
    std::cerr << error_line("compare", "", e.what()) << "\n";
    return kExitNothing;
  } catch (const std::exception& e) {
    std::cerr << error_line("compare", "", e.what()) << "\n";
    return kExitError;
  }
  const int rc = write_result("compare", out, [&] { return markdown ? compare_markdown(c) : compare_text(c); }, [&] { return compare_json(c); },
                              "the comparison");
  if (rc != 0) return rc;
  if (c.regressions) {
    std::cerr << fmt::format("raybench compare: {} regression(s): B is worse than A by more than {:.3g} % beyond noise\n", c.regressions,
                             100 * o.threshold);
    return kExitError;
  }
  return kExitOk;
}

}  // namespace rb::app
