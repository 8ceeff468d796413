// no_lobe.glsl — stand-ins for lobe functions a material kind does not have.
// Every kind in WP_MATERIAL_KINDS (kinds.glsl) names a prefix whose five
// functions the BSDF dispatch calls (bsdf.glsl):
//   bool  P_is_delta(l)                        whether the lobe is a delta lobe (for these parameters)
//   float P_pdf(l, ns, wo, wi)                 density of P_sample's directions (smooth lobes)
//   Spectrum P_eval(l, ns, wo, wi)             f * |cos(wi)| (smooth lobes)
//   vec3  P_sample(l, ns, wo, u)               a direction, or zero (smooth lobes)
//   Spectrum P_sample_delta(l, ns, ng, wo, uPick, wi)
//                                              a delta lobe's direction and f * |cos| / pdf
// `l` is the lobe's Lobe (bsdf.glsl): its colour and parameters at the hit,
// and l.front, whether wo is on the outer side. Conventions as in bsdf.glsl:
// wo and wi point away from the surface, ns and ng face wo, uPick and u.z in
// [0, 1) are free for the lobe's own choices. A smooth lobe of a kind marked
// LOBE_TRANSMISSIVE also sees directions below the surface. A kind with only smooth or only delta lobes
// takes the other half from the macros below; the kinds that have no lobe
// of their own (lights, blends) take both.
#ifndef WP_NO_LOBE_GLSL
#define WP_NO_LOBE_GLSL

// P has no delta lobe.
#define WP_NO_DELTA_LOBE(P)                                                             \
  bool P##_is_delta(Lobe l) {                                                           \
    return false;                                                                       \
  }                                                                                     \
  Spectrum P##_sample_delta(Lobe l, vec3 ns, vec3 ng, vec3 wo, float uPick, OUT(vec3) wi) { \
    wi = vec3(0.0f);                                                                        \
    return Spectrum(0.0f);                                                                  \
  }

// P has no smooth lobe.
#define WP_NO_SMOOTH_LOBE(P)                          \
  float P##_pdf(Lobe l, vec3 ns, vec3 wo, vec3 wi) {  \
    return 0.0f;                                      \
  }                                                   \
  Spectrum P##_eval(Lobe l, vec3 ns, vec3 wo, vec3 wi) { \
    return Spectrum(0.0f);                               \
  }                                                   \
  vec3 P##_sample(Lobe l, vec3 ns, vec3 wo, vec3 u) { \
    return vec3(0.0f);                                \
  }

WP_NO_SMOOTH_LOBE(no_lobe)
WP_NO_DELTA_LOBE(no_lobe)

#endif  // WP_NO_LOBE_GLSL
