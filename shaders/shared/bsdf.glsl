// bsdf.glsl — materials as sample / eval / pdf triples in world space.
//
// At a hit, material_at.glsl resolves the material (blends flattened,
// textures looked up) into a Bsdf: up to BSDF_MAX_LOBES weighted lobes whose
// weights sum to 1. Each lobe is of a material kind (kinds.glsl), whose
// functions live in materials/KIND.glsl. Lobes are either smooth (they have a
// density: Lambertian, rough metal, Phong, Blinn-Phong) or delta (mirror
// metal, dielectric): eval and pdf see only the smooth lobes, and bsdf_sample
// reports when it picked a delta lobe.
//
// Conventions: wo points away from the surface towards the previous vertex, wi
// towards the next; ns and ng face wo. eval returns f * |cos(wi)|, sample returns
// f * |cos| / pdf. The darts glossy lobes (metal, Phong, Blinn-Phong) define
// f * cos as albedo times their sampling density, as darts does, so sampling
// them returns exactly the albedo and directions below the surface are absorbed.
#ifndef WP_BSDF_GLSL
#define WP_BSDF_GLSL

// Lobes a BSDF of this scene can have: one unless it has blend materials.
#define BSDF_LOBES_OF_SCENE (COMPOSITE_MATERIALS_COMPILED ? BSDF_MAX_LOBES : 1u)
// Slots of a lobe's extra parameters (Lobe.extra).
#define LOBE_EXTRA_SLOTS 3

struct Bsdf {
  vec3 ns;  // shading normal, on wo's side of the geometric surface
  uint lobeCount;
  vec3 ng;  // geometric normal, on wo's side
  bool front;  // wo is on the front (outer) side: a dielectric is entered, not left
  uint lobeType[BSDF_MAX_LOBES];      // MAT_* of each lobe
  Spectrum lobeColor[BSDF_MAX_LOBES];  // albedo (white for the dielectric)
  // The kind's parameters at the hit (kinds.glsl), params.x apart from the
  // rest, which only kernels with kinds that read them store: lavapipe keeps
  // arrays written at a varying index in memory, and every store costs.
  float lobeParam[BSDF_MAX_LOBES];      // params.x
  vec3 lobeParamYzw[BSDF_MAX_LOBES];    // params.yzw
  vec4 lobeParams2[BSDF_MAX_LOBES];     // params2
  // Lobe.extra, one array a slot, stored where a compiled feature reads it
  // (one array of arrays cost lavapipe 8 % of a layered scene's shading).
  vec4 lobeExtra0[BSDF_MAX_LOBES];
  vec4 lobeExtra1[BSDF_MAX_LOBES];
  vec4 lobeExtra2[BSDF_MAX_LOBES];
  // A lobe's dispersion (FEATURE_DISPERSION): a metal-rough lobe's 20 /
  // Abbe number (> 0), or a dielectric's named glass, -(GLASS_* + 1) (< 0).
  float lobeDispersion[BSDF_MAX_LOBES];
  float lobeWeight[BSDF_MAX_LOBES];
#ifdef WP_SPECTRUM_W
  // The spectral mode's fourth wavelength of the colours a kind keeps in its
  // parameters (LOBE_FOURTH_*; spectral.glsl's bsdf_at_wavelengths).
  vec4 lobeFourth[BSDF_MAX_LOBES];
#endif
  // A sheen layer (MAT_SHEEN): x max3 of its colour (0: none), y its
  // roughness, z x times its bounded albedo at wo; and the lobes under it
  // (bit i: lobe i), which sheen_cover_scale scales.
  vec4 sheen;
  uint sheenCovers;
};

// What one lobe's functions read: its colour and parameters, and which side
// wo is on (the dielectrics' ratio of indices depends on it).
struct Lobe {
  vec4 params;
  vec4 params2;
  // More of the kind's parameters at the hit, as its materials/ file lays
  // them out (metal-rough's extensions: MR_LOBE_* slots, kinds.glsl); zero
  // in a slot no compiled feature reads.
  vec4 extra[LOBE_EXTRA_SLOTS];
  Spectrum color;
  bool front;
#ifdef WP_SPECTRUM_W
  vec4 fourth;  // Bsdf.lobeFourth
#endif
};

// Where Lobe.fourth keeps the fourth wavelength of a colour parameter: a
// conductor's eta (params.yzw) and k (params2.xyz); CS184 glass's
// reflectance (params2.xyz); metal-rough's specular tint (params2.xyz) and
// diffuse transmission colour (its extra slot's xyz).
#define LOBE_FOURTH_ETA 0
#define LOBE_FOURTH_K 1
#define LOBE_FOURTH_PARAMS2 0
#define LOBE_FOURTH_TRANSMISSION 1

// Colour parameter xyz of lobe l as a Spectrum, its fourth wavelength's
// value from slot `slot` of Lobe.fourth.
Spectrum lobe_spectrum(Lobe l, vec3 xyz, int slot) {
#ifdef WP_SPECTRUM_W
  return Spectrum(xyz.x, xyz.y, xyz.z, slot == 0 ? l.fourth.x : l.fourth.y);
#else
  return xyz;
#endif
}

// Whether a compiled feature reads slot `slot` of Lobe.extra (the features'
// table, kinds.glsl).
bool lobe_extra_compiled(uint slot) {
  return (FEATURES_OF_SCENE & (0u WP_FEATURES(WP_READS_LOBE_EXTRA))) != 0u;
}

// Sets and reads slot `slot` of lobe k's extra parameters.
void bsdf_set_extra(INOUT(Bsdf) b, uint k, uint slot, vec4 value) {
  if (!lobe_extra_compiled(slot)) return;
  if (slot == 0u) b.lobeExtra0[k] = value;
  if (slot == 1u) b.lobeExtra1[k] = value;
  if (slot == 2u) b.lobeExtra2[k] = value;
}

vec4 bsdf_extra(INOUT(Bsdf) b, uint k, uint slot) {  // (INOUT: C++ would copy b)
  if (!lobe_extra_compiled(slot)) return vec4(0.0f);
  return slot == 0u ? b.lobeExtra0[k] : slot == 1u ? b.lobeExtra1[k] : b.lobeExtra2[k];
}

// Stores lobe k's parameters: l's (its colour and side are the Bsdf's own).
void bsdf_store_params(INOUT(Bsdf) b, uint k, Lobe l) {
  b.lobeParam[k] = l.params.x;
  if (MATERIAL_PARAMS_YZW_COMPILED) b.lobeParamYzw[k] = vec3(l.params.y, l.params.z, l.params.w);
  if (MATERIAL_PARAMS2_COMPILED) b.lobeParams2[k] = l.params2;
  for (uint slot = 0u; slot < uint(LOBE_EXTRA_SLOTS); ++slot) bsdf_set_extra(b, k, slot, l.extra[slot]);
}

// A lobe's parameters `params`, `params2`, its extra slots zero.
Lobe lobe_with_params(vec4 params, vec4 params2) {
  Lobe l;
  l.params = params;
  l.params2 = params2;
  for (uint slot = 0u; slot < uint(LOBE_EXTRA_SLOTS); ++slot) l.extra[slot] = vec4(0.0f);
  l.color = Spectrum(0.0f);
  l.front = true;
#ifdef WP_SPECTRUM_W
  l.fourth = vec4(0.0f);
#endif
  return l;
}

// Sets lobe k's parameters, its extra slots zero.
void bsdf_set_params(INOUT(Bsdf) b, uint k, vec4 params, vec4 params2) {
  bsdf_store_params(b, k, lobe_with_params(params, params2));
}

// The index of refraction of colour channel `channel` (1 red, 2 green, 3
// blue) of a volume of index `ior` and dispersion `dispersion` (20 / Abbe
// number): green keeps the material's index, red and blue lie half the
// spread n_F - n_C = (ior - 1) dispersion / 20 below and above it
// (KHR_materials_dispersion, README.md "Implementation": its GLSL sample),
// red at least 1 (METAL_ROUGH_MIN_IOR).
float dispersed_ior(float ior, float dispersion, uint channel) {
  float halfSpread = (ior - 1.0f) * 0.025f * dispersion;
  if (channel == 1u) return max(ior - halfSpread, METAL_ROUGH_MIN_IOR);
  return channel == 3u ? ior + halfSpread : ior;
}

Lobe lobe_of(Bsdf b, uint i) {
  Lobe l;
  vec3 yzw = MATERIAL_PARAMS_YZW_COMPILED ? b.lobeParamYzw[i] : vec3(0.0f);
  l.params = vec4(b.lobeParam[i], yzw.x, yzw.y, yzw.z);
  l.params2 = MATERIAL_PARAMS2_COMPILED ? b.lobeParams2[i] : vec4(0.0f);
  for (uint slot = 0u; slot < uint(LOBE_EXTRA_SLOTS); ++slot) l.extra[slot] = bsdf_extra(b, i, slot);
  l.color = b.lobeColor[i];
  l.front = b.front;
#ifdef WP_SPECTRUM_W
  l.fourth = b.lobeFourth[i];  // (zero unless the spectral mode set it: bsdf_at)
#endif
  return l;
}

vec3 reflect_about(vec3 wo, vec3 n) {
  return n * (2.0f * dot(wo, n)) - wo;
}

// Unpolarised Fresnel reflectance of a smooth dielectric boundary. cosI is the
// cosine on the incident side, eta the ratio transmitted-side / incident-side ior.
float fresnel_dielectric(float cosI, float eta) {
  cosI = clamp(cosI, 0.0f, 1.0f);
  float sin2T = (1.0f - cosI * cosI) / (eta * eta);
  if (sin2T >= 1.0f) return 1.0f;  // total internal reflection
  float cosT = sqrt(1.0f - sin2T);
  float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
  float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
  return 0.5f * (rs * rs + rp * rp);
}

#include "microfacet.glsl"

// Each material kind's lobe functions (no_lobe.glsl lists them), one file a
// kind, as WP_MATERIAL_KINDS names them.
#include "materials/no_lobe.glsl"
#include "materials/lambertian.glsl"
#include "materials/metal.glsl"
#include "materials/dielectric.glsl"
#include "materials/phong.glsl"
#include "materials/blinn_phong.glsl"
#include "materials/rough_conductor.glsl"
#include "materials/rough_dielectric.glsl"
#include "materials/metal_rough.glsl"
#include "materials/beckmann_conductor.glsl"
#include "materials/cs184_glass.glsl"
#include "materials/clearcoat.glsl"
#include "materials/sheen.glsl"

// The albedo scaling of the lobes under a sheen at wi, KHR_materials_sheen's
// 1 - s max(E(cos_o), E(cos_i)) (s the sheen colour's largest channel, E
// bounded by 1), over the share of the weight bsdf_at gave them, 1 - s E(cos_o).
float sheen_cover_scale(Bsdf b, vec3 wi) {
  float ei = b.sheen.x * sheen_albedo_bounded(abs(dot(wi, b.ns)), b.sheen.y);
  return (1.0f - max(b.sheen.z, ei)) / max(1.0f - b.sheen.z, 1e-6f);
}

// The factor sheen_cover_scale gives lobe i at wi (1 for lobes no sheen covers).
float lobe_cover_scale(Bsdf b, uint i, float coverScale) {
  return MATERIAL_COMPILED(MAT_SHEEN) && ((b.sheenCovers >> i) & 1u) != 0u ? coverScale : 1.0f;
}

// The lobe functions of a lobe of kind `type`, dispatched through the kind
// table: one branch per kind, each compiled only where the scene has the kind.
#define WP_LOBE_IS_DELTA(id, name, prefix, lobes) \
  if (MATERIAL_COMPILED(id) && type == id) return prefix##_is_delta(l);
#define WP_LOBE_TRANSMITS(id, name, prefix, lobes) \
  if (MATERIAL_COMPILED(id) && type == id) return ((lobes) & LOBE_TRANSMISSIVE) != 0u && !prefix##_is_delta(l);
#define WP_LOBE_PDF(id, name, prefix, lobes) \
  if (MATERIAL_COMPILED(id) && type == id) return prefix##_pdf(l, ns, wo, wi);
#define WP_LOBE_EVAL(id, name, prefix, lobes) \
  if (MATERIAL_COMPILED(id) && type == id) return prefix##_eval(l, ns, wo, wi);
#define WP_LOBE_SAMPLE(id, name, prefix, lobes) \
  if (MATERIAL_COMPILED(id) && type == id) return prefix##_sample(l, ns, wo, u);
#define WP_LOBE_SAMPLE_DELTA(id, name, prefix, lobes) \
  if (MATERIAL_COMPILED(id) && type == id) return prefix##_sample_delta(l, ns, ng, wo, uPick, wi);

bool lobe_is_delta(uint type, Lobe l) {
  WP_MATERIAL_KINDS(WP_LOBE_IS_DELTA)
  return false;
}

// Whether a smooth lobe has a density on the far side of the surface.
bool lobe_transmits(uint type, Lobe l) {
  WP_MATERIAL_KINDS(WP_LOBE_TRANSMITS)
  return false;
}

// Density (solid angle) with which a smooth lobe of `type` samples wi; ns is
// the shading normal on wo's side. 0 for delta lobes.
float lobe_pdf(uint type, Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  WP_MATERIAL_KINDS(WP_LOBE_PDF)
  return 0.0f;
}

// f * |cos| of a smooth lobe (zero where it does not reach).
Spectrum lobe_eval(uint type, Lobe l, vec3 ns, vec3 wo, vec3 wi) {
  WP_MATERIAL_KINDS(WP_LOBE_EVAL)
  return Spectrum(0.0f);
}

// Direction from a smooth lobe, or a zero vector when the lobe produced none.
vec3 lobe_sample(uint type, Lobe l, vec3 ns, vec3 wo, vec3 u) {
  WP_MATERIAL_KINDS(WP_LOBE_SAMPLE)
  return vec3(0.0f);
}

// Direction from a delta lobe, and f * |cos| / pdf (zero when absorbed).
Spectrum lobe_sample_delta(uint type, Lobe l, vec3 ns, vec3 ng, vec3 wo, float uPick, OUT(vec3) wi) {
  WP_MATERIAL_KINDS(WP_LOBE_SAMPLE_DELTA)
  wi = vec3(0.0f);
  return Spectrum(0.0f);
}

// Loops over lobes run to the constant BSDF_LOBES_OF_SCENE and skip unused
// slots: with constant indices the compiler keeps the lobe arrays in registers
// (lavapipe spills dynamically indexed local arrays to memory).

bool bsdf_has_smooth_lobe(Bsdf b) {
  bool any = false;
  for (uint i = 0u; i < BSDF_LOBES_OF_SCENE; ++i) {
    if (i < b.lobeCount && !lobe_is_delta(b.lobeType[i], lobe_of(b, i))) any = true;
  }
  return any;
}

bool bsdf_has_delta_lobe(Bsdf b) {
  bool any = false;
  for (uint i = 0u; i < BSDF_LOBES_OF_SCENE; ++i) {
    if (i < b.lobeCount && lobe_is_delta(b.lobeType[i], lobe_of(b, i))) any = true;
  }
  return any;
}

// Where wi leaves: above both the geometric and the shading surface
// (reflection) or below both (transmission). A direction between the two
// surfaces reaches no lobe, so shading normals cannot leak light through a
// surface; reflective lobes see reflections only.
bool bsdf_reflects(Bsdf b, vec3 wi) {
  return dot(wi, b.ng) > 0.0f && dot(wi, b.ns) > 0.0f;
}

bool bsdf_transmits(Bsdf b, vec3 wi) {
  return dot(wi, b.ng) < 0.0f && dot(wi, b.ns) < 0.0f;
}

// f(wo, wi) * |cos(wi)| summed over the smooth lobes.
Spectrum bsdf_eval(Bsdf b, vec3 wo, vec3 wi) {
  Spectrum f = Spectrum(0.0f);
  bool reflects = bsdf_reflects(b, wi);
  bool transmits = bsdf_transmits(b, wi);
  float coverScale = MATERIAL_COMPILED(MAT_SHEEN) && b.sheenCovers != 0u ? sheen_cover_scale(b, wi) : 1.0f;
  for (uint i = 0u; i < BSDF_LOBES_OF_SCENE; ++i) {
    Lobe l = lobe_of(b, i);
    uint type = b.lobeType[i];
    if (i < b.lobeCount && !lobe_is_delta(type, l) && (reflects || (transmits && lobe_transmits(type, l))))
      f += lobe_eval(type, l, b.ns, wo, wi) * (b.lobeWeight[i] * lobe_cover_scale(b, i, coverScale));
  }
  return f;
}

// Density with which bsdf_sample produces wi through its smooth lobes.
float bsdf_pdf(Bsdf b, vec3 wo, vec3 wi) {
  float pdf = 0.0f;
  bool reflects = bsdf_reflects(b, wi);
  bool transmits = bsdf_transmits(b, wi);
  for (uint i = 0u; i < BSDF_LOBES_OF_SCENE; ++i) {
    Lobe l = lobe_of(b, i);
    uint type = b.lobeType[i];
    if (i < b.lobeCount && !lobe_is_delta(type, l) && (reflects || (transmits && lobe_transmits(type, l))))
      pdf += lobe_pdf(type, l, b.ns, wo, wi) * b.lobeWeight[i];
  }
  return pdf;
}

// Samples wi. Returns f * |cos| / pdf (zero when the sample is absorbed), writes
// the pdf (of the smooth lobes' mixture) and whether a delta lobe was taken, in
// which case pdf is 0 and MIS does not apply. u.z picks the lobe and is then
// reused (rescaled) for a delta lobe's own choice (the dielectric's between
// reflection and refraction); a smooth lobe gets (u.x, u.y, u.w).
Spectrum bsdf_sample(Bsdf b, vec3 wo, vec4 u, OUT(vec3) wi, OUT(float) pdf, OUT(bool) isDelta) {
  wi = vec3(0.0f);
  pdf = 0.0f;
  isDelta = false;
  if (b.lobeCount == 0u) return Spectrum(0.0f);
  // Pick lobe k with probability lobeWeight[k]; copy its fields out with
  // constant indices.
  uint type = b.lobeType[0];
  Lobe l = lobe_of(b, 0u);
  uint picked = 0u;
  float uPick = clamp(u.z / b.lobeWeight[0], 0.0f, 0.99999994f);
  float below = 0.0f;
  for (uint i = 1u; i < BSDF_LOBES_OF_SCENE; ++i) {
    below += b.lobeWeight[i - 1u];
    if (i < b.lobeCount && u.z >= below) {
      type = b.lobeType[i];
      l = lobe_of(b, i);
      picked = i;
      uPick = clamp((u.z - below) / b.lobeWeight[i], 0.0f, 0.99999994f);
    }
  }
  if (lobe_is_delta(type, l)) {
    isDelta = true;
    Spectrum weight = lobe_sample_delta(type, l, b.ns, b.ng, wo, uPick, wi);
    if (MATERIAL_COMPILED(MAT_SHEEN) && ((b.sheenCovers >> picked) & 1u) != 0u) weight *= sheen_cover_scale(b, wi);
    return weight;
  }
  wi = lobe_sample(type, l, b.ns, wo, vec3(u.x, u.y, u.w));
  pdf = bsdf_pdf(b, wo, wi);
  if (pdf <= 0.0f) {
    pdf = 0.0f;
    return Spectrum(0.0f);
  }
  return bsdf_eval(b, wo, wi) / pdf;
}

#endif  // WP_BSDF_GLSL
