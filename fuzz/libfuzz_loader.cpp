// A libFuzzer target per scene loader (clang's libFuzzer, Debian package clang): the `libfuzzer`
// preset builds fuzz_obj, fuzz_ply, fuzz_nff and fuzz_json from this file (RB_FUZZ_FORMAT names
// the loader), with ASan and UBSan. Every input must load or throw SceneError, and a loaded scene
// must pass check_numbers or be refused by it with SceneError: no crash, hang, leak or other
// exception. Run one for longer with e.g.
//   build/libfuzzer/fuzz/fuzz_ply -max_total_time=600 -max_len=4096 CORPUS_DIR
#include "scene/csg_scene.hpp"
#include "scene/loaders.hpp"
#include "scene/sources.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  using namespace rb::scene;
  try {
#if RB_FUZZ_FORMAT == 1
    const Scene s = parse_obj(text, "input.obj");
#elif RB_FUZZ_FORMAT == 2
    const Scene s = parse_ply(text, "input.ply");
#elif RB_FUZZ_FORMAT == 3
    const Scene s = parse_nff(text, "input.nff");
#else
    const Scene s = parse_json_scene(text, "input.json");
#endif
    check_numbers(s, "input");
    (void)s.bounds();
  } catch (const SceneError&) {
  }
  return 0;
}
