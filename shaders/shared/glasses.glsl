// glasses.glsl — named glasses: indices of refraction by Sellmeier's
// equation, n^2 = 1 + sum B_i l^2 / (l^2 - C_i), l in micrometres, so that
// a glass named in a scene disperses as it does (the dielectric kinds'
// "glass"; integrator.glsl's disperse). Columns: id, name, B1..B4, C1..C4
// (um^2). Sources:
//   BK7           Schott N-BK7 data sheet (Schott optical glass catalogue).
//   fused silica  I. H. Malitson, J. Opt. Soc. Am. 55, 1205 (1965), at 20 C.
//   water         M. Daimon and A. Masumura, Appl. Opt. 46, 3811 (2007),
//                 at 20 C (their four-term fit).
//   diamond       F. Peter, Z. Phys. 15, 358 (1923).
#ifndef WP_GLASSES_GLSL
#define WP_GLASSES_GLSL

#define GLASS_BK7 0u
#define GLASS_FUSED_SILICA 1u
#define GLASS_WATER 2u
#define GLASS_DIAMOND 3u
#define WP_GLASSES(X)                                                                                                 \
  X(GLASS_BK7, "BK7", 1.03961212f, 0.231792344f, 1.01046945f, 0.0f, 0.00600069867f, 0.0200179144f, 103.560653f, 0.0f) \
  X(GLASS_FUSED_SILICA, "fused silica", 0.6961663f, 0.4079426f, 0.8974794f, 0.0f, 0.00467914826f, 0.0135120631f,     \
    97.9340025f, 0.0f)                                                                                                \
  X(GLASS_WATER, "water", 5.684027565e-1f, 1.726177391e-1f, 2.086189578e-2f, 1.130748688e-1f, 5.101829712e-3f,       \
    1.821153936e-2f, 2.620722293e-2f, 1.069792721e1f)                                                                 \
  X(GLASS_DIAMOND, "diamond", 0.3306f, 4.3356f, 0.0f, 0.0f, 0.030625f, 0.011236f, 0.0f, 0.0f)
#define GLASS_COUNT 4u

// The wavelengths (nm) of the Fraunhofer C, d and F lines, at which an RGB
// render takes a dispersive glass's red, green and blue indices
// (dispersed_ior's spread is n_F - n_C about n_d).
#define FRAUNHOFER_C_NM 656.27f
#define FRAUNHOFER_D_NM 587.56f
#define FRAUNHOFER_F_NM 486.13f

float sellmeier_ior(vec4 b, vec4 c, float lambdaNm) {
  float l2 = lambdaNm * lambdaNm * 1e-6f;
  float n2 = 1.0f + b.x * l2 / (l2 - c.x) + b.y * l2 / (l2 - c.y) + b.z * l2 / (l2 - c.z) + b.w * l2 / (l2 - c.w);
  return sqrt(max(n2, 1.0f));
}

#define WP_GLASS_CASE(id, name, b1, b2, b3, b4, c1, c2, c3, c4) \
  if (glass == id) return sellmeier_ior(vec4(b1, b2, b3, b4), vec4(c1, c2, c3, c4), lambdaNm);

// The index of refraction of glass `glass` (GLASS_*) at lambdaNm.
float glass_ior(uint glass, float lambdaNm) {
  WP_GLASSES(WP_GLASS_CASE)
  return 1.5f;
}

#endif  // WP_GLASSES_GLSL
