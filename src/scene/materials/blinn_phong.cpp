// blinn_phong.cpp — darts' blinn-phong (shaders/shared/materials/blinn_phong.glsl): a cos^n lobe of the half vector about the normal.
#include "scene/materials/material_module.h"

namespace wp::materials {

extern const MaterialModule blinn_phong{
    MAT_BLINN_PHONG,
    {ParamSpec::texture("albedo", glm::vec3(0.8f), unit_range()).with_problem("albedo above 1 would create energy"),
     ParamSpec::number("exponent", 20.0f, closed_range(0.0f, 1e6f))},
    [](const MaterialInputs& in, SceneMaterial& m) {
      m.record.info.y = in.texture("albedo");
      m.record.params.x = in.number("exponent");
    }};

}  // namespace wp::materials
