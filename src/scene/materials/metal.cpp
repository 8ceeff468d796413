// metal.cpp — darts' metal (shaders/shared/materials/metal.glsl): the mirror
// direction plus roughness times a point in the unit sphere.
#include "scene/materials/material_module.h"

namespace wp::materials {

extern const MaterialModule metal{
    MAT_METAL,
    {ParamSpec::texture("albedo", glm::vec3(0.8f), unit_range()).with_problem("albedo above 1 would create energy"),
     ParamSpec::number("roughness", 0.0f, unit_range()).clamped()},  // clamped, as darts' metal.cpp clamps it
    [](const MaterialInputs& in, SceneMaterial& m) {
      m.record.info.y = in.texture("albedo");
      m.record.params.x = in.number("roughness");
    }};

}  // namespace wp::materials
