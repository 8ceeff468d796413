// ray_sets.h — the fixed ray sets of the traversal benchmarks (`bench
// --raycast`, `bench --simt`): camera rays through every pixel, then from
// every hit one cosine-distributed bounce and one shadow ray that next-event
// estimation aims at an emitter, leaving the surface as the path tracer does.
#pragma once

#include <vector>

#include "render/compiled_scene.h"

namespace wp::bench {

struct RaySets {
  std::vector<shader::ShadowRay> primary, bounce, shadow;
  std::vector<float> primaryHits;  // the CPU traversal's distances: the primary rays' reference
};

// The rays in the order the kernels take them: camera rays in pixel order,
// bounce and shadow rays in the order of the pixels whose hits they leave.
RaySets make_rays(const CompiledScene& cs);

}  // namespace wp::bench
