// compile_spectral.cpp — compile_scene's share of the spectral mode: whether
// the kernels need the uplift table, and where they do not, the memo of the
// scene's constant colours (spectral.glsl's spectral_colour_memo), from
// which they uplift each with a hash and two or three fetches.
#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cstring>
#include <utility>
#include <vector>

#include "render/compile_parts.h"
#include "render/shader_cpp.h"

namespace wp {

namespace {

struct ColourKey {
  glm::vec3 rgb;
  uint32_t kind;
};

// Moves a colour makes before its placement is given up (and the memo grown).
constexpr int kMaxEvictions = 64;

// Whether the kernels may uplift a reflectance they compute rather than
// read: a texture's other than a constant's (a checker picks constants), a
// blend's or a layer's weighted colours, metal-rough's (factors times
// textures), vertex colours' tints. Such a scene keeps the table for
// reflectances (FEATURE_SPECTRAL_TABLE).
bool computes_reflectances(const shader::SceneParams& p) {
  const uint32_t textures = KIND_BIT(TEX_MARBLE) | KIND_BIT(TEX_IMAGE);
  const uint32_t materials = KIND_BIT(MAT_BLEND) | KIND_BIT(MAT_CLEARCOAT) | KIND_BIT(MAT_SHEEN) | KIND_BIT(MAT_METAL_ROUGH);
  const uint32_t features = KIND_BIT(FEATURE_VERTEX_DATA) | KIND_BIT(FEATURE_SPECULAR_TINT) | KIND_BIT(FEATURE_DIFFUSE_TRANSMISSION);
  return (p.kinds.x & materials) != 0u || (p.kinds.y & textures) != 0u || (p.kinds.w & features) != 0u;
}

// Whether they may uplift a radiance they compute: a point or spot light's
// at a distance, an environment map's, a textured emitter's, one emitting
// by the cosine or under a clear coat, the photons' emitted and gathered
// light. Such a scene keeps the table for unbounded quantities
// (FEATURE_SPECTRAL_UNBOUNDED_TABLE).
bool computes_radiances(const shader::SceneParams& p) {
  const uint32_t lights = KIND_BIT(LIGHT_POINT) | KIND_BIT(LIGHT_SPOT) | KIND_BIT(LIGHT_ENVIRONMENT);
  const uint32_t features = KIND_BIT(FEATURE_EMISSION_TEXTURES) | KIND_BIT(FEATURE_COSINE_EMISSION);
  return p.mode.x == INTEGRATOR_PHOTONS || (p.kinds.x & KIND_BIT(MAT_CLEARCOAT)) != 0u || (p.kinds.z & lights) != 0u ||
         (p.kinds.w & features) != 0u;
}

// The colours of the kinds the kernels uplift without the table (`memoised`:
// bit k for kind k), as they read them: after max(rgb, 0), neither black
// nor grey (colour_spectrum returns those as they are); one entry per
// colour and kind, bit for bit.
std::vector<ColourKey> constant_colours(const CompiledScene& out, uint32_t memoised) {
  std::vector<ColourKey> keys;
  auto add = [&](glm::vec3 rgb, uint32_t kind) {
    if ((memoised & (1u << kind)) == 0u) return;
    rgb = glm::max(rgb, glm::vec3(0.0f));
    const float m = std::max(rgb.x, std::max(rgb.y, rgb.z));
    if (!(m > 0.0f) || (rgb.x == rgb.y && rgb.y == rgb.z)) return;
    keys.push_back({rgb, kind});
  };
  // A constant texture is a lobe's colour or an emitter's radiance.
  for (const shader::Texture& t : out.textures) {
    if ((t.info.x & TEX_TYPE_MASK) != TEX_CONSTANT) continue;
    add(glm::vec3(t.color0), SPECTRAL_COLOUR_REFLECTANCE);
    add(glm::vec3(t.color0), SPECTRAL_COLOUR_UNBOUNDED);
  }
  for (const shader::Material& m : out.materials) {
    const uint32_t kind = m.info.x;
    if ((kind == MAT_ROUGH_CONDUCTOR || kind == MAT_BECKMANN_CONDUCTOR) && m.params2.w < CONDUCTOR_NAMED) {
      add(glm::vec3(m.params.y, m.params.z, m.params.w), SPECTRAL_COLOUR_UNBOUNDED);  // eta
      add(glm::vec3(m.params2), SPECTRAL_COLOUR_UNBOUNDED);                          // k
    }
    if (kind == MAT_CS184_GLASS) add(glm::vec3(m.params2), SPECTRAL_COLOUR_REFLECTANCE);
    // A glTF volume's attenuation coefficient (volume_transmittance).
    if (kind == MAT_METAL_ROUGH) add(glm::vec3(m.extra[MR_VOLUME]), SPECTRAL_COLOUR_UNBOUNDED);
  }
  for (const shader::Medium& m : out.media) {
    add(glm::vec3(m.sigmaA), SPECTRAL_COLOUR_UNBOUNDED);
    add(glm::vec3(m.sigmaS), SPECTRAL_COLOUR_UNBOUNDED);
    add(glm::vec3(m.sigmaN), SPECTRAL_COLOUR_UNBOUNDED);
  }
  for (const shader::PointLight& l : out.pointLights) add(glm::vec3(l.intensity), SPECTRAL_COLOUR_UNBOUNDED);
  add(glm::vec3(out.params.background), SPECTRAL_COLOUR_UNBOUNDED);
  auto bits = [](const ColourKey& k) {
    std::array<uint32_t, 4> b{};
    std::memcpy(b.data(), &k.rgb, sizeof(k.rgb));
    b[3] = k.kind;
    return b;
  };
  std::sort(keys.begin(), keys.end(), [&](const ColourKey& a, const ColourKey& b) { return bits(a) < bits(b); });
  keys.erase(std::unique(keys.begin(), keys.end(), [&](const ColourKey& a, const ColourKey& b) { return bits(a) == bits(b); }), keys.end());
  return keys;
}

// Places every key in one of its two candidate slots of a table of `slots`
// (cuckoo hashing: a key whose slots are both taken moves one occupant to
// its other slot). The key each slot holds (-1: none), or nothing where a
// key found no place.
std::vector<int> place(shader::SceneView& view, const std::vector<ColourKey>& keys, uint32_t slots) {
  std::vector<int> entryAt(slots, -1);
  auto candidate = [&](const ColourKey& k, int probe) {
    const uint32_t h = view.spectral_colour_hash(k.rgb, k.kind);
    return (probe == 0 ? h : view.pcg_hash(h)) & (slots - 1u);
  };
  for (int i = 0; i < int(keys.size()); ++i) {
    int moving = i;
    uint32_t slot = candidate(keys[i], 0);
    if (entryAt[slot] >= 0 && entryAt[candidate(keys[i], 1)] < 0) slot = candidate(keys[i], 1);
    for (int kick = 0; kick < kMaxEvictions && moving >= 0; ++kick) {
      std::swap(moving, entryAt[slot]);
      if (moving < 0) break;
      const uint32_t a = candidate(keys[moving], 0);
      slot = slot == a ? candidate(keys[moving], 1) : a;
    }
    if (moving >= 0) return {};
  }
  return entryAt;
}

}  // namespace

void compile_spectral_colours(CompiledScene& out) {
  out.spectralColours.assign(1, glm::vec4(0.0f, 0.0f, 0.0f, -1.0f));
  out.params.media.y = 0u;
  if (!out.spectral) return;
  uint32_t memoised = 0u;
  if (computes_reflectances(out.params)) out.params.kinds.w |= KIND_BIT(FEATURE_SPECTRAL_TABLE);
  else memoised |= 1u << SPECTRAL_COLOUR_REFLECTANCE;
  if (computes_radiances(out.params)) out.params.kinds.w |= KIND_BIT(FEATURE_SPECTRAL_UNBOUNDED_TABLE);
  else memoised |= 1u << SPECTRAL_COLOUR_UNBOUNDED;
  if (memoised == 0u) return;
  const std::vector<ColourKey> keys = constant_colours(out, memoised);
  // Without either table the kernels read no coefficient from the tables:
  // the device gets the texels before them (the host's views read them all).
  const uint32_t both = (1u << SPECTRAL_COLOUR_REFLECTANCE) | (1u << SPECTRAL_COLOUR_UNBOUNDED);
  if (memoised == both) out.spectra.count = size_t(SPECTRA_RGB_COEFFICIENTS);
  if (keys.empty()) return;
  // The coefficients are the table's (the view's kernels still have it).
  shader::SceneView view = out.view();
  view.scene.kinds.w |= KIND_BIT(FEATURE_SPECTRAL_TABLE) | KIND_BIT(FEATURE_SPECTRAL_UNBOUNDED_TABLE);
  uint32_t slots = 2;
  while (slots < 2 * keys.size()) slots *= 2;
  std::vector<int> entryAt;
  for (; (entryAt = place(view, keys, slots)).empty(); slots *= 2) {
  }
  out.spectralColours.assign(2 * size_t(slots), glm::vec4(0.0f, 0.0f, 0.0f, -1.0f));
  for (uint32_t s = 0; s < slots; ++s) {
    if (entryAt[s] < 0) continue;
    const ColourKey& k = keys[entryAt[s]];
    float scale = 0.0f;
    const glm::vec3 c = view.colour_coefficients(k.rgb, k.kind, scale);
    out.spectralColours[2 * s] = glm::vec4(k.rgb, float(k.kind));
    out.spectralColours[2 * s + 1] = glm::vec4(c, 0.0f);
  }
  out.params.media.y = slots;
}

}  // namespace wp
