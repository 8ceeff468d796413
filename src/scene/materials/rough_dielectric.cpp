// rough_dielectric.cpp — GGX microfacet glass (shaders/shared/materials/
// rough_dielectric.glsl): params (ior, alpha).
#include "scene/materials/pack_helpers.h"

namespace wp::materials {

extern const MaterialModule rough_dielectric{
    MAT_ROUGH_DIELECTRIC,
    {ParamSpec::texture("albedo", glm::vec3(1.0f), unit_range()).with_problem("albedo above 1 would create energy"),
     ParamSpec::number("ior", 1.5f, positive_range()), ParamSpec::number("roughness", 0.3f, unit_range())},
    [](const MaterialInputs& in, SceneMaterial& m) {
      m.record.info.y = in.texture("albedo");
      m.record.params = glm::vec4(in.number("ior"), ggx_alpha(in.number("roughness")), 0.0f, 0.0f);
    }};

}  // namespace wp::materials
