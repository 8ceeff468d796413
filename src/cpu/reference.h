// reference.h — the CPU reference renderer. It runs the integrator through the
// very functions the kernels run (shaders/shared/*.glsl compiled as C++), one
// sample at a time instead of one stage at a time, on all cores with TBB.
#pragma once

#include "image/image.h"
#include "render/compiled_scene.h"
#include "util/progress.h"

namespace wp {

// threads <= 0: all cores. Throws RenderError if any traversal hit its step cap.
ImageStats render_cpu(const CompiledScene& scene, int threads, Progress& progress);

}  // namespace wp
