// `raybench render SCENE -o image.png`: the recursive ray tracer, with ray and test statistics.
#include "apps/commands.hpp"
#include "apps/render_run.hpp"
#ifdef RB_HAVE_MPI
#include "render/mpi.hpp"
#endif

#include <iostream>

namespace rb::app {

int run_render_command(const RenderRunOptions& o, const JsonOut& out) {
  try {
#ifdef RB_HAVE_MPI
    render::MpiSession mpi(nullptr, nullptr);
    const nlohmann::json j = run_render(o, mpi.active() ? &mpi : nullptr);
    if (mpi.rank() != 0) return 0;
#else
    const nlohmann::json j = run_render(o, nullptr);
#endif
    return write_result("render", out.json, out.file, [&] { return render_text(j); }, [&] { return j; });
  } catch (const std::exception& e) {
    std::cerr << "raybench render: " << o.scene << ": " << e.what() << "\n";
    return 1;
  }
}

}  // namespace rb::app
