// types.h — the records the kernels and the host share, as C++: types.glsl
// (with the limit, kind and layer tables it includes) and bindings.glsl, in
// namespace wp::shader, GLM standing in for GLSL's vectors (common.glsl).
//
// The bottom layer of the bridge: bvh/, scene/ and whatever only builds,
// stores or moves these records include this, so that they do not compile
// the integrator. render/shader_cpp.h adds the code that evaluates them;
// only the renderers and the tests need that.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>

#include "../../shaders/shared/common.glsl"

namespace wp::shader {
#include "../../shaders/shared/types.glsl"
#include "../../shaders/shared/bindings.glsl"

// Host-side layout checks; tests/test_layout.cpp checks the GLSL side.
static_assert(sizeof(BvhNode) == 16 * BVH_NODE_TEXELS && sizeof(WideNode) == 16 * WIDE_NODE_TEXELS &&
              sizeof(Triangle) == 16 * TRIANGLE_TEXELS && sizeof(TriangleShading) == 16 * TRIANGLE_SHADING_TEXELS &&
              sizeof(TriangleVertexData) == 16 * TRIANGLE_VERTEX_DATA_TEXELS &&
              sizeof(Sphere) == 16 * SPHERE_TEXELS && sizeof(Material) == 16 * MATERIAL_TEXELS &&
              sizeof(Texture) == 16 * TEXTURE_TEXELS && sizeof(PointLight) == 16 * POINT_LIGHT_TEXELS &&
              sizeof(Emitter) == 16 * EMITTER_TEXELS && sizeof(Medium) == 16 * MEDIUM_TEXELS && sizeof(Photon) == 16 * PHOTON_TEXELS &&
              sizeof(Instance) == 16 * INSTANCE_TEXELS && sizeof(Hit) == 32);
// (PathState and ShadowRay, whose colours are a Spectrum, travel field by
// field: kernel.glsl's read_path and write_path, and the ray caster's
// write_shadow_rays.)
static_assert(sizeof(BvhNode) == 32 && offsetof(BvhNode, bmax) == 16 && offsetof(BvhNode, count) == 28);
static_assert(sizeof(WideNode) == 80 && offsetof(WideNode, childBase) == 16 && offsetof(WideNode, meta4567) == 28 &&
              offsetof(WideNode, qlo) == 32 && offsetof(WideNode, qhi) == 64);
static_assert(sizeof(Triangle) == 48 && offsetof(Triangle, v2) == 32 && offsetof(Triangle, shading) == 44);
static_assert(sizeof(TriangleShading) == 64 && offsetof(TriangleShading, flags) == 44 && offsetof(TriangleShading, uv12) == 48);
static_assert(sizeof(TriangleVertexData) == 128 && offsetof(TriangleVertexData, color0) == 48 && offsetof(TriangleVertexData, uv1_2) == 112);
static_assert(sizeof(Sphere) == 112 && offsetof(Sphere, material) == 96 && offsetof(Sphere, area) == 104);
static_assert(sizeof(Instance) == 112 && offsetof(Instance, root) == 96 && offsetof(Instance, mesh) == 104);
static_assert(sizeof(Material) == 176 && offsetof(Material, children) == 16 && offsetof(Material, params) == 32 &&
              offsetof(Material, params2) == 48 && offsetof(Material, extra) == 64 && offsetof(Material, media) == 16 * MATERIAL_MEDIA_TEXEL);
static_assert(sizeof(Medium) == 144 && offsetof(Medium, sigmaA) == 16 && offsetof(Medium, sigmaN) == 48 &&
              offsetof(Medium, toIndex0) == 64 && offsetof(Medium, boundsHi) == 128);
static_assert(sizeof(Texture) == 96 && offsetof(Texture, color1) == 32 && offsetof(Texture, map2) == 80);
static_assert(sizeof(PointLight) == 48 && offsetof(PointLight, intensity) == 16 && offsetof(PointLight, direction) == 32);
static_assert(sizeof(Emitter) == 16 && offsetof(Emitter, pmf) == 12);
static_assert(sizeof(Photon) == 32 && offsetof(Photon, power) == 16 && offsetof(Photon, from) == 28);
static_assert(sizeof(SceneParams) == 240 && offsetof(SceneParams, mode) == 112 && offsetof(SceneParams, environment) == 128 &&
              offsetof(SceneParams, accel) == 144 && offsetof(SceneParams, kinds) == 160 && offsetof(SceneParams, mis) == 176 &&
              offsetof(SceneParams, camWindow) == 192 && offsetof(SceneParams, media) == 208 &&
              offsetof(SceneParams, photons) == 224);
static_assert(sizeof(Hit) == 32 && offsetof(Hit, instance) == 16);
static_assert(sizeof(PixelAccum) == 32);
static_assert(sizeof(AovSample) == 4 * AOV_CHANNELS && sizeof(AovAccum) == 8 * AOV_CHANNELS);
static_assert(sizeof(KernelPush) == 48);
}  // namespace wp::shader
