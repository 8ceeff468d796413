// registry.cpp — every material kind's module, in the id order of
// WP_MATERIAL_KINDS (shaders/shared/kinds.glsl; a test checks each row has
// its module and each module's parameters).
#include "scene/materials/material_module.h"

namespace wp {
namespace materials {
extern const MaterialModule lambertian, diffuse_light, metal, dielectric, phong, blinn_phong, blend, rough_conductor, rough_dielectric,
    metal_rough, beckmann_conductor, cs184_glass, clearcoat, sheen, interface;
}

const std::vector<const MaterialModule*>& material_modules() {
  using namespace materials;
  static const std::vector<const MaterialModule*> all = {&lambertian,  &diffuse_light,      &metal,       &dielectric, &phong,
                                                         &blinn_phong, &blend,              &rough_conductor, &rough_dielectric, &metal_rough,
                                                         &beckmann_conductor, &cs184_glass, &clearcoat,   &sheen,      &interface};
  return all;
}

}  // namespace wp
