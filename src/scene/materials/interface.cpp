// interface.cpp — no surface: the boundary of a medium that rays pass
// straight through (darts' "material": null; shaders/shared/media.glsl).
#include "scene/materials/material_module.h"

namespace wp::materials {

extern const MaterialModule interface{MAT_INTERFACE, {}, [](const MaterialInputs&, SceneMaterial&) {}};

}  // namespace wp::materials
