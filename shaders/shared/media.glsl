// media.glsl — participating media (FEATURE_MEDIA): the medium records, the
// media a surface bounds, free-flight sampling, transmittance and the phase
// function. The integrator (integrator.glsl) calls these between a ray's
// trace and its surface: the wavefront kernels, the megakernel and the CPU
// reference share every line.
//
// Conventions (pbrt-v4's and Mitsuba 3's): a path carries the medium its ray
// travels in (PathState.medium; the camera's from SceneParams.media.x). A
// surface whose material holds media (Material.media) bounds them: a ray
// leaving it against its geometric normal enters the inside one, along it
// the outside one; a surface without them leaves a ray in its medium. An
// interface material (MAT_INTERFACE) has no surface at all: rays pass it
// without scattering and without counting a bounce.
//
// Chromatic coefficients: collisions are sampled against one majorant for
// all three channels (Medium.sigmaS.w), and each collision is absorbed,
// scattered or null with probabilities proportional to the coefficients
// weighted by the path's throughput (Kutz et al. 2017, "Spectral and
// Decomposition Tracking for Rendering Heterogeneous Volumes", spectral
// tracking), whose weights keep the throughput bounded. Null collisions
// come from the channels below the majorant and from fictitious particles
// (darts' "real fraction" below 1).
#ifndef WP_MEDIA_GLSL
#define WP_MEDIA_GLSL

// What a free flight met (medium_free_flight).
#define MEDIUM_EVENT_SURFACE 0u  // the end of the segment: its surface, or nothing
#define MEDIUM_EVENT_SCATTER 1u  // a real scattering collision inside the medium
#define MEDIUM_EVENT_ABSORB 2u   // absorbed: the path ends

Medium load_medium(uint i) {
  int at = int(i) * MEDIUM_TEXELS;
  Medium m;
  m.info = texelFetch(mediumTexels, at);
  m.sigmaA = texel_vec4(texelFetch(mediumTexels, at + 1));
  m.sigmaS = texel_vec4(texelFetch(mediumTexels, at + 2));
  m.sigmaN = texel_vec4(texelFetch(mediumTexels, at + 3));
  return m;
}

// The media material `material` bounds: x inside, y outside (WP_INVALID:
// none, the surface is not a boundary).
uvec2 material_media(uint material) {
  uvec4 t = texelFetch(materialTexels, int(material) * MATERIAL_TEXELS + MATERIAL_MEDIA_TEXEL);
  return uvec2(t.x, t.y);
}

// The medium a ray in `current` is in after it leaves a surface of
// `material` and geometric normal ng in direction dir.
uint medium_beyond(uint current, uint material, vec3 ng, vec3 dir) {
  uvec2 m = material_media(material);
  if (m.x == WP_INVALID) return current;
  return dot(dir, ng) < 0.0f ? m.x : m.y;
}

bool is_interface(uint material) {
  return MATERIAL_COMPILED(MAT_INTERFACE) && load_material(material).info.x == MAT_INTERFACE;
}

// Samples the distance to the next real collision along a ray in medium m,
// within [0, tmax) (tmax may be WP_INF), by delta tracking against the
// majorant with spectral tracking's event probabilities. Multiplies
// `throughput` by the collision weights; returns the event and, for a
// scattering collision, its distance t. A flight longer than
// MEDIUM_COLLISIONS_MAX collisions ends absorbed (a bound on the loop, as
// lavapipe's budget requires; it takes over a hundred mean free paths of
// null collisions).
uint medium_free_flight(Medium m, float tmax, INOUT(uint) rng, INOUT(vec3) throughput, OUT(float) t) {
  t = tmax;
  float majorant = m.sigmaS.w;
  if (m.info.x == MEDIUM_VACUUM || !(majorant > 0.0f)) return MEDIUM_EVENT_SURFACE;
  vec3 sa = vec3(m.sigmaA.x, m.sigmaA.y, m.sigmaA.z);
  vec3 ss = vec3(m.sigmaS.x, m.sigmaS.y, m.sigmaS.z);
  vec3 sn = max(vec3(majorant) - sa - ss, vec3(0.0f));
  float at = 0.0f;
  for (uint i = 0u; i < MEDIUM_COLLISIONS_MAX; ++i) {
    at -= log(1.0f - rng_next(rng)) / majorant;
    if (at >= tmax) return MEDIUM_EVENT_SURFACE;
    // A homogeneous medium's coefficients are the same here as anywhere.
    vec3 wa = sa * throughput;
    vec3 ws = ss * throughput;
    vec3 wn = sn * throughput;
    float pa = wa.x + wa.y + wa.z;
    float ps = ws.x + ws.y + ws.z;
    float pn = wn.x + wn.y + wn.z;
    float c = pa + ps + pn;
    if (!(c > 0.0f)) return MEDIUM_EVENT_ABSORB;
    float u = rng_next(rng) * c;
    if (u < pa) return MEDIUM_EVENT_ABSORB;  // the medium emits nothing
    if (u < pa + ps) {
      throughput *= ss * (c / (majorant * ps));
      t = at;
      return MEDIUM_EVENT_SCATTER;
    }
    throughput *= sn * (c / (majorant * pn));
  }
  return MEDIUM_EVENT_ABSORB;
}

// The fraction of light that crosses distance d (may be WP_INF) of medium
// m. Without null particles, Beer-Lambert's law in closed form; with them,
// ratio tracking against the majorant (unbiased; the estimator darts' null
// particles are there to exercise).
vec3 medium_transmittance(Medium m, float d, INOUT(uint) rng) {
  if (m.info.x == MEDIUM_VACUUM) return vec3(1.0f);
  vec3 sigmaT = vec3(m.sigmaA.x + m.sigmaS.x, m.sigmaA.y + m.sigmaS.y, m.sigmaA.z + m.sigmaS.z);
  if (!(d < WP_INF)) {
    return vec3(sigmaT.x > 0.0f ? 0.0f : 1.0f, sigmaT.y > 0.0f ? 0.0f : 1.0f, sigmaT.z > 0.0f ? 0.0f : 1.0f);
  }
  if (!(max(m.sigmaN.x, max(m.sigmaN.y, m.sigmaN.z)) > 0.0f)) return exp(-sigmaT * d);
  float majorant = m.sigmaS.w;
  vec3 ratio = max(vec3(1.0f) - sigmaT / majorant, vec3(0.0f));
  vec3 tr = vec3(1.0f);
  float at = 0.0f;
  for (uint i = 0u; i < MEDIUM_COLLISIONS_MAX; ++i) {
    at -= log(1.0f - rng_next(rng)) / majorant;
    if (at >= d) break;
    tr *= ratio;
  }
  return tr;
}

// The medium's phase function for light travelling along `dir` and
// scattered into wi, per steradian (Henyey-Greenstein; g = 0 isotropic).
float medium_phase(Medium m, vec3 dir, vec3 wi) {
  return henyey_greenstein_pdf(dot(dir, wi), m.sigmaA.w);
}

// A direction scattered from `dir` with the phase function's density.
vec3 medium_sample_phase(Medium m, vec3 dir, vec2 u) {
  vec3 t;
  vec3 bt;
  make_frame(dir, t, bt);
  return frame_to_world(square_to_henyey_greenstein(u, m.sigmaA.w), t, bt, dir);
}

#endif  // WP_MEDIA_GLSL
