// metal_rough.cpp — glTF 2.0's metal-rough material and its extensions
// (shaders/shared/materials/metal_rough.glsl). The names are darts-style;
// import_gltf.cpp translates glTF's, and gives glTF's own defaults where
// they differ (an extension's factors).
#include <algorithm>
#include <cmath>

#include "scene/materials/material_module.h"

namespace wp::materials {

// The single-scattering albedo of particles whose medium shows `multiple`
// after many bounces (KHR_materials_volume_scatter's README.md:123-127 at
// PR #2453's 134d0766, Kulla and Conty 2017's fit), each channel in [0, 1].
static glm::vec3 single_scattering_albedo(glm::vec3 multiple) {
  glm::vec3 out;
  for (int c = 0; c < 3; ++c) {
    const double a = multiple[c];
    const double s = 4.09712 + 4.20863 * a - std::sqrt(9.59217 + 41.6808 * a + 17.7126 * a * a);
    out[c] = float(std::clamp(1.0 - s * s, 0.0, 1.0));
  }
  return out;
}

extern const MaterialModule metal_rough{
    MAT_METAL_ROUGH,
    {
        ParamSpec::texture("base_color", glm::vec3(1.0f), unit_range()).with_problem("base_color above 1 would create energy"),
        ParamSpec::number("metallic", 1.0f, unit_range()),
        ParamSpec::number("roughness", 1.0f, unit_range()),
        // As glTF's metallicRoughnessTexture: green scales roughness, blue metallic.
        ParamSpec::optional_texture("metallic_roughness"),
        ParamSpec::number("ior", 1.5f, positive_range()),
        ParamSpec::number("transmission", 0.0f, unit_range()),
        ParamSpec::optional_texture("transmission_texture"),  // its red scales transmission
        ParamSpec::optional_texture("emit"),                  // as glTF's emissive materials, which also scatter
        // KHR_materials_specular: a factor and a colour, each scaled by a texture.
        ParamSpec::number("specular", 1.0f, unit_range()).or_texture("specular_texture"),
        ParamSpec::optional_texture("specular_texture"),
        ParamSpec::colour("specular_color", glm::vec3(1.0f), closed_range(0.0f, 1e3f)).or_texture("specular_color_texture"),
        ParamSpec::optional_texture("specular_color_texture"),
        // KHR_materials_volume: the transmission refracts into a volume whose
        // absorption takes the light to attenuation_color after
        // attenuation_distance; KHR_materials_dispersion: 20 / Abbe number.
        // KHR_materials_diffuse_transmission: the share of the diffuse base
        // that passes through the surface, and its colour, each scaled by a
        // texture (the factor's read in red: glTF's alpha, as grey).
        ParamSpec::number("diffuse_transmission", 0.0f, unit_range()).or_texture("diffuse_transmission_texture"),
        ParamSpec::optional_texture("diffuse_transmission_texture"),
        ParamSpec::colour("diffuse_transmission_color", glm::vec3(1.0f), unit_range()).or_texture("diffuse_transmission_color_texture"),
        ParamSpec::optional_texture("diffuse_transmission_color_texture"),
        ParamSpec::group("volume"),
        ParamSpec::colour("volume.attenuation_color", glm::vec3(1.0f), unit_range()),
        ParamSpec::number("volume.attenuation_distance", 1e30f, positive_range()),
        ParamSpec::number("volume.dispersion", 0.0f, closed_range(0.0f, 1000.0f)).with_problem("dispersion must lie in [0, 1000] (20 / Abbe number)"),
        // KHR_materials_volume_scatter: the attenuation is the extinction of
        // particles that scatter, multiscatter_color the albedo they show
        // after many bounces, scatter_anisotropy their Henyey-Greenstein g.
        ParamSpec::colour("volume.multiscatter_color", glm::vec3(0.0f), unit_range()),
        ParamSpec::number("volume.scatter_anisotropy", 0.0f, closed_range(-0.99f, 0.99f)).with_problem("scatter_anisotropy must lie in [-0.99, 0.99]"),
        // KHR_materials_iridescence: a thin film of `ior`, from
        // thickness_minimum nm where thickness_texture's green is 0 to
        // thickness_maximum where it is 1 (the maximum without one), mixed
        // in by `factor`.
        ParamSpec::group("iridescence"),
        ParamSpec::number("iridescence.factor", 1.0f, unit_range()).or_texture("iridescence.factor_texture"),
        ParamSpec::optional_texture("iridescence.factor_texture"),
        ParamSpec::number("iridescence.ior", 1.3f, closed_range(1.0f, 10.0f)),
        ParamSpec::number("iridescence.thickness_minimum", 100.0f, closed_range(0.0f, 1e5f)),
        ParamSpec::number("iridescence.thickness_maximum", 400.0f, closed_range(0.0f, 1e5f)),
        ParamSpec::optional_texture("iridescence.thickness_texture"),
        // KHR_materials_anisotropy: strength, the direction's rotation from
        // the tangent (radians), a texture of directions (red, green) and
        // strengths (blue).
        ParamSpec::group("anisotropy"),
        ParamSpec::number("anisotropy.strength", 1.0f, unit_range()),
        ParamSpec::number("anisotropy.rotation", 0.0f, closed_range(-1e4f, 1e4f)).with_problem("rotation must be a number of radians"),
        ParamSpec::optional_texture("anisotropy.texture"),
    },
    [](const MaterialInputs& in, SceneMaterial& m) {
      shader::Material& r = m.record;
      r.info.y = in.texture("base_color");
      r.info.w = in.texture("metallic_roughness");
      r.children.y = in.texture("transmission_texture");
      m.emission = in.texture("emit");
      r.params = glm::vec4(in.number("roughness"), in.number("metallic"), in.number("ior"), in.number("transmission"));
      // metal_rough.glsl reads the specular factor and colour less 1, so that a record of zeros is glTF's default.
      r.params2 = glm::vec4(in.colour("specular_color") - glm::vec3(1.0f), in.number("specular") - 1.0f);
      // The extensions' slots, as metal_rough.glsl lays them out.
      const auto bits = [](uint32_t texture) { return glm::uintBitsToFloat(texture); };
      r.extra[MR_TEXTURES] = glm::vec4(bits(in.texture("specular_texture")), bits(in.texture("specular_color_texture")),
                                       bits(in.texture("iridescence.factor_texture")), bits(in.texture("iridescence.thickness_texture")));
      glm::vec3 attenuation(0.0f);
      if (in.given("volume.attenuation_color") || in.given("volume.attenuation_distance"))
        attenuation = -glm::log(glm::max(in.colour("volume.attenuation_color"), glm::vec3(1e-6f))) / in.number("volume.attenuation_distance");
      r.extra[MR_VOLUME] = glm::vec4(attenuation, in.flag("volume") ? 1.0f + in.number("volume.dispersion") : 0.0f);
      // With scattering, a homogeneous medium inside takes the whole extinction (media.glsl).
      if (in.flag("volume") && (in.given("volume.multiscatter_color") || in.given("volume.scatter_anisotropy")) && attenuation != glm::vec3(0.0f)) {
        SceneMedium inside;
        const glm::vec3 albedo = single_scattering_albedo(in.colour("volume.multiscatter_color"));
        inside.sigmaS = attenuation * albedo;
        inside.sigmaA = attenuation - inside.sigmaS;
        inside.g = in.number("volume.scatter_anisotropy");
        m.boundsMedia = true;
        m.interior = in.add_medium(inside);
        m.exterior = WP_INVALID;
        r.extra[MR_VOLUME] = glm::vec4(glm::vec3(0.0f), r.extra[MR_VOLUME].w);
      }
      r.extra[MR_IRIDESCENCE] = in.flag("iridescence") ? glm::vec4(in.number("iridescence.factor"), in.number("iridescence.ior"),
                                                                   in.number("iridescence.thickness_minimum"), in.number("iridescence.thickness_maximum"))
                                                       : glm::vec4(0.0f);
      // A texture given for the factor alone (darts) is the factor.
      const uint32_t dtTexture = in.texture("diffuse_transmission_texture");
      const float dt = in.given("diffuse_transmission") || dtTexture == WP_INVALID ? in.number("diffuse_transmission") : 1.0f;
      r.extra[MR_DIFFUSE_TRANSMISSION] = glm::vec4(in.colour("diffuse_transmission_color"), dt);
      r.extra[MR_DIFFUSE_TRANSMISSION_TEXTURES] = glm::vec4(bits(dtTexture), bits(in.texture("diffuse_transmission_color_texture")), 0.0f, 0.0f);
      const float rotation = in.flag("anisotropy") ? in.number("anisotropy.rotation") : 0.0f;
      r.extra[MR_ANISOTROPY] = glm::vec4(in.flag("anisotropy") ? in.number("anisotropy.strength") : 0.0f, std::cos(rotation), std::sin(rotation),
                                         bits(in.flag("anisotropy") ? in.texture("anisotropy.texture") : WP_INVALID));
    },
    // The features the kernels compile in for it.
    [](const shader::Material& r) {
      uint32_t f = 0u;
      const glm::uvec4 textures = glm::floatBitsToUint(r.extra[MR_TEXTURES]);
      if (r.params2 != glm::vec4(0.0f) || textures.x != WP_INVALID || textures.y != WP_INVALID) f |= KIND_BIT(FEATURE_SPECULAR_TINT);
      if (r.extra[MR_IRIDESCENCE].x > 0.0f) f |= KIND_BIT(FEATURE_IRIDESCENCE);
      if (r.extra[MR_ANISOTROPY].x > 0.0f) f |= KIND_BIT(FEATURE_ANISOTROPY);
      if (r.extra[MR_VOLUME].w > 0.0f) f |= KIND_BIT(FEATURE_VOLUME);
      if (r.extra[MR_VOLUME].w > 1.0f) f |= KIND_BIT(FEATURE_DISPERSION);
      if (r.extra[MR_DIFFUSE_TRANSMISSION].w > 0.0f) f |= KIND_BIT(FEATURE_DIFFUSE_TRANSMISSION);
      return f;
    },
    // The textures its lobe reads besides the base colour and metallic-roughness.
    [](const shader::Material& r) {
      const glm::uvec4 textures = glm::floatBitsToUint(r.extra[MR_TEXTURES]);
      const glm::uvec4 dtTextures = glm::floatBitsToUint(r.extra[MR_DIFFUSE_TRANSMISSION_TEXTURES]);
      return std::vector<uint32_t>{r.children.y, textures.x, textures.y, textures.z, textures.w, glm::floatBitsToUint(r.extra[MR_ANISOTROPY].w),
                                   dtTextures.x, dtTextures.y};
    }};

}  // namespace wp::materials
