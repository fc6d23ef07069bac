// One `raybench render` run (also used by the report's Rendering section): load the scene, build
// the BVH, render it recursively (one process, or this rank's tiles under MPI), and describe the
// result as JSON and as a summary with Haines' published SPD statistics beside ours.
#pragma once

#include "apps/render_options.hpp"
#include "render/render.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace rb::render {
class MpiSession;
}

namespace rb::app {

// Haines' published figures for a classical ray tracer on an SPD scene at its default size (eye
// hits, reflection, refraction and shadow rays; his hierarchy's test counts where given).
struct HainesFigures {
  const char* scene;
  double eye_hit, reflect, refract, shadow;
  double poly_tests, sphere_tests, box_tests;  // < 0: not published
};
std::optional<HainesFigures> haines_figures(const std::string& spd_name);

// Renders; on MPI rank 0 (or without MPI) returns the result and writes the PNG. `mpi` may be null.
nlohmann::json run_render(const RenderRunOptions& o, const render::MpiSession* mpi = nullptr);
// The summary the terminal shows, from run_render's JSON (apps/render_text.cpp).
std::string render_text(const nlohmann::json& j);

}  // namespace rb::app
