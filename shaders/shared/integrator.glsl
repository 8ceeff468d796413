// integrator.glsl — the path tracer, one bounce at a time. The wavefront kernels
// call these functions stage by stage (generate, extend, shade, connect,
// accumulate); the megakernel and the CPU reference run them in one loop per
// sample, trace_sample (below). Unidirectional path tracing with next-event
// estimation and multiple importance sampling (power heuristic) between BSDF
// and emitter sampling, and Russian roulette; the darts variants without MIS
// (mats, nee), the one-sample mixture, and the normals / ambient-occlusion
// previews. "max bounces" counts scattering events (pbrt's maxdepth): 0 shows
// emitters only, 1 adds direct lighting.
#ifndef WP_INTEGRATOR_GLSL
#define WP_INTEGRATOR_GLSL

uint path_depth(PathState p) {
  return p.flags & PATH_DEPTH_MASK;
}

// a / b (x) and a % b (y) without integer division, for a and b below 2^30
// (b > 0) and a quotient below 2^21: lavapipe divides a vector of integers
// one lane at a time, a scalar division per lane. float(a) and a division
// of up to 2.5 ulps (as Vulkan allows) err by at most 6 parts in 2^24 of the
// quotient, so the float quotient is less than one off the true one, and one
// step either way makes it exact (DivMod and Camera tests).
uvec2 div_mod(uint a, uint b) {
  uint q = uint(float(a) / float(b));
  int r = int(a) - int(q * b);
  if (r < 0) {
    q -= 1u;
    r += int(b);
  } else if (r >= int(b)) {
    q += 1u;
    r -= int(b);
  }
  return uvec2(q, uint(r));
}

// Pixel index `pixel` as its column and row. Images are at most 16384 x 16384
// (the scene loader's and the command line's limit): quotients below 2^14.
uvec2 pixel_xy(uint pixel) {
  uvec2 qr = div_mod(pixel, scene.image.x);
  return uvec2(qr.y, qr.x);
}

// Camera ray for `pixel`, with pixel jitter and (aperture > 0) thin-lens sampling.
void path_begin(INOUT(PathState) p, uint pixel, uint sampleIndex) {
  uint width = scene.image.x;
  uint height = scene.image.y;
  p.rng = rng_seed(pixel, sampleIndex, scene.counts.y);
  vec2 jitter = rng_next2(p.rng);
  vec2 lensU = rng_next2(p.rng);
  // FEATURE_COMPILED: compiled out of the kernels for other samplers, since its
  // integer divisions cost every camera ray even where not taken.
  if (FEATURE_COMPILED(FEATURE_CMJ) && scene.mode.y == SAMPLER_CMJ && sampleIndex < scene.mode.z) {
    // The camera's dimensions (pixel area, lens) from per-pixel CMJ patterns;
    // later bounces stay independent.
    uint pattern = pcg_hash(pixel ^ pcg_hash(scene.counts.y));
    jitter = cmj_sample(sampleIndex, scene.mode.z, pattern);
    lensU = cmj_sample(sampleIndex, scene.mode.z, pcg_hash(pattern));
  }
  uvec2 xy = pixel_xy(pixel);
  float fx = scene.camWindow.x + (float(xy.x) + jitter.x) / float(width) * scene.camWindow.z;
  float fy = scene.camWindow.y + (float(xy.y) + jitter.y) / float(height) * scene.camWindow.w;
  // The point of the frame, in units of its half-height.
  vec2 frame = vec2((2.0f * fx - 1.0f) * scene.camLens.y, 1.0f - 2.0f * fy);
  vec3 dirCam = vec3(0.0f, 0.0f, -1.0f);
  vec3 originCam = vec3(0.0f);
  if (scene.camLens.x < 0.0f) {
    // Orthographic (camLens.x: minus the half-height seen): parallel rays
    // from the frame's point; a lens means nothing to it.
    originCam = vec3(frame.x * -scene.camLens.x, frame.y * -scene.camLens.x, 0.0f);
  } else {
    dirCam = vec3(frame.x * scene.camLens.x, frame.y * scene.camLens.x, -1.0f);
    if (scene.camLens.z > 0.0f) {
      vec2 lens = square_to_disk_concentric(lensU) * scene.camLens.z;
      originCam = vec3(lens.x, lens.y, 0.0f);
      dirCam = dirCam * scene.camLens.w - originCam;  // through the point in focus
    }
  }
  p.origin = xform_point(scene.camToWorld0, scene.camToWorld1, scene.camToWorld2, originCam);
  p.dir = normalize(xform_vector(scene.camToWorld0, scene.camToWorld1, scene.camToWorld2, dirCam));
  p.pixel = pixel;
  p.throughput = Spectrum(1.0f);
  p.radiance = Spectrum(0.0f);
  p.flags = PATH_SPECULAR;  // depth 0; camera rays count emitters with full weight
  p.bsdfPdf = 0.0f;
  p.medium = FEATURE_COMPILED(FEATURE_MEDIA) ? scene.media.x : 0u;
  p.travelled = 0.0f;
  p.crossings = 0u;
  // The spectral mode's wavelengths: a pixel's samples take them from its
  // own randomly shifted sequence (wavelength_sequence), so that each
  // sample's are uniform and unbiased while a pixel's spread over the range
  // far more evenly than independent draws: most of the colour noise a few
  // samples show is the luck of their wavelengths.
  uint shift = pcg_hash(pixel ^ pcg_hash(scene.counts.y ^ 0x5bd1e995u));
  float u = wavelength_sequence(shift, sampleIndex);
  p.wavelengths = spectral_mode() ? WP_WAVELENGTH_SAMPLE(u) : 0.0f;
}

// A shadow ray that adds `contribution` to the path's pixel when the segment
// from origin to origin + tmax * dir is unoccluded.
void shadow_ray_none(OUT(ShadowRay) sr) {
  sr.tmax = -1.0f;
  sr.origin = vec3(0.0f);
  sr.dir = vec3(0.0f);
  sr.contribution = Spectrum(0.0f);
  sr.path = WP_INVALID;
  sr.media = 0u;
}

// A shadow ray's media word: the medium its segment starts in, and a seed
// for the tracking of its transmittance drawn from the path's state (the
// wavefront kernels trace the ray apart from its path).
uint shadow_ray_media(uint medium, uint rng, uint slot) {
  return (pcg_hash(rng ^ (slot * 0x9e3779b9u)) & 0xffff0000u) | medium;
}

// The segment a shadow ray checks for light sample ls, seen from surface
// point p of geometric normal ng, leaving from the side ls.wi points to: it
// ends just in front of the light point, or is unbounded towards the
// environment. (The ray-casting benchmark aims its shadow rays with it too.)
//
// "Just in front" is off the emitter's surface along its normal, or, for a
// point light or a light no ray meets, pulled back towards p: such a light
// may sit exactly on other geometry (CS184's Cornell files put the point or
// area light in the plane of the lamp mesh), and a segment ending on a
// surface is blocked or not by rounding, differently on every device.
void aim_shadow_ray(vec3 p, vec3 ng, LightSample ls, OUT(vec3) origin, OUT(vec3) dir, OUT(float) tmax) {
  origin = offset_ray(p, dot(ls.wi, ng) >= 0.0f ? ng : -ng);  // a transmissive lobe sees lights behind the surface
  if (ls.dist == WP_INF) {
    dir = ls.wi;
    tmax = WP_INF;
  } else {
    vec3 target = offset_ray(ls.p, ls.isDelta != 0u ? -ls.wi : ls.n);
    dir = target - origin;
    tmax = 1.0f;
  }
}

// The shadow rays one path vertex may cast: one per light sample. On the GPU
// the array has exactly the scene's light samples (a specialization
// constant); in C++, MAX_LIGHT_SAMPLES.
struct ShadowRays {
  ShadowRay ray[LIGHT_SAMPLE_SLOTS];
};

// The normals and ambient-occlusion integrators: one hit, no paths.
void shade_preview(INOUT(PathState) p, SurfaceHit s, Bsdf b, OUT(ShadowRay) sr) {
  if (INTEGRATOR_OF_SCENE == INTEGRATOR_NORMALS) {
    p.radiance += spectrum_rgb(((b.front ? b.ns : -b.ns) + vec3(1.0f)) * 0.5f);  // the shading normal, a normal map's included
    return;
  }
  // Ambient occlusion: the cosine-weighted fraction of the hemisphere that is
  // unoccluded, estimated with one visibility ray of unbounded length.
  vec3 t;
  vec3 bt;
  make_frame(b.ns, t, bt);
  vec2 u = rng_next2(p.rng);
  vec3 wi = frame_to_world(square_to_cosine_hemisphere(u), t, bt, b.ns);
  if (dot(wi, b.ng) <= 0.0f) return;
  sr.origin = offset_ray(s.p, b.ng);
  sr.dir = wi;
  sr.tmax = WP_INF;
  sr.contribution = Spectrum(1.0f);
}

// A dispersive volume's boundary (FEATURE_DISPERSION) refracts each colour
// by its own index. The first one a path meets picks one channel uniformly
// (in the spectral mode, always its hero wavelength, as pbrt-v4 does: a
// pixel's samples spread their heroes evenly, path_begin), which the path
// carries alone from then on, three (four) times as strong (the other channels'
// light is estimated by the paths that picked them); its lobes, and every
// dispersive lobe after, take that channel's index: in RGB the red, green
// or blue of dispersed_ior (a named glass's at the C, d and F lines), in the
// spectral mode the index at the hero's wavelength.
void disperse(INOUT(PathState) p, INOUT(Bsdf) b, vec4 lambdas) {
  if (!bsdf_disperses(b)) return;
  uint channel = (p.flags & PATH_CHANNEL_MASK) >> PATH_CHANNEL_SHIFT;
  if (channel == 0u) {
    channel = 1u + min(uint(rng_next(p.rng) * 3.0f), 2u);
    if (spectral_mode()) channel = 1u;
    p.flags |= channel << PATH_CHANNEL_SHIFT;
    p.throughput = spectrum_keep_channel(p.throughput, channel);
  }
  disperse_lobes(b, channel, lambdas);
}

// Russian roulette once the path is long enough (depth: the scattering
// events before this one); unbiased by reweighting. Returns false where the
// path ends.
bool survives_roulette(INOUT(PathState) p, uint depth) {
  if (depth + 1u < scene.image.w) return true;
  float maxT = spectrum_max(p.throughput);
  float q = clamp(1.0f - maxT, 0.0f, 0.95f);
  if (rng_next(p.rng) < q) return false;
  p.throughput /= (1.0f - q);
  return true;
}

// A real scattering collision at x inside medium `med` (FEATURE_MEDIA):
// next-event estimation weighted by the phase function, then a direction
// from the phase function; MIS as at a surface.
bool path_scatter_in_medium(INOUT(PathState) p, Medium med, vec3 x, vec4 lambdas, bool useNee, bool useMis, OUT(ShadowRays) srs) {
  uint depth = path_depth(p);
  if (depth >= scene.image.z) return false;
  uint lightSamples = LIGHT_SAMPLES_OF_SCENE;
  LightSample ls;
  for (uint j = 0u; j < LIGHT_SAMPLE_SLOTS; ++j) {
    if (j >= lightSamples) break;
    vec3 uLight = rng_next3(p.rng);
    if (!(useNee && sample_emitter(x, uLight, ls))) continue;
    Spectrum le = path_radiance(ls.radiance, lambdas);
    float f = medium_phase(med, p.dir, ls.wi);
    if (ls.pdf <= 0.0f || f <= 0.0f) continue;
    float nPdf = float(lightSamples) * ls.pdf;
    float w = useMis && ls.isDelta == 0u ? power_heuristic(nPdf, f, scene.mis.x) : 1.0f;
    srs.ray[j].contribution = p.throughput * le * (f * w / nPdf);
    aim_shadow_ray(x, ls.wi, ls, srs.ray[j].origin, srs.ray[j].dir, srs.ray[j].tmax);
    srs.ray[j].media = shadow_ray_media(p.medium, p.rng, j);
  }
  vec2 u = rng_next2(p.rng);
  vec3 wi = medium_sample_phase(med, p.dir, u);
  p.bsdfPdf = medium_phase(med, p.dir, wi);  // the phase function's weight f / pdf is 1
  p.origin = x;
  p.dir = wi;
  p.flags = (depth + 1u) | (p.flags & PATH_CHANNEL_MASK);
  p.travelled = 0.0f;
  return survives_roulette(p, depth);
}

// A ray that met an interface (MAT_INTERFACE) passes it into the medium on
// its far side, unchanged and without a bounce; the way from the last
// scattering vertex grows (emitters met later weigh their MIS from there).
bool path_cross_interface(INOUT(PathState) p, SurfaceHit s, float t) {
  p.crossings += 1u;
  if (p.crossings > MEDIUM_CROSSINGS_MAX) return false;
  p.travelled += t;
  p.medium = medium_beyond(p.medium, s.material, s.ng, p.dir);
  p.origin = offset_ray(s.p, dot(p.dir, s.ng) >= 0.0f ? s.ng : -s.ng);
  return true;
}

// Accounts for what the path's ray hit and prepares the next bounce. Writes
// LIGHT_SAMPLES_OF_SCENE shadow rays, valid (tmax > 0) where next-event
// estimation found a candidate. Returns true while the path continues.
bool path_shade(INOUT(PathState) p, Hit h, OUT(ShadowRays) srs) {
  uint lightSamples = LIGHT_SAMPLES_OF_SCENE;
  // The slots beyond the scene's light samples (C++ has MAX_LIGHT_SAMPLES) stay untouched.
  for (uint j = 0u; j < LIGHT_SAMPLE_SLOTS; ++j) {
    if (j >= lightSamples) break;
    shadow_ray_none(srs.ray[j]);
  }
  uint mode = INTEGRATOR_OF_SCENE;  // equals scene.mode.x
  bool preview = mode == INTEGRATOR_NORMALS || mode == INTEGRATOR_AO;
  bool mixture = mode == INTEGRATOR_MIXTURE;
  bool useNee = !mixture && (scene.counts.w & SCENE_FLAG_NO_NEE) == 0u && scene.counts.x > 0u;
  bool useMis = useNee && (scene.counts.w & SCENE_FLAG_NO_BSDF_MIS) == 0u;
  bool cs184 = (scene.counts.w & SCENE_FLAG_CS184) != 0u;
  // The spectral mode: the path's wavelengths, at which it sees every colour.
  vec4 lambdas = spectral_mode() ? path_wavelengths(p.wavelengths) : vec4(0.0f);
  // The medium between the ray's origin and its hit: the path may scatter
  // (or be absorbed) in it first.
  if (FEATURE_COMPILED(FEATURE_MEDIA) && !preview && p.medium != 0u) {
    MediumCoefficients coefficients;
    Medium med = load_medium_at(p.medium, lambdas, coefficients);
    float t;
    uint event = medium_free_flight(med, coefficients, p.origin, p.dir, h.prim == WP_INVALID ? WP_INF : h.t, p.rng, p.throughput, t);
    if (event == MEDIUM_EVENT_ABSORB) return false;
    if (event == MEDIUM_EVENT_SCATTER) return path_scatter_in_medium(p, med, p.origin + t * p.dir, lambdas, useNee, useMis, srs);
  }
  if (h.prim == WP_INVALID) {
    if (preview || (cs184 && path_depth(p) > 0u)) return false;
    float w = 1.0f;
    if (LIGHT_COMPILED(LIGHT_ENVIRONMENT) && scene.environment.y != WP_INVALID && (p.flags & PATH_SPECULAR) == 0u && useNee) {
      // NEE at the previous vertex could have picked this direction of the environment map.
      float lightPdf = load_emitter(scene.environment.y).pmf * environment_pdf(p.dir);
      w = useMis ? power_heuristic(p.bsdfPdf, float(lightSamples) * lightPdf, scene.mis.x) : 0.0f;
    }
    p.radiance += p.throughput * path_radiance(background_radiance(p.dir), lambdas) * w;
    return false;
  }
  SurfaceHit s = surface_at(p.origin, p.dir, h);
  if (FEATURE_COMPILED(FEATURE_MEDIA) && !preview && is_interface(s.material)) return path_cross_interface(p, s, h.t);
  vec3 wo = -p.dir;
  Bsdf b = bsdf_at(s, wo);
  // The photon mapper gathers through the BSDF in RGB: its photons carry
  // their power in RGB (photon_bounce).
  Bsdf gatherBsdf = b;
  // The spectral mode: the BSDF's colours at the path's wavelengths.
  if (spectral_mode()) bsdf_at_wavelengths(b, p.wavelengths, lambdas);
  // A segment that ends on the inside of a volume's boundary crossed the
  // volume, which absorbed some of the light along it.
  if (FEATURE_COMPILED(FEATURE_VOLUME) && !b.front) p.throughput *= volume_transmittance(s.material, h.t, lambdas);
  if (FEATURE_COMPILED(FEATURE_DISPERSION)) disperse(p, b, lambdas);
  if (preview) {
    shade_preview(p, s, b, srs.ray[0]);
    return false;
  }
  uint depth = path_depth(p);

  // Emission, seen from the front side only.
  vec3 emitted = emitted_radiance(s, wo);
  if (emitted.x > 0.0f || emitted.y > 0.0f || emitted.z > 0.0f) {
    Spectrum le = path_radiance(emitted, lambdas);
    float w = 1.0f;
    if ((p.flags & PATH_SPECULAR) == 0u && s.emitter == WP_INVALID) {
      // Outside the light table (CS184's emissive meshes): only BSDF sampling
      // finds it, but CS184's estimator, sampling lights, ignores it here.
      w = cs184 && (scene.counts.w & SCENE_FLAG_NO_NEE) == 0u ? 0.0f : 1.0f;
    } else if ((p.flags & PATH_SPECULAR) == 0u && useNee) {
      // NEE at the previous vertex could have picked this point too.
      // (From the last scattering vertex, behind the interfaces passed since.)
      float lightPdf = FEATURE_COMPILED(FEATURE_MEDIA) ? emitter_pdf(s.emitter, p.origin - p.dir * p.travelled, s, p.dir, h.t + p.travelled)
                                                       : emitter_pdf(s.emitter, p.origin, s, p.dir, h.t);
      w = useMis ? power_heuristic(p.bsdfPdf, float(lightSamples) * lightPdf, scene.mis.x) : 0.0f;
    }
    p.radiance += p.throughput * le * w;
  }
  if (depth >= scene.image.z || b.lobeCount == 0u) return false;
  bool hasSmooth = bsdf_has_smooth_lobe(b);

  // Next-event estimation: n points, each on one emitter, checked later by
  // shadow rays; MIS counts the n light samples against the one BSDF sample
  // (Veach's multi-sample power heuristic).
  LightSample ls;
  for (uint j = 0u; j < LIGHT_SAMPLE_SLOTS; ++j) {
    if (j >= lightSamples) break;
    vec3 uLight = rng_next3(p.rng);
    if (!(useNee && hasSmooth && sample_emitter(s.p, uLight, ls))) continue;
    Spectrum le = path_radiance(ls.radiance, lambdas);
    Spectrum f = bsdf_eval(b, wo, ls.wi);
    if (ls.pdf <= 0.0f || !spectrum_positive(f)) continue;
    float nPdf = float(lightSamples) * ls.pdf;
    float w = useMis && ls.isDelta == 0u ? power_heuristic(nPdf, bsdf_pdf(b, wo, ls.wi), scene.mis.x) : 1.0f;
    srs.ray[j].contribution = p.throughput * f * le * (w / nPdf);
    aim_shadow_ray(s.p, b.ng, ls, srs.ray[j].origin, srs.ray[j].dir, srs.ray[j].tmax);
    if (FEATURE_COMPILED(FEATURE_MEDIA)) srs.ray[j].media = shadow_ray_media(medium_beyond(p.medium, s.material, s.ng, ls.wi), p.rng, j);
  }

  // Photon mapping: the photons give all but the direct light here, and
  // only a specular bounce goes on (below).
  bool photons = mode == INTEGRATOR_PHOTONS;
  if (photons && hasSmooth) p.radiance += p.throughput * path_radiance(photon_radiance(s.p, spectral_mode() ? gatherBsdf : b, wo), lambdas);

  // The next direction: from the BSDF, or (mixture) from the one-sample
  // mixture of BSDF and emitter sampling with its exact combined density.
  vec4 uBsdf = rng_next4(p.rng);
  float uStrategy = rng_next(p.rng);
  vec3 wi;
  float pdf = 0.0f;
  bool isDelta;
  Spectrum weight = Spectrum(0.0f);
  float lightProb = mixture && hasSmooth && scene.counts.x > 0u ? 0.5f : 0.0f;
  if (uStrategy < lightProb) {
    if (!sample_emitter(s.p, vec3(uBsdf.x, uBsdf.y, uBsdf.z), ls) || ls.isDelta != 0u) return false;
    wi = ls.wi;
    isDelta = false;
  } else if (FEATURE_COMPILED(FEATURE_UNIFORM_HEMISPHERE) && (scene.counts.w & SCENE_FLAG_HEMISPHERE) != 0u && hasSmooth &&
             !bsdf_has_delta_lobe(b)) {
    // CS184's -H: uniform over the hemisphere around the shading normal.
    vec3 t;
    vec3 bt;
    make_frame(b.ns, t, bt);
    vec3 local = square_to_uniform_hemisphere(vec2(uBsdf.x, uBsdf.y));
    wi = frame_to_world(local, t, bt, b.ns);
    pdf = square_to_uniform_hemisphere_pdf(local);
    isDelta = false;
    weight = bsdf_eval(b, wo, wi) / pdf;
  } else {
    weight = bsdf_sample(b, wo, uBsdf, wi, pdf, isDelta);
    if (isDelta) weight /= 1.0f - lightProb;
  }
  if (mixture && !isDelta) {
    pdf = mixture_pdf(emitters_pdf_direction(s.p, wi, false), bsdf_pdf(b, wo, wi), lightProb);
    weight = pdf > 0.0f ? bsdf_eval(b, wo, wi) / pdf : Spectrum(0.0f);
  }
  if ((!isDelta && pdf <= 0.0f) || !spectrum_positive(weight)) return false;
  // (A smooth lobe picked with some probability, a delta one with the rest:
  // following only the delta picks, weighted by their probability, keeps
  // the specular paths unbiased.)
  if (photons && !isDelta) return false;
  p.throughput *= weight;
  p.bsdfPdf = pdf;
  p.origin = offset_ray(s.p, dot(wi, s.ng) >= 0.0f ? s.ng : -s.ng);
  p.dir = wi;
  // (A dispersed path keeps its colour channel.)
  p.flags = (depth + 1u) | (isDelta ? PATH_SPECULAR : 0u) | (p.flags & PATH_CHANNEL_MASK);
  if (FEATURE_COMPILED(FEATURE_MEDIA)) {
    p.medium = medium_beyond(p.medium, s.material, s.ng, wi);
    p.travelled = 0.0f;
  }

  if (cs184) {
    // CS184's Russian roulette: continue with probability min(1, 10 times the
    // luminance of the sampled BSDF value f), except at the first bounce of
    // paths allowed several. weight is f |cos| / pdf (f |cos| for a delta lobe).
    if (depth == 0u && scene.image.z > 1u) return true;
    float cosI = abs(dot(wi, b.ns));
    float q = cosI > 0.0f ? min(1.0f, 10.0f * spectrum_illuminance(weight) * (isDelta ? 1.0f : pdf) / cosI) : 1.0f;
    if (rng_next(p.rng) >= q) return false;
    p.throughput /= q;
    return true;
  }
  return survives_roulette(p, depth);
}

bool radiance_is_finite(vec3 l) {
  return !(isnan(l.x) || isnan(l.y) || isnan(l.z) || isinf(l.x) || isinf(l.y) || isinf(l.z));
}

// What one sample of radiance l adds to its pixel's sums (PixelAccum, which
// the GPU accumulates per batch and the host folds into ImageStats; the CPU
// reference adds it to ImageStats directly): l and a count of one, and the
// squares of l and of its illuminance (for adaptive sampling). The one
// definition of what a pixel accumulates.
PixelAccum sample_moments(vec3 l) {
  float y = illuminance(l);
  PixelAccum a;
  a.sum = vec4(l.x, l.y, l.z, 1.0f);
  a.sumSq = vec4(l.x * l.x, l.y * l.y, l.z * l.z, y * y);
  return a;
}

// What one sample's AOV record adds to its pixel's AOV sums: itself and its
// squares.
AovAccum aov_moments(AovSample s) {
  AovAccum a;
  a.sumA = s.a;
  a.sumB = s.b;
  a.sumSqA = s.a * s.a;
  a.sumSqB = s.b * s.b;
  return a;
}

// What the camera ray of a path hit first, as the AOV layers record it
// (layers.glsl): the albedo (the sum of the BSDF's lobe colours; an
// emitter's radiance or the background's where nothing scatters; clamped to
// [0, 1]), the shading normal facing the camera, and the distance with a
// coverage of 1 (0 and 0 on a miss). Called with the path as it left the
// camera and the hit of that ray; draws no random numbers, so AOVs change
// nothing else of a render.
AovSample aov_sample(PathState p, Hit h) {
  AovSample a;
  a.a = vec4(0.0f);
  a.b = vec4(0.0f);
  if (h.prim == WP_INVALID) {
    vec3 bg = clamp(background_radiance(p.dir), vec3(0.0f), vec3(1.0f));
    a.a = vec4(bg.x, bg.y, bg.z, 0.0f);
    return a;
  }
  SurfaceHit s = surface_at(p.origin, p.dir, h);
  vec3 wo = -p.dir;
  Bsdf b = bsdf_at(s, wo);
  vec3 albedo = vec3(0.0f);
  for (uint i = 0u; i < BSDF_MAX_LOBES; ++i) {
    if (i < b.lobeCount) albedo += spectrum_xyz(b.lobeColor[i]) * b.lobeWeight[i];
  }
  if (b.lobeCount == 0u) albedo = emitted_radiance(s, wo);
  albedo = clamp(albedo, vec3(0.0f), vec3(1.0f));
  a.a = vec4(albedo.x, albedo.y, albedo.z, b.ns.x);
  a.b = vec4(b.ns.y, b.ns.z, h.t, 1.0f);
  return a;
}

// The fraction of a shadow ray's contribution that reaches its path
// (FEATURE_MEDIA): the segment traced for its closest hits, passing the
// interfaces on it into the media beyond them (each segment's transmittance
// estimated by medium_transmittance), and blocked (0) by any other surface;
// without interfaces in the scene, one walk that any hit ends. `truncated`
// counts the walks that reached the step cap (the ray then counts as
// blocked). `wavelengths`: its path's sample of them (the spectral mode).
Spectrum shadow_ray_transmittance(ShadowRay sr, float wavelengths, INOUT(uint) truncated) {
  uint medium = sr.media & 0xffffu;
  uint rng = pcg_hash(sr.media ^ floatBitsToUint(sr.origin.x + sr.origin.y + sr.origin.z));
  vec3 o = sr.origin;
  vec3 dir = sr.dir;
  float tmax = sr.tmax;
  // A finite segment keeps its end (aim_shadow_ray's point just off the
  // light) as it passes interfaces: the offsets off each interface, added
  // to a shortened length, pushed the end into the light, which blocked it.
  bool finite = tmax < WP_INF;
  vec3 end = finite ? o + dir * tmax : vec3(0.0f);
  Spectrum tr = Spectrum(1.0f);
  vec4 lambdas = spectral_mode() ? path_wavelengths(wavelengths) : vec4(0.0f);
  const bool interfaces = MATERIAL_COMPILED(MAT_INTERFACE);
  for (uint k = 0u; k <= MEDIUM_CROSSINGS_MAX; ++k) {
    Hit h;
    if (trace_ray(o, dir, tmax, !interfaces, h) != TRACE_OK) {
      truncated += 1u;
      return Spectrum(0.0f);
    }
    if (!interfaces && h.prim != WP_INVALID) return Spectrum(0.0f);
    float t = h.prim == WP_INVALID ? tmax : h.t;
    if (medium != 0u) {
      MediumCoefficients coefficients;
      Medium m = load_medium_at(medium, lambdas, coefficients);
      tr *= medium_transmittance(m, coefficients, o, dir, t, rng);
    }
    if (h.prim == WP_INVALID) return tr;
    SurfaceHit s = surface_at(o, dir, h);
    if (!is_interface(s.material) || !spectrum_positive(tr)) return Spectrum(0.0f);
    medium = medium_beyond(medium, s.material, s.ng, dir);
    o = offset_ray(s.p, dot(dir, s.ng) >= 0.0f ? s.ng : -s.ng);
    if (finite) {
      dir = end - o;
      tmax = 1.0f;
    }
  }
  return Spectrum(0.0f);
}

// Closest-hit passes a path takes at most: one per bounce and the camera
// ray's, and with interfaces one per interface it may pass.
uint path_passes_max() {
  return scene.image.z + 1u + (FEATURE_COMPILED(FEATURE_MEDIA) && MATERIAL_COMPILED(MAT_INTERFACE) ? MEDIUM_CROSSINGS_MAX : 0u);
}

// Rays traced and traversals truncated by trace_sample.
struct SampleRays {
  uint closest;    // closest-hit rays (the camera ray and each bounce's)
  uint shadow;     // next-event estimation's shadow rays
  uint truncated;  // traversals that reached the step cap (the image would be wrong)
};

// A sample's start: path p begun (path_begin), no AOV
// sample yet (trace_pass records the first hit's).
void sample_begin(uint pixel, uint sampleIndex, OUT(PathState) p, OUT(AovSample) aov) {
  path_begin(p, pixel, sampleIndex);
  aov.a = vec4(0.0f);
  aov.b = vec4(0.0f);
}

// One pass of a path begun by sample_begin: its ray's closest hit, shading
// there, and the shadow rays that shading cast (their light added to the
// path's radiance where unblocked). Returns whether the path goes on; a
// truncated traversal ends it (counted in *rays).
bool trace_pass(INOUT(PathState) p, uint pass, INOUT(SampleRays) rays, INOUT(AovSample) aov) {
  Hit h;
  rays.closest += 1u;
  if (trace_ray(p.origin, p.dir, WP_INF, false, h) != TRACE_OK) {
    rays.truncated += 1u;
    return false;
  }
  if (AOVS_OF_SCENE && pass == 0u) aov = aov_sample(p, h);
  ShadowRays srs;
  bool alive = path_shade(p, h, srs);
  for (uint j = 0u; j < LIGHT_SAMPLE_SLOTS; ++j) {
    if (j >= LIGHT_SAMPLES_OF_SCENE) break;
    ShadowRay sr = srs.ray[j];
    if (sr.tmax <= 0.0f) continue;
    if (FEATURE_COMPILED(FEATURE_MEDIA)) {
      rays.shadow += 1u;
      p.radiance += sr.contribution * shadow_ray_transmittance(sr, p.wavelengths, rays.truncated);
      continue;
    }
    Hit blocker;
    rays.shadow += 1u;
    if (trace_ray(sr.origin, sr.dir, sr.tmax, true, blocker) != TRACE_OK) {
      rays.truncated += 1u;
    } else if (blocker.prim == WP_INVALID) {
      p.radiance += sr.contribution;
    }
  }
  return alive;
}

// One sample of one pixel, from the camera ray through every bounce's closest
// hit, shading and shadow rays (trace_pass); the path's radiance is the
// sample. The megakernel (gpu-mega) and the CPU reference run this loop; the
// wavefront kernels run the same steps (path_begin, trace_ray, path_shade,
// the shadow rays) as stages over queues of paths. On lavapipe one
// invocation's loops share a budget of 65,535 iterations: the host lowers
// the traversal step cap (scene.counts.z) so that a whole path's traversals
// fit. Where the render records AOV layers (AOVS_OF_SCENE), *aov receives
// the first hit's.
PathState trace_sample(uint pixel, uint sampleIndex, OUT(SampleRays) rays, OUT(AovSample) aov) {
  rays.closest = 0u;
  rays.shadow = 0u;
  rays.truncated = 0u;
  PathState p;
  sample_begin(pixel, sampleIndex, p, aov);
  // path_shade ends every path at max bounces (and its interfaces).
  uint passes = path_passes_max();
  for (uint pass = 0u; pass < passes; ++pass) {
    if (!trace_pass(p, pass, rays, aov)) break;
  }
  return p;
}

#endif  // WP_INTEGRATOR_GLSL
