// photons.glsl — photon mapping (INTEGRATOR_PHOTONS, Jensen's two-pass
// method): photons leave the lights and bounce through the scene, each
// leaving a record at every non-specular surface it reaches after its first
// bounce; the records are balanced into a kd-tree (src/render/photon_pass.cpp,
// through PhotonMap); camera paths follow specular bounces to their first
// non-specular vertex, take its direct light by next-event estimation and
// everything else from the photons around it (photon_radiance). The
// photons are traced with this code (photon_emit, photon_bounce) by the
// photons kernel (photons.comp) or on the host; both renderers gather with it.
#ifndef WP_PHOTONS_GLSL
#define WP_PHOTONS_GLSL

// A unit vector in 32 bits: octahedral, two snorm16 (Cigolle et al. 2014).
uint pack_unit_vector(vec3 v) {
  vec3 n = v / (abs(v.x) + abs(v.y) + abs(v.z));
  vec2 e = vec2(n.x, n.y);
  if (n.z < 0.0f) e = vec2((1.0f - abs(n.y)) * (n.x >= 0.0f ? 1.0f : -1.0f), (1.0f - abs(n.x)) * (n.y >= 0.0f ? 1.0f : -1.0f));
  return packSnorm2x16(e);
}

vec3 unpack_unit_vector(uint packed) {
  vec2 e = unpackSnorm2x16(packed);
  vec3 n = vec3(e.x, e.y, 1.0f - abs(e.x) - abs(e.y));
  if (n.z < 0.0f) n = vec3((1.0f - abs(e.y)) * (e.x >= 0.0f ? 1.0f : -1.0f), (1.0f - abs(e.x)) * (e.y >= 0.0f ? 1.0f : -1.0f), n.z);
  return normalize(n);
}

// f(wo, wi): what a photon arriving from wi gives towards wo, per unit of
// its power and of area (bsdf_eval includes the cosine, which the photon's
// flux already holds). In RGB: the photon mapper gathers in RGB.
vec3 photon_bsdf(Bsdf b, vec3 wo, vec3 wi) {
  float c = abs(dot(wi, b.ns));
  return c > 0.0f ? spectrum_xyz(bsdf_eval(b, wo, wi)) / c : vec3(0.0f);
}

// A photon on its way from a light (photon_emit, photon_bounce).
struct PhotonPath {
  vec3 origin;
  uint rng;
  vec3 dir;
  uint bounce;  // surfaces met so far
  Spectrum power;  // its flux, its share of the lights' total power (the spectral mode: at its wavelengths)
  uint alive;   // 0 once absorbed, escaped or past max bounces
  // The spectral mode: its wavelength sample (path_wavelengths), and 1 once
  // a dispersive boundary left it its hero wavelength alone.
  float wavelengths;
  uint heroOnly;
};

// Photon `index` of `total` leaves a light picked in proportion to its
// power, from a point uniform on its surface in a cosine-weighted direction
// (point and spot lights: uniform over their sphere or cone). `seed` picks
// the photon map: the same seed, the same photons.
PhotonPath photon_emit(uint index, uint total, uint seed) {
  PhotonPath path;
  path.rng = pcg_hash(index * 0x9e3779b9u ^ pcg_hash(seed + 0x51ed270bu));
  path.bounce = 0u;
  path.alive = 0u;
  path.origin = vec3(0.0f);
  path.dir = vec3(0.0f, 0.0f, 1.0f);
  path.power = Spectrum(0.0f);
  vec3 power = vec3(0.0f);  // (in RGB)
  // The spectral mode: each photon's wavelengths, from the map's randomly
  // shifted sequence (as a pixel's samples take theirs, path_begin).
  path.wavelengths = spectral_mode() ? wavelength_sequence(pcg_hash(seed ^ 0x2545f491u), index) : 0.0f;
  path.heroOnly = 0u;
  if (scene.counts.x == 0u) return path;
  float pmf;
  Emitter e = load_emitter(pick_emitter(rng_next(path.rng), pmf));
  vec2 uPos = rng_next2(path.rng);
  vec2 uDir = rng_next2(path.rng);
  if ((e.prim & (EMITTER_POINT_BIT | EMITTER_ENVIRONMENT)) == EMITTER_POINT_BIT) {
    PointLight l = load_point_light(e.prim & ~EMITTER_POINT_BIT);
    vec3 shine = vec3(l.direction.x, l.direction.y, l.direction.z);
    vec3 intensity = vec3(l.intensity.x, l.intensity.y, l.intensity.z);
    path.origin = vec3(l.position.x, l.position.y, l.position.z);
    if (LIGHT_COMPILED(LIGHT_SPOT) && l.position.w == float(LIGHT_SPOT)) {
      // Uniform in the outer cone; glTF's falloff between the cones.
      vec3 t;
      vec3 b;
      make_frame(shine, t, b);
      float cone = 1.0f - l.direction.w;
      path.dir = frame_to_world(square_to_uniform_cone(uDir, cone), t, b, shine);
      float ramp = clamp((dot(shine, path.dir) - l.direction.w) / max(l.intensity.w - l.direction.w, 1e-3f), 0.0f, 1.0f);
      power = intensity * (ramp * ramp / (pmf * uniform_cone_pdf(cone)));
    } else {
      path.dir = square_to_uniform_sphere(uDir);
      power = intensity * (4.0f * WP_PI / pmf);
    }
  } else {
    // A point uniform by area on a sphere or a triangle, a direction
    // cosine-weighted about its normal (either side, where CS184's lights
    // emit from both).
    SurfaceHit s;
    float area;
    if (LIGHT_COMPILED(LIGHT_SPHERE) && (e.prim & HIT_SPHERE_BIT) != 0u) {
      Sphere sp = load_sphere(e.prim & ~HIT_SPHERE_BIT);
      vec3 pl = square_to_uniform_sphere(uPos);
      s = sphere_surface_of(sp, xform_point(sp.toWorld0, sp.toWorld1, sp.toWorld2, pl));
      area = sp.area;
    } else {
      Triangle tri = load_triangle(e.prim & ~EMITTER_UNSEEN_BIT);
      vec2 bary = square_to_triangle_barycentric(uPos);
      s = triangle_surface_of(tri, bary.x, bary.y);
      area = triangle_area(tri);
    }
    vec3 n = s.ng;
    float sides = 1.0f;
    if ((scene.counts.w & SCENE_FLAG_CS184) != 0u) {
      sides = 2.0f;
      if (rng_next(path.rng) < 0.5f) n = -n;
    }
    vec3 t;
    vec3 b;
    make_frame(n, t, b);
    vec3 local = square_to_cosine_hemisphere(uDir);
    path.dir = frame_to_world(local, t, b, n);
    // Le cos / (pmf pdfA pdfDir), with pdfDir = cos / pi.
    power = local.z > 0.0f ? emitted_radiance(s, path.dir) * (WP_PI * area * sides / pmf) : vec3(0.0f);
    path.origin = offset_ray(s.p, n);
  }
  path.power = path_radiance(power / float(total), path_wavelengths(path.wavelengths));
  path.alive = spectrum_positive(path.power) ? 1u : 0u;
  return path;
}

// What photon_bounce did: PHOTON_STORED where it left a record in ph;
// PHOTON_TRUNCATED where its ray outran the traversal step cap (the photon
// is then lost, and the map would be wrong: the caller fails).
#define PHOTON_STORED 1u
#define PHOTON_TRUNCATED 2u

// Takes the photon to the next surface on its way. Where that surface has
// a smooth lobe and the photon has bounced before (the camera pass takes
// direct light by next-event estimation), it leaves a record there. Then
// the photon bounces by BSDF sampling with Russian roulette on what the
// bounce keeps (its power stays about what it left the light with), or ends
// (alive = 0) where it is absorbed, escapes or has met max bounces surfaces.
// Returns PHOTON_* bits.
uint photon_bounce(INOUT(PhotonPath) path, OUT(Photon) ph) {
  ph.position = vec3(0.0f);
  ph.axis = 0u;
  ph.power = vec3(0.0f);
  ph.from = 0u;
  if (path.alive == 0u) return 0u;
  Hit h;
  if (trace_ray(path.origin, path.dir, WP_INF, false, h) != TRACE_OK) {
    path.alive = 0u;
    return PHOTON_TRUNCATED;
  }
  if (h.prim == WP_INVALID) {
    path.alive = 0u;
    return 0u;
  }
  SurfaceHit s = surface_at(path.origin, path.dir, h);
  vec3 wo = -path.dir;
  Bsdf b = bsdf_at(s, wo);
  bool stored = path.bounce > 0u && b.lobeCount > 0u && bsdf_has_smooth_lobe(b);
  if (stored) {
    ph.position = s.p;
    // The spectral mode stores the photon's power in linear sRGB, as the
    // film takes a sample's (the camera's paths gather it in RGB and uplift
    // the sum: integrator.glsl).
    ph.power = spectral_mode() ? spectral_sample_rgb(path.power, path.wavelengths) : spectrum_xyz(path.power);
    ph.from = pack_unit_vector(wo);
  }
  if (spectral_mode()) {
    // Its BSDF at its wavelengths; a dispersive boundary leaves it its hero
    // alone, four times as strong (integrator.glsl's disperse).
    vec4 lambdas = path_wavelengths(path.wavelengths);
    bsdf_at_wavelengths(b, path.wavelengths, lambdas);
    if (FEATURE_COMPILED(FEATURE_DISPERSION) && bsdf_disperses(b)) {
      if (path.heroOnly == 0u) path.power = spectrum_keep_channel(path.power, 1u);
      path.heroOnly = 1u;
      disperse_lobes(b, 1u, lambdas);
    }
  }
  path.bounce += 1u;
  if (b.lobeCount == 0u || path.bounce > scene.image.z) {
    path.alive = 0u;
    return stored ? PHOTON_STORED : 0u;
  }
  vec4 u = rng_next4(path.rng);
  vec3 wi;
  float pdf;
  bool isDelta;
  Spectrum weight = bsdf_sample(b, wo, u, wi, pdf, isDelta);
  float q = min(1.0f, spectrum_max(weight));
  if (!(q > 0.0f) || rng_next(path.rng) >= q) {
    path.alive = 0u;
    return stored ? PHOTON_STORED : 0u;
  }
  path.power *= weight / q;
  path.origin = offset_ray(s.p, dot(wi, s.ng) >= 0.0f ? s.ng : -s.ng);
  path.dir = wi;
  return stored ? PHOTON_STORED : 0u;
}

// What photon ph gives towards wo through b, per unit area: nothing where it
// arrived from the other side of the surface.
vec3 photon_contribution(Photon ph, Bsdf b, vec3 wo) {
  vec3 wi = unpack_unit_vector(ph.from);
  return (dot(wi, b.ng) > 0.0f) == (dot(wo, b.ng) > 0.0f) ? photon_bsdf(b, wo, wi) * ph.power : vec3(0.0f);
}

// The photons' estimate of the radiance that leaves point x towards wo,
// through BSDF b: the photons nearest x (the search count, darts' "search
// count"; 0: all within the search radius), their power weighted by the
// BSDF for the direction each arrived from, over the disc they fill. Only
// photons that arrived from wo's side of the surface count. The k-nearest
// search keeps the k + 1 nearest in a max-heap and takes the disc out to the
// (k+1)-th (PhotonMap::gather_nearest, which the tests compare).
vec3 photon_radiance(vec3 x, Bsdf b, vec3 wo) {
  uint count = scene.photons.x;
  if (count == 0u) return vec3(0.0f);
  uint k = scene.photons.y;
  float radius2 = uintBitsToFloat(scene.photons.z);
  // The heap of the k + 1 nearest: squared distance and photon, farthest on top.
  float heapD[PHOTON_SEARCH_MAX + 1];
  uint heapI[PHOTON_SEARCH_MAX + 1];
  uint heapSize = 0u;
  uint want = k > 0u ? min(k, PHOTON_SEARCH_MAX) + 1u : 0u;
  vec3 sum = vec3(0.0f);
  // The kd-tree's ranges still to visit, with the squared distance of x to
  // the plane that split them off (a range beyond the search radius is skipped).
  uint stackLo[PHOTON_STACK_MAX];
  uint stackHi[PHOTON_STACK_MAX];
  float stackD[PHOTON_STACK_MAX];
  uint sp = 1u;
  stackLo[0] = 0u;
  stackHi[0] = count;
  stackD[0] = 0.0f;
  for (uint step = 0u; step < PHOTON_SEARCH_STEPS_MAX; ++step) {
    if (sp == 0u) break;
    sp -= 1u;
    uint lo = stackLo[sp];
    uint hi = stackHi[sp];
    if (stackD[sp] > radius2 || lo >= hi) continue;
    uint mid = lo + (hi - lo) / 2u;
    Photon ph = load_photon(mid);
    vec3 v = ph.position - x;
    float dist2 = dot(v, v);
    if (dist2 <= radius2) {
      if (want == 0u) {
        sum += photon_contribution(ph, b, wo);
      } else if (heapSize < want) {
        // Sift up.
        uint c = heapSize;
        heapSize += 1u;
        for (uint j = 0u; j < PHOTON_HEAP_LEVELS && c > 0u; ++j) {
          uint parent = (c - 1u) / 2u;
          if (heapD[parent] >= dist2) break;
          heapD[c] = heapD[parent];
          heapI[c] = heapI[parent];
          c = parent;
        }
        heapD[c] = dist2;
        heapI[c] = mid;
        if (heapSize == want) radius2 = heapD[0];
      } else if (dist2 < heapD[0]) {
        // Replace the farthest and sift down.
        uint c = 0u;
        for (uint j = 0u; j < PHOTON_HEAP_LEVELS; ++j) {
          uint l = 2u * c + 1u;
          uint size = min(heapSize, PHOTON_SEARCH_MAX + 1u);  // (the compiler cannot see that bound)
          if (l >= size) break;
          uint r = l + 1u;
          uint big = r < size && heapD[r] > heapD[l] ? r : l;
          if (heapD[big] <= dist2) break;
          heapD[c] = heapD[big];
          heapI[c] = heapI[big];
          c = big;
        }
        heapD[c] = dist2;
        heapI[c] = mid;
        radius2 = heapD[0];
      }
    }
    if (hi - lo > 1u) {
      float d = vec_component(x, ph.axis) - vec_component(ph.position, ph.axis);
      bool leftFirst = d < 0.0f;
      // The far side (pushed first, visited last), then the near side.
      if (sp + 2u <= PHOTON_STACK_MAX) {
        stackLo[sp] = leftFirst ? mid + 1u : lo;
        stackHi[sp] = leftFirst ? hi : mid;
        stackD[sp] = d * d;
        stackLo[sp + 1u] = leftFirst ? lo : mid + 1u;
        stackHi[sp + 1u] = leftFirst ? mid : hi;
        stackD[sp + 1u] = 0.0f;
        sp += 2u;
      }
    }
  }
  if (want == 0u) return sum / (WP_PI * radius2);
  // The k nearest (all but the heap's top, where k + 1 were found) over the
  // disc out to the (k+1)-th, or the search disc where fewer lie in it.
  float area = WP_PI * (heapSize == want ? heapD[0] : uintBitsToFloat(scene.photons.z));
  for (uint i = 0u; i < PHOTON_SEARCH_MAX + 1u; ++i) {
    if (i >= heapSize) break;
    if (heapSize == want && i == 0u) continue;
    sum += photon_contribution(load_photon(heapI[i]), b, wo);
  }
  return sum / area;
}

#endif  // WP_PHOTONS_GLSL
