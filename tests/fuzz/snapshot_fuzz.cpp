// libFuzzer target: the snapshot loader (snapshot_fuzz_one.hpp states the
// contract). Built only with clang and -DLOCKSTEP_FUZZ=ON; run by
// tests/fuzz/run_fuzz.sh beside scene_fuzz (docs/FUZZING.md).
#include <cstddef>
#include <cstdint>

#include "snapshot_fuzz_one.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  (void)lockstep::fuzz::fuzz_one_snapshot(data, size);
  return 0;
}
