// clearcoat.cpp — KHR_materials_clearcoat as a layer (shaders/shared/
// materials/clearcoat.glsl): an untinted GGX coat over `base`, its factor in
// `albedo`'s red, its roughness texture in `amount` (green), its ior in
// params.x. (A coat's own normal map is a surface property: SceneMaterial::normalMap.)
#include "scene/materials/pack_helpers.h"

namespace wp::materials {

extern const MaterialModule clearcoat{
    MAT_CLEARCOAT,
    {ParamSpec::material("base"), ParamSpec::texture("factor", glm::vec3(1.0f), unit_range()),
     ParamSpec::texture("roughness", glm::vec3(0.0f), unit_range()), ParamSpec::number("ior", 1.5f, positive_range()),
     ParamSpec::optional_texture("emit")},
    [](const MaterialInputs& in, SceneMaterial& m) {
      m.emission = in.texture("emit");
      m.record.children.x = layer_base(in, false);
      m.record.info.y = in.texture("factor");
      m.record.info.w = in.texture("roughness");
      m.record.params.x = in.number("ior");
    }};

}  // namespace wp::materials
