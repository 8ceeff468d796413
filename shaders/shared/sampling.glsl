// sampling.glsl — warps from the unit square to the domains a path tracer samples,
// each paired with its pdf, plus the MIS heuristic. tests/test_sampling.cpp
// checks every warp against its pdf with a chi-square test.
#ifndef WP_SAMPLING_GLSL
#define WP_SAMPLING_GLSL

// Shirley-Chiu concentric map to the unit disk (area-preserving, low distortion).
vec2 square_to_disk_concentric(vec2 u) {
  float ox = 2.0f * u.x - 1.0f;
  float oy = 2.0f * u.y - 1.0f;
  if (ox == 0.0f && oy == 0.0f) return vec2(0.0f);
  float r;
  float theta;
  if (abs(ox) > abs(oy)) {
    r = ox;
    theta = (WP_PI / 4.0f) * (oy / ox);
  } else {
    r = oy;
    theta = (WP_PI / 2.0f) - (WP_PI / 4.0f) * (ox / oy);
  }
  return vec2(r * cos(theta), r * sin(theta));
}

float square_to_disk_concentric_pdf(vec2 p) {
  return dot(p, p) <= 1.0f ? WP_INV_PI : 0.0f;
}

// Cosine-weighted hemisphere around +Z (Malley's method).
vec3 square_to_cosine_hemisphere(vec2 u) {
  vec2 d = square_to_disk_concentric(u);
  float z = sqrt(max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return vec3(d.x, d.y, z);
}

float square_to_cosine_hemisphere_pdf(vec3 v) {
  return v.z > 0.0f ? v.z * WP_INV_PI : 0.0f;
}

// Uniform over the hemisphere around +Z (CS184's "hemisphere sampling").
vec3 square_to_uniform_hemisphere(vec2 u) {
  float z = u.x;
  float r = sqrt(max(0.0f, 1.0f - z * z));
  float phi = 2.0f * WP_PI * u.y;
  return vec3(r * cos(phi), r * sin(phi), z);
}

float square_to_uniform_hemisphere_pdf(vec3 v) {
  return v.z > 0.0f ? 0.5f * WP_INV_PI : 0.0f;
}

vec3 square_to_uniform_sphere(vec2 u) {
  float z = 1.0f - 2.0f * u.x;
  float r = sqrt(max(0.0f, 1.0f - z * z));
  float phi = 2.0f * WP_PI * u.y;
  return vec3(r * cos(phi), r * sin(phi), z);
}

float square_to_uniform_sphere_pdf(vec3 v) {
  return 1.0f / (4.0f * WP_PI);
}

// Uniform barycentrics (b1, b2) on a triangle: the point is (1-b1-b2)v0 + b1 v1 + b2 v2.
// Uses the square-root parameterisation (Osada et al.); pdf is 1 / area.
vec2 square_to_triangle_barycentric(vec2 u) {
  float su = sqrt(u.x);
  return vec2(1.0f - su, u.y * su);
}

// Directions of normalize(c + radius * s) for a unit vector c, a radius in
// (0, 1] and s uniform on the unit sphere (darts' rough metal; at radius 1,
// the cosine lobe around c): the density, per unit solid angle, of direction
// d. The ray t * d meets that sphere of points where t = cos + or - h; each
// meeting at t > 0 adds t^2 / (4 pi radius^2 |cos gamma|), gamma the angle
// between the ray and the sphere's normal there, and |cos gamma| = h / radius.
// The density grows without bound (integrably) towards the cone's rim.
float fuzzed_direction_pdf(vec3 d, vec3 c, float radius) {
  float cosA = dot(d, c);
  float h2 = cosA * cosA - 1.0f + radius * radius;
  if (h2 <= 0.0f) return 0.0f;
  float h = sqrt(h2);
  float t1 = cosA + h;
  if (t1 <= 0.0f) return 0.0f;
  float t0 = cosA - h;
  float squares = t1 * t1 + (t0 > 0.0f ? t0 * t0 : 0.0f);
  return squares / (4.0f * WP_PI * radius * h);
}

// cos^n lobe around +Z: pdf (n + 1) / (2 pi) cos^n theta over the hemisphere.
vec3 square_to_cosine_power(vec2 u, float exponent) {
  float cosTheta = pow(max(1.0f - u.x, 0.0f), 1.0f / (exponent + 1.0f));
  float sinTheta = sqrt(max(0.0f, 1.0f - cosTheta * cosTheta));
  float phi = 2.0f * WP_PI * u.y;
  return vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta);
}

float cosine_power_pdf(float cosTheta, float exponent) {
  return cosTheta > 0.0f ? (exponent + 1.0f) * (0.5f * WP_INV_PI) * pow(cosTheta, exponent) : 0.0f;
}

// Uniform in the cone of directions within theta_max of +Z, given 1 - cos(theta_max)
// (passed as such so tiny cones keep their precision).
vec3 square_to_uniform_cone(vec2 u, float oneMinusCosMax) {
  float oneMinusCos = u.x * oneMinusCosMax;
  float cosTheta = 1.0f - oneMinusCos;
  float sinTheta = sqrt(max(0.0f, oneMinusCos * (2.0f - oneMinusCos)));
  float phi = 2.0f * WP_PI * u.y;
  return vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta);
}

float uniform_cone_pdf(float oneMinusCosMax) {
  return 1.0f / (2.0f * WP_PI * oneMinusCosMax);
}

// Henyey-Greenstein's phase function, the scattering of participating media
// (darts' final project, include/darts/medium.h; pbrt-v4's HGPhaseFunction):
// the density per steradian of scattering into a direction at cos theta =
// cosTheta from the direction travelled, for asymmetry g in (-1, 1) (g > 0
// scatters forward): (1 - g^2) / (4 pi (1 + g^2 - 2 g cos theta)^(3/2)).
float henyey_greenstein_pdf(float cosTheta, float g) {
  // 1 + g^2 - 2 g cos theta as (1 - |g|)^2 + 2 |g| (1 -+ cos theta): no
  // cancellation at the peak, on either side.
  float a = abs(g);
  float d = (1.0f - a) * (1.0f - a) + 2.0f * a * (g < 0.0f ? 1.0f + cosTheta : 1.0f - cosTheta);
  return (1.0f - g * g) / (4.0f * WP_PI * d * sqrt(d));
}

// A direction about +Z (the direction travelled) with that density: the cdf
// inverted in closed form for |g|, as the distance 1 -+ cos theta from the
// peak so that a peaked lobe keeps its precision, mirrored for g < 0;
// uniform where |g| is too small for the inversion.
vec3 square_to_henyey_greenstein(vec2 u, float g) {
  float a = abs(g);
  float fromPeak;
  if (a < 1e-3f) {
    fromPeak = 2.0f * u.x;
  } else {
    float q = 1.0f - a + 2.0f * a * u.x;
    fromPeak = clamp((1.0f - a) * (1.0f - u.x) * ((1.0f - a * a) / q + 1.0f - a) / q, 0.0f, 2.0f);
  }
  float sinTheta = sqrt(max(0.0f, fromPeak * (2.0f - fromPeak)));
  float phi = 2.0f * WP_PI * u.y;
  return vec3(sinTheta * cos(phi), sinTheta * sin(phi), g < 0.0f ? fromPeak - 1.0f : 1.0f - fromPeak);
}

// Balance heuristic, for the one-sample mixture of BSDF and emitter sampling.
float mixture_pdf(float pdfA, float pdfB, float probA) {
  return probA * pdfA + (1.0f - probA) * pdfB;
}

// Luminance (Rec. 709): weighs emitters and environment texels for sampling,
// and is the "illuminance" of CS184's adaptive sampling.
float illuminance(vec3 l) {
  return LUMINANCE_R * l.x + LUMINANCE_G * l.y + LUMINANCE_B * l.z;
}

// A path's colour's brightness for its sampling decisions: the illuminance
// in RGB, the mean over the wavelengths in the spectral mode.
float spectrum_illuminance(Spectrum c) {
  return SPECTRUM_CHANNELS == 4u ? spectrum_average(c) : illuminance(spectrum_xyz(c));
}

// Veach's power heuristic: the weight of strategy A, pdfA^beta / (pdfA^beta
// + pdfB^beta); beta = 2 is Veach's choice and darts' default, beta = 1 the
// balance heuristic. The weights of A and B sum to one for every beta, which
// is what keeps the combination unbiased. Other exponents are written as
// 1 / (1 + (b / a)^beta), which no pdf can overflow.
float power_heuristic(float pdfA, float pdfB, float beta) {
  if (beta == 2.0f) {
    float a = pdfA * pdfA;
    float b = pdfB * pdfB;
    return a + b > 0.0f ? a / (a + b) : 0.0f;
  }
  if (pdfA <= 0.0f) return 0.0f;
  float r = pdfB / pdfA;
  return 1.0f / (1.0f + (beta == 1.0f ? r : pow(r, beta)));
}

// Orthonormal basis around unit n (Duff et al., JCGT 2017), no branch on n.z.
void make_frame(vec3 n, OUT(vec3) t, OUT(vec3) b) {
  float s = n.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (s + n.z);
  float c = n.x * n.y * a;
  t = vec3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
  b = vec3(c, s + n.y * n.y * a, -n.y);
}

vec3 frame_to_world(vec3 v, vec3 t, vec3 b, vec3 n) {
  return t * v.x + b * v.y + n * v.z;
}

#endif  // WP_SAMPLING_GLSL
