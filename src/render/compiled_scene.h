// compiled_scene.h — a scene in the form the renderers consume: the BVH node
// array, triangles and spheres in leaf order, materials, the emitter alias
// table and the uniform parameters. The GPU uploads these arrays as they are;
// the CPU reference reads them through shader::SceneView.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bvh/bvh.h"
#include "bvh/wide_bvh.h"
#include "render/adaptive.h"
#include "render/spectra.h"
#include "scene/scene.h"
#include "shader/types.h"

namespace wp {

// The integrator's view of a compiled scene (render/shader_cpp.h): only
// the code that renders or tests with it includes that.
namespace shader {
struct SceneView;
}

// The node layout the kernels and the CPU reference traverse: the 8-wide
// compressed BVH (the default: fewer, smaller node fetches per ray) or the
// binary BVH it is collapsed from.
enum class BvhLayout { Wide, Binary };

// The order in which the wide walk visits a node's hit children: the slots
// of the ray's octant (no sort), nearest first (a sorting network), or
// (Auto) nearest first in scenes with instances and the octant's elsewhere.
enum class WideChildOrder { Auto, Octant, Distance };

struct RenderOptions {
  int spp = -1;          // -1: the scene's sampler count
  int maxBounces = -1;   // -1: the scene's integrator setting
  uint32_t seed = 0;
  // Iterations one traversal may take before it reports itself truncated
  // (limits.glsl).
  uint32_t traversalStepCap = TRAVERSAL_STEP_BUDGET;
  AdaptiveSampling adaptive;  // off unless batch > 0
  int lightSamples = 1;        // next-event estimation samples per path vertex (1..MAX_LIGHT_SAMPLES)
  BvhLayout bvhLayout = BvhLayout::Wide;
  bool clusteredBuild = false;  // build with SplitMethod::ClusteredSah where the scene's build would be binned SAH
  WideCollapse wideCollapse = WideCollapse::Sah;  // how the wide layout's nodes are picked from the binary tree
  WideChildOrder wideChildOrder = WideChildOrder::Auto;
  // The wide walk visits an instance's root in the iteration that enters it
  // (an iteration fewer per instance, a dependent load more), not the next.
  bool rootAtEntry = false;
  // Each iteration of the binary walk tests a primitive and visits a node
  // (trace_binary_fused), instead of doing one or the other.
  bool binaryFused = false;
  // Overrides of the scene file's integrator and sampler (command line).
  std::optional<IntegratorKind> integrator;
  std::optional<SamplerKind> sampler;
  // AOV layers to record beside the colour (layers.glsl names).
  std::vector<std::string> aovs;
  // The spectral mode (spectral.glsl): overrides the scene file's choice
  // where set (the command line's --spectral / --rgb).
  std::optional<bool> spectral;
  // The photon mapper's photons: traced while compiling, on the host, or
  // left to the GPU renderer, which traces them with its kernels
  // (CompiledScene::photonMapLeftToDevice).
  bool photonsOnHost = true;
};

// What instancing saved: the meshes placed by instances (each with its own
// bottom-level tree) against the triangles they place, and the bytes of each
// level (its nodes and primitive records).
struct InstancingStats {
  size_t meshes = 0;               // meshes with a bottom-level tree
  size_t instances = 0;            // instances placing them
  size_t uniqueTriangles = 0;      // the triangles of those meshes
  size_t instancedTriangles = 0;   // the triangles the instances place (each mesh's times its instances)
  size_t topLevelBytes = 0;        // the top level's nodes and records (world triangles, placeholders) and the instances
  size_t bottomLevelBytes = 0;     // the meshes' trees and triangles
};

struct CompiledScene {
  shader::SceneParams params{};
  BvhLayout bvhLayout = BvhLayout::Wide;
  std::vector<shader::BvhNode> nodes;       // the binary layout's nodes (one unused node otherwise)
  std::vector<shader::WideNode> wideNodes;  // the wide layout's nodes (one unused node otherwise)
  // Primitive records in leaf order: triangles, and a placeholder for each
  // sphere; spheres in scene order.
  std::vector<shader::Triangle> triangles;
  std::vector<shader::Sphere> spheres;
  std::vector<shader::Instance> instances;  // FEATURE_INSTANCES (one unused record otherwise)
  InstancingStats instancing;
  std::vector<shader::Material> materials;
  std::vector<shader::Emitter> emitters;
  std::vector<shader::Texture> textures;
  std::vector<glm::uvec2> texels;
  std::vector<shader::TriangleShading> triangleShading;
  std::vector<shader::TriangleVertexData> triangleVertexData;  // parallel to triangleShading, or empty (FEATURE_VERTEX_DATA)
  std::vector<shader::PointLight> pointLights;
  std::vector<shader::Medium> media;  // 0: the vacuum, then the scene's (Scene::media)
  std::vector<uint32_t> volumeWords;   // BINDING_VOLUMES: grid media's NanoVDB grids and majorant grids
  std::vector<shader::Photon> photons;  // BINDING_PHOTONS: the photon map (INTEGRATOR_PHOTONS), a balanced kd-tree
  // The photons the map is traced from, and their seed; where the map was
  // left to the device (RenderOptions::photonsOnHost false), photons is
  // empty and each GPU renderer traces it.
  uint32_t photonCount = 0, photonSeed = 0;
  bool photonMapLeftToDevice = false;
  double photonPassSeconds = 0.0;  // the host's trace and balance, where it built the map
  std::vector<float> floatTables;  // BINDING_FLOAT_TABLES: the sheen's albedo, the environment map's distribution
  // BINDING_SPECTRA: the spectral mode's tables (linked into the program,
  // render/spectra.h), or one placeholder texel in RGB.
  SpectraTexels spectra;
  bool spectral = false;
  // BINDING_SPECTRAL_COLOURS: the memo of the scene's constant colours
  // (compile_spectral_colours), a placeholder texel in RGB.
  std::vector<glm::vec4> spectralColours;
  std::string cameraName;  // the scene file's camera rendered through, where it has several (a glTF's)
  EightBitCurve eightBitCurve = EightBitCurve::Srgb;  // Scene::eightBitCurve
  int cs184Skeleton = 0;                              // Scene::cs184Skeleton
  int width = 0;
  int height = 0;
  int spp = 0;  // samples per pixel (with adaptive sampling: at most)
  AdaptiveSampling adaptive;
  std::vector<std::string> aovs;  // AOV layers recorded, in layers.glsl's order
  int bvhDepth = 0;      // levels of the traversed layout's tree
  double binarySahCost = 0.0;  // the binary layout's SAH cost, as its builder measured it (bvh_sah_cost)
  double bvhBuildSeconds = 0.0;
  SplitMethod bvhSplit = SplitMethod::Sah;  // how the builder split (the scene's method, Auto resolved by size)
  // Shade classes (sorting by material class, types.glsl): per class, the
  // material kinds (x) and texture kinds (y) its materials need; each
  // material's sort key (its class + 1) is its children.w. And the texture
  // kinds every shade kernel needs (emission, the environment), the misses'
  // kernel included.
  std::vector<glm::uvec2> shadeClasses;
  uint32_t shadeCommonKinds = 0;

  shader::SceneView view() const;
  // The kinds (as SceneParams.kinds) of the shade kernel for sort key `key`:
  // class + 1, or SORT_KEY_MISS. The scene's kinds less the material and
  // texture kinds the key's paths cannot need.
  glm::uvec4 shade_key_kinds(uint32_t key) const;
  // The SAH cost of the tree in its layout. The 8-wide tree's is computed
  // from its nodes on each call (wide_sah_cost; 0.7 s at 10M triangles), so
  // that compiling a scene for a render does not pay for it.
  double bvh_sah_cost() const;
  // Bytes the scene occupies on the GPU: BVH, primitives, shading data,
  // materials, textures, emitters.
  size_t gpu_bytes() const;
};

CompiledScene compile_scene(const Scene& scene, const RenderOptions& options);
// Bytes the hit buffer holds per path slot: a Hit's first 16, and the
// instance where the scene has instances (kernel.glsl's write_hit).
inline uint64_t hit_record_bytes(const CompiledScene& cs) {
  return (cs.params.kinds.w & KIND_BIT(FEATURE_INSTANCES)) != 0u ? 32u : 16u;
}
// The camera's part of the kernels' parameters: where it stands, its field,
// lens and the window of the frame it sees (what `wavepath view` changes
// between passes, WavefrontRenderer::update_params).
void set_camera_params(const Camera& camera, shader::SceneParams& params);

// The primitives' bounds, numbered as compile_scene numbers them: the
// triangles, then the spheres.
BvhInput bvh_input(const Scene& scene);

// Mean colour of a texture over its domain (exact for constants and images,
// the average of the two colours for checkers and marble). Used to weigh
// textured emitters; it only steers sampling, never the estimate.
glm::vec3 texture_mean(const std::vector<shader::Texture>& textures, const std::vector<glm::uvec2>& texels, uint32_t index);

// The sampling distribution of an environment map image texture: CDF over
// rows, then a CDF per row, weighted by luminance times sin(theta). Each cell's
// weight is the largest of its 3x3 neighbourhood (bilinear lookups reach into
// neighbouring texels) plus a floor, so no direction with radiance has zero density.
std::vector<float> environment_cdf(const shader::Texture& t, const std::vector<glm::uvec2>& texels);

// Vose's alias table for sampling index i with probability weights[i] / sum.
// Exposed for the sampling tests.
std::vector<shader::Emitter> build_alias_table(const std::vector<double>& weights);

}  // namespace wp
