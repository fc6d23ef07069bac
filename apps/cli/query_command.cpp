// `raybench query`: one-off intersection queries (JSON lines).
#include "apps/cli/command.hpp"
#include "core/output_file.hpp"

#include <sstream>

namespace rb::app::cli {
namespace {

class QueryCommand final : public Command {
  bool query_double = false;
 public:
  explicit QueryCommand(CLI::App& root) : Command(root, "query", "One-off intersection queries (JSON lines)") {
    sub_->add_flag("--double", query_double, "Run the kernels in double precision (on the\nsame float-rounded primitive and ray)");
    json_option("Write the answers to FILE (no FILE: stdout)");
    sub_->footer(
        "JSON lines on stdin, one JSON line out per query, e.g.\n"
        "  {\"primitive\": {\"type\":\"sphere\",\"center\":[0,0,5],\"radius\":1},\n"
        "   \"ray\": {\"origin\":[0,0,0],\"direction\":[0,0,1]}}\n"
        "The answer: hit, t, point, normal, uv for every method that applies (or\n"
        "\"method\": NAME). Types: sphere(center,radius[,pole,equator]) triangle(v0,v1,v2)\n"
        "plane(point,normal[,u,v]) parallelogram(origin,u,v) polygon(vertices)\n"
        "box(min,max) cylinder(base,axis,radius,height[,caps])\n"
        "cone(apex,axis,angle|radius+height[,caps]) torus(center,axis,major,minor)\n"
        "quadric(coefficients: a b c d e f g h j k of seed 004). CSG trees:\n"
        "union|intersection(children or left,right), difference(left,right) of sphere,\n"
        "box, polyhedron, cylinder, cone, torus, ellipsoid and quadric leaves, each node\n"
        "with an optional transform (the JSON scene format); their answer adds\n"
        "\"intervals\". A malformed line gets {\"line\": N, \"error\": ...} and a line on\n"
        "stderr; the exit status is 1 if any line failed.");
  }
  int run(Context&) override {
    if (sub_->count("--json") && !json_file_.empty() && json_file_ != "-") {
      std::ostringstream f;
      int rc = run_query(std::cin, f, std::cerr, query_double);
      try {
        rb::write_output(json_file_, f.str());
      } catch (const std::exception& e) {
        std::cerr << error_line("query", json_file_, e.what()) << "\n";
        rc = kExitError;
      }
      return rc;
    }
    return run_query(std::cin, std::cout, std::cerr, query_double);
  }
};

}  // namespace

std::unique_ptr<Command> make_query(CLI::App& root) { return std::make_unique<QueryCommand>(root); }

}  // namespace rb::app::cli
