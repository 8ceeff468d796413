// fuzz_loaders.h — hands arbitrary bytes to wavepath's input loaders, as
// the fuzz targets (tests/fuzz/fuzz_*.cpp, built with -DWAVEPATH_FUZZ=ON)
// and the replay of their findings in the test suite both do.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace wp {

enum class FuzzedInput {
  Scene,  // a darts JSON scene, loaded and compiled (BVH, materials, textures)
  Obj,    // a Wavefront OBJ mesh
  Image,  // an image file, after a first byte that picks its name: input.png, .exr or .tga (byte % 3)
  Partial,  // a partial render's EXR, read as `wavepath merge` and --resume read one
  Gltf,     // a glTF model, loaded and compiled, after a first byte that picks its name: input.gltf or input.glb (byte % 2)
  Collada,  // a CS184 COLLADA scene, loaded (with --consistent-lights too) and compiled
  Nvdb,     // a NanoVDB file, the density grid of a medium: read, compiled (majorant grid) and tracked through
};

// The kind a corpus folder holds: "scene", "obj", "image", "partial", "gltf", "collada" or "nvdb".
FuzzedInput fuzzed_input_named(const std::string& name);

// Writes the bytes to a file in a private temporary folder (beside a small
// valid mesh, mesh.obj, and texture, tex.png, that a fuzzed scene may name)
// and loads it as `kind`. Returns true when the loader accepted the input and
// false when it refused it with an InputError, whose message must name the
// file. Anything else escapes: another exception, a crash, a hang, or a
// sanitizer's report, each a bug.
bool load_fuzzed(FuzzedInput kind, const uint8_t* data, size_t size);

}  // namespace wp
