// `raybench render SCENE [-o image.png]`: the recursive ray tracer, with ray and test statistics.
#include "apps/cli.hpp"
#include "apps/commands.hpp"
#include "apps/results/machine.hpp"
#include "apps/render_run.hpp"
#include "core/output_file.hpp"
#ifdef RB_HAVE_MPI
#include "render/mpi.hpp"
#endif

#include <fmt/format.h>

#include <cctype>
#include <filesystem>
#include <iostream>

namespace rb::app {

// The image's name when -o is not given: the scene's, in the current folder ("data/bunny.obj" ->
// "bunny.png", "spd:balls:3" -> "spd_balls_3.png").
std::string default_image_name(const std::string& scene) {
  std::string n = is_generated_scene(scene) ? scene : std::filesystem::path(scene).stem().string();
  for (char& c : n)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
  return (n.empty() ? std::string("render") : n) + ".png";
}

int run_render_command(const RenderRunOptions& opt, const JsonOut& json_out) {
  RenderRunOptions o = opt;
  JsonOut out = json_out;  // the table moves to stderr when the image is standard output
  int rank = 0;
#ifdef RB_HAVE_MPI
  render::MpiSession mpi(nullptr, nullptr);
  rank = mpi.rank();
#endif
  const bool talk = rank == 0;
  if (!stdout_for_one_output("render", "-o", o.out, out, talk)) return kExitError;
  if (!is_generated_scene(o.scene))
    if (const std::string why = check_input_file(o.scene); !why.empty()) {
      if (talk) std::cerr << error_line("render", o.scene, why) << "\n";
      return kExitError;
    }
  std::string warn;
  o.threads = resolve_threads(o.threads, &warn);
  if (talk) {
    std::cerr << fmt::format("raybench render {}: {} thread(s) of {} hardware threads, {} warm-up + {} timed render(s)\n", o.scene, o.threads,
                             hardware_threads(), o.warmup, o.repetitions);
    if (!warn.empty()) std::cerr << wrap_words(warn);
  }
  if (o.out.empty()) {
    // Every render writes its image: without -o, the scene's name in the current folder.
    o.out = default_image_name(o.scene);
    if (const std::string why = check_output_file(o.out); !why.empty()) {
      if (talk) std::cerr << error_line("render", o.out, why) << "\n";
      return kExitError;
    }
    if (talk) std::cerr << "raybench render: no -o given: the image goes to " << o.out << " in the current folder\n";
  }
  nlohmann::json j;
  try {
#ifdef RB_HAVE_MPI
    j = run_render(o, mpi.active() ? &mpi : nullptr);
    if (!talk) return kExitOk;
#else
    j = run_render(o, nullptr);
#endif
  } catch (const NothingToDo& e) {
    if (talk) std::cerr << error_line("render", o.scene, e.what()) << "\n";
    return kExitNothing;
  } catch (const std::exception& e) {
    if (talk) std::cerr << error_line("render", o.scene, e.what()) << "\n";
    return kExitError;
  }
  const double load = load_average();
  if (!o.spd) j.erase("haines");  // Haines' published figures belong to his protocol only
  j["machine"] = machine().json();
  const int rc = write_result("render", out, [&] { return fit_columns(render_text(j), 6); }, [&] { return j; }, "the render result");
  if (j.contains("cv") && j["cv"].is_number())
    if (const std::string w = noise_warning(j["cv"].get<double>(), "the timed renders"); !w.empty()) std::cerr << wrap_words(w);
  if (const std::string w = busy_warning(load, o.threads * int(j.value("ranks", 1))); !w.empty()) std::cerr << wrap_words(w);
  return rc;
}

}  // namespace rb::app
