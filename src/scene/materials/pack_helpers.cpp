#include "scene/materials/pack_helpers.h"

#include "render/shader_cpp.h"
#include "render/spectra.h"

namespace wp::materials {

uint32_t surface_part(const MaterialInputs& in, const std::string& key) {
  const uint32_t m = in.material(key);
  const uint32_t kind = in.scene().materials[m].kind;
  if (kind == MAT_LIGHT) in.fail(key, "a blend or a layer cannot contain a diffuse_light");
  if (kind == MAT_INTERFACE) in.fail(key, "a blend or a layer cannot contain an interface (it has no surface)");
  return m;
}

uint32_t layer_base(const MaterialInputs& in, bool sheen) {
  const uint32_t base = surface_part(in, "base");
  const Scene& s = in.scene();
  if (s.materials[base].emission != WP_INVALID) in.fail("base", "a layer's base cannot emit: give \"emit\" to the layer");
  if (material_lobes(s, base) + 1 > int(BSDF_MAX_LOBES))
    in.fail("a material may combine at most " + std::to_string(BSDF_MAX_LOBES) + " lobes in all");
  if (material_layers(s, base) + 1 > LAYERS_MAX)
    in.fail("layers may lie at most " + std::to_string(LAYERS_MAX) + " deep over a base material");
  if (sheen && material_sheens(s, base) > 0) in.fail("a material may hold at most one sheen");
  return base;
}

std::vector<ParamSpec> conductor_params() {
  return {ParamSpec::colour("eta", glm::vec3(0.0f), Range{0.0f, 1e3f, true, true}), ParamSpec::colour("k", glm::vec3(0.0f), Range{0.0f, 1e3f, false, true}),
          ParamSpec::choice("metal", "none|" + metal_names())};
}

void pack_conductor_index(const MaterialInputs& in, glm::vec3& eta, glm::vec3& k, float& named) {
  const std::string& metal = in.choice("metal");
  if (metal == "none") {
    if (!in.given("eta") || !in.given("k")) in.fail("a conductor needs \"eta\" and \"k\", or \"metal\": one of " + metal_names(", "));
    eta = in.colour("eta");
    k = in.colour("k");
    named = 0.0f;
    return;
  }
  if (in.given("eta") || in.given("k")) in.fail("metal", "a named metal brings its measured eta and k: give \"metal\" or \"eta\" and \"k\", not both");
  const uint32_t id = *metal_named(metal);
  metal_rgb(id, eta, k);
  named = CONDUCTOR_NAMED * float(id + 1u);
}

namespace {

#define WP_GLASS_NAME(id, name, b1, b2, b3, b4, c1, c2, c3, c4) name,
const char* const kGlassNames[] = {WP_GLASSES(WP_GLASS_NAME)};
#undef WP_GLASS_NAME

}  // namespace

std::vector<ParamSpec> dielectric_params() {
  std::string glasses = "none";
  for (const char* g : kGlassNames) glasses += std::string("|") + g;
  return {ParamSpec::number("ior", 1.5f, positive_range()), ParamSpec::choice("glass", glasses)};
}

float pack_dielectric_ior(const MaterialInputs& in, float& glass) {
  const std::string& name = in.choice("glass");
  glass = 0.0f;
  if (name == "none") return in.number("ior");
  if (in.given("ior")) in.fail("glass", "a named glass brings its own index of refraction: give \"glass\" or \"ior\", not both");
  for (uint32_t g = 0; g < GLASS_COUNT; ++g) {
    if (name != kGlassNames[g]) continue;
    glass = float(g + 1u);
    return shader::ShaderMath().glass_ior(g, FRAUNHOFER_D_NM);
  }
  in.fail("glass", "unknown glass \"" + name + "\"");
}

uint32_t dielectric_features(const shader::Material& record) {
  return record.params.w > 0.0f ? KIND_BIT(FEATURE_DISPERSION) : 0u;
}

}  // namespace wp::materials
