// `raybench trace SCENE`: trace a whole scene with the BVH, beside Embree on the same rays.
#include "apps/commands.hpp"
#include "apps/trace_run.hpp"

#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <memory>

namespace rb::app {

Command add_trace_command(CLI::App& app) {
  auto o = std::make_shared<TraceRunOptions>();
  auto json_out = std::make_shared<std::string>();
  auto* cmd = app.add_subcommand("trace", "Trace a whole scene through the BVH (binary or 8-wide, single rays or packets, TBB threads) "
                                          "beside Embree on the same rays: Mrays/s, build time, memory, traversal cost, mismatch rate");
  cmd->add_option("scene", o->scene, "A .obj/.ply/.nff/.json file, spd:NAME[:SIZE], lecture:NAME or csg:NAME (as `raybench info`)")->required();
  cmd->add_option("--rays", o->ray_set, "Ray set: primary, shadow, diffuse or random")
      ->check(CLI::IsMember({"primary", "shadow", "diffuse", "random"}))->capture_default_str();
  cmd->add_option("--threads", o->threads, "Threads for tracing (TBB) and for both builds")->check(CLI::Range(1, 256))->capture_default_str();
  cmd->add_option("--packet", o->packet, "Rays per packet: 1 (single rays), 8 or 16")->check(CLI::IsMember({1, 8, 16}))->capture_default_str();
  cmd->add_option("--layout", o->layout, "BVH layout: wide (8-wide SoA nodes) or binary (single rays only)")
      ->check(CLI::IsMember({"wide", "binary"}))->capture_default_str();
  cmd->add_option("--count", o->count, "About this many rays (primary: the nearest square image of 4x4 tiles)")
      ->check(CLI::Range(std::size_t(1), std::size_t(1) << 28))->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed of the ray set")->capture_default_str();
  cmd->add_flag("--robust", o->robust, "Robust slab test (Ize 2013: far distance scaled by 1 + 2 gamma(3)) instead of the FMA form");
  cmd->add_option("-r,--repetitions", o->repetitions, "Timed runs (the median is quoted)")->check(CLI::Range(1, 100))->capture_default_str();
  cmd->add_option("--brute", o->brute_rays, "Rays checked against the brute-force loop over all objects (-1: a budget by scene size)")
      ->capture_default_str();
  cmd->add_flag("!--no-embree", o->embree, "Skip Embree");
  cmd->add_option("--json", *json_out, "Write the result as JSON to this file (no argument or '-': stdout) instead of the table")
      ->expected(0, 1);
  return {cmd, [o, json_out, cmd]() -> int {
    try {
      const nlohmann::json j = run_trace(*o, true);
      return write_result("trace", cmd->count("--json") > 0, *json_out, [&] { return trace_text(j); }, [&] { return j; });
    } catch (const std::exception& e) {
      std::cerr << "raybench trace: " << o->scene << ": " << e.what() << "\n";
      return 1;
    }
  }};
}

}  // namespace rb::app
