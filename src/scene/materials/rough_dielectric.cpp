// rough_dielectric.cpp — GGX microfacet glass (shaders/shared/materials/
// rough_dielectric.glsl): params (ior, alpha, 0, a named glass: GLASS_* + 1, or 0).
#include "scene/materials/pack_helpers.h"

namespace wp::materials {

namespace {

std::vector<ParamSpec> schema() {
  std::vector<ParamSpec> p{ParamSpec::texture("albedo", glm::vec3(1.0f), unit_range()).with_problem("albedo above 1 would create energy")};
  for (const ParamSpec& d : dielectric_params()) p.push_back(d);
  p.push_back(ParamSpec::number("roughness", 0.3f, unit_range()));
  return p;
}

}  // namespace

extern const MaterialModule rough_dielectric{
    MAT_ROUGH_DIELECTRIC, schema(),
    [](const MaterialInputs& in, SceneMaterial& m) {
      float glass;
      m.record.info.y = in.texture("albedo");
      const float ior = pack_dielectric_ior(in, glass);
      m.record.params = glm::vec4(ior, ggx_alpha(in.number("roughness")), 0.0f, glass);
    },
    dielectric_features};

}  // namespace wp::materials
