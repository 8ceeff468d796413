// dielectric.cpp — darts' dielectric (shaders/shared/materials/dielectric.glsl):
// smooth glass. params: x ior, w a named glass (GLASS_* + 1, or 0).
#include "scene/materials/pack_helpers.h"

namespace wp::materials {

extern const MaterialModule dielectric{MAT_DIELECTRIC, dielectric_params(),
                                       [](const MaterialInputs& in, SceneMaterial& m) {
                                         float glass;
                                         m.record.params.x = pack_dielectric_ior(in, glass);
                                         m.record.params.w = glass;
                                       },
                                       dielectric_features};

}  // namespace wp::materials
