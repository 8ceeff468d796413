// sheen.cpp — KHR_materials_sheen as a layer (shaders/shared/materials/
// sheen.glsl): a Charlie sheen of `color` (albedo) and roughness (amount's
// green) over `base`, which it scales by its albedo.
#include "scene/materials/pack_helpers.h"

namespace wp::materials {

extern const MaterialModule sheen{
    MAT_SHEEN,
    {ParamSpec::material("base"), ParamSpec::texture("color", glm::vec3(1.0f), unit_range()),
     ParamSpec::texture("roughness", glm::vec3(0.5f), unit_range()), ParamSpec::optional_texture("emit")},
    [](const MaterialInputs& in, SceneMaterial& m) {
      m.emission = in.texture("emit");
      m.record.children.x = layer_base(in, true);
      m.record.info.y = in.texture("color");
      m.record.info.w = in.texture("roughness");
    }};

}  // namespace wp::materials
