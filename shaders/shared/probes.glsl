// probes.glsl — one evaluation of the shared scene code at a time, for the
// darts test scenes (`wavepath test`, src/darts/): a material's sample and
// density at a made-up hit, a sample of the emitters' surfaces and its
// density, and the surface a ray hits. probe.comp runs them on the GPU, the
// CPU reference through SceneView, so both test the code that renders.
//
// A query rides in a ShadowRay record and its answer in a Hit record:
//   PROBE_MATERIAL_SAMPLE  in: origin, tmax = 4 random numbers; dir = wo;
//                          contribution = the normal; path = kind | material.
//                          out: (t, u, v) = wi; prim = PROBE_* status bits.
//   PROBE_MATERIAL_PDF     in: origin = wi, the rest as above. out: t = pdf.
//   PROBE_SURFACE_SAMPLE   in: origin = 3 random numbers; contribution = the
//                          point seen from. out: (t, u, v) = wi; prim = status.
//   PROBE_SURFACE_PDF      in: dir = wi; contribution = the point. out: t = pdf.
//   PROBE_INTERSECT        in: origin, dir, tmax: a ray; media = which answer.
//                          out: PROBE_ANSWER_HIT: t and prim; _POINT,
//                          _GEOMETRIC_NORMAL, _SHADING_NORMAL: (t, u, v);
//                          prim = PROBE_TRUNCATED past the step cap.
//   PROBE_TEXTURE          in: origin = the point; dir.xy = the UV;
//                          path = kind | texture. out: (t, u, v) = colour.
#ifndef WP_PROBES_GLSL
#define WP_PROBES_GLSL

#define PROBE_KIND_SHIFT 24u
#define PROBE_INDEX_MASK 0xffffffu
#define PROBE_MATERIAL_SAMPLE 0u
#define PROBE_MATERIAL_PDF 1u
#define PROBE_SURFACE_SAMPLE 2u
#define PROBE_SURFACE_PDF 3u
#define PROBE_INTERSECT 4u
#define PROBE_TEXTURE 5u

// Status bits of a sample.
#define PROBE_VALID 1u  // a direction with positive weight
#define PROBE_DELTA 2u  // from a delta lobe (no density)

#define PROBE_TRUNCATED 0xfffffffeu

#define PROBE_ANSWER_HIT 0u
#define PROBE_ANSWER_POINT 1u
#define PROBE_ANSWER_GEOMETRIC_NORMAL 2u
#define PROBE_ANSWER_SHADING_NORMAL 3u

// The made-up hit the material probes shade: at the origin, flat, facing
// `normal`, at uv (0.5, 0.5), as darts' material tests place it.
SurfaceHit probe_surface(uint material, vec3 normal) {
  SurfaceHit s;
  s.p = vec3(0.0f);
  s.material = material;
  s.ng = normal;
  s.emitter = WP_INVALID;
  s.ns = normal;
  s.pad = 0.0f;
  s.uv = vec4(0.5f);
  s.tangent = vec4(0.0f, 0.0f, 0.0f, 1.0f);
  s.color = vec4(1.0f);
  return s;
}

Hit probe_answer(vec3 v, uint prim) {
  Hit h = no_hit(v.x);
  h.prim = prim;
  h.u = v.y;
  h.v = v.z;
  return h;
}

Hit run_probe(ShadowRay q) {
  uint kind = q.path >> PROBE_KIND_SHIFT;
  uint index = q.path & PROBE_INDEX_MASK;
  vec3 point = spectrum_xyz(q.contribution);  // (the queries' third vector)
  if (kind == PROBE_MATERIAL_SAMPLE || kind == PROBE_MATERIAL_PDF) {
    vec3 wo = q.dir;
    Bsdf b = bsdf_at(probe_surface(index, point), wo);
    if (kind == PROBE_MATERIAL_PDF) return probe_answer(vec3(bsdf_pdf(b, wo, q.origin), 0.0f, 0.0f), 0u);
    vec3 wi;
    float pdf;
    bool isDelta;
    Spectrum weight = bsdf_sample(b, wo, vec4(q.origin, q.tmax), wi, pdf, isDelta);
    bool valid = isDelta ? dot(wi, wi) > 0.0f && spectrum_positive(weight) : pdf > 0.0f;
    return probe_answer(wi, (valid ? PROBE_VALID : 0u) | (isDelta ? PROBE_DELTA : 0u));
  }
  if (kind == PROBE_SURFACE_SAMPLE) {
    if (scene.counts.x == 0u) return probe_answer(vec3(0.0f), 0u);
    float pmf;
    Emitter e = load_emitter(pick_emitter(q.origin.x, pmf));
    SurfaceHit s;
    vec3 wi;
    float dist;
    float pdf;
    bool valid = sample_emitter_surface(e, pmf, point, vec2(q.origin.y, q.origin.z), s, wi, dist, pdf);
    return probe_answer(wi, valid && pdf > 0.0f ? PROBE_VALID : 0u);
  }
  if (kind == PROBE_SURFACE_PDF) {
    return probe_answer(vec3(emitters_pdf_direction(point, q.dir, true), 0.0f, 0.0f), 0u);
  }
  if (kind == PROBE_TEXTURE) return probe_answer(texture_eval(index, vec4(q.dir.x, q.dir.y, q.dir.x, q.dir.y), q.origin), 0u);
  // PROBE_INTERSECT
  Hit h = no_hit(q.tmax);
  if (trace_ray(q.origin, q.dir, q.tmax, false, h) != TRACE_OK) return probe_answer(vec3(0.0f), PROBE_TRUNCATED);
  if (q.media == PROBE_ANSWER_HIT || h.prim == WP_INVALID) return probe_answer(vec3(h.t, 0.0f, 0.0f), h.prim);
  SurfaceHit s = surface_at(q.origin, q.dir, h);
  if (q.media == PROBE_ANSWER_POINT) return probe_answer(s.p, h.prim);
  return probe_answer(q.media == PROBE_ANSWER_GEOMETRIC_NORMAL ? s.ng : s.ns, h.prim);
}

#endif  // WP_PROBES_GLSL
