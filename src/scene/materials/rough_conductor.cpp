// rough_conductor.cpp — a GGX microfacet metal (shaders/shared/materials/
// rough_conductor.glsl): params (alpha, eta), params2 (k, 0).
#include "scene/materials/pack_helpers.h"

namespace wp::materials {

extern const MaterialModule rough_conductor{
    MAT_ROUGH_CONDUCTOR,
    {ParamSpec::texture("albedo", glm::vec3(1.0f), unit_range()).with_problem("albedo above 1 would create energy"),
     ParamSpec::required_colour("eta", Range{0.0f, 1e3f, true, true}), ParamSpec::required_colour("k", Range{0.0f, 1e3f, false, true}),
     ParamSpec::number("roughness", 0.3f, unit_range())},
    [](const MaterialInputs& in, SceneMaterial& m) {
      m.record.info.y = in.texture("albedo");
      m.record.params = glm::vec4(ggx_alpha(in.number("roughness")), in.colour("eta"));
      m.record.params2 = glm::vec4(in.colour("k"), 0.0f);
    }};

}  // namespace wp::materials
