// integrator.glsl — the path tracer, one bounce at a time. The wavefront kernels
// call these functions stage by stage (generate, extend, shade, connect,
// accumulate); the CPU reference calls the same functions in a loop per sample.
// Unidirectional path tracing with next-event estimation and multiple importance
// sampling (power heuristic) between BSDF and emitter sampling, and Russian
// roulette. "max bounces" counts scattering events (pbrt's maxdepth): 0 shows
// emitters only, 1 adds direct lighting.
#ifndef WP_INTEGRATOR_GLSL
#define WP_INTEGRATOR_GLSL

uint path_depth(PathState p) {
  return p.flags & PATH_DEPTH_MASK;
}

// Camera ray for `pixel`, with pixel jitter and (aperture > 0) thin-lens sampling.
void path_begin(INOUT(PathState) p, uint pixel, uint sampleIndex) {
  uint width = scene.image.x;
  uint height = scene.image.y;
  p.rng = rng_seed(pixel, sampleIndex, scene.counts.y);
  float fx = (float(pixel % width) + rng_next(p.rng)) / float(width);
  float fy = (float(pixel / width) + rng_next(p.rng)) / float(height);
  vec2 lensU = vec2(rng_next(p.rng), rng_next(p.rng));
  float tanHalf = scene.camLens.x;
  vec3 dirCam = vec3((2.0f * fx - 1.0f) * tanHalf * scene.camLens.y, (1.0f - 2.0f * fy) * tanHalf, -1.0f);
  vec3 originCam = vec3(0.0f);
  if (scene.camLens.z > 0.0f) {
    vec2 lens = square_to_disk_concentric(lensU) * scene.camLens.z;
    originCam = vec3(lens.x, lens.y, 0.0f);
    dirCam = dirCam * scene.camLens.w - originCam;  // through the point in focus
  }
  p.origin = xform_point(scene.camToWorld0, scene.camToWorld1, scene.camToWorld2, originCam);
  p.dir = normalize(xform_vector(scene.camToWorld0, scene.camToWorld1, scene.camToWorld2, dirCam));
  p.pixel = pixel;
  p.throughput = vec3(1.0f);
  p.radiance = vec3(0.0f);
  p.flags = PATH_SPECULAR;  // depth 0; camera rays count emitters with full weight
  p.bsdfPdf = 0.0f;
}

// 1, except where `wavepath compare --plant-bias` or a test plants a bias to
// show that the statistical comparison detects it.
float planted_bias(uint pixel) {
  uint x = pixel % scene.image.x;
  uint y = pixel / scene.image.x;
  bool inside = x >= scene.debugRegion.x && x < scene.debugRegion.z && y >= scene.debugRegion.y && y < scene.debugRegion.w;
  return inside ? scene.debug.x : 1.0f;
}

// Accounts for what the path's ray hit and prepares the next bounce. Writes a
// shadow ray (tmax > 0) when next-event estimation found a candidate. Returns
// true while the path continues.
bool path_shade(INOUT(PathState) p, Hit h, OUT(ShadowRay) sr) {
  sr.tmax = -1.0f;
  sr.origin = vec3(0.0f);
  sr.dir = vec3(0.0f);
  sr.contribution = vec3(0.0f);
  sr.path = WP_INVALID;
  sr.pad = 0u;
  float radianceScale = planted_bias(p.pixel);
  if (h.prim == WP_INVALID) {
    p.radiance += p.throughput * vec3(scene.background.x, scene.background.y, scene.background.z) * radianceScale;
    return false;
  }
  uint depth = path_depth(p);
  bool useNee = (scene.counts.w & SCENE_FLAG_NO_NEE) == 0u && scene.counts.x > 0u;
  bool useMis = useNee && (scene.counts.w & SCENE_FLAG_NO_BSDF_MIS) == 0u;
  SurfaceHit s = surface_at(p.origin, p.dir, h);
  Material m = materials[s.material];
  vec3 wo = -p.dir;
  float cosO = dot(s.ng, wo);

  // Emission, seen from the front side only.
  if (material_emits(m) && cosO > 0.0f) {
    float w = 1.0f;
    if ((p.flags & PATH_SPECULAR) == 0u && useNee) {
      // This emitter could also have been reached by NEE from the previous vertex.
      float lightPdf = emitter_pdf_area(s.emitter) * h.t * h.t / cosO;
      w = useMis ? power_heuristic(p.bsdfPdf, lightPdf) : 0.0f;
    }
    p.radiance += p.throughput * vec3(m.emission.x, m.emission.y, m.emission.z) * (w * radianceScale);
  }
  if (depth >= scene.image.z || !material_scatters(m)) return false;

  vec3 n = cosO >= 0.0f ? s.ng : -s.ng;  // BSDFs are two-sided: face the viewer

  // Next-event estimation: one point on one emitter, checked later by a shadow ray.
  vec3 uLight = vec3(rng_next(p.rng), rng_next(p.rng), rng_next(p.rng));
  LightSample ls;
  if (useNee && sample_emitter(uLight, ls)) {
    vec3 toLight = ls.p - s.p;
    float dist2 = dot(toLight, toLight);
    vec3 wi = toLight * inversesqrt(dist2);
    float cosL = -dot(ls.n, wi);
    vec3 f = bsdf_eval(m, n, wo, wi);
    if (cosL > 0.0f && dist2 > 0.0f && (f.x > 0.0f || f.y > 0.0f || f.z > 0.0f)) {
      float lightPdf = ls.pdfArea * dist2 / cosL;
      float w = useMis ? power_heuristic(lightPdf, bsdf_pdf(m, n, wo, wi)) : 1.0f;
      sr.contribution = p.throughput * f * ls.emission * (w * radianceScale / lightPdf);
      sr.origin = offset_ray(s.p, n);
      sr.dir = offset_ray(ls.p, ls.n) - sr.origin;
      sr.tmax = 1.0f;
    }
  }

  // BSDF sampling for the next bounce.
  vec2 uBsdf = vec2(rng_next(p.rng), rng_next(p.rng));
  vec3 wi;
  float pdf;
  vec3 weight = bsdf_sample(m, n, wo, uBsdf, wi, pdf);
  if (pdf <= 0.0f || (weight.x <= 0.0f && weight.y <= 0.0f && weight.z <= 0.0f)) return false;
  p.throughput *= weight;
  p.bsdfPdf = pdf;
  p.origin = offset_ray(s.p, dot(wi, s.ng) >= 0.0f ? s.ng : -s.ng);
  p.dir = wi;
  p.flags = depth + 1u;  // Lambertian has no delta lobe: clears PATH_SPECULAR

  // Russian roulette once the path is long enough; unbiased by reweighting.
  if (depth + 1u >= scene.image.w) {
    float maxT = max(p.throughput.x, max(p.throughput.y, p.throughput.z));
    float q = clamp(1.0f - maxT, 0.0f, 0.95f);
    if (rng_next(p.rng) < q) return false;
    p.throughput /= (1.0f - q);
  }
  return true;
}

bool radiance_is_finite(vec3 l) {
  return !(isnan(l.x) || isnan(l.y) || isnan(l.z) || isinf(l.x) || isinf(l.y) || isinf(l.z));
}

#endif  // WP_INTEGRATOR_GLSL
