// phong.cpp — darts' phong (shaders/shared/materials/phong.glsl): a cos^n lobe about the mirror direction.
#include "scene/materials/material_module.h"

namespace wp::materials {

extern const MaterialModule phong{
    MAT_PHONG,
    {ParamSpec::texture("albedo", glm::vec3(0.8f), unit_range()).with_problem("albedo above 1 would create energy"),
     ParamSpec::number("exponent", 20.0f, closed_range(0.0f, 1e6f))},
    [](const MaterialInputs& in, SceneMaterial& m) {
      m.record.info.y = in.texture("albedo");
      m.record.params.x = in.number("exponent");
    }};

}  // namespace wp::materials
