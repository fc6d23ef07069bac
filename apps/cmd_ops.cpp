// `raybench ops` (the operations table) and `raybench machine` (what every result records).
#include "apps/commands.hpp"
#include "apps/machine.hpp"
#include "bench/ops_table.hpp"

namespace rb::app {

int run_ops_command(bool notes, const JsonOut& out) {
  const auto rows = rb::opstable::build();
  return write_result("ops", out, [&] { return rb::opstable::to_text(rows, notes); }, [&] { return rb::opstable::to_json(rows); },
                      std::to_string(rows.size()) + " rows");
}

int run_machine_command(const JsonOut& out) {
  const Machine m = machine();
  return write_result("machine", out, [&] { return m.text(); }, [&] { return m.json(); }, "the machine and build block");
}

}  // namespace rb::app
