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
  vec4 uv;       // texture coordinates: xy the first set, zw the second (glTF's TEXCOORD_1; else the first again)
  vec4 tangent;  // for normal maps and anisotropy: xyz the tangent along increasing u (not unit), w the bitangent's handedness (+-1)
  vec4 color;    // the vertex colour, RGBA (1 without)
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
  vec2 uv = sphere_uv(pl);
  s.uv = vec4(uv.x, uv.y, uv.x, uv.y);
  // d p / d u of sphere_uv, along the parallels (zero at the poles).
  vec3 t = TANGENTS_COMPILED ? xform_vector(sp.toWorld0, sp.toWorld1, sp.toWorld2, vec3(pl.z, 0.0f, -pl.x)) : vec3(0.0f);
  s.tangent = vec4(t.x, t.y, t.z, 1.0f);
  s.color = vec4(1.0f);
  s.material = sp.material;
  s.emitter = sp.emitter;
  s.pad = 0.0f;
  return s;
}

SurfaceHit sphere_surface(uint i, vec3 pw) {
  return sphere_surface_of(load_sphere(i), pw);
}

// The tangent (d p / d u, not unit) and its handedness of a triangle with
// corners v0, v1, v2 at UVs t0, t1, t2, for normal maps where the mesh has
// no tangents; zero where the UVs are degenerate.
vec4 triangle_uv_tangent(Triangle tri, vec2 t0, vec2 t1, vec2 t2, vec3 ng) {
  vec3 e1 = tri.v1 - tri.v0;
  vec3 e2 = tri.v2 - tri.v0;
  vec2 d1 = t1 - t0;
  vec2 d2 = t2 - t0;
  float det = d1.x * d2.y - d2.x * d1.y;
  if (det == 0.0f) return vec4(0.0f, 0.0f, 0.0f, 1.0f);
  vec3 dpdu = (e1 * d2.y - e2 * d1.y) / det;
  vec3 dpdv = (e2 * d1.x - e1 * d2.x) / det;
  return vec4(dpdu.x, dpdu.y, dpdu.z, dot(cross(ng, dpdu), dpdv) < 0.0f ? -1.0f : 1.0f);
}

// The surface of triangle `tri` at barycentrics (b1, b2).
SurfaceHit triangle_surface_of(Triangle tri, float b1, float b2) {
  float b0 = 1.0f - b1 - b2;
  SurfaceHit s;
  s.p = tri.v0 * b0 + tri.v1 * b1 + tri.v2 * b2;
  s.ng = normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
  s.ns = s.ng;
  s.uv = vec4(b1, b2, b1, b2);
  s.tangent = vec4(0.0f, 0.0f, 0.0f, 1.0f);
  s.color = vec4(1.0f);
  vec2 t0 = vec2(0.0f, 0.0f);
  vec2 t1 = vec2(1.0f, 0.0f);
  vec2 t2 = vec2(0.0f, 1.0f);
  if (FEATURE_COMPILED(FEATURE_SHADING_DATA) && tri.shading != WP_INVALID) {
    TriangleShading sh = load_shading(tri.shading);
    t0 = vec2(sh.u0, sh.v0);
    t1 = vec2(sh.uv12.x, sh.uv12.y);
    t2 = vec2(sh.uv12.z, sh.uv12.w);
    vec2 uv = t0 * b0 + t1 * b1 + t2 * b2;
    s.uv = vec4(uv.x, uv.y, uv.x, uv.y);
    if ((sh.flags & SHADING_NORMALS) != 0u) {
      vec3 n = sh.n0 * b0 + sh.n1 * b1 + sh.n2 * b2;
      float len = length(n);
      if (len > 0.0f) s.ns = dot(n, s.ng) >= 0.0f ? n / len : -n / len;
    }
    if (FEATURE_COMPILED(FEATURE_VERTEX_DATA) && (sh.flags & SHADING_VERTEX_DATA) != 0u) {
      TriangleVertexData vd = load_vertex_data(tri.shading);
      s.color = vd.color0 * b0 + vd.color1 * b1 + vd.color2 * b2;
      vec2 uv1 = vec2(vd.uv1_01.x, vd.uv1_01.y) * b0 + vec2(vd.uv1_01.z, vd.uv1_01.w) * b1 + vec2(vd.uv1_2.x, vd.uv1_2.y) * b2;
      s.uv = vec4(uv.x, uv.y, uv1.x, uv1.y);
      if (TANGENTS_COMPILED) {
        vec4 t = vd.tangent0 * b0 + vd.tangent1 * b1 + vd.tangent2 * b2;
        s.tangent = vec4(t.x, t.y, t.z, vd.tangent0.w < 0.0f ? -1.0f : 1.0f);
      }
    }
  }
  if (TANGENTS_COMPILED && s.tangent.x == 0.0f && s.tangent.y == 0.0f && s.tangent.z == 0.0f)
    s.tangent = triangle_uv_tangent(tri, t0, t1, t2, s.ng);
  s.material = tri.material & TRIANGLE_MATERIAL_MASK;
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
  return load_triangle(h.prim).material & TRIANGLE_MATERIAL_MASK;
}

float triangle_area(Triangle tri) {
  return 0.5f * length(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
}

#endif  // WP_SURFACES_GLSL
