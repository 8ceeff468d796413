// phong.cpp — darts' phong and blinn-phong (shaders/shared/materials/
// phong.glsl and blinn_phong.glsl): a cos^n lobe about the mirror direction,
// or of the half vector about the normal. One schema, two kinds.
#include "scene/materials/material_module.h"

namespace wp::materials {

namespace {

std::vector<ParamSpec> cosine_power_params() {
  return {ParamSpec::texture("albedo", glm::vec3(0.8f), unit_range()).with_problem("albedo above 1 would create energy"),
          ParamSpec::number("exponent", 20.0f, closed_range(0.0f, 1e6f))};
}

void pack_cosine_power(const MaterialInputs& in, SceneMaterial& m) {
  m.record.info.y = in.texture("albedo");
  m.record.params.x = in.number("exponent");
}

}  // namespace

extern const MaterialModule phong{MAT_PHONG, cosine_power_params(), pack_cosine_power};
extern const MaterialModule blinn_phong{MAT_BLINN_PHONG, cosine_power_params(), pack_cosine_power};

}  // namespace wp::materials
