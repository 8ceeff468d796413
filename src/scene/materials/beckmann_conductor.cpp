// beckmann_conductor.cpp — CS184's microfacet conductor (shaders/shared/
// materials/beckmann_conductor.glsl): params (alpha, eta), params2 (k, 1 for
// the 3-2 skeleton's shadowing term, 0 for Smith's).
#include "scene/materials/material_module.h"

namespace wp::materials {

extern const MaterialModule beckmann_conductor{
    MAT_BECKMANN_CONDUCTOR,
    {ParamSpec::texture("albedo", glm::vec3(1.0f), unit_range()).with_problem("albedo above 1 would create energy"),
     ParamSpec::required_number("alpha", closed_range(1e-3f, 10.0f)), ParamSpec::required_colour("eta", Range{0.0f, 1e3f, true, true}),
     ParamSpec::required_colour("k", Range{0.0f, 1e3f, false, true}), ParamSpec::choice("shadowing", "smith|cs184")},
    [](const MaterialInputs& in, SceneMaterial& m) {
      m.record.info.y = in.texture("albedo");
      m.record.params = glm::vec4(in.number("alpha"), in.colour("eta"));
      m.record.params2 = glm::vec4(in.colour("k"), in.choice("shadowing") == "cs184" ? 1.0f : 0.0f);
    }};

}  // namespace wp::materials
