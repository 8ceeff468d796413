// compiled_scene.cpp — compile_scene, which calls its parts
// (compile_parts.h) in turn, the render parameters that are the scene's as
// a whole (camera, image, integrator, sampler), and CompiledScene's own
// members.
#include "render/compiled_scene.h"

#include <glm/glm.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "image/image.h"
#include "render/compile_parts.h"
#include "render/shader_cpp.h"
#include "scene/kinds.h"
#include "scene/transform.h"
#include "util/error.h"

namespace wp {

namespace {

// The camera, the image, the integrator and the sampler: SceneParams less
// what the parts set. `emitters`: the emitter table's size;
// `stackSlots`: the traversal stack's (CompiledGeometry).
void set_render_params(const Scene& scene, const RenderOptions& options, size_t emitters, uint32_t stackSlots, CompiledScene& out) {
  const Camera& cam = scene.camera;
  out.cameraName = cam.name;
  out.eightBitCurve = scene.eightBitCurve;
  out.cs184Skeleton = scene.cs184Skeleton;
  out.width = cam.width;
  out.height = cam.height;
  out.spp = options.spp > 0 ? options.spp : scene.samplesPerPixel;
  out.adaptive = options.adaptive;
  out.aovs = ImageStats(0, 0, image_layers(options.aovs)).aov_names();  // checked, in the table's order
  int maxBounces = options.maxBounces >= 0 ? options.maxBounces : scene.integrator.maxBounces;
  shader::SceneParams& p = out.params;
  set_camera_params(cam, p);
  p.image = glm::uvec4(uint32_t(cam.width), uint32_t(cam.height), uint32_t(maxBounces),
                       uint32_t(scene.integrator.russianRouletteDepth));
  p.mis = glm::vec4(scene.integrator.misPower, 0.0f, 0.0f, 0.0f);
  uint32_t flags = 0;
  IntegratorKind kind = options.integrator ? *options.integrator : scene.integrator.kind;
  if (kind == IntegratorKind::PathMats) flags |= SCENE_FLAG_NO_NEE;
  if (kind == IntegratorKind::PathHemisphere) flags |= SCENE_FLAG_NO_NEE | SCENE_FLAG_HEMISPHERE;
  // The photon mapper takes direct light by next-event estimation alone and
  // ends paths at their first non-specular vertex.
  if (kind == IntegratorKind::PathNee || kind == IntegratorKind::PhotonMapper) flags |= SCENE_FLAG_NO_BSDF_MIS;
  if (scene.cs184Estimator) flags |= SCENE_FLAG_CS184;
  if (scene.cs184LatLong) flags |= SCENE_FLAG_CS184_LATLONG;
  uint32_t mode = INTEGRATOR_PATH;
  if (kind == IntegratorKind::Normals) mode = INTEGRATOR_NORMALS;
  if (kind == IntegratorKind::AmbientOcclusion) mode = INTEGRATOR_AO;
  if (kind == IntegratorKind::PathMixture) mode = INTEGRATOR_MIXTURE;
  if (kind == IntegratorKind::PhotonMapper) mode = INTEGRATOR_PHOTONS;
  // The mixture's exact light density visits every emitter at every bounce;
  // the shade kernel's loop budget (and patience) bound how many that may be.
  if (mode == INTEGRATOR_MIXTURE && emitters > MAX_MIXTURE_EMITTERS) {
    throw InputError(scene.sourcePath + ": \"path tracer mixture\" evaluates every emitter at every bounce; this scene has " +
                     std::to_string(emitters) + " emitters (at most " + std::to_string(MAX_MIXTURE_EMITTERS) +
                     "): use \"path tracer mis\"");
  }
  SamplerKind sampler = options.sampler ? *options.sampler : scene.sampler;
  if (options.lightSamples < 1 || uint32_t(options.lightSamples) > MAX_LIGHT_SAMPLES) {
    throw InputError("light samples per vertex must lie in [1, " + std::to_string(MAX_LIGHT_SAMPLES) + "], got " +
                     std::to_string(options.lightSamples));
  }
  p.mode = glm::uvec4(mode, sampler == SamplerKind::Cmj ? SAMPLER_CMJ : SAMPLER_INDEPENDENT, uint32_t(out.spp),
                      uint32_t(options.lightSamples));
  // The spectral mode, for the integrators that carry light (a preview's
  // normals or occlusion are no radiance).
  out.spectral = (options.spectral ? *options.spectral : scene.integrator.spectral) && mode != INTEGRATOR_NORMALS && mode != INTEGRATOR_AO;
  out.spectra = out.spectral ? spectra_texels() : spectra_placeholder();
  if (out.spectral) {
    flags |= SCENE_FLAG_SPECTRAL;
    p.kinds.w |= KIND_BIT(FEATURE_SPECTRAL);
  }
  p.counts = glm::uvec4(uint32_t(emitters), options.seed, options.traversalStepCap, flags);
  if (sampler == SamplerKind::Cmj) p.kinds.w |= KIND_BIT(FEATURE_CMJ);
  if ((flags & SCENE_FLAG_HEMISPHERE) != 0u) p.kinds.w |= KIND_BIT(FEATURE_UNIFORM_HEMISPHERE);
  // Nearest first where a wrong turn costs a whole instance's walk (the
  // forest of docs/benchmarks.md: 58 walk steps a camera ray in octant order,
  // 40 nearest first); elsewhere the octant's order, which sorts nothing.
  const bool nearest = options.wideChildOrder == WideChildOrder::Distance ||
                       (options.wideChildOrder == WideChildOrder::Auto && !scene.instances.empty());
  p.accel = glm::uvec4(options.bvhLayout == BvhLayout::Wide ? BVH_LAYOUT_WIDE : BVH_LAYOUT_BINARY,
                       nearest ? WIDE_ORDER_DISTANCE : WIDE_ORDER_OCTANT, stackSlots,
                       (options.rootAtEntry ? WALK_ROOT_AT_ENTRY : 0u) | (options.binaryFused ? WALK_BINARY_FUSED : 0u));
}

// Buffers are never empty: bind a zero element where the scene has none.
void add_placeholder_elements(CompiledScene& out) {
  if (out.triangles.empty()) out.triangles.push_back(shader::Triangle{});
  if (out.spheres.empty()) out.spheres.push_back(shader::Sphere{});
  if (out.instances.empty()) out.instances.push_back(shader::Instance{});
  if (out.emitters.empty()) out.emitters.push_back(shader::Emitter{});
  if (out.materials.empty()) out.materials.push_back(shader::Material{});
  if (out.textures.empty()) out.textures.push_back(shader::Texture{});
  if (out.texels.empty()) out.texels.push_back(glm::uvec2(0u));
  if (out.triangleShading.empty()) out.triangleShading.push_back(shader::TriangleShading{});
  if (out.triangleVertexData.empty()) out.triangleVertexData.push_back(shader::TriangleVertexData{});
  if (out.pointLights.empty()) out.pointLights.push_back(shader::PointLight{});
}

}  // namespace

float luminance(glm::vec3 c) {
  return shader::ShaderMath{}.illuminance(c);
}

shader::SceneView CompiledScene::view() const {
  shader::SceneView v;
  v.scene = params;
  v.spectrumChannels = (params.kinds.w & KIND_BIT(FEATURE_SPECTRAL)) != 0u ? 4u : 3u;
  // The arrays the kernels read as texel buffers, as texels.
  auto texels_of = [](const auto& records) { return reinterpret_cast<const glm::uvec4*>(records.data()); };
  v.nodeTexels = texels_of(nodes);
  v.wideNodeTexels = texels_of(wideNodes);
  v.triangleTexels = texels_of(triangles);
  v.shadingTexels = texels_of(triangleShading);
  v.vertexDataTexels = texels_of(triangleVertexData);
  v.sphereTexels = texels_of(spheres);
  v.instanceTexels = texels_of(instances);
  v.materialTexels = texels_of(materials);
  v.emitterTexels = texels_of(emitters);
  v.textureTexels = texels_of(textures);
  v.pointLightTexels = texels_of(pointLights);
  v.mediumTexels = texels_of(media);
  v.volumeWords = volumeWords.data();
  v.volumeWordCount = volumeWords.size();
  v.photonTexels = texels_of(photons);
  v.imageTexels = texels.data();
  v.floatTables = floatTables.data();
  v.spectrumTexels = spectra.texels;
  v.spectralColourTexels = spectralColours.data();
  return v;
}

glm::uvec4 CompiledScene::shade_key_kinds(uint32_t key) const {
  const bool hits = key != SORT_KEY_MISS && key <= shadeClasses.size();
  const glm::uvec2 cls = hits ? shadeClasses[key - 1] : glm::uvec2(0u);
  return glm::uvec4(cls.x & params.kinds.x, (cls.y | shadeCommonKinds) & params.kinds.y, params.kinds.z, params.kinds.w);
}

double CompiledScene::bvh_sah_cost() const {
  // The 8-wide tree's own cost: the binary tree it came from is split down to
  // single primitives, so that tree's cost says little.
  return bvhLayout == BvhLayout::Wide ? wide_sah_cost(wideNodes) : binarySahCost;
}

size_t CompiledScene::gpu_bytes() const {
  size_t nodeBytes = bvhLayout == BvhLayout::Wide ? wideNodes.size() * sizeof(shader::WideNode) : nodes.size() * sizeof(shader::BvhNode);
  return nodeBytes + triangles.size() * sizeof(shader::Triangle) +
         spheres.size() * sizeof(shader::Sphere) + instances.size() * sizeof(shader::Instance) + materials.size() * sizeof(shader::Material) +
         emitters.size() * sizeof(shader::Emitter) + textures.size() * sizeof(shader::Texture) +
         texels.size() * sizeof(glm::uvec2) + triangleShading.size() * sizeof(shader::TriangleShading) +
         triangleVertexData.size() * sizeof(shader::TriangleVertexData) +
         pointLights.size() * sizeof(shader::PointLight) + media.size() * sizeof(shader::Medium) + volumeWords.size() * sizeof(uint32_t) + photons.size() * sizeof(shader::Photon) +
         floatTables.size() * sizeof(float) + spectra.count * sizeof(glm::vec4) +
         spectralColours.size() * sizeof(glm::vec4);
}

void set_camera_params(const Camera& cam, shader::SceneParams& p) {
  rows_3x4(cam.toWorld, p.camToWorld0, p.camToWorld1, p.camToWorld2);
  p.camLens = glm::vec4(cam.orthoHalfHeight > 0.0f ? -cam.orthoHalfHeight : std::tan(glm::radians(cam.vfovDegrees) * 0.5f),
                        cam.aspect > 0.0f ? cam.aspect : float(cam.width) / float(cam.height),
                        cam.apertureRadius, cam.focusDistance);
  p.camWindow = cam.window;
}

CompiledScene compile_scene(const Scene& scene, const RenderOptions& options) {
  // Each part reads what the parts before it filled (compile_parts.h says what).
  CompiledScene out;
  const std::vector<double> materialRadiance = compile_materials(scene, out);
  const CompiledGeometry geometry = compile_geometry(scene, options, materialRadiance, out);
  compile_media(scene, out);
  const size_t emitters = compile_lights(scene, materialRadiance, geometry, out);
  flag_triangle_materials(scene, materialRadiance, out);
  compile_kinds(scene, out);
  add_placeholder_elements(out);
  set_render_params(scene, options, emitters, geometry.stackSlots, out);
  compile_spectral_colours(out);
  if (out.params.mode.x == INTEGRATOR_PHOTONS) compile_photons(scene, options, out);
  return out;
}

}  // namespace wp
