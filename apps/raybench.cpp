// raybench: the command-line front end. `raybench --help` lists the subcommands. The only file that
// includes CLI11 (header-only, about 6 s of compile time per file that includes it): the subcommands
// in other files are plain functions of the options parsed here (apps/commands.hpp).
//
// The conventions every subcommand follows (README "Command-line conventions", apps/cli.hpp):
// exit status 0 done, 1 a parse or input error, 2 nothing to do; one error line naming the input
// and the reason; every output path checked before the work starts; --json [FILE|-] everywhere;
// --filter a regex everywhere; --threads 0 all hardware threads; help within 80 columns.
#include <sstream>
#include "core/output_file.hpp"
#include "apps/interrupt.hpp"
#include "apps/accuracy_run.hpp"
#include "apps/build_info.hpp"
#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "apps/compare.hpp"
#include "apps/history.hpp"
#include "apps/machine.hpp"
#include "apps/render_options.hpp"
#include "apps/report.hpp"
#include "apps/results.hpp"
#include "apps/trace_options.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>

namespace {

using rb::app::JsonOut;

// --json [FILE|-]: no FILE or '-' writes to stdout.
CLI::Option* add_json(CLI::App* sub, std::string& file, const std::string& what) {
  return sub->add_option("--json", file, what)->expected(0, 1)->type_name("[FILE|-]");
}
JsonOut json_out(CLI::App* sub, const std::string& file) { return {sub->count("--json") > 0, file, {}}; }

// A command's positional arguments, and its options whose FILE is optional (--json, --dump-json).
// The parser gives such an option the next word, so `trace --json csg:die` would read the scene
// as the JSON file and then miss the scene. The positionals are therefore not required by the
// parser: when some are missing and such an option took a word, that word was the positional
// given at its place (the option then writes to stdout); what is still missing is an error.
struct Positionals {
  CLI::App* sub;
  std::vector<std::pair<std::string, std::string*>> args;          // name, value, in order
  std::vector<std::pair<std::string, std::string*>> optional_file;  // option, its FILE
};
CLI::Option* add_positional(Positionals& p, const std::string& name, std::string& value, const std::string& what) {
  p.args.emplace_back(name, &value);
  return p.sub->add_option(name, value, what);
}
// "" when every positional is there (after taking back the swallowed ones), else the error.
std::string complete_positionals(const Positionals& p) {
  std::vector<std::string> given;
  for (const auto& [name, v] : p.args)
    if (!v->empty()) given.push_back(*v);
  for (const auto& [opt, file] : p.optional_file) {
    if (given.size() == p.args.size()) break;
    if (!p.sub->count(opt) || file->empty() || *file == "-") continue;
    std::size_t before = 0;  // positional words parsed before the option
    for (const CLI::Option* o : p.sub->parse_order()) {
      if (o->check_name(opt)) break;
      before += o->get_positional();
    }
    given.insert(given.begin() + std::ptrdiff_t(std::min(before, given.size())), *file);
    file->clear();
  }
  for (std::size_t i = 0; i < p.args.size(); ++i) {
    if (i >= given.size()) return p.args[i].first + " is required";
    *p.args[i].second = given[i];
  }
  return "";
}

// A value from a fixed set of names; anything else is refused with the names and the closest one.
CLI::Validator one_of(std::vector<std::string> names) {
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ",") + n;
  return CLI::Validator(
      [names, list](std::string& s) -> std::string {
        if (std::find(names.begin(), names.end(), s) != names.end()) return "";
        return "'" + s + "' is not one of " + list + rb::did_you_mean(s, names);
      },
      "{" + list + "}");
}

// A count given as an integer or in scientific notation (4e9, 1e6), refused outside 1..max with
// the bound named before anything is allocated; passed on as the integer.
CLI::Validator count_up_to(std::size_t max, const std::string& what) {
  return CLI::Validator(
      [max, what](std::string& s) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v)) return "expected a number, got '" + s + "'";
        if (!(v >= 1 && v <= double(max))) return s + " is outside 1.." + std::to_string(max) + " (the most " + what + " one run takes)";
        if (v != std::floor(v)) return "expected a whole number, got '" + s + "'";
        s = std::to_string(static_cast<unsigned long long>(v));
        return "";
      },
      "1.." + std::to_string(max));
}

// A packet size given as one of `allowed` ("auto" or a number), passed on as the number (auto: 0);
// anything else is refused with the allowed sizes named.
CLI::Validator packet_size_choice(std::vector<std::string> allowed) {
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  return CLI::Validator(
      [allowed, list](std::string& s) -> std::string {
        if (std::find(allowed.begin(), allowed.end(), s) == allowed.end()) return "'" + s + "' is not a packet size here; choose " + list;
        if (s == "auto") s = "0";
        return "";
      },
      "");
}

// The command line as typed, for the results history.
std::string command_line(int argc, char** argv) {
  std::string s;
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    if (i == 0) a = "raybench";
    const bool plain = !a.empty() && a.find_first_of(" \t\n'\"\\$`*?[]{}()<>|&;#~") == std::string::npos;
    if (!plain) {
      std::string q = "'";
      for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
      a = q + "'";
    }
    s += (i ? " " : "") + a;
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace rb::app;
  CLI::App app{
      "raybench: a data-oriented SIMD benchmark engine for ray x scene intersection.\n"
      "Every intersection method is one kernel template run as scalar float/double,\n"
      "as 8-lane AVX2 SIMD and as an operation-counting number.\n"
      "Start with `raybench report`; `raybench COMMAND --help` explains each command."};
  app.name("raybench");
  app.set_version_flag("--version", version_text(), "Version, git revision and build flags");
  app.require_subcommand(1);
  app.footer(
      "Conventions: exit status 0 done, 1 a parse or input error, 2 nothing to do;\n"
      "--json [FILE|-] (no FILE or '-': stdout) and --filter REGEX on every command\n"
      "that has results or names; --threads 0 uses every hardware thread;\n"
      "--history FILE (or RAYBENCH_HISTORY) keeps a run in the results history.\n"
      "Outputs: a file is replaced whole (a temporary renamed over it), a symlink's\n"
      "target likewise (the link stays); a FIFO or a device is written as it is\n"
      "(--json /dev/null discards, /dev/full fails with exit 1); '-', /dev/stdout,\n"
      "/dev/stderr and /dev/fd/N are this process's own descriptors; a directory,\n"
      "a socket or a block device is refused before the work.");

  // ---- report ----
  ReportOptions ro;
  std::string report_history;
  bool report_no_history = false;
  auto* report = app.add_subcommand("report", "The main job: every measurement, as a report");
  report->add_option("-o,--out", ro.out, "Output folder")->capture_default_str();
  report->add_option("-r,--repetitions", ro.repetitions, "Benchmark repetitions (medians quoted)")
      ->capture_default_str()->check(CLI::Range(1, 100));
  report->add_option("--min-time", ro.min_time, "Seconds per benchmark repetition")->capture_default_str()->check(CLI::Range(0.001, 10.0));
  report->add_option("--filter", ro.filter, "Only the benchmarks whose name\n(kernel/method/variant/case) matches this regex")
      ->capture_default_str();
  report->add_flag("!--no-charts", ro.charts, "Skip the matplotlib charts");
  report->add_flag("--quick", ro.quick, "A small report in about a minute, to check its\nlayout and links: 2 repetitions of 0.005 s\n(unless -r, --min-time say otherwise), few\nrays, 128x128 renders, fewer scenes");
  add_json(report, ro.json_file, "The summary JSON also to FILE (no FILE: stdout,\nthe terminal summary then to stderr)");
  report->add_option("--history", report_history, "Keep the run in this results history\n(default: $RAYBENCH_HISTORY, else\nresults/history.sqlite)")
      ->type_name("FILE");
  report->add_flag("--no-history", report_no_history, "Do not keep the run in a results history");
  report->footer(
      "Runs the ops table, the scalar-vs-SIMD kernel benchmarks, scene loading, tracing\n"
      "beside Embree, the recursive renderer, the accuracy lab and CSG on the embedded\n"
      "scenes, and writes OUT/index.md with JSON and PNG charts beside it (a few\n"
      "minutes on a 2-core machine). Two report folders compare with\n"
      "`raybench compare A B`; each run is kept in results/history.sqlite.");

  // ---- ops ----
  std::string ops_json, ops_filter;
  bool ops_notes = false;
  auto* ops = app.add_subcommand("ops", "Operations per intersection, lecture vs measured");
  ops->add_flag("--notes", ops_notes, "Under every row, the reason for each difference");
  ops->add_option("--filter", ops_filter, "Only the rows whose kernel/method/case matches\nthis regex (e.g. sphere/, /miss$)");
  add_json(ops, ops_json, "Write the rows as JSON to FILE (no FILE: stdout)");
  ops->footer(
      "For every kernel and method: the lecture's operation counts beside those\n"
      "measured by running the kernel with Counted<float> on a ray that hits and one\n"
      "that misses, and the per-lane count of the 8-lane SIMD instantiation.");

  // ---- bench ----
  BenchOptions bo;
  std::string bench_json, bench_history;
  bool bench_list = false;
  auto* bench = app.add_subcommand("bench", "Kernel benchmarks: scalar against 8-lane SIMD");
  bench->add_option("--filter", bo.filter, "Only the benchmarks whose name\n(kernel/method/variant/case) matches this regex")
      ->capture_default_str();
  bench->add_option("-r,--repetitions", bo.repetitions, "Repetitions (the median is quoted)")->capture_default_str()->check(CLI::Range(1, 100));
  bench->add_option("--min-time", bo.min_time, "Seconds per repetition")->capture_default_str()->check(CLI::Range(0.001, 10.0));
  bench->add_option("--seed", bo.seed, "Seed of the rays and primitives\n(0: the report's data)")->capture_default_str();
  bench->add_flag("--list", bench_list, "List the benchmarks the filter selects and exit");
  add_json(bench, bench_json, "Google Benchmark JSON, every repetition, to FILE\n(no FILE: stdout instead of the table)");
  bench->add_option("--history", bench_history, "Keep the run in this results history\n(default: $RAYBENCH_HISTORY)")->type_name("FILE");
  bench->footer(
      "Google Benchmark medians, L1-resident, one thread: every kernel x {true scalar,\n"
      "8 rays x 1 primitive, 1 ray x 8 primitives} x {hit, miss, half}. The table shows\n"
      "the median tests per second, the coefficient of variation over the repetitions,\n"
      "operations per test and the SIMD speedup over the scalar form. The --json file\n"
      "is what Google Benchmark's compare.py and `raybench compare` read.");

  // ---- info ----
  std::string info_scene, info_json, info_dump;
  auto* info = app.add_subcommand("info", "Describe a scene: counts, bounds, memory");
  Positionals info_args{info, {}, {{"--json", &info_json}, {"--dump-json", &info_dump}}};
  add_positional(info_args, "scene", info_scene, "A scene (see below)");
  add_json(info, info_json, "Write the description as JSON to FILE\n(no FILE: stdout)");
  info->add_option("--dump-json", info_dump, "Write the scene itself in the JSON scene\nformat to FILE (no FILE: stdout), a start\nfor a scene of your own (docs/SCENE_FORMAT.md)")
      ->expected(0, 1)
      ->type_name("[FILE|-]");
  info->footer(
      "Scenes: a .obj, .ply or .nff file, a .json scene (CSG trees),\n"
      "spd:NAME[:SIZE] (balls gears mount rings teapot tetra tree), lecture:NAME,\n"
      "csg:NAME (spheres_minus lens die torus_box ellipsoid_minus_cylinder), or\n"
      "precision:NAME (scenes that test a tracer's precision: ball_ground,\n"
      "ball_ground_far, planet, mesh_spheres[_1e3|_1e5|_1e7], far_spheres,\n"
      "thin_torus, far_cylinders, mixed_scales, scanned, scanned_double,\n"
      "scattered, pipes), or\n"
      "heightfield[:NXxNY] (a wavy height field of NX x NY quads; default 708x707,\n"
      "about a million triangles).\n"
      "Shows primitive counts per kind, bounds, camera, lights, materials, the\n"
      "memory of the input form and of each SoA kernel batch, and the tracer's plan.");

  // ---- query ----
  bool query_double = false;
  std::string query_json;
  auto* query = app.add_subcommand("query", "One-off intersection queries (JSON lines)");
  query->add_flag("--double", query_double, "Run the kernels in double precision (on the\nsame float-rounded primitive and ray)");
  add_json(query, query_json, "Write the answers to FILE (no FILE: stdout)");
  query->footer(
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

  // ---- trace ----
  TraceRunOptions to;
  std::string trace_json, trace_history;
  auto* trace = app.add_subcommand("trace", "Trace a scene through the BVH beside Embree");
  Positionals trace_args{trace, {}, {{"--json", &trace_json}}};
  add_positional(trace_args, "scene", to.scene, "A scene, as `raybench info` takes it");
  trace->add_option("--rays", to.ray_set, "Ray set")->check(one_of({"primary", "shadow", "diffuse", "random"}))->capture_default_str();
  trace->add_option("--threads", to.threads, "Threads for tracing and both builds\n(0: every hardware thread)")
      ->check(CLI::Range(0, 256))->capture_default_str();
  trace->add_option("--packet", to.packet, "Rays per packet: 1 (single rays), 8, 16,\n64 or 256 (coherent packets)")
      ->check(CLI::IsMember({1, 8, 16, 64, 256}))
      ->capture_default_str();
  trace->add_option("--count", to.count, "About this many rays (primary: the nearest\nsquare image of 16x16 blocks)")
      ->transform(count_up_to(std::size_t(1) << 28, "rays"))->capture_default_str();
  trace->add_option("--seed", to.seed, "Seed of the ray set")->capture_default_str();
  trace->add_option("--model", to.model, "How the scene is modelled: auto (what it\nneeds: `raybench plan`), fast or exact")
      ->check(one_of({"auto", "fast", "exact"}))->capture_default_str();
  trace->add_option("--slab", to.slab, "Slab test: plan (the model's), conservative,\nfast or robust")
      ->check(one_of({"plan", "conservative", "fast", "robust"}))->capture_default_str();
  trace->add_option("-r,--repetitions", to.repetitions, "Timed rounds, engines alternating (the median is\nquoted; from 6 rounds raybench / Embree has a\n95 % interval)")
      ->check(CLI::Range(1, 100))->capture_default_str();
  trace->add_option("--warmup", to.warmup, "Untimed runs per engine before the timed ones")->check(CLI::Range(0, 100))->capture_default_str();
  trace->add_option("--brute", to.brute_rays, "Rays checked against the brute-force loop\n(-1: a budget by scene size, 0: none)")
      ->capture_default_str();
  trace->add_flag("!--no-embree", to.embree, "Skip Embree");
  trace->add_option("--builds", to.builds,
                    "Builds per engine to time: above 1, the build\ntimes quoted are the medians of this many\n"
                    "builds after an untimed one (as the report)")
      ->check(CLI::Range(1, 100))->capture_default_str();
  trace->add_option("--builder", to.builder,
                    "The tree raybench traces: sah (its own) or\nEmbree's builder (embree: medium quality,\n"
                    "embree-high: high, with spatial splits of\ntriangles); with Embree's the SAH tree is\ntimed beside it")
      ->check(one_of({"sah", "embree", "embree-high"}))->capture_default_str();
  add_json(trace, trace_json, "Write the result as JSON to FILE\n(no FILE: stdout instead of the table)");
  trace->add_option("--history", trace_history, "Keep the run in this results history\n(default: $RAYBENCH_HISTORY)")->type_name("FILE");
  trace->footer(
      "One binned-SAH build gives a binary and an 8-wide BVH; the rays (primary,\n"
      "shadow, diffuse or random, from one seed) are traced as single rays or\n"
      "packets on TBB threads, and Embree 3 traces the same float triangles and rays in\n"
      "the same process, on a device with its native ISA and one limited to AVX2, with\n"
      "the call for the packet size (rtcIntersect1/8/16, rtcIntersect1M streams for 64\n"
      "and 256; rtcOccluded* for shadow rays); the fastest is the yardstick. After\n"
      "--warmup untimed runs the engines alternate run by run; the table gives the\n"
      "median Mrays/s with its range and coefficient of variation, build time, memory,\n"
      "traversal cost and the rate of rays the engines disagree on. A warning follows\n"
      "when the runs varied by over 5 % or the machine was busy. Arrays of 2 MiB and\n"
      "more are advised for transparent huge pages, as Embree does for its own;\n"
      "RAYBENCH_NO_HUGE_PAGES=1 turns that off.");

  // ---- render ----
  RenderRunOptions rdo;
  rdo.warmup = 1;
  rdo.repetitions = 5;  // 4 or more on each side let `compare`'s U test reach p < 0.05
  std::string render_json, render_history;
  auto* render = app.add_subcommand("render", "Render a scene with the recursive ray tracer");
  Positionals render_args{render, {}, {{"--json", &render_json}}};
  add_positional(render_args, "scene", rdo.scene, "A scene, as `raybench info` takes it");
  render->add_option("-o,--out", rdo.out, "PNG file to write (default: SCENE.png in the\ncurrent folder; '-': stdout, the table then to\nstderr)")->type_name("FILE");
  render->add_option("--width", rdo.width, "Image width in pixels (default 512, or the\nscene camera's resolution)")->check(CLI::Range(1, 16384));
  render->add_option("--height", rdo.height, "Image height in pixels (default: from the width\nby the scene camera's aspect ratio, or the width)")->check(CLI::Range(1, 16384));
  render->add_option("--depth", rdo.depth, "Maximum ray tree depth (the eye ray is 1)")->check(CLI::Range(1, 64))->capture_default_str();
  render->add_option("--threads", rdo.threads, "TBB threads per MPI rank\n(0: every hardware thread)")->check(CLI::Range(0, 256))->capture_default_str();
  render->add_flag("--spd", rdo.spd, "Haines' SPD protocol, his counts beside ours");
  render->add_flag("!--no-counts", rdo.count_tests, "Skip counting box and primitive tests");
  render->add_option("--eye-packet", rdo.eye_packet,
                     "Eye rays per packet: 1, 8, 16 or 64 (a 16x4\nblock of the image), or auto: the fastest of\n64, 16 and 8 "
                     "in trial renders before\nthe timed ones")
      ->transform(packet_size_choice({"auto", "1", "8", "16", "64"}))
      ->type_name("auto|1|8|16|64")
      ->default_str("auto");
  render->add_option("--secondary-packet", rdo.secondary_packet,
                     "Reflection, refraction and shadow rays: 1 one\nby one, 8 sorted by octant into packets, or\nauto: the "
                     "faster in trial renders")
      ->transform(packet_size_choice({"auto", "1", "8"}))
      ->type_name("auto|1|8")
      ->default_str("auto");
  render->add_option("--model", rdo.model, "How the scene is modelled: auto (what it\nneeds: `raybench plan`), fast or exact")
      ->check(one_of({"auto", "fast", "exact"}))->capture_default_str();
  render->add_option("-r,--repetitions", rdo.repetitions, "Timed renders (the median is quoted)")->check(CLI::Range(1, 100))->capture_default_str();
  render->add_option("--warmup", rdo.warmup, "Untimed renders before the timed ones")->check(CLI::Range(0, 100))->capture_default_str();
  add_json(render, render_json, "Write the result as JSON to FILE\n(no FILE: stdout instead of the summary)");
  render->add_option("--history", render_history, "Keep the run in this results history\n(default: $RAYBENCH_HISTORY)")->type_name("FILE");
  render->footer(
      "The recursive ray tracer through the 8-wide BVH: shadows, Lambert and Phong,\n"
      "reflection, Snell refraction. Writes the image (SCENE.png in the current folder\n"
      "without -o) and prints rays by kind, box and primitive tests by kind, the time\n"
      "split and Mrays/s (median of the timed renders, with range and CV).\n"
      "--spd follows Haines' SPD protocol (513 x 513 corner rays averaged, depth 5,\n"
      "one-sided opaque surfaces but the teapot's) and shows his published counts\n"
      "beside ours. Under `mpirun -n N` the tiles are split across the ranks.");

  // ---- accuracy ----
  rb::acc::Options ao;
  std::string accuracy_json, accuracy_history;
  bool accuracy_list = false;
  auto* accuracy = app.add_subcommand("accuracy", "The accuracy lab: where each method fails");
  accuracy->add_flag("--full", ao.full, "Every case with 100000 rays (default: 10000)");
  accuracy->add_option("--seed", ao.seed, "Seed of every case generator")->capture_default_str();
  accuracy->add_option("--rays", ao.rays, "Rays per case (overrides the mode's count)")->check(CLI::Range(std::size_t(8), std::size_t(1) << 24));
  accuracy->add_option("--filter", ao.filter, "Only the cases whose family/case matches this\nregex (e.g. triangle/octa, ^torus/)");
  accuracy->add_flag("!--no-timing", ao.timing, "Skip the ns-per-test timing");
  accuracy->add_flag("--list", accuracy_list, "List the cases the filter selects and exit");
  add_json(accuracy, accuracy_json, "Write the rows as JSON to FILE\n(no FILE: stdout instead of the table)");
  accuracy->add_option("--history", accuracy_history, "Keep the run in this results history\n(default: $RAYBENCH_HISTORY)")->type_name("FILE");
  accuracy->footer(
      "Adversarial, seeded rays per primitive family (edges and vertices of closed\n"
      "meshes, far and grazing rays, planets, apexes, tangents, slab planes, spawned\n"
      "rays) against exact references from the same float inputs: false hits and\n"
      "misses, leaks, t error in ulps, self-hits and ns per test, per method in float,\n"
      "double and 8-lane SIMD.");

  // ---- csg ----
  int csg_reps = 5;
  std::size_t csg_rays = std::size_t(1) << 15;
  bool csg_markdown = false;
  std::string csg_json, csg_filter;
  auto* csg = app.add_subcommand("csg", "CSG queries per second, scalar vs 8-ray packets");
  csg->add_option("-r,--repetitions", csg_reps, "Timed runs (the median is quoted)")->check(CLI::Range(1, 100))->capture_default_str();
  csg->add_option("--rays", csg_rays, "Rays per scene")->check(CLI::Range(std::size_t(8), std::size_t(1) << 24))->capture_default_str();
  csg->add_flag("--markdown", csg_markdown, "The report's CSG section (markdown, with the\noperations per query) instead of the table");
  csg->add_option("--filter", csg_filter, "Only the scenes whose csg:NAME matches this\nregex (e.g. die, ^csg:lens$)");
  add_json(csg, csg_json, "Write the figures as JSON to FILE\n(no FILE: stdout instead of the table)");

  // ---- compare ----
  CompareOptions co;
  std::string compare_a, compare_b, compare_json;
  double compare_threshold = -1, compare_noise = 5;
  bool compare_markdown = false;
  auto* compare = app.add_subcommand("compare", "Compare two results: ratios and U-test p-values");
  Positionals compare_args{compare, {}, {{"--json", &compare_json}}};
  add_positional(compare_args, "A", compare_a, "The baseline: a JSON result or a report folder\n(with --history: a run id)");
  add_positional(compare_args, "B", compare_b, "The result to compare with it, of the same kind\n(with --history: a run id)");
  compare->add_option("--history", co.history, "A and B are two runs of this results history,\nby id (`raybench history` lists them)")->type_name("FILE");
  compare->add_option("--threshold", compare_threshold, "Exit 1 when a row is worse than A beyond noise\nby more than PCT percent")
      ->type_name("PCT")->check(CLI::Range(0.0, 1e6));
  compare->add_option("--alpha", co.alpha, "Significance level of the U test")->capture_default_str()->check(CLI::Range(1e-9, 0.5));
  compare->add_option("--noise", compare_noise, "A single figure (no repetitions) differs when\nit moved by more than PCT percent")
      ->type_name("PCT")->capture_default_str()->check(CLI::Range(0.0, 1e6));
  compare->add_option("--filter", co.filter, "Only the rows whose section/name matches this\nregex");
  compare->add_option("--metric", co.metric, "Only this metric (e.g. tests_per_s,\nmrays_per_s, false_hit_ppm)");
  compare->add_flag("--all", co.all, "Also list the seeded figures that did not change");
  compare->add_flag("--force", co.force, "Compare two trace or render runs made with other\nsettings (scene, ray set, packet, threads, rays,\nmodel) anyway, matched by metric");
  compare->add_flag("--markdown", compare_markdown, "Markdown tables instead of the text table");
  add_json(compare, compare_json, "Write the comparison as JSON to FILE\n(no FILE: stdout instead of the table)");
  compare->footer(
      "A and B: JSON results of one kind (bench, trace, render, accuracy, csg) or two\n"
      "report folders. Per row: both figures, B/A, and for repeated measurements the\n"
      "two-sided Mann-Whitney U test's p-value (as Google Benchmark's compare.py); a\n"
      "timing differs beyond noise when p < alpha, or, as a single figure, when it\n"
      "moved by more than --noise. Seeded figures (accuracy rates, test counts) differ\n"
      "when they are not equal. The summary gives the geometric mean of the speed\n"
      "ratios and how many rows are faster or slower. With --threshold, a regression\n"
      "exits 1: `raybench compare base.json new.json --threshold 5` guards CI.\n"
      "Only the subject's own figures are judged (summary, --threshold): Embree's\n"
      "figures and build times measured once are shown in brackets, and judged only\n"
      "when --metric names them. Two trace or render runs of other settings are\n"
      "refused (--force compares them).");

  // ---- history ----
  HistoryOptions ho;
  std::string history_json;
  auto* history = app.add_subcommand("history", "The results history: runs, a metric over time");
  history->add_option("--history", ho.path, "The history file (default: $RAYBENCH_HISTORY,\nelse results/history.sqlite)")->type_name("FILE");
  history->add_option("--filter", ho.filter, "Only figures whose section/name matches this\nregex");
  history->add_option("--metric", ho.metric, "Follow this metric across the runs (e.g.\ntests_per_s, mrays_per_s)");
  history->add_option("--plot", ho.plot, "Draw the metric across the runs into this PNG\n('-': stdout, the table then to stderr)")->type_name("FILE");
  add_json(history, history_json, "Write the runs or the series as JSON to FILE\n(no FILE: stdout instead of the table)");
  history->footer(
      "Runs of bench, trace, render, accuracy and report are kept with --history FILE\n"
      "or RAYBENCH_HISTORY (report: results/history.sqlite by default), keyed by the\n"
      "git revision and dirty flag the binary was built from, its build flags and\n"
      "PGO phase, the machine and the time. Without --metric: the runs. With --metric:\n"
      "its value in every run (several figures: their geometric mean and range).");

  // ---- machine ----
  std::string machine_json;
  // ---- plan ----
  std::string plan_scene, plan_json, plan_model = "auto";
  bool plan_verify = false;
  auto* plan = app.add_subcommand("plan", "How a scene is modelled for tracing, and why");
  Positionals plan_args{plan, {}, {{"--json", &plan_json}}};
  add_positional(plan_args, "scene", plan_scene, "A scene, as `raybench info` takes it");
  plan->add_option("--model", plan_model, "auto (what the scene needs), fast or exact")
      ->check(one_of({"auto", "fast", "exact"}))->capture_default_str();
  plan->add_flag("--verify", plan_verify, "Run the lab cases every choice rests on and\nshow their failure figures (a few seconds)");
  add_json(plan, plan_json, "Write the profile and the plan as JSON to\nFILE (no FILE: stdout instead of the text)");
  plan->footer(
      "Model no more than a scene needs. The scene's numerical profile per primitive\n"
      "kind (sizes, coordinates against them, how far away each kind is seen), then\n"
      "the plan: the frame of reference coordinates are taken in before they are\n"
      "rounded to float, each kind's method, precision and storage, the slab test\n"
      "and where secondary rays start, each with its reason and the accuracy lab's\n"
      "cases it rests on. `trace` and `render` follow the plan (--model auto).");

  auto* mach = app.add_subcommand("machine", "The machine and build recorded with results");
  add_json(mach, machine_json, "The JSON block every result carries, to FILE\n(no FILE: stdout)");

  // A misspelled command gets the closest one's name, before CLI11 would answer "A subcommand is
  // required" or reject the argument.
  std::vector<std::string> commands;
  for (const auto* s : app.get_subcommands({})) commands.push_back(s->get_name());
  std::string sub_name;
  if (argc > 1 && argv[1][0] != '-') {
    sub_name = argv[1];
    if (std::find(commands.begin(), commands.end(), sub_name) == commands.end()) {
      std::cerr << "raybench: '" << sub_name << "' is not a command" << did_you_mean(sub_name, commands)
                << " (raybench --help lists them)\n";
      return kExitError;
    }
  }
  if (argc == 1) {
    std::cerr << app.help() << "\nraybench: a command is required\n";
    return kExitError;
  }
  install_interrupt_handlers(sub_name);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::string msg = e.what();
    // An unknown option: name the closest option of the command.
    if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
      const CLI::App* sub = sub_name.empty() ? &app : app.get_subcommand(sub_name);
      std::vector<std::string> opts;
      for (const auto* o : sub->get_options())
        for (const auto& l : o->get_lnames()) opts.push_back("--" + l);
      for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a.rfind("--", 0) == 0 && msg.find(a) != std::string::npos) {
          msg += did_you_mean(a.substr(0, a.find('=')), opts);
          break;
        }
      }
    }
    std::cerr << error_line(sub_name.empty() ? "" : sub_name, "", msg) << " (raybench " << (sub_name.empty() ? "" : sub_name + " ")
              << "--help)\n";
    return kExitError;
  }

  for (const Positionals* p : {&info_args, &trace_args, &render_args, &compare_args, &plan_args}) {
    if (!*p->sub) continue;
    if (const std::string why = complete_positionals(*p); !why.empty()) {
      std::cerr << error_line(p->sub->get_name(), "", why) << " (raybench " << p->sub->get_name() << " --help)\n";
      return kExitError;
    }
  }

  // Every output is checked before the work starts: a long run must not end in "cannot write".
  std::vector<std::pair<CLI::App*, std::string>> files = {
      {report, ro.json_file}, {ops, ops_json},       {bench, bench_json}, {info, info_json},         {query, query_json},
      {trace, trace_json},    {render, render_json}, {render, rdo.out},   {accuracy, accuracy_json}, {csg, csg_json},
      {compare, compare_json}, {history, history_json}, {history, ho.plot}, {mach, machine_json}, {plan, plan_json}, {info, info_dump}};
  for (const auto& [sub, path] : files) {
    if (!*sub || path.empty() || path == "-") continue;
    if (const std::string why = check_output_file(path); !why.empty()) {
      std::cerr << error_line(sub->get_name(), path, why) << "\n";
      return kExitError;
    }
  }
  if (*report)
    if (const std::string why = check_output_dir(ro.out); !why.empty()) {
      std::cerr << error_line("report", ro.out, why) << "\n";
      return kExitError;
    }

  // The results history, opened (and created) before the work starts too.
  std::unique_ptr<History> hist;
  const std::string cmdline = command_line(argc, argv);
  auto open_history = [&](const std::string& option, const std::string& fallback) {
    const std::string path = history_path(option, fallback);
    if (path.empty()) return true;
    try {
      hist = std::make_unique<History>(path);
    } catch (const std::exception& e) {
      std::cerr << error_line(sub_name, "", e.what()) << "\n";
      return false;
    }
    return true;
  };
  auto keep = [&](const std::string& kind, const nlohmann::json& doc) {
    nlohmann::json m = machine_of(doc);
    if (m.is_null()) m = machine().json();
    const long long id = hist->store(kind, cmdline, m, figures_of(kind, doc).figures);
    std::cerr << "kept as run " << id << " in the results history " << hist->path() << "\n";
  };
  auto recorder = [&](const std::string& kind) -> std::function<void(const nlohmann::json&)> {
    if (!hist) return {};
    return [&, kind](const nlohmann::json& doc) { keep(kind, doc); };
  };

  int rc = kExitOk;
  try {
    if (*report) {
      ro.json = report->count("--json") > 0;
      if (ro.quick && report->count("--repetitions") == 0) ro.repetitions = 2;
      if (ro.quick && report->count("--min-time") == 0) ro.min_time = 0.005;
      if (!report_no_history && !open_history(report_history, kReportHistory)) return kExitError;
      rc = run_report(ro);
      if (rc == 0 && hist) {
        const ResultSet r = load_results(ro.out);
        const long long id = hist->store("report", cmdline, r.machine.is_null() ? machine().json() : r.machine, r.figures);
        std::cerr << "kept as run " << id << " in the results history " << hist->path() << "\n";
      }
    } else if (*ops) {
      rc = run_ops_command(ops_notes, ops_filter, json_out(ops, ops_json));
    } else if (*bench) {
      if (!bench_list && !open_history(bench_history, "")) return kExitError;
      JsonOut out = json_out(bench, bench_json);
      out.record = recorder("bench");
      rc = run_bench_command(bo, bench_list, out);
    } else if (*info) {
      rc = info->count("--dump-json") ? run_dump_scene_command(info_scene, info_dump)
                                      : run_info_command(info_scene, json_out(info, info_json));
    } else if (*query) {
      if (query->count("--json") && !query_json.empty() && query_json != "-") {
        std::ostringstream f;
        rc = run_query(std::cin, f, std::cerr, query_double);
        try {
          rb::write_output(query_json, f.str());
        } catch (const std::exception& e) {
          std::cerr << error_line("query", query_json, e.what()) << "\n";
          rc = kExitError;
        }
      } else {
        rc = run_query(std::cin, std::cout, std::cerr, query_double);
      }
    } else if (*trace) {
      if (!open_history(trace_history, "")) return kExitError;
      JsonOut out = json_out(trace, trace_json);
      out.record = recorder("trace");
      rc = run_trace_command(to, out);
    } else if (*render) {
      if (!open_history(render_history, "")) return kExitError;
      JsonOut out = json_out(render, render_json);
      out.record = recorder("render");
      rc = run_render_command(rdo, out);
    } else if (*accuracy) {
      if (!accuracy_list && !open_history(accuracy_history, "")) return kExitError;
      JsonOut out = json_out(accuracy, accuracy_json);
      out.record = recorder("accuracy");
      rc = run_accuracy_command(ao, accuracy_list, out);
    } else if (*csg) {
      rc = run_csg_command(csg_reps, csg_rays, csg_markdown, csg_filter, json_out(csg, csg_json));
    } else if (*compare) {
      co.threshold = compare_threshold >= 0 ? compare_threshold / 100 : -1;
      co.noise = compare_noise / 100;
      rc = run_compare_command(compare_a, compare_b, co, compare_markdown, json_out(compare, compare_json));
    } else if (*history) {
      rc = run_history_command(ho, json_out(history, history_json));
    } else if (*plan) {
      rc = run_plan_command(plan_scene, plan_model, plan_verify, json_out(plan, plan_json));
    } else if (*mach) {
      rc = run_machine_command(json_out(mach, machine_json));
    }
  } catch (const NothingToDo& e) {
    std::cerr << error_line(sub_name, "", e.what()) << "\n";
    rc = kExitNothing;
  } catch (const std::exception& e) {
    std::cerr << error_line(sub_name, "", e.what()) << "\n";
    rc = kExitError;
  }
  // The table or JSON printed on standard output must have got there too (a full disk, /dev/full).
  std::cout.flush();
  if (!std::cout && rc == kExitOk) {
    std::cerr << error_line(sub_name, "", "cannot write standard output") << "\n";
    rc = kExitError;
  }
  return rc;
}
