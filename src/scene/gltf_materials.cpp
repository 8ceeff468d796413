// gltf_materials.cpp — the glTF importer's materials: metal-rough with the
// KHR_materials_* extensions it reads, and the sheen and clear coat layers
// over it (gltf_importer.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "scene/gltf_importer.h"

namespace wp::gltf_import {

// ---- materials -----------------------------------------------------------

const std::set<std::string>& material_extensions() {
  static const std::set<std::string> names = {"KHR_materials_anisotropy", "KHR_materials_clearcoat", "KHR_materials_diffuse_transmission",   "KHR_materials_dispersion",
                                              "KHR_materials_emissive_strength", "KHR_materials_ior", "KHR_materials_iridescence",
                                              "KHR_materials_sheen",      "KHR_materials_specular",    "KHR_materials_transmission",
                                              "KHR_materials_volume",     "KHR_materials_volume_scatter"};
  return names;
}

uint32_t GltfImporter::material_for(int index, const std::string& where) {
  if (index < 0) {  // the specification's default material
    // The module's defaults are the specification's: white, metallic 1, roughness 1, ior 1.5.
    if (defaultMaterial_ == WP_INVALID)
      defaultMaterial_ = add_material(scene_, MaterialParams(MAT_METAL_ROUGH, "glTF default material", complaint(where)));
    return defaultMaterial_;
  }
  if (index >= int(model_.materials.size())) fail(where, "names material " + std::to_string(index) + ", which does not exist");
  auto found = materials_.find(index);
  if (found != materials_.end()) return found->second;
  const tinygltf::Material& g = model_.materials[size_t(index)];
  const std::string at = "/materials/" + std::to_string(index);
  const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
  if (g.occlusionTexture.index >= 0) unread_.insert("occlusion maps (a path tracer computes occlusion)");
  const std::string name = g.name.empty() ? "material " + std::to_string(index) : g.name;
  MaterialParams m(MAT_METAL_ROUGH, name, complaint(at));
  const glm::vec3 base = factor3(pbr.baseColorFactor, glm::vec3(1.0f), at + "/pbrMetallicRoughness/baseColorFactor");
  const std::vector<double>& baseFactor = pbr.baseColorFactor;
  const float alpha = baseFactor.size() == 4 ? unit(baseFactor[3], at + "/pbrMetallicRoughness/baseColorFactor/3") : 1.0f;
  m.texture("base_color",
            texture_times(TextureRef(pbr.baseColorTexture), glm::vec4(base, alpha), ColorEncoding::Srgb, at + "/pbrMetallicRoughness/baseColorTexture"),
            complaint(at + "/pbrMetallicRoughness/baseColorFactor"));
  uint32_t normalMap = WP_INVALID;
  if (g.normalTexture.index >= 0) {
    const float scale = float(g.normalTexture.scale);
    if (!std::isfinite(scale) || std::fabs(scale) > 1e3f) fail(at + "/normalTexture/scale", "must be a finite number of at most 1000");
    normalMap = texture_times(TextureRef(g.normalTexture), glm::vec4(scale, scale, 1.0f, 1.0f), ColorEncoding::Linear, at + "/normalTexture");
  }
  m.number("metallic", unit(pbr.metallicFactor, at + "/pbrMetallicRoughness/metallicFactor"), complaint(at + "/pbrMetallicRoughness/metallicFactor"));
  m.number("roughness", unit(pbr.roughnessFactor, at + "/pbrMetallicRoughness/roughnessFactor"),
           complaint(at + "/pbrMetallicRoughness/roughnessFactor"));
  if (pbr.metallicRoughnessTexture.index >= 0)
    m.texture("metallic_roughness", texture_times(TextureRef(pbr.metallicRoughnessTexture), glm::vec4(1.0f), ColorEncoding::Linear,
                                                  at + "/pbrMetallicRoughness/metallicRoughnessTexture"));
  auto iorExt = g.extensions.find("KHR_materials_ior");
  if (iorExt != g.extensions.end() && iorExt->second.Has("ior")) {
    const float ior = float(iorExt->second.Get("ior").GetNumberAsDouble());
    if (!(ior >= 1.0f && ior <= 10.0f)) fail(at + "/extensions/KHR_materials_ior/ior", "must lie in [1, 10]");
    m.number("ior", ior, complaint(at + "/extensions/KHR_materials_ior/ior"));
  }
  std::string tat;
  if (const tinygltf::Value* transmission = material_extension(g, "KHR_materials_transmission", at, tat)) {
    const tinygltf::Value& t = *transmission;
    if (t.Has("transmissionFactor")) {
      if (!t.Get("transmissionFactor").IsNumber()) fail(tat + "/transmissionFactor", "expected a number");
      m.number("transmission", unit(t.Get("transmissionFactor").GetNumberAsDouble(), tat + "/transmissionFactor"),
               complaint(tat + "/transmissionFactor"));
    }
    if (t.Has("transmissionTexture"))
      m.texture("transmission_texture", extension_texture(t, "transmissionTexture", glm::vec4(1.0f), ColorEncoding::Linear, tat));
  }
  // KHR_materials_diffuse_transmission (README.md:70-160 at 603619ef): the
  // factor (its texture's alpha) and colour (its texture sRGB).
  std::string eat;
  if (const tinygltf::Value* diffuse = material_extension(g, "KHR_materials_diffuse_transmission", at, eat)) {
    const tinygltf::Value& e = *diffuse;
    m.number("diffuse_transmission", extension_number(e, "diffuseTransmissionFactor", 0.0f, 0.0f, 1.0f, eat), complaint(eat + "/diffuseTransmissionFactor"));
    m.colour("diffuse_transmission_color", extension_color(e, "diffuseTransmissionColorFactor", glm::vec3(1.0f), 1.0f, eat),
             complaint(eat + "/diffuseTransmissionColorFactor"));
    if (e.Has("diffuseTransmissionTexture"))
      m.texture("diffuse_transmission_texture", extension_texture(e, "diffuseTransmissionTexture", glm::vec4(1.0f), ColorEncoding::AlphaAsGrey, eat));
    if (e.Has("diffuseTransmissionColorTexture"))
      m.texture("diffuse_transmission_color_texture",
                extension_texture(e, "diffuseTransmissionColorTexture", glm::vec4(1.0f), ColorEncoding::Srgb, eat));
  }
  // Surface properties, not the kind's parameters: on the top layer (below).
  bool doubleSided = g.doubleSided;
  float alphaCutoff = 0.0f;
  // MASK cuts out where alpha < cutoff; BLEND is rendered as stochastic
  // transparency (a ray passes with probability 1 - alpha), which a path
  // tracer converges to the blend a rasterizer draws.
  if (g.alphaMode == "MASK") {
    if (!(g.alphaCutoff >= 0.0 && g.alphaCutoff <= 1.0)) fail(at + "/alphaCutoff", "must lie in [0, 1]");
    alphaCutoff = float(g.alphaCutoff);
  } else if (g.alphaMode == "BLEND") {
    alphaCutoff = -1.0f;
  } else if (g.alphaMode != "OPAQUE") {
    fail(at + "/alphaMode", "is \"" + g.alphaMode + "\", not OPAQUE, MASK or BLEND");
  }
  float strength = 1.0f;
  auto strengthExt = g.extensions.find("KHR_materials_emissive_strength");
  if (strengthExt != g.extensions.end() && strengthExt->second.Has("emissiveStrength")) {
    strength = float(strengthExt->second.Get("emissiveStrength").GetNumberAsDouble());
    if (!(strength >= 0.0f && strength < 1e6f))
      fail(at + "/extensions/KHR_materials_emissive_strength/emissiveStrength", "must be a number from 0 to 1e6");
  }
  const glm::vec3 emissive = factor3(g.emissiveFactor, glm::vec3(0.0f), at + "/emissiveFactor") * strength;
  const uint32_t emission = emissive == glm::vec3(0.0f) ? WP_INVALID
      : texture_times(TextureRef(g.emissiveTexture), glm::vec4(emissive, 1.0f), ColorEncoding::Srgb, at + "/emissiveTexture");
  read_specular(g, at, m);
  if (read_volume(g, at, m)) doubleSided = true;
  // KHR_materials_volume_scatter (a draft, KhronosGroup/glTF PR #2453 at
  // 134d0766: README.md:70-153): particles that scatter in the volume, whose
  // extinction the attenuation is, as a homogeneous medium inside. Its
  // multiscatterColorFactor was multiscatterColor until that commit (as in
  // the sample ScatteringSkull): both are read. Its texture, read where a
  // path enters, would need a medium per path: not read.
  std::string sat;
  if (const tinygltf::Value* scatter = material_extension(g, "KHR_materials_volume_scatter", at, sat)) {
    const tinygltf::Value& s = *scatter;
    const char* key = s.Has("multiscatterColorFactor") ? "multiscatterColorFactor" : "multiscatterColor";
    m.colour("volume.multiscatter_color", extension_color(s, key, glm::vec3(0.0f), 1.0f, sat), complaint(sat + "/" + key));
    m.number("volume.scatter_anisotropy", std::clamp(extension_number(s, "scatterAnisotropy", 0.0f, -1.0f, 1.0f, sat), -0.99f, 0.99f),
             complaint(sat + "/scatterAnisotropy"));
    if (s.Has("multiscatterColorTexture")) unread_.insert("multiscatterColorTexture (a medium is one colour throughout)");
  }
  read_iridescence(g, at, m);
  read_anisotropy(g, at, m);
  // The layers, each over what lies below (the extensions' order): the
  // base, a sheen, a clear coat. The top carries the surface's emission,
  // sidedness and cut-out; the base its alpha texture and normal map.
  uint32_t coatNormalMap = WP_INVALID;
  std::optional<MaterialParams> sheen = sheen_layer(g, at, name), coat = clearcoat_layer(g, at, name, coatNormalMap);
  MaterialParams& top = coat ? *coat : sheen ? *sheen : m;
  if (emission != WP_INVALID) top.texture("emit", emission, complaint(at + "/emissiveTexture"));
  uint32_t id = add_material(scene_, m);
  scene_.materials[id].normalMap = normalMap;
  for (std::optional<MaterialParams>* layer : {&sheen, &coat}) {
    if (!*layer) continue;
    (*layer)->material("base", id);
    id = add_material(scene_, **layer);
    if (layer == &coat) scene_.materials[id].normalMap = coatNormalMap;
  }
  scene_.materials[id].doubleSided = doubleSided;
  scene_.materials[id].alphaCutoff = alphaCutoff;
  materials_[index] = id;
  return id;
}

Complaint GltfImporter::complaint(const std::string& where) const {
  return [this, where](const std::string& problem) { fail(where, problem); };
}

// The UV set (0 or 1) a mesh of material m needs tangents in: that of a
// normal map of its surface or of a coat over it, or of its anisotropy's
// texture (the first found; an anisotropy without a texture takes the
// first set); -1 where nothing needs tangents.
int GltfImporter::uv_set_needing_tangents(uint32_t m) const {
  for (int depth = 0; depth <= LAYERS_MAX; ++depth) {
    const SceneMaterial& mat = scene_.materials[m];
    if (mat.normalMap != WP_INVALID) return scene_.textures[mat.normalMap].secondUvSet ? 1 : 0;
    if (mat.kind == MAT_METAL_ROUGH && mat.record.extra[MR_ANISOTROPY].x > 0.0f) {
      const uint32_t t = glm::floatBitsToUint(mat.record.extra[MR_ANISOTROPY].w);  // metal_rough.cpp's record
      return t != WP_INVALID && scene_.textures[t].secondUvSet ? 1 : 0;
    }
    if (!is_layer(mat.kind)) break;
    m = mat.part(0);
  }
  return -1;
}

const tinygltf::Value* GltfImporter::material_extension(const tinygltf::Material& g, const char* name, const std::string& at,
                                                        std::string& where) const {
  auto found = g.extensions.find(name);
  if (found == g.extensions.end()) return nullptr;
  where = at + "/extensions/" + name;
  if (!found->second.IsObject()) fail(where, "expected an object");
  return &found->second;
}

// A number of an extension's object in [lo, hi], or `fallback` if absent.
float GltfImporter::extension_number(const tinygltf::Value& ext, const char* key, float fallback, float lo, float hi, const std::string& at) const {
  if (!ext.Has(key)) return fallback;
  const tinygltf::Value& v = ext.Get(key);
  if (!v.IsNumber()) fail(at + "/" + key, "expected a number");
  const double x = v.GetNumberAsDouble();
  if (!(x >= lo && x <= hi)) fail(at + "/" + key, "must lie in [" + number_text(lo) + ", " + number_text(hi) + "]");
  return float(x);
}

// A colour of an extension's object (3 numbers in [0, hi]), or `fallback`.
glm::vec3 GltfImporter::extension_color(const tinygltf::Value& ext, const char* key, glm::vec3 fallback, float hi, const std::string& at) const {
  if (!ext.Has(key)) return fallback;
  const tinygltf::Value& v = ext.Get(key);
  if (!v.IsArray() || v.ArrayLen() != 3) fail(at + "/" + key, "expected 3 numbers");
  glm::vec3 c;
  for (int i = 0; i < 3; ++i) {
    if (!v.Get(i).IsNumber()) fail(at + "/" + key + "/" + std::to_string(i), "expected a number");
    c[i] = float(v.Get(i).GetNumberAsDouble());
    if (!(c[i] >= 0.0f && c[i] <= hi)) fail(at + "/" + key + "/" + std::to_string(i), "must lie in [0, " + number_text(hi) + "]");
  }
  return c;
}

std::string GltfImporter::number_text(float v) {
  if (v > 1e30f) return "infinity";
  char text[32];
  std::snprintf(text, sizeof text, "%g", double(v));
  return text;
}

// An extension's texture (a textureInfo, or a normalTextureInfo, whose
// scale multiplies the factor's first two channels) times `factor`.
uint32_t GltfImporter::extension_texture(const tinygltf::Value& ext, const char* key, glm::vec4 factor, ColorEncoding encoding, const std::string& at,
                                         bool normal) {
  const std::string where = at + "/" + key;
  const tinygltf::Value& ti = ext.Get(key);
  if (!ti.IsObject() || !ti.Has("index") || !ti.Get("index").IsInt()) fail(where, "expected a textureInfo with an index");
  tinygltf::TextureInfo info;
  info.index = ti.Get("index").GetNumberAsInt();
  if (ti.Has("texCoord")) info.texCoord = ti.Get("texCoord").IsInt() ? ti.Get("texCoord").GetNumberAsInt() : -1;
  if (ti.Has("extensions") && ti.Get("extensions").IsObject() && ti.Get("extensions").Has("KHR_texture_transform"))
    info.extensions["KHR_texture_transform"] = ti.Get("extensions").Get("KHR_texture_transform");
  if (normal && ti.Has("scale")) {
    if (!ti.Get("scale").IsNumber()) fail(where + "/scale", "expected a number");
    const float scale = float(ti.Get("scale").GetNumberAsDouble());
    if (!std::isfinite(scale) || std::fabs(scale) > 1e3f) fail(where + "/scale", "must be a finite number of at most 1000");
    factor.x *= scale;
    factor.y *= scale;
  }
  return texture_times(TextureRef(info), factor, encoding, where);
}

// KHR_materials_specular on metal-rough m: params2 holds the factor and
// colour less 1 (metal_rough.glsl), the textures scale them.
void GltfImporter::read_specular(const tinygltf::Material& g, const std::string& at, MaterialParams& m) {
  std::string eat;
  const tinygltf::Value* found = material_extension(g, "KHR_materials_specular", at, eat);
  if (!found) return;
  const tinygltf::Value& e = *found;
  const float specular = extension_number(e, "specularFactor", 1.0f, 0.0f, 1.0f, eat);
  const glm::vec3 color = extension_color(e, "specularColorFactor", glm::vec3(1.0f), 1e3f, eat);
  m.number("specular", specular, complaint(eat + "/specularFactor"));
  m.colour("specular_color", color, complaint(eat + "/specularColorFactor"));
  if (e.Has("specularTexture"))
    m.texture("specular_texture", extension_texture(e, "specularTexture", glm::vec4(1.0f), ColorEncoding::AlphaAsGrey, eat));
  if (e.Has("specularColorTexture"))
    m.texture("specular_color_texture", extension_texture(e, "specularColorTexture", glm::vec4(1.0f), ColorEncoding::Srgb, eat));
}

// KHR_materials_volume on metal-rough m: a thickness above 0 makes its
// transmission refract into a volume (0, the default, is thin-walled);
// the attenuation colour c reached after attenuationDistance d gives the
// absorption coefficient -ln(c) / d (README.md:150). The thickness
// texture is a rasterizer's stand-in for the distance a path tracer
// traces, and is not read (README.md:125).
// Whether the material is a volume's boundary.
bool GltfImporter::read_volume(const tinygltf::Material& g, const std::string& at, MaterialParams& m) const {
  std::string eat;
  const tinygltf::Value* found = material_extension(g, "KHR_materials_volume", at, eat);
  if (!found) return false;
  const tinygltf::Value& e = *found;
  const float thickness = extension_number(e, "thicknessFactor", 0.0f, 0.0f, 1e30f, eat);
  const float distance = extension_number(e, "attenuationDistance", 1e30f, 0.0f, 1e30f, eat);
  if (!(distance > 0.0f)) fail(eat + "/attenuationDistance", "must be above 0");
  const glm::vec3 color = extension_color(e, "attenuationColor", glm::vec3(1.0f), 1.0f, eat);
  m.flag("volume", thickness > 0.0f, complaint(eat + "/thicknessFactor"));
  m.colour("volume.attenuation_color", color, complaint(eat + "/attenuationColor"));
  m.number("volume.attenuation_distance", distance, complaint(eat + "/attenuationDistance"));
  // KHR_materials_dispersion (20 / Abbe number) spreads the volume's index
  // over the colours; a thin-walled surface does not disperse (README.md).
  std::string dat;
  if (const tinygltf::Value* dispersion = material_extension(g, "KHR_materials_dispersion", at, dat))
    m.number("volume.dispersion", extension_number(*dispersion, "dispersion", 0.0f, 0.0f, 1000.0f, dat), complaint(dat + "/dispersion"));
  // "doubleSided has no effect on volume boundaries" (README.md:110-115):
  // paths inside meet the boundary from behind.
  return thickness > 0.0f;
}

// KHR_materials_iridescence on metal-rough m: a thin film's factor (times
// the red of its texture), ior and thickness range (nm; its texture's green
// picks within it, the maximum without one; README.md:61-88).
void GltfImporter::read_iridescence(const tinygltf::Material& g, const std::string& at, MaterialParams& m) {
  std::string eat;
  const tinygltf::Value* found = material_extension(g, "KHR_materials_iridescence", at, eat);
  if (!found) return;
  const tinygltf::Value& e = *found;
  m.flag("iridescence", true, complaint(eat));
  m.number("iridescence.factor", extension_number(e, "iridescenceFactor", 0.0f, 0.0f, 1.0f, eat), complaint(eat + "/iridescenceFactor"));
  m.number("iridescence.ior", extension_number(e, "iridescenceIor", 1.3f, 1.0f, 10.0f, eat), complaint(eat + "/iridescenceIor"));
  m.number("iridescence.thickness_minimum", extension_number(e, "iridescenceThicknessMinimum", 100.0f, 0.0f, 1e5f, eat),
           complaint(eat + "/iridescenceThicknessMinimum"));
  m.number("iridescence.thickness_maximum", extension_number(e, "iridescenceThicknessMaximum", 400.0f, 0.0f, 1e5f, eat),
           complaint(eat + "/iridescenceThicknessMaximum"));
  if (e.Has("iridescenceTexture"))
    m.texture("iridescence.factor_texture", extension_texture(e, "iridescenceTexture", glm::vec4(1.0f), ColorEncoding::Linear, eat));
  if (e.Has("iridescenceThicknessTexture"))
    m.texture("iridescence.thickness_texture", extension_texture(e, "iridescenceThicknessTexture", glm::vec4(1.0f), ColorEncoding::Linear, eat));
}

// KHR_materials_anisotropy on metal-rough m: strength, rotation (radians)
// and a texture of directions (red, green: 2 c - 1 in the tangent frame)
// and strengths (blue), linear (README.md:65-90).
void GltfImporter::read_anisotropy(const tinygltf::Material& g, const std::string& at, MaterialParams& m) {
  std::string eat;
  const tinygltf::Value* found = material_extension(g, "KHR_materials_anisotropy", at, eat);
  if (!found) return;
  const tinygltf::Value& e = *found;
  m.flag("anisotropy", true, complaint(eat));
  m.number("anisotropy.strength", extension_number(e, "anisotropyStrength", 0.0f, 0.0f, 1.0f, eat), complaint(eat + "/anisotropyStrength"));
  m.number("anisotropy.rotation", extension_number(e, "anisotropyRotation", 0.0f, -1e4f, 1e4f, eat), complaint(eat + "/anisotropyRotation"));
  if (e.Has("anisotropyTexture"))
    m.texture("anisotropy.texture", extension_texture(e, "anisotropyTexture", glm::vec4(1.0f), ColorEncoding::Linear, eat));
}

// KHR_materials_sheen, to lie over the base; none where the sheen is black.
std::optional<MaterialParams> GltfImporter::sheen_layer(const tinygltf::Material& g, const std::string& at, const std::string& name) {
  std::string eat;
  const tinygltf::Value* found = material_extension(g, "KHR_materials_sheen", at, eat);
  if (!found) return std::nullopt;
  const tinygltf::Value& e = *found;
  const glm::vec3 color = extension_color(e, "sheenColorFactor", glm::vec3(0.0f), 1.0f, eat);
  const float roughness = extension_number(e, "sheenRoughnessFactor", 0.0f, 0.0f, 1.0f, eat);
  if (color == glm::vec3(0.0f)) return std::nullopt;  // "If sheenColorFactor is zero, the whole sheen layer is disabled."
  MaterialParams sheen(MAT_SHEEN, name + " (sheen)", complaint(eat));
  sheen.texture("color", e.Has("sheenColorTexture") ? extension_texture(e, "sheenColorTexture", glm::vec4(color, 1.0f), ColorEncoding::Srgb, eat)
                                                   : add_texture(scene_, constant_texture(color)));
  sheen.texture("roughness", e.Has("sheenRoughnessTexture")
                                 ? extension_texture(e, "sheenRoughnessTexture", glm::vec4(roughness), ColorEncoding::AlphaAsGrey, eat)
                                 : add_texture(scene_, constant_texture(glm::vec3(roughness))));
  return sheen;
}

// KHR_materials_clearcoat, to lie over the base (and its own normal map in
// `normalMap`); none where the coat is 0.
std::optional<MaterialParams> GltfImporter::clearcoat_layer(const tinygltf::Material& g, const std::string& at, const std::string& name, uint32_t& normalMap) {
  std::string eat;
  const tinygltf::Value* found = material_extension(g, "KHR_materials_clearcoat", at, eat);
  if (!found) return std::nullopt;
  const tinygltf::Value& e = *found;
  const float factor = extension_number(e, "clearcoatFactor", 0.0f, 0.0f, 1.0f, eat);
  const float roughness = extension_number(e, "clearcoatRoughnessFactor", 0.0f, 0.0f, 1.0f, eat);
  if (factor == 0.0f) return std::nullopt;  // "If clearcoatFactor = 0, the clearcoat layer is disabled."
  MaterialParams coat(MAT_CLEARCOAT, name + " (clear coat)", complaint(eat));  // the module's ior is the extension's, 1.5
  coat.texture("factor", e.Has("clearcoatTexture") ? extension_texture(e, "clearcoatTexture", glm::vec4(factor), ColorEncoding::Linear, eat)
                                                   : add_texture(scene_, constant_texture(glm::vec3(factor))));
  coat.texture("roughness", e.Has("clearcoatRoughnessTexture")
                                ? extension_texture(e, "clearcoatRoughnessTexture", glm::vec4(roughness), ColorEncoding::Linear, eat)
                                : add_texture(scene_, constant_texture(glm::vec3(roughness))));
  if (e.Has("clearcoatNormalTexture"))
    normalMap = extension_texture(e, "clearcoatNormalTexture", glm::vec4(1.0f), ColorEncoding::Linear, eat, true);
  return coat;
}

// A colour factor (its first three numbers; a fourth, alpha, is not used).
glm::vec3 GltfImporter::factor3(const std::vector<double>& v, glm::vec3 fallback, const std::string& where) const {
  if (v.empty()) return fallback;
  if (v.size() < 3) fail(where, "expected 3 or 4 numbers");
  const glm::vec3 c{float(v[0]), float(v[1]), float(v[2])};
  if (!(c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f && c.x <= 1.0f && c.y <= 1.0f && c.z <= 1.0f)) fail(where, "must lie in [0, 1]");
  return c;
}

float GltfImporter::unit(double v, const std::string& where) const {
  if (!(v >= 0.0 && v <= 1.0)) fail(where, "must lie in [0, 1]");
  return float(v);
}

}  // namespace wp::gltf_import
