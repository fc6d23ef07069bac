// The accuracy lab: named, seeded adversarial cases per primitive family, exact references
// computed from the same float inputs, and per method x precision x case failure figures.
//
// A case is a set of (ray, primitive) tests built only from float inputs (the rays as stored by
// make_ray, the primitives as stored by their builders). Its reference is computed from exactly
// those floats: GMP rationals decide hit or miss where a ray meets a triangle's edge or a box's
// slab plane, MPFR (512 bits) gives the roots of the quadrics, a long double isolation of the
// torus quartic (re-centred at the closest approach) gives the torus roots. The methods run as
// scalar float, scalar double (the same floats, widened) and 8-lane float SIMD (rays in lanes).
//
// The lab's translation units are compiled with FMA contraction on in every preset, so the
// figures are those of the release build (accuracy/CMakeLists.txt).
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rb::scene {
struct Scene;
}
namespace rb::kinds {
enum class Kind : std::uint8_t;
}

namespace rb::acc {

// The lab's cases through the whole tracer (the BVH rows of the closed-mesh triangle cases, the
// whole scenes): in the library rb_accuracy_tracer, which links the tracer; rb_accuracy alone runs
// the kernel families only.
struct TracerCases;
const TracerCases& tracer_cases();

// Timed rounds of a whole-scene case (family "scene") by default; the report's quick mode takes fewer.
inline constexpr int kWholeSceneRounds = 15;

struct Options {
  bool full = false;              // larger ray counts and every case variant
  std::uint32_t seed = 1;         // seed of every generator
  std::size_t rays = 0;           // rays per case (0: 10000 quick, 100000 full)
  std::string filter;             // regex searched in "family/case" (POSIX extended; empty: all)
  bool timing = true;             // measure ns per test (off: every ns figure is NaN)
  // Timed rounds of each whole-scene case (family "scene"; accuracy/scenes.cpp), with timing on.
  int scene_rounds = kWholeSceneRounds;
  // Where the embedded meshes are (their folder `meshes/`): the scene family's real meshes (the
  // bunny, the dragon) are traced from there; empty, or real_meshes false: those cases are left out.
  std::string data_dir;
  bool real_meshes = true;
  std::function<void(double, const std::string&)> progress;  // fraction done, what
  // &tracer_cases() to include the cases through the whole tracer; nullptr: the kernels' only.
  const TracerCases* tracer = nullptr;
};

// One method in one precision on one case. Rates are per million tests (rays for leak_ppm).
// NaN where a figure does not apply (no t to compare, no closed mesh, no spawned rays).
struct Row {
  std::string family, method, precision, case_name, what;
  std::size_t rays = 0, tests = 0;
  double false_hit_ppm = 0, false_miss_ppm = 0, leak_ppm = 0, multi_hit_ppm = 0, nan_ppm = 0, wrong_root_ppm = 0;
  double t_err_ulp_p50 = 0, t_err_ulp_p99 = 0, t_err_ulp_max = 0, scaled_err_p99 = 0;
  double self_hit_ppm = 0, iterations = 0, ns_per_test = 0;
  // Whole scenes (family "scene") with timing: the seconds of each timed round, the models of a
  // scene taking turns within every round (so that a ratio of two models can be taken round by
  // round); ns_per_test is from their median.
  std::vector<double> round_seconds;
  std::size_t false_hits = 0, false_misses = 0, leaks = 0, self_hits = 0, nans = 0, wrong_roots = 0;
  nlohmann::json json() const;
  // A row back from json() (a report's record: `raybench report --from`). Throws on a missing key.
  static Row from_json(const nlohmann::json& j);
  // The failure figure of the "where each method fails" table, in ppm: false hits + false misses
  // + self-hits + NaN + wrong roots; on closed meshes leaks + NaN + wrong (farther) hits.
  double failure_ppm() const;
};

// A family's case list: name and one-line description, for --list and the report.
struct CaseInfo {
  std::string family, name, what;
};
// Every case, with the tracer's (families "bvh" and "scene") when `tracer` is given.
std::vector<CaseInfo> case_list(const TracerCases* tracer);

// Whether --filter selects the case "family/case": a POSIX extended regular expression searched in
// it, as every --filter of the command line. Throws std::regex_error on a bad expression.
bool selects(const std::string& filter, const std::string& family_case);

// Runs every selected case of every family. Rows come out in a stable order.
std::vector<Row> run_lab(const Options& o);

// (rb_accuracy_tracer) One whole scene traced under the fast, auto and exact models (rows in that order) against the
// exact reference (the rows of family "scene", accuracy/scenes.cpp): about `rays` primary rays
// through the scene's view and a spawned secondary ray per hit. Where the auto model stores
// primitives apart in local frames, a fourth row, method kApartInDouble, is its plan with them in
// double. `timed_rounds` timed rounds (none: no timing) in which the rows' trees take turns, each
// turn repeating the trace to last about kWholeSceneTurn seconds for the fast model.
inline constexpr const char* kApartInDouble = "auto_apart_double";
inline constexpr double kWholeSceneTurn = 0.015;
std::vector<Row> whole_scene_rows(const scene::Scene& s, const std::string& case_name, const std::string& what, std::size_t rays,
                                  int timed_rounds, std::uint64_t seed);
// (rb_accuracy_tracer) What storing a kind apart costs (the rows of family "storage"; the evidence
// behind each kind's kinds::StorageCost): the scene under the auto plan with every primitive of kind
// `k` in its batch (method kStorageFloat), then stored apart in local frames (kStorageLocal) and in
// double (kStorageDouble), checked and timed as whole_scene_rows does. The kind's share of a ray's
// time is what changes, so a scene of that kind alone (a mesh, a field of spheres) shows it best.
inline constexpr const char* kStorageFloat = "in_frame";
inline constexpr const char* kStorageLocal = "local_frames";
inline constexpr const char* kStorageDouble = "double";
std::vector<Row> storage_rows(const scene::Scene& s, kinds::Kind k, const std::string& case_name, const std::string& what,
                              std::size_t rays, int timed_rounds, std::uint64_t seed);
}  // namespace rb::acc
