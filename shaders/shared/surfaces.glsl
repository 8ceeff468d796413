// surfaces.glsl — what a ray hit: the surface point, its normals, UVs,
// material and emitter, for spheres and triangles.
#ifndef WP_SURFACES_GLSL
#define WP_SURFACES_GLSL

struct SurfaceHit {
  vec3 p;  // position, reprojected onto the surface
  uint material;
  vec3 ng;  // unit geometric normal; its side is the emitting (front) side
  uint emitter;
  vec3 ns;  // unit shading normal (interpolated vertex normals), on ng's side
  float pad;
  vec2 uv;  // texture coordinates
};

// darts / Ray Tracing in One Weekend sphere coordinates on the unit sphere
// (y up): u around the y axis, v from the south pole (0) to the north pole (1).
vec2 sphere_uv(vec3 pl) {
  float theta = acos(clamp(-pl.y, -1.0f, 1.0f));
  float phi = atan(-pl.z, pl.x) + WP_PI;
  return vec2(phi * (0.5f * WP_INV_PI), theta * WP_INV_PI);
}

// The surface of sphere `sp` nearest to world point pw (reprojected onto it).
SurfaceHit sphere_surface_of(Sphere sp, vec3 pw) {
  vec3 pl = normalize(xform_point(sp.toObject0, sp.toObject1, sp.toObject2, pw));
  SurfaceHit s;
  s.p = xform_point(sp.toWorld0, sp.toWorld1, sp.toWorld2, pl);
  s.ng = normalize(xform_normal_by_inverse(sp.toObject0, sp.toObject1, sp.toObject2, pl));
  s.ns = s.ng;
  s.uv = sphere_uv(pl);
  s.material = sp.material;
  s.emitter = sp.emitter;
  s.pad = 0.0f;
  return s;
}

SurfaceHit sphere_surface(uint i, vec3 pw) {
  return sphere_surface_of(load_sphere(i), pw);
}

// The surface of triangle `tri` at barycentrics (b1, b2).
SurfaceHit triangle_surface_of(Triangle tri, float b1, float b2) {
  float b0 = 1.0f - b1 - b2;
  SurfaceHit s;
  s.p = tri.v0 * b0 + tri.v1 * b1 + tri.v2 * b2;
  s.ng = normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
  s.ns = s.ng;
  s.uv = vec2(b1, b2);
  if (FEATURE_COMPILED(FEATURE_SHADING_DATA) && tri.shading != WP_INVALID) {
    TriangleShading sh = load_shading(tri.shading);
    s.uv = vec2(sh.u0, sh.v0) * b0 + vec2(sh.uv12.x, sh.uv12.y) * b1 + vec2(sh.uv12.z, sh.uv12.w) * b2;
    if (sh.hasNormals != 0u) {
      vec3 n = sh.n0 * b0 + sh.n1 * b1 + sh.n2 * b2;
      float len = length(n);
      if (len > 0.0f) s.ns = dot(n, s.ng) >= 0.0f ? n / len : -n / len;
    }
  }
  s.material = tri.material;
  s.emitter = tri.emitter;
  s.pad = 0.0f;
  return s;
}

SurfaceHit triangle_surface(uint i, float b1, float b2) {
  return triangle_surface_of(load_triangle(i), b1, b2);
}

// The surface at a hit of the ray (o, d).
SurfaceHit surface_at(vec3 o, vec3 d, Hit h) {
  if (FEATURE_COMPILED(FEATURE_SPHERES) && (h.prim & HIT_SPHERE_BIT) != 0u) return sphere_surface(h.prim & ~HIT_SPHERE_BIT, o + d * h.t);
  return triangle_surface(h.prim, h.u, h.v);
}

// The material at a ray's hit, or WP_INVALID where it hit nothing. Only the
// texel holding the material is fetched; the loaders stay the one definition
// of where it lies.
uint hit_material(Hit h) {
  if (h.prim == WP_INVALID) return WP_INVALID;
  if (FEATURE_COMPILED(FEATURE_SPHERES) && (h.prim & HIT_SPHERE_BIT) != 0u) return load_sphere(h.prim & ~HIT_SPHERE_BIT).material;
  return load_triangle(h.prim).material;
}

float triangle_area(Triangle tri) {
  return 0.5f * length(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
}

#endif  // WP_SURFACES_GLSL
