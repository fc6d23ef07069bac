// `raybench compare A B`: two results of one kind, row by row (apps/compare.hpp).
#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "apps/compare.hpp"

#include <fmt/format.h>

#include <iostream>

namespace rb::app {

int run_compare_command(const std::string& a, const std::string& b, const CompareOptions& o, bool markdown, const JsonOut& out) {
  Comparison c;
  try {
    ResultSet ra = load_results(a);  // A first: an error names A before B
    ResultSet rb = load_results(b);
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
