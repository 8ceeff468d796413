// blend.cpp — darts' blend: (1 - amount) a + amount b, flattened into its
// parts' lobes by bsdf_at (shaders/shared/bsdf.glsl).
#include "scene/materials/pack_helpers.h"

namespace wp::materials {

extern const MaterialModule blend{
    MAT_BLEND,
    {ParamSpec::texture("amount", glm::vec3(0.5f), unit_range()).allowing_fresnel().with_problem("blend amount must lie in [0, 1]"),
     ParamSpec::material("a"), ParamSpec::material("b")},
    [](const MaterialInputs& in, SceneMaterial& m) {
      m.record.info.w = in.texture("amount");
      const uint32_t a = surface_part(in, "a"), b = surface_part(in, "b");
      m.record.children.x = a;
      m.record.children.y = b;
      const Scene& s = in.scene();
      if (material_lobes(s, a) + material_lobes(s, b) > int(BSDF_MAX_LOBES))
        in.fail("a blend may combine at most " + std::to_string(BSDF_MAX_LOBES) + " materials in all");
      if (material_sheens(s, a) + material_sheens(s, b) > 1) in.fail("a material may hold at most one sheen");
    }};

}  // namespace wp::materials
