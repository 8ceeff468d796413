#include "scene/materials/pack_helpers.h"

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

}  // namespace wp::materials
