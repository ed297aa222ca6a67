// libFuzzer target: scene loader + a few frames of the fixed and double
// engines (scene_fuzz_one.hpp states the contract). Built only with clang and
// -DLOCKSTEP_FUZZ=ON; run by tests/fuzz/run_fuzz.sh (docs/FUZZING.md).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "scene_fuzz_one.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A FuzzFinding (or any other exception) escapes: libFuzzer reports it as a
  // crash ("uncaught exception") and saves the input.
  (void)lockstep::fuzz::fuzz_one_scene(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
