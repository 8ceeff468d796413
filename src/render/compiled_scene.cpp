#include "render/compiled_scene.h"
#include "render/shader_cpp.h"

#include <glm/gtc/matrix_access.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>

#include "bvh/wide_bvh.h"
#include "render/photon_pass.h"
#include "scene/kinds.h"
#include "image/image.h"
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

float luminance(glm::vec3 c) {
  return shader::ShaderMath{}.illuminance(c);
}

// An image texel: RGB from two packed half-float pairs (as texel_at in scene.glsl).
glm::vec3 texel_rgb(glm::uvec2 packed) {
  glm::vec2 rg = glm::unpackHalf2x16(packed.x);
  return glm::vec3(rg.x, rg.y, glm::unpackHalf2x16(packed.y).x);
}

// The light kind of a punctual light record (types.glsl's PointLight).
uint32_t punctual_light_kind(const shader::PointLight& l) {
  return uint32_t(l.position.w);
}

// Whether a primitive record stands for a sphere or an instance.
bool is_placeholder(const shader::Triangle& t) {
  return t.material == WP_INVALID || t.material == PRIM_INSTANCE;
}

// The kinds a compiled scene uses (SceneParams.kinds; kinds.glsl), before its
// empty arrays get their placeholder element: every material's and texture's
// kind, the light kinds of the emitter table's prims (`emitters`), and the
// features. `environment`: an environment map replaces the background. The
// sampler's and the integrator's features are added by compile_scene.
glm::uvec4 scene_kinds(const CompiledScene& cs, const std::vector<uint32_t>& emitters, bool spheres, bool environment) {
  glm::uvec4 k(0u);
  for (const shader::Material& m : cs.materials) {
    k.x |= KIND_BIT(m.info.x);
    if (m.children.z != WP_INVALID) k.w |= KIND_BIT(FEATURE_NORMAL_MAPS);
    if (m.info.z != WP_INVALID && (cs.textures[m.info.z].info.x & TEX_TYPE_MASK) != TEX_CONSTANT) k.w |= KIND_BIT(FEATURE_EMISSION_TEXTURES);
    if (m.info.x == MAT_LIGHT && m.params.x != 0.0f) k.w |= KIND_BIT(FEATURE_COSINE_EMISSION);
    if (m.info.x == MAT_METAL_ROUGH && (m.params2 != glm::vec4(0.0f) || m.moreTextures.x != WP_INVALID || m.moreTextures.y != WP_INVALID))
      k.w |= KIND_BIT(FEATURE_SPECULAR_TINT);
    if (m.info.x == MAT_METAL_ROUGH && m.iridescence.x > 0.0f) k.w |= KIND_BIT(FEATURE_IRIDESCENCE);
    if (m.info.x == MAT_METAL_ROUGH && m.anisotropy.x > 0.0f) k.w |= KIND_BIT(FEATURE_ANISOTROPY);
    if (m.info.x == MAT_METAL_ROUGH && m.volume.w > 0.0f) k.w |= KIND_BIT(FEATURE_VOLUME);
    if (m.info.x == MAT_METAL_ROUGH && m.volume.w > 1.0f) k.w |= KIND_BIT(FEATURE_DISPERSION);
  }
  for (const shader::Texture& t : cs.textures) k.y |= KIND_BIT(t.info.x & TEX_TYPE_MASK);
  for (uint32_t prim : emitters) {
    if (prim == EMITTER_ENVIRONMENT) k.z |= KIND_BIT(LIGHT_ENVIRONMENT);
    else if (prim & EMITTER_POINT_BIT) k.z |= KIND_BIT(punctual_light_kind(cs.pointLights[prim & ~EMITTER_POINT_BIT]));
    else if (prim & HIT_SPHERE_BIT) k.z |= KIND_BIT(LIGHT_SPHERE);
    else k.z |= KIND_BIT(LIGHT_AREA);
  }
  if (environment) k.z |= KIND_BIT(LIGHT_ENVIRONMENT);
  if (spheres) k.w |= KIND_BIT(FEATURE_SPHERES);
  if (!cs.triangleShading.empty()) k.w |= KIND_BIT(FEATURE_SHADING_DATA);
  if (!cs.triangleVertexData.empty()) k.w |= KIND_BIT(FEATURE_VERTEX_DATA);
  if (!cs.instances.empty()) k.w |= KIND_BIT(FEATURE_INSTANCES);
  for (const shader::Triangle& t : cs.triangles) {
    if (is_placeholder(t)) continue;
    if (t.material & TRIANGLE_ONE_SIDED) k.w |= KIND_BIT(FEATURE_ONE_SIDED);
    if (t.material & TRIANGLE_CUTOUT) k.w |= KIND_BIT(FEATURE_CUTOUTS);
  }
  return k;
}

// The texture kinds texture t's lookup runs: its own, and a checker's
// squares' (nested up to TEXTURE_MAX_NESTING deep, as texture_eval follows).
uint32_t lookup_kinds(const std::vector<shader::Texture>& textures, uint32_t t, int depth = 0) {
  if (t == WP_INVALID || t >= textures.size()) return 0u;
  const shader::Texture& tex = textures[t];
  const uint32_t kind = tex.info.x & TEX_TYPE_MASK;
  if (kind != TEX_CHECKER || depth >= TEXTURE_MAX_NESTING) return KIND_BIT(kind);
  return KIND_BIT(kind) | lookup_kinds(textures, tex.info.y, depth + 1) | lookup_kinds(textures, tex.info.z, depth + 1);
}

// The kinds a ray that hits material m needs for its BSDF: x its material
// kinds (a blend's children's too), y the texture kinds it looks up. (Its
// emission's kinds every shade kernel has: shade_classes.)
glm::uvec2 bsdf_kinds(const CompiledScene& cs, uint32_t m, int depth = 0) {
  const shader::Material& mat = cs.materials[m];
  glm::uvec2 k(KIND_BIT(mat.info.x),
               lookup_kinds(cs.textures, mat.info.y) | lookup_kinds(cs.textures, mat.info.w) | lookup_kinds(cs.textures, mat.children.z));
  if (mat.info.x == MAT_METAL_ROUGH)  // its transmission and specular textures
    k.y |= lookup_kinds(cs.textures, mat.children.y) | lookup_kinds(cs.textures, mat.moreTextures.x) | lookup_kinds(cs.textures, mat.moreTextures.y) |
           lookup_kinds(cs.textures, mat.moreTextures.z) | lookup_kinds(cs.textures, mat.moreTextures.w) |
           lookup_kinds(cs.textures, glm::floatBitsToUint(mat.anisotropy.w));
  // The loader bounds a blend's lobes (BSDF_MAX_LOBES), and so its depth.
  if (mat.info.x == MAT_BLEND && depth < int(BSDF_MAX_LOBES))
    k |= bsdf_kinds(cs, mat.children.x, depth + 1) | bsdf_kinds(cs, mat.children.y, depth + 1);
  if (is_layer(mat.info.x) && depth < int(BSDF_MAX_LOBES)) k |= bsdf_kinds(cs, mat.children.x, depth + 1);  // its base
  return k;
}

// Groups the materials that primitives use into shade classes by the kinds
// they need (bsdf_kinds), in order of first use, and writes each
// material's sort key (class + 1) to its children.w. Past SHADE_CLASSES_MAX
// classes, the rest share the last, which needs all of their kinds. Fills
// shadeClasses and shadeCommonKinds.
void shade_classes(CompiledScene& cs, uint32_t environmentTexture) {
  uint32_t common = lookup_kinds(cs.textures, environmentTexture);
  for (const shader::Material& m : cs.materials) common |= lookup_kinds(cs.textures, m.info.z);  // emission, hit or sampled
  cs.shadeCommonKinds = common;
  std::vector<bool> used(cs.materials.size(), false);
  for (const shader::Triangle& t : cs.triangles)
    if (!is_placeholder(t)) used[t.material & TRIANGLE_MATERIAL_MASK] = true;
  for (const shader::Sphere& sp : cs.spheres) used[sp.material] = true;
  for (uint32_t m = 0; m < cs.materials.size(); ++m) {
    cs.materials[m].children.w = SORT_KEY_MISS + 1u;  // for unused materials: any class will do
    if (!used[m]) continue;
    const glm::uvec2 kinds = bsdf_kinds(cs, m);
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

shader::SceneView CompiledScene::view() const {
  shader::SceneView v;
  v.scene = params;
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
         floatTables.size() * sizeof(float);
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
      return glm::vec3(sum / double(std::max<size_t>(n, 1))) * glm::vec3(t.color0);
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

// The scene's textures and images as the kernels read them: each texture a
// record (types.glsl), the images' texels back to back as RGBA half floats.
struct PackedTextures {
  std::vector<shader::Texture> textures;
  std::vector<glm::uvec2> texels;
};

static PackedTextures pack_textures(const Scene& scene) {
  PackedTextures out;
  std::vector<uint32_t> firstTexel;
  for (const LinearImage& img : scene.images) {
    firstTexel.push_back(uint32_t(out.texels.size()));
    for (size_t i = 0; i < img.pixels.size(); ++i) {
      const glm::vec3 c = img.pixels[i];
      const float alpha = img.alpha.empty() ? 1.0f : img.alpha[i];
      out.texels.emplace_back(glm::packHalf2x16(glm::vec2(c.x, c.y)), glm::packHalf2x16(glm::vec2(c.z, alpha)));
    }
  }
  for (const SceneTexture& in : scene.textures) {
    shader::Texture t{};
    t.info = glm::uvec4(in.kind | (in.solid ? TEX_SOLID : 0u) | (in.secondUvSet ? TEX_UV1 : 0u) | in.wrapU << TEX_WRAP_U_SHIFT |
                            in.wrapV << TEX_WRAP_V_SHIFT,
                        0u, 0u, 0u);
    rows_3x4(in.mapping, t.map0, t.map1, t.map2);
    switch (in.kind) {
      case TEX_CHECKER:
        t.info.y = in.even;
        t.info.z = in.odd;
        t.color0.w = in.scale;
        break;
      case TEX_MARBLE:
        t.color0 = glm::vec4(in.color, in.scale);
        t.color1 = glm::vec4(in.veins, 0.0f);
        break;
      case TEX_IMAGE: {
        const LinearImage& img = scene.images.at(in.image);
        t.info.y = firstTexel[in.image];
        t.info.z = uint32_t(img.width);
        t.info.w = uint32_t(img.height);
        t.color0 = glm::vec4(in.color, in.alpha);
        break;
      }
      case TEX_FRESNEL: t.color0.x = in.ior; break;
      default: t.color0 = glm::vec4(in.color, in.alpha); break;
    }
    out.textures.push_back(t);
  }
  return out;
}

static shader::Material pack_material(const SceneMaterial& in) {
  shader::Material m{};
  m.info = glm::uvec4(in.kind, in.albedo, in.emission, in.amount);
  m.children = glm::uvec4(in.a, in.b, in.normalMap, WP_INVALID);  // w: the sort key (shade_classes)
  if (in.kind != MAT_BLEND && !is_layer(in.kind)) m.children.x = glm::floatBitsToUint(in.alphaCutoff);
  if (in.kind == MAT_METAL_ROUGH) m.children.y = in.transmission;
  m.moreTextures = glm::uvec4(in.specular, in.specularColor, in.iridescenceTexture, in.iridescenceThickness);
  m.volume = glm::vec4(in.attenuation, in.volume ? 1.0f + in.dispersion : 0.0f);
  m.iridescence = in.iridescence;
  m.anisotropy = glm::vec4(in.anisotropy, std::cos(in.anisotropyRotation), std::sin(in.anisotropyRotation),
                           glm::uintBitsToFloat(in.anisotropyTexture));
  m.params = in.params;
  m.params2 = in.params2;
  // Media: index 0 is the vacuum, the scene's follow (compile_scene).
  auto medium = [](uint32_t i) { return i == WP_INVALID ? 0u : i + 1u; };
  m.media = in.boundsMedia ? glm::uvec4(medium(in.interior), medium(in.exterior), 0u, 0u) : glm::uvec4(WP_INVALID, WP_INVALID, 0u, 0u);
  return m;
}

// A medium's record. A grid medium's grid and majorant grid go to the end
// of `volumeWords` (BINDING_VOLUMES), each grid once however many media
// read it.
static shader::Medium pack_medium(const SceneMedium& in, std::vector<uint32_t>& volumeWords,
                                  std::map<const DensityGrid*, uint32_t>& gridAt) {
  shader::Medium m{};  // a vacuum: kind 0, nothing in it
  if (in.kind == MEDIUM_VACUUM) return m;
  m.info = glm::uvec4(in.kind, 0u, 0u, 0u);
  const glm::vec3 total = in.sigmaA + in.sigmaS + in.sigmaN;
  m.sigmaA = glm::vec4(in.sigmaA, in.g);
  // Homogeneous: the majorant. Grid: what scales the majorant grid's
  // densities into majorants.
  m.sigmaS = glm::vec4(in.sigmaS, std::max(total.x, std::max(total.y, total.z)));
  m.sigmaN = glm::vec4(in.sigmaN, 0.0f);
  if (in.kind != MEDIUM_NANOVDB) return m;
  const DensityGrid& g = *in.grid;
  auto placed = gridAt.find(&g);
  if (placed == gridAt.end()) {
    placed = gridAt.emplace(&g, uint32_t(volumeWords.size())).first;
    volumeWords.insert(volumeWords.end(), g.words.begin(), g.words.end());
  }
  const glm::uvec3 cells = majorant_cells(in);
  const std::vector<float> majorants = majorant_grid(g, cells);
  m.info = glm::uvec4(in.kind, placed->second * 4u, uint32_t(volumeWords.size()), cells.x | (cells.y << 10u) | (cells.z << 20u));
  for (float v : majorants) volumeWords.push_back(glm::floatBitsToUint(v));
  if (uint64_t(volumeWords.size()) * 4u > 0xffffffffull)
    throw InputError(g.file + ": the scene's grids take more than the 4 GiB the kernels address");
  const glm::dmat4 toIndex = g.worldToIndex * glm::inverse(glm::dmat4(in.gridToScene));
  m.toIndex0 = glm::vec4(glm::row(toIndex, 0));
  m.toIndex1 = glm::vec4(glm::row(toIndex, 1));
  m.toIndex2 = glm::vec4(glm::row(toIndex, 2));
  m.boundsLo = glm::vec4(glm::vec3(g.indexMin) - 1.0f, 0.0f);
  m.boundsHi = glm::vec4(glm::vec3(g.indexMax) + 1.0f, 0.0f);
  return m;
}

// Luminance of each material's mean emitted radiance (0: it does not emit).
static std::vector<double> material_radiance(const Scene& scene, const PackedTextures& packed) {
  std::vector<double> radiance(scene.materials.size(), 0.0);
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    uint32_t tex = scene.materials[m].emission;
    if (tex != WP_INVALID) radiance[m] = luminance(texture_mean(packed.textures, packed.texels, tex));
  }
  return radiance;
}

// A triangle's record without its shading data (compile_scene adds that)
// and before the emitter table names it.
static shader::Triangle triangle_record(const SceneTriangle& t) {
  shader::Triangle g{};
  g.v0 = t.v[0];
  g.v1 = t.v[1];
  g.v2 = t.v[2];
  g.material = t.material;
  g.emitter = WP_INVALID;
  g.shading = WP_INVALID;
  return g;
}

// bvh_input with the scene's material_radiance already at hand, and the
// instances' world boxes (placeholders after the spheres, which emit nothing).
static BvhInput bvh_input(const Scene& scene, const std::vector<double>& radiance, const std::vector<Aabb>& instanceBoxes) {
  BvhInput input;
  const size_t count = scene.triangles.size() + scene.spheres.size() + instanceBoxes.size();
  reserve_huge(input.bounds, count);
  for (const SceneTriangle& t : scene.triangles) input.bounds.push_back(triangle_bounds(t));
  for (const SceneSphere& s : scene.spheres) input.bounds.push_back(sphere_bounds(s.toWorld));
  input.bounds.insert(input.bounds.end(), instanceBoxes.begin(), instanceBoxes.end());
  if (std::any_of(radiance.begin(), radiance.end(), [](double r) { return r > 0.0; })) {
    reserve_huge(input.emits, count);
    for (const SceneTriangle& t : scene.triangles) {
      const glm::vec3 front = glm::cross(t.v[1] - t.v[0], t.v[2] - t.v[0]);  // as surface_at's ng
      uint8_t sides = 0;
      for (int a = 0; a < 3; ++a) sides |= uint8_t((front[a] < 0.0f ? 1u : 0u) | (front[a] > 0.0f ? 2u : 0u)) << (2 * a);
      input.emits.push_back(radiance[t.material] > 0.0 ? sides : 0);
    }
    for (const SceneSphere& s : scene.spheres) input.emits.push_back(radiance[s.material] > 0.0 ? 0x3f : 0);
    input.emits.resize(count, 0);
  }
  return input;
}

// An instance's world box: the union of its mesh's top boxes (`parts`)
// placed by its transform, tighter than the mesh's whole box placed, grown by
// a few ulps of its coordinates against rounding in the walk's transform of
// the ray.
static Aabb instance_box(const std::vector<Aabb>& parts, const glm::mat4& toWorld) {
  Aabb w;
  for (const Aabb& b : parts) {
    const auto [lo, hi] = placed_bounds(b.lo, b.hi, toWorld);
    w.grow(lo);
    w.grow(hi);
  }
  const glm::vec3 pad = 4e-7f * glm::max(glm::abs(w.lo), glm::abs(w.hi)) + glm::vec3(1e-30f);
  w.lo -= pad;
  w.hi += pad;
  return w;
}

// The boxes under the root of a tree: a wide root's children, or a binary
// tree's nodes two levels down (each box whole where it is a leaf).
static std::vector<Aabb> top_boxes(const std::vector<shader::WideNode>& wide, const std::vector<shader::BvhNode>& binary) {
  std::vector<Aabb> parts;
  if (!wide.empty()) {
    const shader::WideNode& root = wide[0];
    for (int slot = 0; slot < 8; ++slot)
      if (((slot < 4 ? root.meta0123 : root.meta4567) >> ((slot & 3) * 8)) & 0xffu) parts.push_back(wide_child_box(root, slot));
    return parts;
  }
  std::vector<uint32_t> level{0u};
  for (int depth = 0; depth < 2; ++depth) {
    std::vector<uint32_t> next;
    for (uint32_t n : level) {
      if (binary[n].count != 0u) parts.push_back(node_box(binary[n]));
      else next.insert(next.end(), {binary[n].leftFirst, binary[n].leftFirst + 1u});
    }
    level = std::move(next);
  }
  for (uint32_t n : level) parts.push_back(node_box(binary[n]));
  return parts;
}

BvhInput bvh_input(const Scene& scene) {
  std::vector<Aabb> boxes;
  for (const SceneInstance& i : scene.instances) {
    const SceneInstancedMesh& m = scene.instancedMeshes[i.mesh];
    Aabb b;
    b.lo = m.lo;
    b.hi = m.hi;
    boxes.push_back(instance_box({b}, i.toWorld));
  }
  return bvh_input(scene, material_radiance(scene, pack_textures(scene)), boxes);
}

void set_camera_params(const Camera& cam, shader::SceneParams& p) {
  rows_3x4(cam.toWorld, p.camToWorld0, p.camToWorld1, p.camToWorld2);
  p.camLens = glm::vec4(cam.orthoHalfHeight > 0.0f ? -cam.orthoHalfHeight : std::tan(glm::radians(cam.vfovDegrees) * 0.5f),
                        cam.aspect > 0.0f ? cam.aspect : float(cam.width) / float(cam.height),
                        cam.apertureRadius, cam.focusDistance);
  p.camWindow = cam.window;
}

// What the photon mapper refuses: light no photon carries (the background,
// an environment map, lights at infinity, CS184's point lights that do not
// fall off) and media, which its photons do not cross yet.
static void check_photon_mapper_scene(const Scene& scene, bool media) {
  const std::string at = scene.sourcePath + ": the photon mapper ";
  if (media) throw InputError(at + "does not trace photons through participating media; use a path tracer");
  if (scene.environment != WP_INVALID || scene.background != glm::vec3(0.0f))
    throw InputError(at + "carries light from emitters only, and this scene's background or environment lights it too: "
                          "make the background black (\"background\": 0) or use a path tracer");
  for (const ScenePointLight& l : scene.pointLights) {
    if (l.kind == ScenePointLight::Kind::Directional || l.kind == ScenePointLight::Kind::Hemisphere)
      throw InputError(at + "emits photons from area, sphere, point and spot lights; this scene has a light at infinity");
    if (!l.falloff) throw InputError(at + "needs point lights that fall off with distance (CS184's do not)");
  }
}

CompiledScene compile_scene(const Scene& scene, const RenderOptions& options) {
  CompiledScene out;
  const size_t numTris = scene.triangles.size();
  const size_t numSpheres = scene.spheres.size();
  size_t records = numTris + numSpheres + scene.lightOnlyTriangles.size() + scene.instances.size();
  for (const SceneInstancedMesh& m : scene.instancedMeshes) records += m.triangles.size();
  if (records >= size_t(EMITTER_UNSEEN_BIT)) throw InputError(scene.sourcePath + ": too many primitives");

  PackedTextures packed = pack_textures(scene);
  const std::vector<double> materialRadiance = material_radiance(scene, packed);
  const bool wide = options.bvhLayout == BvhLayout::Wide;
  out.bvhLayout = options.bvhLayout;
  const auto start = std::chrono::steady_clock::now();
  // The split method for a tree of `primitives` (Auto resolved by size).
  auto accel_for = [&](size_t primitives) {
    AcceleratorSettings accel = scene.accelerator;
    accel.split = split_for(accel, primitives);
    if (options.clusteredBuild && accel.split == SplitMethod::Sah) accel.split = SplitMethod::ClusteredSah;
    return accel;
  };
  // The trees of the instanced meshes first (bottom level): the top level's
  // boxes of their instances come from them.
  struct MeshTree {
    std::vector<shader::WideNode> wideNodes;
    std::vector<shader::BvhNode> nodes;
    std::vector<uint32_t> order;
    int depth = 0;
    std::vector<Aabb> topBoxes;
  };
  std::vector<MeshTree> meshTrees(scene.instancedMeshes.size());
  for (size_t m = 0; m < scene.instancedMeshes.size(); ++m) {
    BvhInput in;
    for (const SceneTriangle& t : scene.instancedMeshes[m].triangles) in.bounds.push_back(triangle_bounds(t));
    const AcceleratorSettings accel = accel_for(in.bounds.size());
    MeshTree& tree = meshTrees[m];
    if (wide) {
      WideBvh w = build_wide_bvh(in, accel, options.wideCollapse);
      tree.wideNodes = std::move(w.nodes);
      tree.order = std::move(w.order);
      tree.depth = w.depth;
    } else {
      Bvh b = build_bvh(in, accel);
      tree.nodes = std::move(b.nodes);
      tree.order = std::move(b.order);
      tree.depth = b.depth;
    }
    tree.topBoxes = top_boxes(tree.wideNodes, tree.nodes);
  }
  std::vector<Aabb> instanceBoxes;
  reserve_huge(instanceBoxes, scene.instances.size());
  for (const SceneInstance& i : scene.instances) instanceBoxes.push_back(instance_box(meshTrees[i.mesh].topBoxes, i.toWorld));
  const size_t numInstances = scene.instances.size();
  BvhInput input = bvh_input(scene, materialRadiance, instanceBoxes);
  Aabb sceneBounds;
  for (const Aabb& b : input.bounds) sceneBounds.grow(b);
  const AcceleratorSettings accel = accel_for(input.bounds.size());
  out.bvhSplit = accel.split;
  uint32_t stackSlots;
  std::vector<uint32_t> order;
  if (wide) {
    // Collapsed from the builder's arrays, without laying out the binary tree.
    WideBvh w = build_wide_bvh(input, accel, options.wideCollapse);
    out.wideNodes = std::move(w.nodes);
    order = std::move(w.order);
    out.bvhDepth = w.depth;
    stackSlots = uint32_t(std::max(w.depth, 1)) - 1u + WIDE_STACK_PRIM_GROUPS;  // a node group per level below the root, and the primitive groups
    out.nodes.push_back(shader::BvhNode{});
  } else {
    Bvh bvh = build_bvh(input, accel);
    out.binarySahCost = bvh.sahCost;
    out.nodes = std::move(bvh.nodes);
    order = std::move(bvh.order);
    out.bvhDepth = bvh.depth;
    stackSlots = uint32_t(bvh.depth) + 1u;
    out.wideNodes.push_back(shader::WideNode{});
  }
  out.bvhBuildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();  // both levels' trees
  input = {};
  // The builder bounds the depth, and with it the kernels' traversal stacks.
  if (out.bvhDepth > BVH_MAX_DEPTH) throw RenderError("internal error: BVH deeper than BVH_MAX_DEPTH");
  // An instance's walk stacks on the top level's (traverse_*.glsl).
  uint32_t meshSlots = 0;
  for (const MeshTree& tree : meshTrees)
    meshSlots = std::max(meshSlots, wide ? uint32_t(std::max(tree.depth, 1)) - 1u + WIDE_STACK_PRIM_GROUPS : uint32_t(tree.depth) + 1u);
  if (numInstances > 0) stackSlots += INSTANCE_ENTRY_SLOTS + meshSlots;

  // Primitive records in leaf order (both layouts' leaves index them): each
  // triangle, and for each sphere and each instance a placeholder naming it;
  // then each instanced mesh's triangles in its tree's leaf order.
  size_t meshTriangles = 0;
  for (const MeshTree& tree : meshTrees) meshTriangles += tree.order.size();
  reserve_huge(out.triangles, order.size() + meshTriangles);
  reserve_huge(out.triangleShading, scene.triangleShading.size());
  // Tangents, colours and second UVs: a record beside every shading record
  // once any triangle has them.
  auto has_vertex_data = [](const std::vector<SceneTriangleShading>& shading) {
    return std::any_of(shading.begin(), shading.end(), [](const SceneTriangleShading& s) { return s.hasVertexData; });
  };
  const bool vertexData = has_vertex_data(scene.triangleShading) ||
                          std::any_of(scene.instancedMeshes.begin(), scene.instancedMeshes.end(),
                                      [&](const SceneInstancedMesh& m) { return has_vertex_data(m.shading); });
  if (vertexData) reserve_huge(out.triangleVertexData, scene.triangleShading.size());
  // A triangle's record, with its shading data (from `shading`) where it has any.
  auto add_triangle = [&](const SceneTriangle& t, const std::vector<SceneTriangleShading>& shading) {
    shader::Triangle g = triangle_record(t);
    if (t.shading != WP_INVALID) {
      const SceneTriangleShading& in = shading[t.shading];
      shader::TriangleShading sh{};
      g.shading = uint32_t(out.triangleShading.size());
      sh.flags = (in.hasNormals ? SHADING_NORMALS : 0u) | (in.hasVertexData ? SHADING_VERTEX_DATA : 0u);
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
      if (vertexData) {
        shader::TriangleVertexData vd{};
        const glm::vec2* uv1 = in.hasUv1 ? in.uv1 : uv;
        vd.tangent0 = in.tangent[0];
        vd.tangent1 = in.tangent[1];
        vd.tangent2 = in.tangent[2];
        vd.color0 = in.color[0];
        vd.color1 = in.color[1];
        vd.color2 = in.color[2];
        vd.uv1_01 = glm::vec4(uv1[0], uv1[1]);
        vd.uv1_2 = glm::vec4(uv1[2], 0.0f, 0.0f);
        out.triangleVertexData.push_back(vd);
      }
    }
    out.triangles.push_back(g);
  };
  for (uint32_t id : order) {
    shader::Triangle g{};
    if (id >= numTris) {
      const bool sphere = id < numTris + numSpheres;
      g.material = sphere ? WP_INVALID : PRIM_INSTANCE;
      g.emitter = WP_INVALID;
      g.shading = id - uint32_t(sphere ? numTris : numTris + numSpheres);
      if (!sphere) {
        g.v0 = instanceBoxes[g.shading].lo;
        g.v1 = instanceBoxes[g.shading].hi;
      }
      out.triangles.push_back(g);
      continue;
    }
    add_triangle(scene.triangles[id], scene.triangleShading);
  }
  out.instancing.topLevelBytes = out.triangles.size() * sizeof(shader::Triangle) +
                                 (wide ? out.wideNodes.size() * sizeof(shader::WideNode) : out.nodes.size() * sizeof(shader::BvhNode)) +
                                 numInstances * sizeof(shader::Instance);
  // The instanced meshes' trees after the top level's, their node and
  // primitive indices moved by where they now start.
  std::vector<uint32_t> meshRoot(meshTrees.size());
  for (size_t m = 0; m < meshTrees.size(); ++m) {
    MeshTree& tree = meshTrees[m];
    const uint32_t nodeBase = uint32_t(wide ? out.wideNodes.size() : out.nodes.size());
    const uint32_t primBase = uint32_t(out.triangles.size());
    meshRoot[m] = nodeBase;
    for (shader::WideNode n : tree.wideNodes) {
      n.childBase += nodeBase;
      n.primBase += primBase;
      out.wideNodes.push_back(n);
    }
    for (shader::BvhNode n : tree.nodes) {
      n.leftFirst += n.count == 0u ? nodeBase : primBase;
      out.nodes.push_back(n);
    }
    const SceneInstancedMesh& mesh = scene.instancedMeshes[m];
    for (uint32_t id : tree.order) add_triangle(mesh.triangles[id], mesh.shading);
    out.instancing.bottomLevelBytes += (tree.wideNodes.size() * sizeof(shader::WideNode) + tree.nodes.size() * sizeof(shader::BvhNode)) +
                                       tree.order.size() * sizeof(shader::Triangle);
    out.instancing.uniqueTriangles += tree.order.size();
    tree = MeshTree{};
  }
  for (const SceneInstance& i : scene.instances) {
    shader::Instance g{};
    rows_3x4(i.toWorld, g.toWorld0, g.toWorld1, g.toWorld2);
    rows_3x4(glm::inverse(i.toWorld), g.toObject0, g.toObject1, g.toObject2);
    g.root = meshRoot[i.mesh];
    g.flags = glm::determinant(glm::mat3(i.toWorld)) < 0.0f ? INSTANCE_MIRRORED : 0u;
    g.mesh = i.mesh;
    out.instances.push_back(g);
  }
  out.instancing.meshes = meshTrees.size();
  out.instancing.instances = numInstances;
  out.instancing.instancedTriangles = instanced_triangle_count(scene);
  // Light-only triangles after the leaves' records, where no leaf reaches them.
  const size_t firstLightOnly = out.triangles.size();
  for (const SceneTriangle& t : scene.lightOnlyTriangles) out.triangles.push_back(triangle_record(t));
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

  for (const SceneMaterial& m : scene.materials) out.materials.push_back(pack_material(m));
  if (scene.media.size() >= MEDIA_MAX) throw InputError(scene.sourcePath + ": more than " + std::to_string(MEDIA_MAX - 1) + " media");
  out.media.push_back(shader::Medium{});  // the vacuum
  std::map<const DensityGrid*, uint32_t> gridAt;
  for (const SceneMedium& m : scene.media) out.media.push_back(pack_medium(m, out.volumeWords, gridAt));
  // The float tables start with the sheen's albedo (bindings.glsl).
  out.floatTables.assign(std::begin(shader::SHEEN_ALBEDO), std::end(shader::SHEEN_ALBEDO));
  out.textures = std::move(packed.textures);
  out.texels = std::move(packed.texels);
  for (const ScenePointLight& l : scene.pointLights) {
    shader::PointLight p{glm::vec4(l.position, float(LIGHT_POINT)), glm::vec4(l.intensity, l.falloff ? 1.0f : 0.0f),
                         glm::vec4(l.direction, 0.0f)};
    if (l.kind == ScenePointLight::Kind::Directional) p.position.w = float(LIGHT_DIRECTIONAL);
    if (l.kind == ScenePointLight::Kind::Hemisphere) p.position.w = float(LIGHT_HEMISPHERE);
    if (l.kind == ScenePointLight::Kind::Spot) {
      p.position.w = float(LIGHT_SPOT);
      p.intensity.w = l.cosInner;
      p.direction.w = l.cosOuter;
    }
    out.pointLights.push_back(p);
  }

  // Emitters: every primitive whose material emits (under CS184's estimator
  // only the light-only triangles), and every point light, picked in
  // proportion to power (luminance of the mean emitted radiance times pi
  // times area; of the intensity times 4 pi).
  std::vector<double> power;
  std::vector<uint32_t> prims;
  auto emits = [&](uint32_t material, float area) {
    double p = materialRadiance[material] * WP_PI * double(area);
    return p > 0.0 ? p : 0.0;
  };
  for (size_t i = 0; i < out.triangles.size(); ++i) {
    shader::Triangle& t = out.triangles[i];
    if (is_placeholder(t)) continue;
    const bool lightOnly = i >= firstLightOnly;
    if (scene.cs184Estimator && !lightOnly) continue;
    double p = emits(t.material, 0.5f * glm::length(glm::cross(t.v1 - t.v0, t.v2 - t.v0)));
    if (p <= 0.0) continue;
    t.emitter = uint32_t(prims.size());
    prims.push_back(uint32_t(i) | (lightOnly ? EMITTER_UNSEEN_BIT : 0u));
    power.push_back(p);
  }
  for (size_t i = 0; i < out.spheres.size(); ++i) {
    if (scene.cs184Estimator) break;  // CS184's emissive spheres are no lights
    shader::Sphere& s = out.spheres[i];
    double p = emits(s.material, s.area);
    if (p <= 0.0) continue;
    s.emitter = uint32_t(prims.size());
    prims.push_back(uint32_t(i) | HIT_SPHERE_BIT);
    power.push_back(p);
  }
  // The environment map: power of its mean radiance falling on a disc the
  // size of the scene (only steers the choice among emitters).
  const double sceneRadius = sceneBounds.empty() ? 0.0 : 0.5 * double(glm::length(sceneBounds.hi - sceneBounds.lo));
  uint32_t environmentEmitter = WP_INVALID;
  if (scene.environment != WP_INVALID) {
    const shader::Texture& env = out.textures[scene.environment];
    const std::vector<float> cdf = environment_cdf(env, out.texels);
    out.floatTables.insert(out.floatTables.end(), cdf.begin(), cdf.end());
    double p = luminance(texture_mean(out.textures, out.texels, scene.environment)) * WP_PI * WP_PI * sceneRadius * sceneRadius * 4.0;
    if (p > 0.0) {
      environmentEmitter = uint32_t(prims.size());
      prims.push_back(EMITTER_ENVIRONMENT);
      power.push_back(p);
    }
  }
  // Punctual lights' power steers the choice too: a spot's is that of its
  // cones' mean solid angle; a directional light's, its irradiance over a
  // disc the size of the scene.
  for (size_t i = 0; i < out.pointLights.size(); ++i) {
    const shader::PointLight& l = out.pointLights[i];
    const uint32_t kind = punctual_light_kind(l);
    double spread = 4.0 * WP_PI;  // a point light's solid angle
    if (kind == LIGHT_SPOT) spread = 2.0 * WP_PI * (1.0 - 0.5 * (double(l.intensity.w) + double(l.direction.w)));
    if (kind == LIGHT_DIRECTIONAL) spread = WP_PI * sceneRadius * sceneRadius;  // the area its light falls on
    if (kind == LIGHT_HEMISPHERE) spread = WP_PI * WP_PI * sceneRadius * sceneRadius;  // pi L on that area
    double p = luminance(glm::vec3(l.intensity)) * spread;
    if (p <= 0.0) continue;
    prims.push_back(uint32_t(i) | EMITTER_POINT_BIT);
    power.push_back(p);
  }
  // What the traversal must know of a triangle's material: whether its back
  // is there, whether its alpha cuts it (an emitter is never cut: light
  // sampling could not see the cuts).
  if (scene.materials.size() > TRIANGLE_MATERIAL_MASK) throw RenderError("the scene has more materials than wavepath can index");
  for (shader::Triangle& t : out.triangles) {
    if (is_placeholder(t)) continue;
    const SceneMaterial& m = scene.materials[t.material];
    if (!m.doubleSided) t.material |= TRIANGLE_ONE_SIDED;
    if (m.alphaCutoff != 0.0f && materialRadiance[t.material & TRIANGLE_MATERIAL_MASK] <= 0.0) t.material |= TRIANGLE_CUTOUT;
  }
  out.emitters = build_alias_table(power);
  for (size_t i = 0; i < prims.size(); ++i) out.emitters[i].prim = prims[i];
  glm::uvec4 kinds = scene_kinds(out, prims, numSpheres > 0, scene.environment != WP_INVALID);
  shade_classes(out, scene.environment);
  if (out.triangles.empty()) out.triangles.push_back(shader::Triangle{});
  if (out.spheres.empty()) out.spheres.push_back(shader::Sphere{});
  if (out.instances.empty()) out.instances.push_back(shader::Instance{});
  // Buffers are never empty: bind a zero element where the scene has none.
  if (out.emitters.empty()) out.emitters.push_back(shader::Emitter{});
  if (out.materials.empty()) out.materials.push_back(shader::Material{});
  if (out.textures.empty()) out.textures.push_back(shader::Texture{});
  if (out.texels.empty()) out.texels.push_back(glm::uvec2(0u));
  if (out.triangleShading.empty()) out.triangleShading.push_back(shader::TriangleShading{});
  if (out.triangleVertexData.empty()) out.triangleVertexData.push_back(shader::TriangleVertexData{});
  if (out.pointLights.empty()) out.pointLights.push_back(shader::PointLight{});

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
  p.background = glm::vec4(scene.background, 0.0f);
  p.environment = glm::uvec4(scene.environment, environmentEmitter, 0u, 0u);
  if (scene.environment != WP_INVALID) {
    p.environment.z = out.textures[scene.environment].info.z;
    p.environment.w = out.textures[scene.environment].info.w;
  }
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
  if (mode == INTEGRATOR_MIXTURE && prims.size() > MAX_MIXTURE_EMITTERS) {
    throw InputError(scene.sourcePath + ": \"path tracer mixture\" evaluates every emitter at every bounce; this scene has " +
                     std::to_string(prims.size()) + " emitters (at most " + std::to_string(MAX_MIXTURE_EMITTERS) +
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
  if (sampler == SamplerKind::Cmj) kinds.w |= KIND_BIT(FEATURE_CMJ);
  if ((flags & SCENE_FLAG_HEMISPHERE) != 0u) kinds.w |= KIND_BIT(FEATURE_UNIFORM_HEMISPHERE);
  p.accel = glm::uvec4(wide ? BVH_LAYOUT_WIDE : BVH_LAYOUT_BINARY, 0u, stackSlots, 0u);
  // Media: any medium, any surface that bounds one or is an interface.
  const bool media = !scene.media.empty() || std::any_of(scene.materials.begin(), scene.materials.end(), [](const SceneMaterial& m) {
    return m.boundsMedia || m.kind == MAT_INTERFACE;
  });
  if (media) kinds.w |= KIND_BIT(FEATURE_MEDIA);
  if (std::any_of(scene.media.begin(), scene.media.end(), [](const SceneMedium& m) { return m.kind == MEDIUM_NANOVDB; }))
    kinds.w |= KIND_BIT(FEATURE_MEDIA_GRID);
  p.media = glm::uvec4(scene.cameraMedium == WP_INVALID ? 0u : scene.cameraMedium + 1u, 0u, 0u, 0u);
  p.kinds = kinds;
  if (mode == INTEGRATOR_PHOTONS) {
    check_photon_mapper_scene(scene, media);
    const IntegratorSettings& s = scene.integrator;
    p.photons = glm::uvec4(0u, s.searchCount, glm::floatBitsToUint(s.searchRadius * s.searchRadius), 0u);
    out.photonCount = s.photons;
    out.photonSeed = s.photonSeed;
    out.photonMapLeftToDevice = !options.photonsOnHost;
    if (options.photonsOnHost) {
      const auto start = std::chrono::steady_clock::now();
      out.photons = balance_photons(trace_photons(out));
      p.photons.x = uint32_t(out.photons.size());
      out.photonPassSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
  }
  return out;
}

}  // namespace wp
