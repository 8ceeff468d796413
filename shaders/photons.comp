#version 460
// Photons from the lights (INTEGRATOR_PHOTONS), traced by the shared code of
// photons.glsl: photon pc.waveStart + i of pc.sampleIndex, seed pc.photonSeed,
// rides in path slot i. PHOTONS_EMIT starts them; each PHOTONS_BOUNCE
// dispatch takes every live one to its next surface, one ray per invocation
// and dispatch with the whole step cap (lavapipe's loop budget). A record
// is appended to the shadow-ray buffer, two texels each, with the photon's
// slot in `axis`: the host puts them in order, photon by photon, bounce by
// bounce (src/gpu/photon_tracer.cpp), so the map does not depend on the
// order the invocations ran in.
#extension GL_GOOGLE_include_directive : require
#include "shared/kernel.glsl"

// A PhotonPath in a path slot's first three texels (four in the spectral
// mode: its wavelengths, and its power's fourth channel).
void write_photon_path(uint i, PhotonPath p) {
  uint at = i * PATH_STATE_TEXELS;
  pathTexelsOut[at] = uvec4(floatBitsToUint(p.origin), p.rng);
  pathTexelsOut[at + 1u] = uvec4(floatBitsToUint(p.dir), p.bounce);
  pathTexelsOut[at + 2u] = uvec4(floatBitsToUint(spectrum_xyz(p.power)), p.alive);
  if (spectral_mode()) pathTexelsOut[at + 3u] = uvec4(floatBitsToUint(p.wavelengths), p.heroOnly, floatBitsToUint(spectrum_values(p.power).w), 0u);
}

PhotonPath read_photon_path(uint i) {
  int at = int(i) * PATH_STATE_TEXELS;
  uvec4 a = texelFetch(pathTexels, at);
  uvec4 b = texelFetch(pathTexels, at + 1);
  uvec4 c = texelFetch(pathTexels, at + 2);
  PhotonPath p;
  p.origin = texel_xyz(a);
  p.rng = a.w;
  p.dir = texel_xyz(b);
  p.bounce = b.w;
  p.alive = c.w;
  uvec4 d = spectral_mode() ? texelFetch(pathTexels, at + 3) : uvec4(0u);
  p.wavelengths = uintBitsToFloat(d.x);
  p.heroOnly = d.y;
  p.power = spectrum_at(vec4(texel_xyz(c), uintBitsToFloat(d.z)));
  return p;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.pathCount) return;
  if (pc.phase == PHOTONS_EMIT) {
    write_photon_path(i, photon_emit(pc.waveStart + i, pc.sampleIndex, pc.photonSeed));
    return;
  }
  PhotonPath p = read_photon_path(i);
  if (p.alive == 0u) return;
  Photon ph;
  uint status = photon_bounce(p, ph);
  if ((status & PHOTON_TRUNCATED) != 0u) atomicAdd(counters[COUNTER_TRUNCATED], 1u);
  if ((status & PHOTON_STORED) != 0u) {
    uint at = atomicAdd(counters[COUNTER_PHOTON_RECORDS], 1u) * PHOTON_TEXELS;
    shadowRayTexelsOut[at] = uvec4(floatBitsToUint(ph.position), i);
    shadowRayTexelsOut[at + 1u] = uvec4(floatBitsToUint(ph.power), ph.from);
  }
  if (p.alive != 0u) atomicAdd(counters[COUNTER_PHOTONS_ALIVE], 1u);
  write_photon_path(i, p);
}
