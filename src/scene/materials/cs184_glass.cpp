// cs184_glass.cpp — CS184's glass and refraction BSDFs (shaders/shared/
// materials/cs184_glass.glsl): params (ior, refraction only), params2 the
// reflectance.
#include "scene/materials/material_module.h"

namespace wp::materials {

extern const MaterialModule cs184_glass{
    MAT_CS184_GLASS,
    {ParamSpec::texture("transmittance", glm::vec3(1.0f), unit_range()).with_problem("transmittance above 1 would create energy"),
     ParamSpec::colour("reflectance", glm::vec3(1.0f), unit_range()), ParamSpec::number("ior", 1.5f, positive_range()),
     ParamSpec::flag("refraction_only")},
    [](const MaterialInputs& in, SceneMaterial& m) {
      m.record.info.y = in.texture("transmittance");
      m.record.params = glm::vec4(in.number("ior"), in.flag("refraction_only") ? 1.0f : 0.0f, 0.0f, 0.0f);
      m.record.params2 = glm::vec4(in.colour("reflectance"), 0.0f);
    }};

}  // namespace wp::materials
