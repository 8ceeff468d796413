// layers.glsl — the output layers beyond the colour (AOVs: arbitrary output
// variables), each listed once, and the records they are accumulated in.
//
// Every sample adds to its pixel's colour layer (sample_moments in
// integrator.glsl: R, G, B and the illuminance Y). A render asked for AOVs
// (`--aov albedo,normal,depth`) also records, per sample, what its camera ray
// hit first (aov_sample in integrator.glsl), as an AovSample of AOV_CHANNELS
// floats, and adds those and their squares to the pixel's AovAccum. The host
// keeps the layers it was asked for (image/image.h); the table below tells
// it where each layer's channels are in the record and what they are called.
//
// The conventions are Open Image Denoise's: albedo in [0, 1] (the first
// hit's reflectance, the sum of its lobes' colours; an emitter's or the
// background's clamped radiance where nothing scatters), normals in world
// space (the first hit's shading normal, facing the camera; zero where the
// ray escaped). Depth is the distance along the camera ray to the first hit,
// with the hit's coverage beside it (1 on a hit, 0 on a miss), so that the
// mean depth of a pixel is taken over the samples that hit something.
#ifndef WP_LAYERS_GLSL
#define WP_LAYERS_GLSL

// Columns: id (the layer's bit in an AOV mask), name (as --aov and the EXR
// layer call it), first channel in AovSample, channel names (comma-separated).
#define AOV_ALBEDO 0u
#define AOV_NORMAL 1u
#define AOV_DEPTH 2u
#define WP_AOV_LAYERS(X)             \
  X(AOV_ALBEDO, "albedo", 0, "R,G,B") \
  X(AOV_NORMAL, "normal", 3, "X,Y,Z") \
  X(AOV_DEPTH, "depth", 6, "Z,A")
#define AOV_CHANNELS 8

#endif  // WP_LAYERS_GLSL
