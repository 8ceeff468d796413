// no_lobe.glsl — stand-ins for lobe functions a material kind does not have.
// Every kind in WP_MATERIAL_KINDS (kinds.glsl) names a prefix whose five
// functions the BSDF dispatch calls (bsdf.glsl):
//   bool  P_is_delta(param)                       whether the lobe is a delta lobe (for this parameter)
//   float P_pdf(param, ns, wo, wi)                density of P_sample's directions (smooth lobes)
//   vec3  P_eval(param, color, ns, wo, wi)        f * |cos(wi)| (smooth lobes)
//   vec3  P_sample(param, ns, wo, u)              a direction, or zero (smooth lobes)
//   vec3  P_sample_delta(param, color, front, ns, ng, wo, uPick, wi)
//                                                 a delta lobe's direction and f * |cos| / pdf
// Conventions as in bsdf.glsl: wo and wi point away from the surface, ns and
// ng face wo, `front` says wo is on the outer side, uPick in [0, 1) is free
// for the lobe's own choices. A kind with only smooth or only delta lobes
// takes the other half from the macros below; the kinds that have no lobe
// of their own (lights, blends) take both.
#ifndef WP_NO_LOBE_GLSL
#define WP_NO_LOBE_GLSL

// P has no delta lobe.
#define WP_NO_DELTA_LOBE(P)                                                                                         \
  bool P##_is_delta(float param) {                                                                                  \
    return false;                                                                                                   \
  }                                                                                                                 \
  vec3 P##_sample_delta(float param, vec3 color, bool front, vec3 ns, vec3 ng, vec3 wo, float uPick, OUT(vec3) wi) { \
    wi = vec3(0.0f);                                                                                                \
    return vec3(0.0f);                                                                                              \
  }

// P has no smooth lobe.
#define WP_NO_SMOOTH_LOBE(P)                                          \
  float P##_pdf(float param, vec3 ns, vec3 wo, vec3 wi) {             \
    return 0.0f;                                                      \
  }                                                                   \
  vec3 P##_eval(float param, vec3 color, vec3 ns, vec3 wo, vec3 wi) { \
    return vec3(0.0f);                                                \
  }                                                                   \
  vec3 P##_sample(float param, vec3 ns, vec3 wo, vec3 u) {            \
    return vec3(0.0f);                                                \
  }

WP_NO_SMOOTH_LOBE(no_lobe)
WP_NO_DELTA_LOBE(no_lobe)

#endif  // WP_NO_LOBE_GLSL
