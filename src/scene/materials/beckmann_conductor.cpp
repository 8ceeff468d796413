// beckmann_conductor.cpp — CS184's microfacet conductor (shaders/shared/
// materials/beckmann_conductor.glsl): params (alpha, eta), params2 (k, 1 for
// the 3-2 skeleton's shadowing term, 0 for Smith's, plus the metal named).
#include "scene/materials/pack_helpers.h"

namespace wp::materials {

namespace {

std::vector<ParamSpec> schema() {
  std::vector<ParamSpec> p{ParamSpec::texture("albedo", glm::vec3(1.0f), unit_range()).with_problem("albedo above 1 would create energy"),
                           ParamSpec::required_number("alpha", closed_range(1e-3f, 10.0f))};
  for (const ParamSpec& c : conductor_params()) p.push_back(c);
  p.push_back(ParamSpec::choice("shadowing", "smith|cs184"));
  return p;
}

}  // namespace

extern const MaterialModule beckmann_conductor{
    MAT_BECKMANN_CONDUCTOR, schema(), [](const MaterialInputs& in, SceneMaterial& m) {
      glm::vec3 eta, k;
      float named;
      pack_conductor_index(in, eta, k, named);
      m.record.info.y = in.texture("albedo");
      m.record.params = glm::vec4(in.number("alpha"), eta);
      m.record.params2 = glm::vec4(k, named + (in.choice("shadowing") == "cs184" ? 1.0f : 0.0f));
    }};

}  // namespace wp::materials
