// lights.glsl — light arriving from outside the scene (the background or
// an environment map) and next-event estimation: picking an emitter, a point
// on it, and the densities MIS needs, for every light kind (kinds.glsl).
#ifndef WP_LIGHTS_GLSL
#define WP_LIGHTS_GLSL

// A point chosen on an emitter by next-event estimation, seen from a shading point.
struct LightSample {
  vec3 wi;     // unit direction from the shading point towards the light
  float dist;  // distance to the light point (the shadow ray stops short of it)
  vec3 radiance;  // emitted radiance towards the shading point (point lights: I / d^2)
  float pdf;      // solid-angle density of wi, pick probability included (point lights: the pick probability)
  vec3 p;         // the light point
  uint isDelta;   // 1 where no BSDF sample can reach the light (point lights, lights no ray meets): no MIS
  vec3 n;         // surface normal at p (zero for point lights)
};

// ---- environment map ----------------------------------------------------------

// Equirectangular: -Z at the image's centre column, +Y at its top row; in
// CS184's layout (SCENE_FLAG_CS184_LATLONG) +X at the centre column and
// azimuth running the other way.
bool environment_cs184() {
  return (scene.counts.w & SCENE_FLAG_CS184_LATLONG) != 0u;
}

vec2 environment_uv(vec3 d) {
  float phi = environment_cs184() ? atan(-d.z, d.x) : atan(d.x, -d.z);
  float theta = acos(clamp(d.y, -1.0f, 1.0f));
  return vec2(0.5f + phi * (0.5f * WP_INV_PI), 1.0f - theta * WP_INV_PI);
}

// The direction of polar angle theta (from +Y) at azimuth phi (the column's,
// 0 at the centre), environment_uv's inverse.
vec3 environment_direction(float theta, float phi) {
  float sinTheta = sin(theta);
  if (environment_cs184()) return vec3(sinTheta * cos(phi), cos(theta), -sinTheta * sin(phi));
  return vec3(sinTheta * sin(phi), cos(theta), -sinTheta * cos(phi));
}

// Radiance arriving from direction d out of the scene: the environment map, or
// the constant background.
vec3 background_radiance(vec3 d) {
  if (!LIGHT_COMPILED(LIGHT_ENVIRONMENT) || scene.environment.x == WP_INVALID) return vec3(scene.background.x, scene.background.y, scene.background.z);
  vec2 uv = environment_uv(d);
  return texture_eval(scene.environment.x, vec4(uv.x, uv.y, uv.x, uv.y), d);
}

// The interval i in [0, count) of the CDF at `offset` with cdf[i] <= u < cdf[i + 1]
// (never an empty one). Bisection: at most 32 steps.
uint cdf_find(uint offset, uint count, float u) {
  uint lo = 0u;
  uint hi = count;
  while (lo + 1u < hi) {
    uint mid = (lo + hi) / 2u;
    if (cdf_at(offset + mid) <= u) lo = mid;
    else hi = mid;
  }
  return lo;
}

// Density of the grid cell (row, col) per unit of the (u, v) square.
float environment_cell_pdf(uint row, uint col) {
  uint w = scene.environment.z;
  uint h = scene.environment.w;
  uint rowCdf = h + 1u + row * (w + 1u);
  float pRow = (cdf_at(row + 1u) - cdf_at(row)) * float(h);
  float pCol = (cdf_at(rowCdf + col + 1u) - cdf_at(rowCdf + col)) * float(w);
  return pRow * pCol;
}

// Solid-angle density with which environment_sample picks direction d: the
// cell's density over the sphere's area element, 2 pi^2 sin(theta).
float environment_pdf(vec3 d) {
  uint w = scene.environment.z;
  uint h = scene.environment.w;
  vec2 uv = environment_uv(d);
  uint col = min(uint(max(uv.x, 0.0f) * float(w)), w - 1u);
  uint row = min(uint(max(1.0f - uv.y, 0.0f) * float(h)), h - 1u);
  float sinTheta = length(vec2(d.x, d.z));  // not sqrt(1 - y^2): that cancels near the poles
  return sinTheta > 0.0f ? environment_cell_pdf(row, col) / (2.0f * WP_PI * WP_PI * sinTheta) : 0.0f;
}

// A direction in proportion to the environment's luminance (times sin theta):
// a row from the marginal CDF, a column from that row's CDF, uniform within the cell.
vec3 environment_sample(vec2 u, OUT(float) pdf) {
  uint w = scene.environment.z;
  uint h = scene.environment.w;
  uint row = cdf_find(0u, h, u.y);
  float r0 = cdf_at(row);
  float dv = clamp((u.y - r0) / (cdf_at(row + 1u) - r0), 0.0f, 1.0f);
  uint rowCdf = h + 1u + row * (w + 1u);
  uint col = cdf_find(rowCdf, w, u.x);
  float c0 = cdf_at(rowCdf + col);
  float du = clamp((u.x - c0) / (cdf_at(rowCdf + col + 1u) - c0), 0.0f, 1.0f);
  float theta = (float(row) + dv) / float(h) * WP_PI;
  float phi = ((float(col) + du) / float(w) - 0.5f) * (2.0f * WP_PI);
  vec3 d = environment_direction(theta, phi);
  float sinTheta = length(vec2(d.x, d.z));  // exactly as environment_pdf computes it
  pdf = sinTheta > 0.0f ? environment_cell_pdf(row, col) / (2.0f * WP_PI * WP_PI * sinTheta) : 0.0f;
  return d;
}

// ---- emitters ----------------------------------------------------------------

// Picks an emitter index with the alias table (in proportion to power) and
// returns the probability of that pick.
uint pick_emitter(float u, OUT(float) pmf) {
  uint count = scene.counts.x;
  float x = u * float(count);
  uint i = min(uint(x), count - 1u);
  Emitter e = load_emitter(i);
  uint chosen = (x - float(i)) < e.threshold ? i : e.alias;
  pmf = load_emitter(chosen).pmf;
  return chosen;
}

// 1 - cos of the half-angle of the cone that sphere sp subtends from ref, or 0
// when ref is inside the sphere (then it sees only the sphere's unlit back).
float sphere_cone(Sphere sp, vec3 ref, OUT(vec3) center, OUT(float) radius) {
  center = vec3(sp.toWorld0.w, sp.toWorld1.w, sp.toWorld2.w);
  radius = sqrt(sp.area * (0.25f * WP_INV_PI));
  vec3 d = center - ref;
  float dc2 = dot(d, d);
  float r2 = radius * radius;
  if (dc2 <= r2) return 0.0f;
  float sin2 = r2 / dc2;
  // Series for small cones, where 1 - sqrt(1 - x) cancels.
  return sin2 < 1e-3f ? sin2 * (0.5f + 0.125f * sin2) : 1.0f - sqrt(1.0f - sin2);
}

// Solid-angle density with which sample_emitter_surface, called at ref,
// reaches the emitter surface point s at distance dist along unit direction
// wi, from either side of the surface.
float emitter_surface_pdf(uint emitter, vec3 ref, SurfaceHit s, vec3 wi, float dist) {
  Emitter e = load_emitter(emitter);
  if (LIGHT_COMPILED(LIGHT_SPHERE) && (e.prim & HIT_SPHERE_BIT) != 0u) {
    vec3 c;
    float r;
    float cone = sphere_cone(load_sphere(e.prim & ~HIT_SPHERE_BIT), ref, c, r);
    return cone > 0.0f ? e.pmf * uniform_cone_pdf(cone) : 0.0f;
  }
  float cosL = abs(dot(s.ng, wi));
  if (!LIGHT_COMPILED(LIGHT_AREA) || cosL <= 0.0f) return 0.0f;
  return e.pmf / triangle_area(load_triangle(e.prim)) * dist * dist / cosL;
}

// Solid-angle density with which sample_emitter, called at ref, reaches the
// emitter surface point s at distance dist along unit direction wi: only its
// front emits.
float emitter_pdf(uint emitter, vec3 ref, SurfaceHit s, vec3 wi, float dist) {
  return dot(s.ng, wi) < 0.0f ? emitter_surface_pdf(emitter, ref, s, wi, dist) : 0.0f;
}

// A point on surface emitter e (a sphere or a triangle, picked with
// probability pmf), seen from ref from either side of the surface: uniform in
// the cone a sphere subtends, uniform by area on a triangle. pdf is the
// solid-angle density of wi, pick probability included.
bool sample_emitter_surface(Emitter e, float pmf, vec3 ref, vec2 uv, OUT(SurfaceHit) s, OUT(vec3) wi, OUT(float) dist,
                            OUT(float) pdf) {
  wi = vec3(0.0f);
  dist = 0.0f;
  pdf = 0.0f;
  if (LIGHT_COMPILED(LIGHT_SPHERE) && (e.prim & HIT_SPHERE_BIT) != 0u) {
    Sphere sp = load_sphere(e.prim & ~HIT_SPHERE_BIT);
    vec3 c;
    float r;
    float cone = sphere_cone(sp, ref, c, r);
    if (cone <= 0.0f) return false;
    vec3 axis = normalize(c - ref);
    vec3 t;
    vec3 b;
    make_frame(axis, t, b);
    vec3 local = square_to_uniform_cone(uv, cone);
    vec3 w = frame_to_world(local, t, b, axis);
    // The nearer intersection of the ray (ref, w) with the sphere.
    float dc = length(c - ref);
    float sin2 = max(0.0f, 1.0f - local.z * local.z);
    float ds = dc * local.z - sqrt(max(0.0f, r * r - dc * dc * sin2));
    s = sphere_surface_of(sp, ref + w * ds);
    pdf = pmf * uniform_cone_pdf(cone);
  } else if (LIGHT_COMPILED(LIGHT_AREA) && (e.prim & (EMITTER_POINT_BIT | EMITTER_ENVIRONMENT)) == 0u) {
    Triangle tri = load_triangle(e.prim & ~EMITTER_UNSEEN_BIT);
    vec2 bary = square_to_triangle_barycentric(uv);
    s = triangle_surface_of(tri, bary.x, bary.y);
    pdf = pmf / triangle_area(tri);  // per unit area; per solid angle below
  } else {
    return false;
  }
  vec3 d = s.p - ref;
  float dist2 = dot(d, d);
  if (dist2 <= 0.0f) return false;
  dist = sqrt(dist2);
  wi = d / dist;
  if (!LIGHT_COMPILED(LIGHT_SPHERE) || (e.prim & HIT_SPHERE_BIT) == 0u) {
    float cosL = abs(dot(s.ng, wi));
    if (cosL <= 0.0f) return false;
    pdf *= dist2 / cosL;
  }
  return true;
}

// Next-event estimation: picks an emitter, then a point on it as seen from ref:
// uniform in the subtended cone for spheres, uniform by area for triangles, by
// luminance for the environment map (a direction, at distance WP_INF).
bool sample_emitter(vec3 ref, vec3 u, OUT(LightSample) ls) {
  ls.wi = vec3(0.0f);
  ls.dist = 0.0f;
  ls.radiance = vec3(0.0f);
  ls.pdf = 0.0f;
  ls.p = vec3(0.0f);
  ls.isDelta = 0u;
  ls.n = vec3(0.0f);
  if (scene.counts.x == 0u) return false;
  float pmf;
  Emitter e = load_emitter(pick_emitter(u.x, pmf));
  vec2 uv = vec2(u.y, u.z);
  if (LIGHT_COMPILED(LIGHT_ENVIRONMENT) && e.prim == EMITTER_ENVIRONMENT) {
    float pdfDir;
    ls.wi = environment_sample(uv, pdfDir);
    if (pdfDir <= 0.0f) return false;
    ls.dist = WP_INF;  // at infinity: the shadow ray is unbounded
    ls.radiance = background_radiance(ls.wi);
    ls.pdf = pmf * pdfDir;
    ls.n = -ls.wi;
    return true;
  }
  if (ANY_LIGHT_COMPILED(PUNCTUAL_LIGHT_BITS) && (e.prim & EMITTER_POINT_BIT) != 0u) {
    PointLight l = load_point_light(e.prim & ~EMITTER_POINT_BIT);
    vec3 shine = vec3(l.direction.x, l.direction.y, l.direction.z);
    vec3 power = vec3(l.intensity.x, l.intensity.y, l.intensity.z);
    ls.pdf = pmf;
    ls.isDelta = 1u;
    if (LIGHT_COMPILED(LIGHT_HEMISPHERE) && l.position.w == float(LIGHT_HEMISPHERE)) {
      // Uniform over the hemisphere about the zenith. No ray meets this
      // light, so, like a delta light, it takes no part in MIS.
      vec3 t;
      vec3 b;
      make_frame(shine, t, b);
      vec3 local = square_to_uniform_hemisphere(uv);
      ls.wi = frame_to_world(local, t, b, shine);
      ls.dist = WP_INF;
      ls.radiance = power;
      ls.pdf = pmf * square_to_uniform_hemisphere_pdf(local);
      return true;
    }
    if (LIGHT_COMPILED(LIGHT_DIRECTIONAL) && l.position.w == float(LIGHT_DIRECTIONAL)) {
      ls.wi = -shine;
      ls.dist = WP_INF;  // at infinity: the shadow ray is unbounded
      ls.radiance = power;
      return true;
    }
    bool spot = LIGHT_COMPILED(LIGHT_SPOT) && l.position.w == float(LIGHT_SPOT);
    if (!spot && !LIGHT_COMPILED(LIGHT_POINT)) return false;  // each kind's code is its own, as kinds.glsl requires
    vec3 d = vec3(l.position.x, l.position.y, l.position.z) - ref;
    float dist2 = dot(d, d);
    if (dist2 <= 0.0f) return false;
    ls.dist = sqrt(dist2);
    ls.wi = d / ls.dist;
    ls.p = vec3(l.position.x, l.position.y, l.position.z);
    ls.radiance = !spot && l.intensity.w == 0.0f ? power : power / dist2;  // CS184's point lights do not fall off
    if (spot) {
      // glTF's falloff: the square of a linear ramp in the cosine between the cones.
      float ramp = clamp((dot(shine, -ls.wi) - l.direction.w) / max(l.intensity.w - l.direction.w, 1e-3f), 0.0f, 1.0f);
      ls.radiance *= ramp * ramp;
    }
    return true;
  }
  SurfaceHit s;
  if (!sample_emitter_surface(e, pmf, ref, uv, s, ls.wi, ls.dist, ls.pdf)) return false;
  if (dot(s.ng, ls.wi) >= 0.0f) return false;  // back side: emits nothing
  ls.p = s.p;
  ls.n = s.ng;
  ls.radiance = emitted_radiance(s, -ls.wi);
  ls.isDelta = (e.prim & EMITTER_UNSEEN_BIT) != 0u ? 1u : 0u;  // no ray meets it: no MIS
  // CS184's area lights take the cosine of the unnormalised direction in
  // their density (light.cpp, AreaLight::sample_L), which scales what they
  // give by the distance; its estimator keeps that.
  if ((e.prim & EMITTER_UNSEEN_BIT) != 0u && (scene.counts.w & SCENE_FLAG_CS184) != 0u) ls.pdf /= ls.dist;
  return true;
}

// Solid-angle density with which sample_emitter at ref produces direction wi:
// the sum over every emitter the line crosses from the front, occluded or not
// (the mixture integrator needs the exact density), or with bothSides from
// either side (the density of sample_emitter_surface). Loops over all emitters.
float emitters_pdf_direction(vec3 ref, vec3 wi, bool bothSides) {
  float pdf = 0.0f;
  RayShear sh = make_ray_shear(wi);
  for (uint i = 0u; i < scene.counts.x; ++i) {
    Emitter e = load_emitter(i);
    if (LIGHT_COMPILED(LIGHT_ENVIRONMENT) && e.prim == EMITTER_ENVIRONMENT) {
      pdf += e.pmf * environment_pdf(wi);  // every direction reaches it
      continue;
    }
    if ((e.prim & (EMITTER_POINT_BIT | EMITTER_ENVIRONMENT | EMITTER_UNSEEN_BIT)) != 0u) continue;
    float t;
    SurfaceHit s;
    if (LIGHT_COMPILED(LIGHT_SPHERE) && (e.prim & HIT_SPHERE_BIT) != 0u) {
      Sphere sp = load_sphere(e.prim & ~HIT_SPHERE_BIT);
      vec3 ol = xform_point(sp.toObject0, sp.toObject1, sp.toObject2, ref);
      vec3 dl = xform_vector(sp.toObject0, sp.toObject1, sp.toObject2, wi);
      if (!intersect_unit_sphere(ol, dl, WP_INF, t)) continue;
      s = sphere_surface_of(sp, ref + wi * t);
    } else if (LIGHT_COMPILED(LIGHT_AREA)) {
      Triangle tri = load_triangle(e.prim);
      float b1;
      float b2;
      if (!intersect_triangle(ref, sh, tri.v0, tri.v1, tri.v2, WP_INF, t, b1, b2)) continue;
      s = triangle_surface_of(tri, b1, b2);
    } else {
      continue;
    }
    if (bothSides || dot(s.ng, wi) < 0.0f) pdf += emitter_surface_pdf(i, ref, s, wi, t);
  }
  return pdf;
}

#endif  // WP_LIGHTS_GLSL
