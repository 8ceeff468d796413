// volume_shapes.h — density grids wavepath writes itself, with NanoVDB's own
// builder (libnanovdb-dev): the smoke plume of scenes/plume.json
// (`wavepath-volume plume`) and the grids the tests need (a density ramp
// with a closed-form optical depth, and grids of the wrong kind). Procedural
// throughout: no downloaded asset.
#pragma once

#include <nanovdb/util/GridBuilder.h>
#include <nanovdb/util/IO.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

namespace wp::volumes {

// Value noise in [0, 1] on the integer lattice, smoothly interpolated.
inline float lattice(int x, int y, int z, uint32_t seed) {
  uint32_t h = uint32_t(x) * 0x8da6b343u ^ uint32_t(y) * 0xd8163841u ^ uint32_t(z) * 0xcb1ab31fu ^ seed * 0x9e3779b9u;
  h ^= h >> 15;
  h *= 0x2c1b3c6du;
  h ^= h >> 12;
  h *= 0x297a2d39u;
  h ^= h >> 15;
  return float(h & 0xffffffu) / float(0xffffff);
}

inline float value_noise(float x, float y, float z, uint32_t seed) {
  const int ix = int(std::floor(x)), iy = int(std::floor(y)), iz = int(std::floor(z));
  auto fade = [](float t) { return t * t * (3.0f - 2.0f * t); };
  const float fx = fade(x - float(ix)), fy = fade(y - float(iy)), fz = fade(z - float(iz));
  auto l = [&](int dx, int dy, int dz) { return lattice(ix + dx, iy + dy, iz + dz, seed); };
  auto mix = [](float a, float b, float t) { return a + (b - a) * t; };
  return mix(mix(mix(l(0, 0, 0), l(1, 0, 0), fx), mix(l(0, 1, 0), l(1, 1, 0), fx), fy),
             mix(mix(l(0, 0, 1), l(1, 0, 1), fx), mix(l(0, 1, 1), l(1, 1, 1), fx), fy), fz);
}

// A rising plume of smoke, `height` voxels tall: a column that widens and
// thins as it rises, sways, and is broken up by three octaves of noise.
// Voxels of size 1 / height, so the plume is one unit tall from its base at
// the origin. Its voxels have non-negative indices (the map centres it):
// every NanoVDB grid spends 270 kB on each 4096^3 block it touches.
inline nanovdb::GridHandle<> plume(int height, uint32_t seed = 7u) {
  nanovdb::GridBuilder<float> builder(0.0f, nanovdb::GridClass::FogVolume);
  const float R = float(height);
  const int half = height / 3;
  builder(
      [&](const nanovdb::Coord& c) -> float {
        const float x = float(c[0] - half), z = float(c[2] - half), y = float(c[1]) / R;
        const float cx = 0.06f * std::sin(y * 7.0f) * R, cz = 0.05f * std::cos(y * 5.0f) * R;
        const float radius = R * (0.035f + 0.2f * y);
        const float dx = x - cx, dz = z - cz;
        const float d2 = (dx * dx + dz * dz) / (radius * radius);
        if (d2 > 4.0f) return 0.0f;
        float n = 0.0f, amp = 0.5f, f = 6.0f / R;
        for (int o = 0; o < 3; ++o, amp *= 0.5f, f *= 2.1f)
          n += amp * value_noise(x * f, float(c[1]) * f - y * 3.0f, z * f, seed + uint32_t(o));
        const float base = std::exp(-2.0f * d2) * (1.0f - 0.75f * y) * std::min(1.0f, y * 12.0f);
        const float d = base * std::max(0.0f, 1.6f * n - 0.25f);
        return d < 0.01f ? 0.0f : d;
      },
      nanovdb::CoordBBox(nanovdb::Coord(0), nanovdb::Coord(2 * half, height - 1, 2 * half)));
  return builder.getHandle<>(1.0 / R, nanovdb::Vec3d(-double(half) / R, 0.0, -double(half) / R), "density");
}

// Density a + b x over the voxels [0, n)^3 (x the voxel's index), voxel size
// `voxel`: along x its optical depth has a closed form, which the tests
// check tracking against.
inline nanovdb::GridHandle<> ramp(int n, float a, float b, double voxel = 1.0, const std::string& name = "density") {
  nanovdb::GridBuilder<float> builder(0.0f, nanovdb::GridClass::FogVolume);
  builder([&](const nanovdb::Coord& c) -> float { return a + b * float(c[0]); },
          nanovdb::CoordBBox(nanovdb::Coord(0), nanovdb::Coord(n - 1)));
  return builder.getHandle<>(voxel, nanovdb::Vec3d(0.0), name);
}

// A narrow-band level set of a sphere: a float grid, but not a fog volume.
inline nanovdb::GridHandle<> level_set_sphere(int radius) {
  nanovdb::GridBuilder<float> builder(3.0f, nanovdb::GridClass::LevelSet);
  builder([&](const nanovdb::Coord& c) -> float {
            const float d = std::sqrt(float(c[0] * c[0] + c[1] * c[1] + c[2] * c[2])) - float(radius);
            return std::clamp(d, -3.0f, 3.0f);
          },
          nanovdb::CoordBBox(nanovdb::Coord(-radius - 3), nanovdb::Coord(radius + 3)), 3.0f);
  return builder.getHandle<>(1.0, nanovdb::Vec3d(0.0), "surface");
}

// A vector grid: not a density.
inline nanovdb::GridHandle<> velocity(int n) {
  nanovdb::GridBuilder<nanovdb::Vec3f> builder(nanovdb::Vec3f(0.0f));
  builder([&](const nanovdb::Coord& c) -> nanovdb::Vec3f { return nanovdb::Vec3f(1.0f, float(c[1]), 0.0f); },
          nanovdb::CoordBBox(nanovdb::Coord(0), nanovdb::Coord(n - 1)));
  return builder.getHandle<>(1.0, nanovdb::Vec3d(0.0), "velocity");
}

}  // namespace wp::volumes
