// noise.glsl — Perlin gradient noise and turbulence for the marble texture.
// The lattice gradients come from hashing the integer cell coordinates (PCG
// hash) instead of a permutation table, so GLSL and C++ need no shared table
// and produce the same values up to floating-point contraction.
#ifndef WP_NOISE_GLSL
#define WP_NOISE_GLSL

// Dot product of offset f with one of the 12 cube-edge gradients picked by h
// (Perlin, "Improving Noise", SIGGRAPH 2002).
float perlin_gradient(uint h, vec3 f) {
  h = h & 15u;
  float a = h < 8u ? f.x : f.y;
  float b = h < 4u ? f.y : ((h == 12u || h == 14u) ? f.x : f.z);
  return ((h & 1u) == 0u ? a : -a) + ((h & 2u) == 0u ? b : -b);
}

uint perlin_hash(ivec3 c) {
  return pcg_hash(uint(c.x) + pcg_hash(uint(c.y) + pcg_hash(uint(c.z))));
}

float perlin_fade(float t) {
  return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f);
}

// Gradient noise in about [-1, 1], zero at lattice points.
float perlin_noise(vec3 p) {
  vec3 cell = floor(p);
  vec3 f = p - cell;
  ivec3 c = ivec3(int(cell.x), int(cell.y), int(cell.z));
  float wx = perlin_fade(f.x);
  float wy = perlin_fade(f.y);
  float wz = perlin_fade(f.z);
  float n000 = perlin_gradient(perlin_hash(c), f);
  float n100 = perlin_gradient(perlin_hash(c + ivec3(1, 0, 0)), f - vec3(1.0f, 0.0f, 0.0f));
  float n010 = perlin_gradient(perlin_hash(c + ivec3(0, 1, 0)), f - vec3(0.0f, 1.0f, 0.0f));
  float n110 = perlin_gradient(perlin_hash(c + ivec3(1, 1, 0)), f - vec3(1.0f, 1.0f, 0.0f));
  float n001 = perlin_gradient(perlin_hash(c + ivec3(0, 0, 1)), f - vec3(0.0f, 0.0f, 1.0f));
  float n101 = perlin_gradient(perlin_hash(c + ivec3(1, 0, 1)), f - vec3(1.0f, 0.0f, 1.0f));
  float n011 = perlin_gradient(perlin_hash(c + ivec3(0, 1, 1)), f - vec3(0.0f, 1.0f, 1.0f));
  float n111 = perlin_gradient(perlin_hash(c + ivec3(1, 1, 1)), f - vec3(1.0f, 1.0f, 1.0f));
  float x00 = mix(n000, n100, wx);
  float x10 = mix(n010, n110, wx);
  float x01 = mix(n001, n101, wx);
  float x11 = mix(n011, n111, wx);
  return mix(mix(x00, x10, wy), mix(x01, x11, wy), wz);
}

#define TURBULENCE_OCTAVES 7

// Sum of |noise| over octaves of doubling frequency and halving weight.
float turbulence(vec3 p) {
  float sum = 0.0f;
  float weight = 1.0f;
  for (int i = 0; i < TURBULENCE_OCTAVES; ++i) {
    sum += weight * abs(perlin_noise(p));
    weight *= 0.5f;
    p = p * 2.0f;
  }
  return sum;
}

// Marble: sine stripes along z, displaced by turbulence; 0 = base, 1 = veins.
float marble_pattern(vec3 p) {
  return 0.5f * (1.0f + sin(p.z + 10.0f * turbulence(p)));
}

#endif  // WP_NOISE_GLSL
