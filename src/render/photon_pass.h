// photon_pass.h — the photon map of a photon-mapping render
// (INTEGRATOR_PHOTONS): photons traced from the lights by the shared code
// (photons.glsl, trace_photon) on the host, balanced into a kd-tree and
// packed for the kernels and the CPU reference, which both gather from it.
#pragma once

#include "bvh/photon_map.h"
#include "render/compiled_scene.h"

namespace wp {

// A built photon map as the kernels read it (BINDING_PHOTONS).
std::vector<shader::Photon> pack_photon_map(const PhotonMap& map);

// Traces `count` photons through compiled scene cs (seed: which photons)
// and stores their records in cs.photons, a balanced kd-tree; sets
// cs.params.photons.x to their number.
void build_photon_map(CompiledScene& cs, uint32_t count, uint32_t seed);

}  // namespace wp
