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

// Two, three or four numbers, drawn in order: C++ leaves the order in which
// a constructor's arguments are evaluated open (GLSL goes left to right), so
// vec2(rng_next(s), rng_next(s)) would give the kernels and the CPU
// reference the same numbers in other places.
vec2 rng_next2(INOUT(uint) state) {
  float x = rng_next(state);
  float y = rng_next(state);
  return vec2(x, y);
}

vec3 rng_next3(INOUT(uint) state) {
  vec2 xy = rng_next2(state);
  float z = rng_next(state);
  return vec3(xy, z);
}

vec4 rng_next4(INOUT(uint) state) {
  vec2 xy = rng_next2(state);
  vec2 zw = rng_next2(state);
  return vec4(xy, zw);
}

// ---- correlated multi-jittered sampling (Kensler 2013) ------------------------
// Sample s of an N-sample pattern p: the N points are jittered in an m x n grid
// (m = floor(sqrt(N))) and stratified in each 1D projection into N strata;
// the pattern is shuffled by hashing, so each pixel gets its own.

// A pseudo-random permutation of [0, l): hash within the next power of two,
// walking the cycle until the value falls below l.
uint cmj_permute(uint i, uint l, uint p) {
  uint w = l - 1u;
  w |= w >> 1u;
  w |= w >> 2u;
  w |= w >> 4u;
  w |= w >> 8u;
  w |= w >> 16u;
  do {
    i ^= p;
    i *= 0xe170893du;
    i ^= p >> 16u;
    i ^= (i & w) >> 4u;
    i ^= p >> 8u;
    i *= 0x0929eb3fu;
    i ^= p >> 23u;
    i ^= (i & w) >> 1u;
    i *= 1u | p >> 27u;
    i *= 0x6935fa69u;
    i ^= (i & w) >> 11u;
    i *= 0x74dcb303u;
    i ^= (i & w) >> 2u;
    i *= 0x9e501cc3u;
    i ^= (i & w) >> 2u;
    i *= 0xc860a3dfu;
    i &= w;
    i ^= i >> 5u;
  } while (i >= l);
  return (i + p) % l;
}

// A hashed float in [0, 1) for index i of pattern p.
float cmj_float(uint i, uint p) {
  i ^= p;
  i ^= i >> 17u;
  i ^= i >> 10u;
  i *= 0xb36534e5u;
  i ^= i >> 12u;
  i ^= i >> 21u;
  i *= 0x93fc4795u;
  i ^= 0xdf6e307fu;
  i ^= i >> 17u;
  i *= 1u | p >> 18u;
  return float(i >> 8u) * (1.0f / 16777216.0f);
}

vec2 cmj_sample(uint s, uint count, uint p) {
  uint m = max(uint(sqrt(float(count))), 1u);
  uint n = (count + m - 1u) / m;
  s = cmj_permute(s, count, p * 0x51633e2du);
  uint sx = cmj_permute(s % m, m, p * 0x68bc21ebu);
  uint sy = cmj_permute(s / m, n, p * 0x02e5be93u);
  float jx = cmj_float(s, p * 0x967a889bu);
  float jy = cmj_float(s, p * 0x368cc8b7u);
  return vec2((float(sx) + (float(sy) + jx) / float(n)) / float(m), (float(s) + jy) / float(count));
}

#endif  // WP_RNG_GLSL
