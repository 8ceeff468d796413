// diffuse_light.cpp — darts' diffuse_light: emits, scatters nothing (no
// lobe). `cosine`: its radiance falls off with the cosine to its normal
// (params.x; CS184 3-2's light quads, cs184_skeleton.cpp).
#include "scene/materials/material_module.h"

namespace wp::materials {

extern const MaterialModule diffuse_light{
    MAT_LIGHT,
    {[] {
       ParamSpec emit = ParamSpec::texture("emit", glm::vec3(0.0f), non_negative_range());
       emit.presence = Presence::Required;
       return emit;
     }(),
     ParamSpec::flag("cosine")},
    [](const MaterialInputs& in, SceneMaterial& m) {
      m.emission = in.texture("emit");
      m.record.params.x = in.flag("cosine") ? 1.0f : 0.0f;
    },
    [](const shader::Material& r) { return r.params.x != 0.0f ? KIND_BIT(FEATURE_COSINE_EMISSION) : 0u; }};

}  // namespace wp::materials
