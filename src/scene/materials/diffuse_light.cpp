// diffuse_light.cpp — darts' diffuse_light: emits, scatters nothing (no lobe).
#include "scene/materials/material_module.h"

namespace wp::materials {

extern const MaterialModule diffuse_light{MAT_LIGHT,
                                          {[] {
                                            ParamSpec emit = ParamSpec::texture("emit", glm::vec3(0.0f), non_negative_range());
                                            emit.presence = Presence::Required;
                                            return emit;
                                          }()},
                                          [](const MaterialInputs& in, SceneMaterial& m) { m.emission = in.texture("emit"); }};

}  // namespace wp::materials
