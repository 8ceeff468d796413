// dielectric.cpp — darts' dielectric (shaders/shared/materials/dielectric.glsl): smooth glass.
#include "scene/materials/material_module.h"

namespace wp::materials {

extern const MaterialModule dielectric{MAT_DIELECTRIC,
                                       {ParamSpec::number("ior", 1.5f, positive_range())},
                                       [](const MaterialInputs& in, SceneMaterial& m) { m.record.params.x = in.number("ior"); }};

}  // namespace wp::materials
