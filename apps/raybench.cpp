// raybench: the command-line front end. `raybench --help` lists the subcommands. The only file that
// includes CLI11 (header-only, about 6 s of compile time per file that includes it): the subcommands
// in other files are plain functions of the options parsed here (apps/commands.hpp).
#include "apps/accuracy_run.hpp"
#include "apps/commands.hpp"
#include "apps/machine.hpp"
#include "apps/render_options.hpp"
#include "apps/report.hpp"
#include "apps/trace_options.hpp"
#include "bench/ops_table.hpp"

#include <CLI/CLI.hpp>

#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{
      "raybench: a data-oriented SIMD benchmark engine for ray x scene intersection.\n"
      "Every intersection method is one kernel template run as scalar float/double, as 8-lane AVX2 SIMD\n"
      "and as an operation-counting number. Start with `raybench report`."};
  app.require_subcommand(1);

  rb::app::ReportOptions ro;
  auto* report = app.add_subcommand("report", "The main job: ops table, scalar-vs-SIMD benchmarks and charts on the embedded "
                                              "defaults; writes OUT/index.md with JSON and PNG beside it");
  report->add_option("-o,--out", ro.out, "Output folder")->capture_default_str();
  report->add_option("-r,--repetitions", ro.repetitions, "Benchmark repetitions (the report quotes medians)")
      ->capture_default_str()->check(CLI::Range(1, 100));
  report->add_option("--min-time", ro.min_time, "Seconds per benchmark repetition")->capture_default_str()->check(CLI::Range(0.001, 10.0));
  report->add_option("--filter", ro.filter, "Only benchmarks whose name (kernel/method/variant/case) matches this regex")
      ->capture_default_str();
  report->add_flag("!--no-charts", ro.charts, "Skip the matplotlib charts");

  std::string ops_json;
  auto* ops = app.add_subcommand("ops", "Operations per intersection: the lecture's counts beside Counted<float> and per-lane "
                                        "Counted<simd8> measurements, with the reason for every difference");
  ops->add_option("--json", ops_json, "Write the rows as a JSON array to this file instead of the table (no FILE or '-': stdout)")
      ->expected(0, 1);

  rb::app::BenchOptions bo;
  auto* bench = app.add_subcommand("bench", "Run the kernel benchmarks (Google Benchmark) and write their JSON, every repetition "
                                            "and its aggregates (what Google Benchmark's compare.py reads)");
  bench->add_option("-o,--out", bo.json_out, "JSON output file")->capture_default_str();
  bench->add_option("--filter", bo.filter, "Regex on kernel/method/variant/case")->capture_default_str();
  bench->add_option("-r,--repetitions", bo.repetitions, "Repetitions")->capture_default_str()->check(CLI::Range(1, 100));
  bench->add_option("--min-time", bo.min_time, "Seconds per repetition")->capture_default_str()->check(CLI::Range(0.001, 10.0));
  bench->add_option("--seed", bo.seed, "Seed of the benchmark rays and primitives (0: the report's data)")->capture_default_str();

  // The subcommands of their own files (apps/commands.hpp): only their options are parsed here.
  std::string info_scene, info_json;
  auto* info = app.add_subcommand("info", "Describe a scene: primitive counts per kind, bounds, camera, lights, materials and memory "
                                          "per batch (input form and SoA kernel batch)");
  info->add_option("scene", info_scene, "A .obj/.ply/.nff file, a .json scene (CSG trees), spd:NAME[:SIZE] (balls gears mount rings teapot tetra tree), lecture:NAME or csg:NAME (spheres_minus lens die torus_box ellipsoid_minus_cylinder)")
      ->required();
  info->add_option("--json", info_json, "Write the description as JSON to this file instead of the table (no FILE or '-': stdout)")
      ->expected(0, 1);

  auto* query = app.add_subcommand(
      "query",
      "One-off intersection queries: JSON lines on stdin, e.g.\n"
      "  {\"primitive\": {\"type\":\"sphere\",\"center\":[0,0,5],\"radius\":1}, \"ray\": {\"origin\":[0,0,0],\"direction\":[0,0,1]}}\n"
      "One JSON line out per query with hit, t, point, normal, uv for every method that applies (or \"method\": NAME).\n"
      "Types: sphere(center,radius[,pole,equator]) triangle(v0,v1,v2) plane(point,normal[,u,v]) parallelogram(origin,u,v)\n"
      "polygon(vertices) box(min,max) cylinder(base,axis,radius,height[,caps]) cone(apex,axis,angle|radius+height[,caps])\n"
      "torus(center,axis,major,minor) quadric(coefficients: a b c d e f g h j k of seed 004).\n"
      "CSG trees: union|intersection(children or left,right) difference(left,right) of sphere box polyhedron cylinder cone torus\n"
      "ellipsoid quadric leaves, each node with an optional transform (the JSON scene format); their answer adds \"intervals\".\n"
      "A malformed line gets {\"line\": N, \"error\": ...} (and a line on stderr); the exit status is 1 if any line failed.");
  bool query_double = false;
  query->add_flag("--double", query_double, "Run the kernels in double precision (on the same float-rounded primitive and ray)");

  rb::app::TraceRunOptions to;
  std::string trace_json;
  auto* trace = app.add_subcommand("trace", "Trace a whole scene through the 8-wide BVH (single rays or packets, TBB threads) "
                                            "beside Embree on the same rays: Mrays/s, build time, memory, traversal cost, mismatch rate");
  trace->add_option("scene", to.scene, "A .obj/.ply/.nff/.json file, spd:NAME[:SIZE], lecture:NAME or csg:NAME (as `raybench info`)")->required();
  trace->add_option("--rays", to.ray_set, "Ray set: primary, shadow, diffuse or random")
      ->check(CLI::IsMember({"primary", "shadow", "diffuse", "random"}))->capture_default_str();
  trace->add_option("--threads", to.threads, "Threads for tracing (TBB) and for both builds")->check(CLI::Range(1, 256))->capture_default_str();
  trace->add_option("--packet", to.packet, "Rays per packet: 1 (single rays), 8 or 16")->check(CLI::IsMember({1, 8, 16}))->capture_default_str();
  trace->add_option("--count", to.count, "About this many rays (primary: the nearest square image of 4x4 tiles)")
      ->check(CLI::Range(std::size_t(1), std::size_t(1) << 28))->capture_default_str();
  trace->add_option("--seed", to.seed, "Seed of the ray set")->capture_default_str();
  trace->add_option("--model", to.model, "How the scene is modelled: auto (what it needs, see `raybench plan`), fast (world "
                                         "coordinates, the cheapest method of every kind in float) or exact (the most accurate of everything)")
      ->check(CLI::IsMember({"auto", "fast", "exact"}))->capture_default_str();
  trace->add_option("--slab", to.slab, "Slab test: plan (the model's), conservative (fast test on widened boxes, robust for far origins), "
                                       "fast (on boxes as built) or robust (Ize 2013: far distance scaled by 1 + 2 gamma(3))")
      ->check(CLI::IsMember({"plan", "conservative", "fast", "robust"}))->capture_default_str();
  trace->add_option("-r,--repetitions", to.repetitions, "Timed runs (the median is quoted)")->check(CLI::Range(1, 100))->capture_default_str();
  trace->add_option("--brute", to.brute_rays, "Rays checked against the brute-force loop over all objects (-1: a budget by scene size)")
      ->capture_default_str();
  trace->add_flag("!--no-embree", to.embree, "Skip Embree");
  trace->add_option("--json", trace_json, "Write the result as JSON to this file (no argument or '-': stdout) instead of the table")
      ->expected(0, 1);

  rb::app::RenderRunOptions rdo;
  std::string render_json;
  auto* render = app.add_subcommand(
      "render",
      "Render a scene with the recursive ray tracer (shadows, Lambert + Phong, reflection, Snell refraction) through the BVH: "
      "a PNG, rays by kind, tests by primitive kind, time and Mrays/s. --spd follows Haines' SPD protocol and shows his "
      "published counts beside ours. Under `mpirun -n N` the tiles are split across the ranks");
  render->add_option("scene", rdo.scene, "A .obj/.ply/.nff file, spd:NAME[:SIZE] or lecture:NAME (as `raybench info`)")->required();
  render->add_option("-o,--out", rdo.out, "PNG file to write");
  render->add_option("--width", rdo.width, "Image width in pixels (default 512, or the NFF file's resolution)")->check(CLI::Range(1, 16384));
  render->add_option("--height", rdo.height, "Image height in pixels (default: the width)")->check(CLI::Range(1, 16384));
  render->add_option("--depth", rdo.depth, "Maximum ray tree depth, the eye ray being depth 1")->check(CLI::Range(1, 64))->capture_default_str();
  render->add_option("--threads", rdo.threads, "TBB threads (per MPI rank)")->check(CLI::Range(1, 256))->capture_default_str();
  render->add_flag("--spd", rdo.spd,
                   "Haines' SPD protocol: rays through the 513 x 513 pixel corners of a 512 x 512 image averaged, depth 5, every ray "
                   "hitting a reflector or transmitter spawns a reflection ray, one-sided opaque surfaces except the teapot");
  render->add_flag("!--no-counts", rdo.count_tests,
                   "Skip counting box and primitive tests (the plain traversal, as `raybench trace` times it); rays are still counted");
  render->add_option("--secondary-packet", rdo.secondary_packet,
                     "Reflection, refraction and shadow rays: 1 one by one, 8 sorted by direction octant and traced as 8-ray packets")
      ->check(CLI::IsMember({1, 8}))->capture_default_str();
  render->add_option("--model", rdo.model, "How the scene is modelled: auto (what it needs, see `raybench plan`), fast or exact")
      ->check(CLI::IsMember({"auto", "fast", "exact"}))->capture_default_str();
  render->add_option("--json", render_json, "Write the result as JSON to this file (no argument or '-': stdout) instead of the summary")
      ->expected(0, 1);

  rb::acc::Options ao;
  std::string accuracy_json;
  bool accuracy_list = false;
  auto* accuracy = app.add_subcommand("accuracy",
                                      "The accuracy lab: adversarial seeded rays per primitive family (edges and vertices of closed meshes, "
                                      "far and grazing rays, planets, apexes, tangents, slab planes, spawned rays) against exact references "
                                      "from the same float inputs; false hits/misses, leaks, t error in ulps, self-hits, ns per test");
  accuracy->add_flag("--full", ao.full, "Every case with 100000 rays (default: 10000 rays per case, about ten seconds)");
  accuracy->add_option("--seed", ao.seed, "Seed of every case generator")->capture_default_str();
  accuracy->add_option("--rays", ao.rays, "Rays per case (overrides the mode's count)")->check(CLI::Range(std::size_t(8), std::size_t(1) << 24));
  accuracy->add_option("--filter", ao.filter, "Only cases whose family/case contains this text (e.g. triangle/octa, torus/)");
  accuracy->add_flag("!--no-timing", ao.timing, "Skip the ns-per-test timing");
  accuracy->add_flag("--list", accuracy_list, "List the cases and exit");
  accuracy->add_option("--json", accuracy_json, "Write the rows as JSON to this file (no argument or '-': stdout) instead of the table")
      ->expected(0, 1);

  int csg_reps = 5;
  std::size_t csg_rays = std::size_t(1) << 15;
  auto* csg = app.add_subcommand("csg", "CSG queries on the embedded CSG scenes: operations per query and queries per second, "
                                        "scalar against 8-ray packets (the report's CSG section, as markdown)");
  csg->add_option("-r,--repetitions", csg_reps, "Timed runs (the median is quoted)")->check(CLI::Range(1, 100))->capture_default_str();
  csg->add_option("--rays", csg_rays, "Rays per scene")->check(CLI::Range(std::size_t(8), std::size_t(1) << 24))->capture_default_str();

  std::string plan_scene, plan_json, plan_model = "auto";
  bool plan_verify = false;
  auto* plan = app.add_subcommand(
      "plan",
      "How a scene is modelled for tracing (model no more than it needs): its numerical profile per primitive kind (sizes, "
      "coordinates against them, how far away each kind is seen), then the frame of reference, each kind's method, precision and "
      "storage, the slab test and the spawn offset of secondary rays, each with its reason and the accuracy-lab cases it rests on");
  plan->add_option("scene", plan_scene, "A scene (as `raybench info`)")->required();
  plan->add_option("--model", plan_model, "auto (the default), fast or exact")->check(CLI::IsMember({"auto", "fast", "exact"}))->capture_default_str();
  plan->add_flag("--verify", plan_verify, "Run the lab cases each choice rests on and show their failure figures (a few seconds)");
  plan->add_option("--json", plan_json, "Write the profile and plan as JSON to this file (no FILE or '-': stdout)")->expected(0, 1);

  auto* mach = app.add_subcommand("machine", "Print the machine and build description recorded with every result (JSON)");

  CLI11_PARSE(app, argc, argv);
  try {
    if (*report) return rb::app::run_report(ro);
    if (*ops) {
      const auto rows = rb::opstable::build();
      return rb::app::write_result("ops", !ops_json.empty(), ops_json, [&] { return rb::opstable::to_text(rows); },
                                   [&] { return rb::opstable::to_json(rows); }, std::to_string(rows.size()) + " rows");
    }
    if (*bench) {
      const int rc = rb::app::run_benchmarks(bo);
      if (rc == 0) std::cerr << "wrote " << bo.json_out << "\n";
      return rc;
    }
    if (*info) return rb::app::run_info_command(info_scene, {info->count("--json") > 0, info_json});
    if (*query) return rb::app::run_query(std::cin, std::cout, std::cerr, query_double);
    if (*trace) return rb::app::run_trace_command(to, {trace->count("--json") > 0, trace_json});
    if (*render) return rb::app::run_render_command(rdo, {render->count("--json") > 0, render_json});
    if (*accuracy) return rb::app::run_accuracy_command(ao, accuracy_list, {accuracy->count("--json") > 0, accuracy_json});
    if (*csg) return rb::app::run_csg_command(csg_reps, csg_rays);
    if (*plan) return rb::app::run_plan_command(plan_scene, plan_model, plan_verify, {plan->count("--json") > 0, plan_json});
    if (*mach) { std::cout << rb::app::machine().json().dump(2) << "\n"; return 0; }
  } catch (const std::exception& e) {
    std::cerr << "raybench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
