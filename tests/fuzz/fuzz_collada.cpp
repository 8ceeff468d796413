// libFuzzer target: arbitrary bytes as a CS184 COLLADA scene (see fuzz_loaders.h).
#include "fuzz/fuzz_loaders.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  wp::load_fuzzed(wp::FuzzedInput::Collada, data, size);
  return 0;
}
