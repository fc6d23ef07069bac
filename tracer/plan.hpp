// How a scene is modelled for tracing: the frame of reference, each kind's method and precision,
// the slab test and the spawn offset of secondary rays. Model no more than a scene needs: the plan
// is made from the scene's numerical profile (tracer/profile.hpp) and the accuracy lab's evidence
// (which method and precision fail under which conditions), and says why it chose what it chose.
//
// Three models:
//   fast   the fixed choice of a tracer that does not look at the scene: world coordinates, the
//          cheapest method of every kind in float, the extent-based spawn epsilon;
//   auto   per scene (the default): the frame, method, precision and spawn scheme that the lab
//          measures with no failure under the scene's conditions, the cheapest such;
//   exact  the most accurate of everything: re-centred frame, each kind's most accurate method in
//          double (double storage where the kind has it), the error-bound spawn offset.
#pragma once

#include "bvh/hit.hpp"
#include "tracer/kinds.hpp"
#include "tracer/profile.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <span>
#include <string>
#include <vector>

namespace rb::tracer {

using kinds::Kind;
using kinds::kKinds;

enum class Model { fast, automatic, exact };
const char* model_name(Model m);
Model parse_model(const std::string& s);  // fast | auto | exact; throws std::invalid_argument

// Where secondary rays start (core/spawn.hpp): the fast model's extent epsilon, or each hit's own
// error bound.
enum class SpawnScheme { extent_eps, error_bound };
const char* spawn_name(SpawnScheme s);

enum class FrameKind { world, centre, camera };
const char* frame_name(FrameKind f);

struct KindPlan {
  std::size_t count = 0;    // primitives of this kind in the scene
  int method = 0;           // index into the kind's methods
  bool f64 = false;         // the kernel in double
  bool f64_storage = false; // the primitives stored in double
  std::string reason;       // why this method and precision (one line)
  std::string evidence;     // the lab cases the choice rests on ("family/case", ...)
  KindClasses classes;      // what float storage in the chosen frame does to each primitive
  // The coarse primitives stored in a batch of their own (scene indices, ascending), with the method
  // they run there; the rest of the kind stays in the batch above. Empty unless the coarse
  // primitives can change more than a negligible share of its hits and either none of them is huge
  // (over a thousand times the smallest object: local frames hold the others) or they are at most
  // kSplitShare of the kind.
  std::vector<std::uint32_t> split;
  int split_method = 0;
  // Those stored in local frames: each leaf's primitives in float relative to an origin of its own
  // (kept in double), the ray re-based there; a leaf whose primitives no origin near them holds in
  // float stays in double (tracer/leaves.hpp, LocalFrame). Otherwise all in double.
  // The cheaper storage at the kind's measured costs (`split_cost`: kinds::StorageCost).
  bool split_local = false;
  kinds::StorageCost split_cost;
  std::string split_reason;
  // The classes, counted, with the worst primitive of each ("" when none was classed: fast model).
  std::string classes_text() const;
};

// The largest share of a kind's primitives that the plan stores apart while the rest stays in float
// when some of the coarse ones are huge (no local frame holds those: they go to double); a kind
// with more coarse primitives than that, some huge, is stored in double as a whole.
inline constexpr double kSplitShare = 0.25;

struct Plan {
  Model model = Model::fast;
  // The frame: every coordinate is taken relative to `origin` (in double) before it is rounded to
  // float; rays are traced in frame coordinates.
  FrameKind frame = FrameKind::world;
  Vec3d origin{0, 0, 0};
  std::string frame_reason;
  std::array<KindPlan, kKinds> kinds{};
  // The slab test, and the bound on |ray origin| (frame coordinates, max norm) for which the
  // conservative node boxes are built: the scene's bounds, camera and lights, with a margin.
  bvh::Slab slab = bvh::Slab::conservative;
  float origin_bound = 0;
  std::string slab_reason;
  // Secondary rays: the scheme (the error bound is each hit's own: SceneAccel::spawn_base), and the
  // extent epsilon (the fast model's offset: 1e-5 of the scene's extent and distance from the
  // origin).
  SpawnScheme spawn = SpawnScheme::error_bound;
  float spawn_eps = 1e-5f;
  std::string spawn_reason;
  // The scale a primitive over a thousand times the smallest object is judged against
  // (tracer/profile.hpp, float_step_ratio): the profile's smallest object.
  double object_min = 1;

  nlohmann::json json() const;
  std::string text() const;  // the plan for a terminal: one line per choice with its reason
};

using kinds::PlanOption;
// A kind's options with the lab's evidence, cheapest first (tracer/kinds.hpp, PlanOption).
std::span<const PlanOption> plan_options(Kind k);

// What storing each kind apart costs (kinds::StorageCost; 1 and 1 for kinds that are never stored
// apart): the kinds' own measured figures, or, in tests, others.
using StorageCosts = std::array<kinds::StorageCost, kKinds>;
const StorageCosts& storage_costs();

// The plan of a scene under a model (at the kinds' own storage costs, or at `costs`).
Plan make_plan(const scene::Scene& s, Model m);
Plan make_plan(const scene::Scene& s, const Profile& p, Model m);
Plan make_plan(const scene::Scene& s, const Profile& p, Model m, const StorageCosts& costs);

}  // namespace rb::tracer
