// rough_conductor.cpp — a GGX microfacet metal (shaders/shared/materials/
// rough_conductor.glsl): params (alpha, eta), params2 (k, the metal named).
#include "scene/materials/pack_helpers.h"

namespace wp::materials {

namespace {

std::vector<ParamSpec> schema() {
  std::vector<ParamSpec> p{ParamSpec::texture("albedo", glm::vec3(1.0f), unit_range()).with_problem("albedo above 1 would create energy")};
  for (const ParamSpec& c : conductor_params()) p.push_back(c);
  p.push_back(ParamSpec::number("roughness", 0.3f, unit_range()));
  return p;
}

}  // namespace

extern const MaterialModule rough_conductor{
    MAT_ROUGH_CONDUCTOR, schema(), [](const MaterialInputs& in, SceneMaterial& m) {
      glm::vec3 eta, k;
      float named;
      pack_conductor_index(in, eta, k, named);
      m.record.info.y = in.texture("albedo");
      m.record.params = glm::vec4(ggx_alpha(in.number("roughness")), eta);
      m.record.params2 = glm::vec4(k, named);
    }};

}  // namespace wp::materials
