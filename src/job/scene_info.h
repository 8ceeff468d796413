// scene_info.h — what `wavepath info` says of a scene: its primitives,
// image, load time, BVH, GPU memory, instances, photon map, the kinds its
// kernels hold, its media and gpu-sort's shade classes (the command line
// prints it; the Python module's Scene.info returns it).
#pragma once

#include <string>

#include "render/compiled_scene.h"
#include "scene/scene.h"

namespace wp {

// The options `info` compiles a scene with for `variant` (a kernel variant
// or "cpu", whose BVH layout it builds; checked): `base` (the command
// line's: none; the Python module's: the Scene's overrides) with the photon
// map traced on the host, so that it can be described.
RenderOptions info_options(const RenderOptions& base, const std::string& variant);

// The lines `wavepath info` prints of `scene` (loaded from `path` in
// `loadSeconds`) compiled as `cs`, each ending in a newline.
std::string scene_info(const std::string& path, const Scene& scene, const CompiledScene& cs, double loadSeconds);

}  // namespace wp
