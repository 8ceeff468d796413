// libFuzzer target: arbitrary bytes as a glTF model, .gltf or .glb by the
// first byte (see fuzz_loaders.h).
#include "fuzz/fuzz_loaders.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  wp::load_fuzzed(wp::FuzzedInput::Gltf, data, size);
  return 0;
}
