// rng.glsl — random numbers shared by the kernels and the CPU reference.
// Each path owns a 32-bit PCG state (PCG-RXS-M-XS 32/32); paths are seeded by
// hashing (pixel, sample index, user seed), so any sample can be reproduced on
// its own and GPU and CPU draw the same sequence for the same sample.
#ifndef WP_RNG_GLSL
#define WP_RNG_GLSL

// PCG hash (Jarkko & Olano, "Hash Functions for GPU Rendering", JCGT 2020).
uint pcg_hash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

uint rng_seed(uint pixel, uint sampleIndex, uint seed) {
  return pcg_hash(pixel ^ pcg_hash(sampleIndex ^ pcg_hash(seed)));
}

uint rng_next_uint(INOUT(uint) state) {
  uint old = state;
  state = old * 747796405u + 2891336453u;
  uint word = ((old >> ((old >> 28u) + 4u)) ^ old) * 277803737u;
  return (word >> 22u) ^ word;
}

// Uniform in [0, 1): the top 24 bits, so the result is exactly representable.
float rng_next(INOUT(uint) state) {
  return float(rng_next_uint(state) >> 8u) * (1.0f / 16777216.0f);
}

#endif  // WP_RNG_GLSL
