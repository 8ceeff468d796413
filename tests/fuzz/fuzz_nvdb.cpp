// libFuzzer target: arbitrary bytes as a NanoVDB file, a medium's density grid (see fuzz_loaders.h).
#include "fuzz/fuzz_loaders.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  wp::load_fuzzed(wp::FuzzedInput::Nvdb, data, size);
  return 0;
}
