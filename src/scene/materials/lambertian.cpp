// lambertian.cpp — darts' lambertian (shaders/shared/materials/lambertian.glsl).
#include "scene/materials/material_module.h"

namespace wp::materials {

extern const MaterialModule lambertian{
    MAT_LAMBERTIAN,
    {ParamSpec::texture("albedo", glm::vec3(0.8f), unit_range()).with_problem("albedo above 1 would create energy"),
     ParamSpec::optional_texture("emit")},  // an OBJ's Ke
    [](const MaterialInputs& in, SceneMaterial& m) {
      m.record.info.y = in.texture("albedo");
      m.emission = in.texture("emit");
    }};

}  // namespace wp::materials
