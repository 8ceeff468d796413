#include "render/compiled_scene.h"

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "bvh/wide_bvh.h"
#include "scene/transform.h"
#include "util/error.h"
#include "util/huge_pages.h"

namespace wp {

namespace {

Aabb triangle_bounds(const SceneTriangle& t) {
  Aabb b;
  for (const glm::vec3& v : t.v) b.grow(v);
  return b;
}

// Exact bounds of a transformed unit sphere: the half-extent along world axis i
// is the length of row i of the linear part.
Aabb sphere_bounds(const glm::mat4& m) {
  glm::vec3 c(m[3]);
  glm::vec3 e;
  for (int i = 0; i < 3; ++i) e[i] = glm::length(glm::vec3(m[0][i], m[1][i], m[2][i]));
  Aabb b;
  b.lo = c - e;
  b.hi = c + e;
  return b;
}

constexpr size_t kMaxMixtureEmitters = 16384;

float luminance(glm::vec3 c) {
  return shader::ShaderMath{}.illuminance(c);
}

// An image texel: RGB from two packed half-float pairs (as texel_at in scene.glsl).
glm::vec3 texel_rgb(glm::uvec2 packed) {
  glm::vec2 rg = glm::unpackHalf2x16(packed.x);
  return glm::vec3(rg.x, rg.y, glm::unpackHalf2x16(packed.y).x);
}

// The FEATURE_* bits of what a compiled scene uses (before its empty arrays
// get their placeholder element); `emitters` are the emitter table's prims,
// `environment` whether an environment map replaces the background.
uint32_t scene_features(const CompiledScene& cs, const std::vector<uint32_t>& emitters, bool spheres, bool environment) {
  uint32_t f = spheres ? FEATURE_SPHERES : 0u;
  for (const shader::Material& m : cs.materials) {
    if (m.info.z != WP_INVALID && (cs.textures[m.info.z].info.x & TEX_TYPE_MASK) != TEX_CONSTANT) f |= FEATURE_EMISSION_TEXTURES;
    switch (m.info.x) {
      case MAT_BLEND: f |= FEATURE_BLEND; break;
      case MAT_METAL: f |= FEATURE_METAL; break;
      case MAT_DIELECTRIC: f |= FEATURE_DIELECTRIC; break;
      case MAT_PHONG: f |= FEATURE_PHONG; break;
      case MAT_BLINN_PHONG: f |= FEATURE_BLINN_PHONG; break;
      default: break;
    }
  }
  for (const shader::Texture& t : cs.textures) {
    switch (t.info.x & TEX_TYPE_MASK) {
      case TEX_CHECKER: f |= FEATURE_CHECKER; break;
      case TEX_MARBLE: f |= FEATURE_MARBLE; break;
      case TEX_IMAGE: f |= FEATURE_IMAGE; break;
      default: break;
    }
  }
  if (!cs.triangleShading.empty()) f |= FEATURE_SHADING_DATA;
  for (uint32_t prim : emitters) {
    if (prim == EMITTER_ENVIRONMENT) f |= FEATURE_ENVIRONMENT;
    else if (prim & EMITTER_POINT_BIT) f |= FEATURE_POINT_LIGHTS;
    else if (prim & HIT_SPHERE_BIT) f |= FEATURE_SPHERE_LIGHTS;
  }
  if (environment) f |= FEATURE_ENVIRONMENT;
  return f;
}

// The FEATURE_* kinds texture t's lookup runs: its own, and a checker's
// squares' (nested up to TEXTURE_MAX_NESTING deep, as texture_eval follows).
uint32_t texture_kinds(const std::vector<shader::Texture>& textures, uint32_t t, int depth = 0) {
  if (t == WP_INVALID || t >= textures.size()) return 0u;
  const shader::Texture& tex = textures[t];
  switch (tex.info.x & TEX_TYPE_MASK) {
    case TEX_CHECKER:
      return depth >= TEXTURE_MAX_NESTING ? FEATURE_CHECKER
                                          : FEATURE_CHECKER | texture_kinds(textures, tex.info.y, depth + 1) |
                                                texture_kinds(textures, tex.info.z, depth + 1);
    case TEX_MARBLE: return FEATURE_MARBLE;
    case TEX_IMAGE: return FEATURE_IMAGE;
    default: return 0u;
  }
}

// The FEATURE_MATERIAL_KINDS a ray that hits material m needs for its BSDF:
// its lobe kinds (a blend's children's too) and its textures' kinds. (Its
// emission's kinds every shade kernel has: shade_classes.)
uint32_t material_kinds(const CompiledScene& cs, uint32_t m, int depth = 0) {
  const shader::Material& mat = cs.materials[m];
  uint32_t f = texture_kinds(cs.textures, mat.info.y) | texture_kinds(cs.textures, mat.info.w);
  switch (mat.info.x) {
    case MAT_BLEND:
      f |= FEATURE_BLEND;
      // The loader bounds a blend's lobes (BSDF_MAX_LOBES), and so its depth.
      if (depth < int(BSDF_MAX_LOBES)) f |= material_kinds(cs, mat.children.x, depth + 1) | material_kinds(cs, mat.children.y, depth + 1);
      break;
    case MAT_METAL: f |= FEATURE_METAL; break;
    case MAT_DIELECTRIC: f |= FEATURE_DIELECTRIC; break;
    case MAT_PHONG: f |= FEATURE_PHONG; break;
    case MAT_BLINN_PHONG: f |= FEATURE_BLINN_PHONG; break;
    default: break;
  }
  return f;
}

// Groups the materials that primitives use into shade classes by the kinds
// they need (material_kinds), in order of first use, and writes each
// material's sort key (class + 1) to its children.w. Past SHADE_CLASSES_MAX
// classes, the rest share the last, which needs all of their kinds. Fills
// shadeClasses and shadeCommonKinds.
void shade_classes(CompiledScene& cs, uint32_t environmentTexture) {
  uint32_t common = texture_kinds(cs.textures, environmentTexture);
  for (const shader::Material& m : cs.materials) common |= texture_kinds(cs.textures, m.info.z);  // emission, hit or sampled
  cs.shadeCommonKinds = common;
  std::vector<bool> used(cs.materials.size(), false);
  for (const shader::Triangle& t : cs.triangles)
    if (t.material != WP_INVALID) used[t.material] = true;
  for (const shader::Sphere& sp : cs.spheres) used[sp.material] = true;
  for (uint32_t m = 0; m < cs.materials.size(); ++m) {
    cs.materials[m].children.w = SORT_KEY_MISS + 1u;  // for unused materials: any class will do
    if (!used[m]) continue;
    const uint32_t kinds = material_kinds(cs, m);
    auto found = std::find(cs.shadeClasses.begin(), cs.shadeClasses.end(), kinds);
    uint32_t c = uint32_t(found - cs.shadeClasses.begin());
    if (found == cs.shadeClasses.end()) {
      if (c < SHADE_CLASSES_MAX) {
        cs.shadeClasses.push_back(kinds);
      } else {
        c = SHADE_CLASSES_MAX - 1;
        cs.shadeClasses[c] |= kinds;
      }
    }
    cs.materials[m].children.w = c + 1u;
  }
}

}  // namespace

std::string feature_names(uint32_t mask) {
  static const std::pair<uint32_t, const char*> kNames[] = {
      {FEATURE_SPHERES, "spheres"},
      {FEATURE_BLEND, "blend"},
      {FEATURE_METAL, "metal"},
      {FEATURE_DIELECTRIC, "dielectric"},
      {FEATURE_PHONG, "phong"},
      {FEATURE_BLINN_PHONG, "blinn-phong"},
      {FEATURE_CHECKER, "checker"},
      {FEATURE_MARBLE, "marble"},
      {FEATURE_IMAGE, "image textures"},
      {FEATURE_SHADING_DATA, "vertex normals or UVs"},
      {FEATURE_POINT_LIGHTS, "point lights"},
      {FEATURE_SPHERE_LIGHTS, "sphere lights"},
      {FEATURE_ENVIRONMENT, "environment map"},
      {FEATURE_CMJ, "cmj sampler"},
      {FEATURE_EMISSION_TEXTURES, "textured emission"},
      {FEATURE_UNIFORM_HEMISPHERE, "uniform hemisphere sampling"},
  };
  static_assert(FEATURE_ALL == 0xffffu, "every feature bit has a name above");
  std::string out;
  for (const auto& [bit, name] : kNames) {
    if ((mask & bit) == 0u) continue;
    if (!out.empty()) out += ", ";
    out += name;
  }
  return out.empty() ? "none" : out;
}

shader::SceneView CompiledScene::view() const {
  shader::SceneView v;
  v.scene = params;
  // The arrays the kernels read as texel buffers, as texels.
  auto texels_of = [](const auto& records) { return reinterpret_cast<const glm::uvec4*>(records.data()); };
  v.nodeTexels = texels_of(nodes);
  v.wideNodeTexels = texels_of(wideNodes);
  v.triangleTexels = texels_of(triangles);
  v.shadingTexels = texels_of(triangleShading);
  v.sphereTexels = texels_of(spheres);
  v.materialTexels = texels_of(materials);
  v.emitterTexels = texels_of(emitters);
  v.textureTexels = texels_of(textures);
  v.pointLightTexels = texels_of(pointLights);
  v.imageTexels = texels.data();
  v.environmentCdf = environmentCdf.data();
  return v;
}

uint32_t CompiledScene::shade_key_features(uint32_t key) const {
  const uint32_t kinds = shadeCommonKinds | (key != SORT_KEY_MISS && key <= shadeClasses.size() ? shadeClasses[key - 1] : 0u);
  return params.accel.y & (~uint32_t(FEATURE_MATERIAL_KINDS) | kinds);
}

double CompiledScene::bvh_sah_cost() const {
  // The 8-wide tree's own cost: the binary tree it came from is split down to
  // single primitives, so that tree's cost says little.
  return bvhLayout == BvhLayout::Wide ? wide_sah_cost(wideNodes) : binarySahCost;
}

size_t CompiledScene::gpu_bytes() const {
  size_t nodeBytes = bvhLayout == BvhLayout::Wide ? wideNodes.size() * sizeof(shader::WideNode) : nodes.size() * sizeof(shader::BvhNode);
  return nodeBytes + triangles.size() * sizeof(shader::Triangle) +
         spheres.size() * sizeof(shader::Sphere) + materials.size() * sizeof(shader::Material) +
         emitters.size() * sizeof(shader::Emitter) + textures.size() * sizeof(shader::Texture) +
         texels.size() * sizeof(glm::uvec2) + triangleShading.size() * sizeof(shader::TriangleShading) +
         pointLights.size() * sizeof(shader::PointLight) + environmentCdf.size() * sizeof(float);
}

std::vector<float> environment_cdf(const shader::Texture& t, const std::vector<glm::uvec2>& texels) {
  const int w = int(t.info.z), h = int(t.info.w);
  auto lum = [&](int x, int y) { return double(luminance(texel_rgb(texels[t.info.y + size_t(y) * size_t(w) + size_t(x)]))); };
  std::vector<double> weight(size_t(w) * size_t(h));
  double total = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double m = 0.0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) m = std::max(m, lum((x + dx + w) % w, std::clamp(y + dy, 0, h - 1)));
      weight[size_t(y) * size_t(w) + size_t(x)] = m;
      total += m;
    }
  double floor = total > 0.0 ? 1e-3 * total / double(weight.size()) : 1.0;
  std::vector<float> cdf(size_t(h + 1) + size_t(h) * size_t(w + 1));
  std::vector<double> rowSum(size_t(h), 0.0);
  for (int y = 0; y < h; ++y) {
    double sinTheta = std::sin(WP_PI * (double(y) + 0.5) / double(h));
    size_t off = size_t(h + 1) + size_t(y) * size_t(w + 1);
    double acc = 0.0;
    std::vector<double> partial(size_t(w) + 1, 0.0);
    for (int x = 0; x < w; ++x) {
      acc += (weight[size_t(y) * size_t(w) + size_t(x)] + floor) * sinTheta;
      partial[size_t(x) + 1] = acc;
    }
    for (int x = 0; x <= w; ++x) cdf[off + size_t(x)] = float(partial[size_t(x)] / acc);
    cdf[off + size_t(w)] = 1.0f;
    rowSum[size_t(y)] = acc;
  }
  double all = 0.0;
  for (double r : rowSum) all += r;
  double acc = 0.0;
  cdf[0] = 0.0f;
  for (int y = 0; y < h; ++y) {
    acc += rowSum[size_t(y)];
    cdf[size_t(y) + 1] = float(acc / all);
  }
  cdf[size_t(h)] = 1.0f;
  return cdf;
}

glm::vec3 texture_mean(const std::vector<shader::Texture>& textures, const std::vector<glm::uvec2>& texels, uint32_t index) {
  const shader::Texture& t = textures.at(index);
  switch (t.info.x & TEX_TYPE_MASK) {
    case TEX_CHECKER:
      return 0.5f * (texture_mean(textures, texels, t.info.y) + texture_mean(textures, texels, t.info.z));
    case TEX_MARBLE:
      return 0.5f * (glm::vec3(t.color0) + glm::vec3(t.color1));
    case TEX_IMAGE: {
      glm::dvec3 sum(0.0);
      size_t n = size_t(t.info.z) * t.info.w;
      for (size_t i = 0; i < n; ++i) sum += glm::dvec3(texel_rgb(texels[t.info.y + i]));
      return glm::vec3(sum / double(std::max<size_t>(n, 1)));
    }
    default:
      return glm::vec3(t.color0);
  }
}

std::vector<shader::Emitter> build_alias_table(const std::vector<double>& weights) {
  size_t n = weights.size();
  std::vector<shader::Emitter> table(n);
  double total = std::accumulate(weights.begin(), weights.end(), 0.0);
  std::vector<double> scaled(n);
  std::vector<uint32_t> small, large;
  for (size_t i = 0; i < n; ++i) {
    table[i].pmf = float(weights[i] / total);
    table[i].alias = uint32_t(i);
    table[i].threshold = 1.0f;
    scaled[i] = weights[i] / total * double(n);
    (scaled[i] < 1.0 ? small : large).push_back(uint32_t(i));
  }
  while (!small.empty() && !large.empty()) {
    uint32_t s = small.back();
    small.pop_back();
    uint32_t l = large.back();
    table[s].threshold = float(scaled[s]);
    table[s].alias = l;
    scaled[l] -= 1.0 - scaled[s];
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // Leftovers are 1 up to rounding: they always keep their own index.
  return table;
}

// Luminance of each material's mean emitted radiance (0: it does not emit).
static std::vector<double> material_radiance(const Scene& scene) {
  std::vector<double> radiance(scene.materials.size(), 0.0);
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    uint32_t tex = scene.materials[m].info.z;
    if (tex != WP_INVALID) radiance[m] = luminance(texture_mean(scene.textures, scene.texels, tex));
  }
  return radiance;
}

// bvh_input with the scene's material_radiance already at hand.
static BvhInput bvh_input(const Scene& scene, const std::vector<double>& radiance) {
  BvhInput input;
  const size_t count = scene.triangles.size() + scene.spheres.size();
  reserve_huge(input.bounds, count);
  for (const SceneTriangle& t : scene.triangles) input.bounds.push_back(triangle_bounds(t));
  for (const SceneSphere& s : scene.spheres) input.bounds.push_back(sphere_bounds(s.toWorld));
  if (std::any_of(radiance.begin(), radiance.end(), [](double r) { return r > 0.0; })) {
    reserve_huge(input.emits, count);
    for (const SceneTriangle& t : scene.triangles) {
      const glm::vec3 front = glm::cross(t.v[1] - t.v[0], t.v[2] - t.v[0]);  // as surface_at's ng
      uint8_t sides = 0;
      for (int a = 0; a < 3; ++a) sides |= uint8_t((front[a] < 0.0f ? 1u : 0u) | (front[a] > 0.0f ? 2u : 0u)) << (2 * a);
      input.emits.push_back(radiance[t.material] > 0.0 ? sides : 0);
    }
    for (const SceneSphere& s : scene.spheres) input.emits.push_back(radiance[s.material] > 0.0 ? 0x3f : 0);
  }
  return input;
}

BvhInput bvh_input(const Scene& scene) {
  return bvh_input(scene, material_radiance(scene));
}

CompiledScene compile_scene(const Scene& scene, const RenderOptions& options) {
  CompiledScene out;
  const size_t numTris = scene.triangles.size();
  const size_t numSpheres = scene.spheres.size();
  if (numTris + numSpheres >= size_t(EMITTER_ENVIRONMENT)) throw InputError(scene.sourcePath + ": too many primitives");

  const std::vector<double> materialRadiance = material_radiance(scene);
  BvhInput input = bvh_input(scene, materialRadiance);
  Aabb sceneBounds;
  for (const Aabb& b : input.bounds) sceneBounds.grow(b);
  AcceleratorSettings accel = scene.accelerator;
  accel.split = split_for(accel, input.bounds.size());
  if (options.clusteredBuild && accel.split == SplitMethod::Sah) accel.split = SplitMethod::ClusteredSah;
  out.bvhSplit = accel.split;
  const bool wide = options.bvhLayout == BvhLayout::Wide;
  out.bvhLayout = options.bvhLayout;
  uint32_t stackSlots;
  std::vector<uint32_t> order;
  const auto start = std::chrono::steady_clock::now();
  if (wide) {
    WideBvh w;
    if (options.bvhRotations) {
      Bvh bvh = build_bvh(input, binary_settings_for_wide(accel, options.wideCollapse));
      rotate_bvh(bvh);
      w = collapse_to_wide(bvh, input.emits, options.wideCollapse, accel.maxLeafSize);
    } else {
      // Collapsed from the builder's arrays, without laying out the binary tree.
      w = build_wide_bvh(input, accel, options.wideCollapse);
    }
    out.bvhBuildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.wideNodes = std::move(w.nodes);
    order = std::move(w.order);
    out.bvhDepth = w.depth;
    stackSlots = uint32_t(std::max(w.depth, 1)) - 1u + WIDE_STACK_PRIM_GROUPS;  // a node group per level below the root, and the primitive groups
    out.nodes.push_back(shader::BvhNode{});
  } else {
    Bvh bvh = build_bvh(input, accel);
    if (options.bvhRotations) rotate_bvh(bvh);
    out.bvhBuildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.binarySahCost = bvh.sahCost;
    out.nodes = std::move(bvh.nodes);
    order = std::move(bvh.order);
    out.bvhDepth = bvh.depth;
    stackSlots = uint32_t(bvh.depth) + 1u;
    out.wideNodes.push_back(shader::WideNode{});
  }
  // The builder bounds the depth, and with it the kernels' traversal stacks.
  if (out.bvhDepth > BVH_MAX_DEPTH) throw RenderError("internal error: BVH deeper than BVH_MAX_DEPTH");

  // Primitive records in leaf order (both layouts' leaves index them): each
  // triangle, and for each sphere a placeholder naming it.
  reserve_huge(out.triangles, order.size());
  reserve_huge(out.triangleShading, scene.triangleShading.size());
  for (uint32_t id : order) {
    shader::Triangle g{};
    if (id >= numTris) {
      g.material = WP_INVALID;
      g.emitter = WP_INVALID;
      g.shading = id - uint32_t(numTris);
      out.triangles.push_back(g);
      continue;
    }
    const SceneTriangle& t = scene.triangles[id];
    g.v0 = t.v[0];
    g.v1 = t.v[1];
    g.v2 = t.v[2];
    g.material = t.material;
    g.emitter = WP_INVALID;
    g.shading = WP_INVALID;
    if (t.shading != WP_INVALID) {
      const SceneTriangleShading& in = scene.triangleShading[t.shading];
      shader::TriangleShading sh{};
      g.shading = uint32_t(out.triangleShading.size());
      sh.hasNormals = in.hasNormals ? 1u : 0u;
      if (in.hasNormals) {
        sh.n0 = in.n[0];
        sh.n1 = in.n[1];
        sh.n2 = in.n[2];
      }
      // Without UVs the barycentrics serve, as for triangles without shading data.
      glm::vec2 uv[3] = {{0, 0}, {1, 0}, {0, 1}};
      if (in.hasUvs) std::copy(in.uv, in.uv + 3, uv);
      sh.u0 = uv[0].x;
      sh.v0 = uv[0].y;
      sh.uv12 = glm::vec4(uv[1], uv[2]);
      out.triangleShading.push_back(sh);
    }
    out.triangles.push_back(g);
  }
  for (const SceneSphere& s : scene.spheres) {
    shader::Sphere g{};
    rows_3x4(s.toWorld, g.toWorld0, g.toWorld1, g.toWorld2);
    rows_3x4(glm::inverse(s.toWorld), g.toObject0, g.toObject1, g.toObject2);
    g.material = s.material;
    g.emitter = WP_INVALID;
    float r = glm::length(glm::vec3(s.toWorld[0]));  // uniform scale (checked when emissive)
    g.area = 4.0f * WP_PI * r * r;
    out.spheres.push_back(g);
  }

  out.materials = scene.materials;
  out.textures = scene.textures;
  out.texels = scene.texels;
  out.pointLights = scene.pointLights;

  // Emitters: every primitive whose material emits, and every point light,
  // picked in proportion to power (luminance of the mean emitted radiance
  // times pi times area; of the intensity times 4 pi).
  std::vector<double> power;
  std::vector<uint32_t> prims;
  auto emits = [&](uint32_t material, float area) {
    double p = materialRadiance[material] * WP_PI * double(area);
    return p > 0.0 ? p : 0.0;
  };
  for (size_t i = 0; i < out.triangles.size(); ++i) {
    shader::Triangle& t = out.triangles[i];
    if (t.material == WP_INVALID) continue;  // a sphere's placeholder
    double p = emits(t.material, 0.5f * glm::length(glm::cross(t.v1 - t.v0, t.v2 - t.v0)));
    if (p <= 0.0) continue;
    t.emitter = uint32_t(prims.size());
    prims.push_back(uint32_t(i));
    power.push_back(p);
  }
  for (size_t i = 0; i < out.spheres.size(); ++i) {
    shader::Sphere& s = out.spheres[i];
    double p = emits(s.material, s.area);
    if (p <= 0.0) continue;
    s.emitter = uint32_t(prims.size());
    prims.push_back(uint32_t(i) | HIT_SPHERE_BIT);
    power.push_back(p);
  }
  // The environment map: power of its mean radiance falling on a disc the
  // size of the scene (only steers the choice among emitters).
  uint32_t environmentEmitter = WP_INVALID;
  if (scene.environmentTexture != WP_INVALID) {
    const shader::Texture& env = out.textures[scene.environmentTexture];
    out.environmentCdf = environment_cdf(env, out.texels);
    double radius = sceneBounds.empty() ? 0.0 : 0.5 * double(glm::length(sceneBounds.hi - sceneBounds.lo));
    double p = luminance(texture_mean(out.textures, out.texels, scene.environmentTexture)) * WP_PI * WP_PI * radius * radius * 4.0;
    if (p > 0.0) {
      environmentEmitter = uint32_t(prims.size());
      prims.push_back(EMITTER_ENVIRONMENT);
      power.push_back(p);
    }
  }
  for (size_t i = 0; i < out.pointLights.size(); ++i) {
    double p = luminance(glm::vec3(out.pointLights[i].intensity)) * 4.0 * WP_PI;
    if (p <= 0.0) continue;
    prims.push_back(uint32_t(i) | EMITTER_POINT_BIT);
    power.push_back(p);
  }
  out.emitters = build_alias_table(power);
  for (size_t i = 0; i < prims.size(); ++i) out.emitters[i].prim = prims[i];
  const uint32_t features = scene_features(out, prims, numSpheres > 0, scene.environmentTexture != WP_INVALID);
  shade_classes(out, scene.environmentTexture);
  if (out.triangles.empty()) out.triangles.push_back(shader::Triangle{});
  if (out.spheres.empty()) out.spheres.push_back(shader::Sphere{});
  // Buffers are never empty: bind a zero element where the scene has none.
  if (out.emitters.empty()) out.emitters.push_back(shader::Emitter{});
  if (out.materials.empty()) out.materials.push_back(shader::Material{});
  if (out.textures.empty()) out.textures.push_back(shader::Texture{});
  if (out.texels.empty()) out.texels.push_back(glm::uvec2(0u));
  if (out.triangleShading.empty()) out.triangleShading.push_back(shader::TriangleShading{});
  if (out.pointLights.empty()) out.pointLights.push_back(shader::PointLight{});
  if (out.environmentCdf.empty()) out.environmentCdf.push_back(0.0f);

  const Camera& cam = scene.camera;
  out.width = cam.width;
  out.height = cam.height;
  out.spp = options.spp > 0 ? options.spp : scene.samplesPerPixel;
  out.adaptive = options.adaptive;
  int maxBounces = options.maxBounces >= 0 ? options.maxBounces : scene.integrator.maxBounces;
  shader::SceneParams& p = out.params;
  rows_3x4(cam.toWorld, p.camToWorld0, p.camToWorld1, p.camToWorld2);
  p.camLens = glm::vec4(std::tan(glm::radians(cam.vfovDegrees) * 0.5f), float(cam.width) / float(cam.height),
                        cam.apertureRadius, cam.focusDistance);
  p.background = glm::vec4(scene.background, 0.0f);
  p.environment = glm::uvec4(scene.environmentTexture, environmentEmitter, 0u, 0u);
  if (scene.environmentTexture != WP_INVALID) {
    p.environment.z = out.textures[scene.environmentTexture].info.z;
    p.environment.w = out.textures[scene.environmentTexture].info.w;
  }
  p.image = glm::uvec4(uint32_t(cam.width), uint32_t(cam.height), uint32_t(maxBounces),
                       uint32_t(scene.integrator.russianRouletteDepth));
  uint32_t flags = 0;
  IntegratorKind kind = options.integrator ? *options.integrator : scene.integrator.kind;
  if (kind == IntegratorKind::PathMats) flags |= SCENE_FLAG_NO_NEE;
  if (kind == IntegratorKind::PathHemisphere) flags |= SCENE_FLAG_NO_NEE | SCENE_FLAG_HEMISPHERE;
  if (kind == IntegratorKind::PathNee) flags |= SCENE_FLAG_NO_BSDF_MIS;
  uint32_t mode = INTEGRATOR_PATH;
  if (kind == IntegratorKind::Normals) mode = INTEGRATOR_NORMALS;
  if (kind == IntegratorKind::AmbientOcclusion) mode = INTEGRATOR_AO;
  if (kind == IntegratorKind::PathMixture) mode = INTEGRATOR_MIXTURE;
  // The mixture's exact light density visits every emitter at every bounce;
  // the shade kernel's loop budget (and patience) bound how many that may be.
  if (mode == INTEGRATOR_MIXTURE && prims.size() > kMaxMixtureEmitters) {
    throw InputError(scene.sourcePath + ": \"path tracer mixture\" evaluates every emitter at every bounce; this scene has " +
                     std::to_string(prims.size()) + " emitters (at most " + std::to_string(kMaxMixtureEmitters) +
                     "): use \"path tracer mis\"");
  }
  SamplerKind sampler = options.sampler ? *options.sampler : scene.sampler;
  if (options.lightSamples < 1 || uint32_t(options.lightSamples) > MAX_LIGHT_SAMPLES) {
    throw InputError("light samples per vertex must lie in [1, " + std::to_string(MAX_LIGHT_SAMPLES) + "], got " +
                     std::to_string(options.lightSamples));
  }
  p.mode = glm::uvec4(mode, sampler == SamplerKind::Cmj ? SAMPLER_CMJ : SAMPLER_INDEPENDENT, uint32_t(out.spp),
                      uint32_t(options.lightSamples));
  p.counts = glm::uvec4(uint32_t(prims.size()), options.seed, options.traversalStepCap, flags);
  p.debug = glm::vec4(options.plantedBias, 0.0f, 0.0f, 0.0f);
  p.debugRegion = options.plantedRegion;
  p.accel = glm::uvec4(wide ? BVH_LAYOUT_WIDE : BVH_LAYOUT_BINARY, features | (sampler == SamplerKind::Cmj ? FEATURE_CMJ : 0u) |
                           ((flags & SCENE_FLAG_HEMISPHERE) != 0u ? FEATURE_UNIFORM_HEMISPHERE : 0u),
                       stackSlots, 0u);
  return out;
}

}  // namespace wp
