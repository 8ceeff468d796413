// scene.h — a scene as the loaders produce it: world-space triangles, spheres
// with their transforms, materials, the camera and the render settings. The
// BVH (src/bvh) and the GPU layout (src/render/compiled_scene.h) are built from it.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "render/shader_cpp.h"

namespace wp {

struct Camera {
  glm::mat4 toWorld{1.0f};  // camera looks down its -Z axis
  float vfovDegrees = 90.0f;
  int width = 512;
  int height = 512;
  float focusDistance = 1.0f;
  float apertureRadius = 0.0f;
};

// How the BVH builder splits a node's primitives (bvh.h): binned SAH; the
// clustered SAH build, faster for large scenes (binned SAH over Morton-order
// clusters at the top, the exact SAH sweep for small nodes); the middle of the
// centroids' extent; or two halves by count (darts' "middle" and "equal").
// Auto, what a scene gets unless it names a method, is one of the two SAH
// builds by the scene's size (split_for in bvh.h).
enum class SplitMethod { Sah, Middle, Equal, ClusteredSah, Auto };

struct AcceleratorSettings {
  int maxLeafSize = 4;
  SplitMethod split = SplitMethod::Auto;
};

// PathHemisphere: BSDF-sampling-only path tracing with directions uniform
// over the hemisphere (CS184's -H), a wavepath extension of the darts names.
enum class IntegratorKind { PathMis, PathNee, PathMats, PathMixture, PathHemisphere, Normals, AmbientOcclusion };

enum class SamplerKind { Independent, Cmj };

// The integrator and sampler names scene files and the command line use
// (darts' names); nullopt for an unknown one. The list is for error messages.
std::optional<IntegratorKind> integrator_named(const std::string& name);
std::optional<SamplerKind> sampler_named(const std::string& name);
extern const char* const kIntegratorNames;  // "normals, ao, path tracer mats, ..."

struct IntegratorSettings {
  IntegratorKind kind = IntegratorKind::PathMis;
  int maxBounces = 64;
  int russianRouletteDepth = 3;  // first depth at which paths may be ended at random
};

struct SceneTriangle {
  glm::vec3 v[3];
  uint32_t material;
  // Its per-vertex normals and UVs (Scene::triangleShading), or WP_INVALID:
  // the normal is flat and the UVs are the barycentrics. Kept apart because
  // most triangles of large scanned meshes have none: 44 bytes a triangle
  // instead of 104.
  uint32_t shading = WP_INVALID;
};

struct SceneTriangleShading {
  bool hasNormals = false;
  bool hasUvs = false;
  glm::vec3 n[3]{};
  glm::vec2 uv[3]{};
};

struct SceneSphere {
  glm::mat4 toWorld;  // places the unit sphere
  uint32_t material;
};

struct Scene {
  std::string sourcePath;
  Camera camera;
  int samplesPerPixel = 1;
  SamplerKind sampler = SamplerKind::Independent;
  glm::vec3 background{0.0f};
  // An image texture used as an equirectangular environment map in place of
  // the constant background, or WP_INVALID.
  uint32_t environmentTexture = WP_INVALID;
  AcceleratorSettings accelerator;
  IntegratorSettings integrator;
  std::vector<shader::Material> materials;
  std::vector<std::string> materialNames;  // parallel to materials, for messages
  std::vector<shader::Texture> textures;   // materials refer to these by index
  std::vector<glm::uvec2> texels;          // every image, RGBA half floats, back to back
  std::vector<shader::PointLight> pointLights;
  std::vector<SceneTriangle> triangles;
  std::vector<SceneTriangleShading> triangleShading;  // SceneTriangle::shading indexes it
  std::vector<SceneSphere> spheres;
};

// A texture of one colour everywhere, with the identity mapping.
shader::Texture constant_texture(glm::vec3 color);

// Appends a texture / a Lambertian material of constant albedo; returns its index.
uint32_t add_texture(Scene& scene, const shader::Texture& texture);
uint32_t add_lambertian(Scene& scene, glm::vec3 albedo, const std::string& name = "lambertian");

// Loads an image file (see texture_image.h) into the scene's texels and
// returns an image texture over them (identity mapping), not yet added.
// `where` is appended to error messages.
shader::Texture image_texture(Scene& scene, const std::string& path, const std::string& where);
// The same, added to the scene; returns the texture's index.
uint32_t add_image_texture(Scene& scene, const std::string& path, const std::string& where);

}  // namespace wp
