// `raybench ops` (the operations table) and `raybench machine` (what every result records).
#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "apps/results/machine.hpp"
#include "bench/ops_table.hpp"

namespace rb::app {

int run_ops_command(bool notes, const std::string& filter, const JsonOut& out) {
  auto rows = rb::opstable::build();
  if (!filter.empty()) {
    const std::regex re = filter_regex(filter);
    std::erase_if(rows, [&](const opstable::Row& r) { return !filter_matches(re, r.kernel + "/" + r.method + "/" + r.kase); });
    if (rows.empty()) throw NothingToDo("--filter '" + filter + "' selects no row (kernel/method/case, e.g. sphere/ or /miss$)");
  }
  return write_result("ops", out, [&] { return rb::opstable::to_text(rows, notes); }, [&] { return rb::opstable::to_json(rows); },
                      std::to_string(rows.size()) + " rows");
}

int run_machine_command(const JsonOut& out) {
  const Machine m = machine();
  return write_result("machine", out, [&] { return m.text(); }, [&] { return m.json(); }, "the machine and build block");
}

}  // namespace rb::app
