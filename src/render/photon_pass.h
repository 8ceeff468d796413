// photon_pass.h — the photon map of a photon-mapping render
// (INTEGRATOR_PHOTONS): photons traced from the lights by the shared code
// (photons.glsl), on the host here or by the GPU renderer's photons kernel
// (WavefrontRenderer, photon_tracer.cpp), then balanced into a kd-tree that
// the kernels and the CPU reference both gather from.
#pragma once

#include "bvh/photon_map.h"
#include "render/compiled_scene.h"

namespace wp {

// The records of cs.photonCount photons of seed cs.photonSeed, traced on
// the host: photon by photon, each one's in the order it left them, with
// the photon's index in `axis` (which balance_photons sets). Throws
// RenderError where a photon's ray outran the traversal step cap.
std::vector<shader::Photon> trace_photons(const CompiledScene& cs);

// Photon records, in the order trace_photons gives them, balanced into the
// kd-tree the kernels read (BINDING_PHOTONS). The same records give the
// same map.
std::vector<shader::Photon> balance_photons(const std::vector<shader::Photon>& records);

// A built photon map as the kernels read it.
std::vector<shader::Photon> pack_photon_map(const PhotonMap& map);

}  // namespace wp
