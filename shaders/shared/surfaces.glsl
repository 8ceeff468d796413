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

// A vertex tangent of an instance's mesh in world space, unit (zero stays
// zero: the kernels then derive one from the UVs).
vec3 placed_tangent(Instance inst, vec3 t) {
  vec3 w = xform_vector(inst.toWorld0, inst.toWorld1, inst.toWorld2, t);
  float len = length(w);
  return len > 0.0f ? w / len : vec3(0.0f);
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

// The surface of triangle `tri` at barycentrics (b1, b2), where `tri` is a
// triangle of the mesh of `instance` (WP_INVALID: a triangle in world space):
// its corners, vertex normals and tangents placed in world space as
// scene.cpp places those of an instance it flattens, so that an instance
// and its flattened copy have the same surface: each vertex normal through
// the inverse transpose and each tangent through the transform, normalized
// before they are interpolated, and a mirroring transform turning the
// bitangent's handedness and (glTF's rule: the determinant decides the
// winding, so the mesh's front stays the front) the order of the corners.
SurfaceHit triangle_surface_placed(Triangle tri, float b1, float b2, uint instance) {
  bool placed = FEATURE_COMPILED(FEATURE_INSTANCES) && instance != WP_INVALID;
  Instance inst;
  bool turned = false;  // corners 1 and 2 (and their data) swapped
  if (placed) {
    inst = load_instance(instance);
    turned = (inst.flags & INSTANCE_MIRRORED) != 0u;
    vec3 v1 = xform_point(inst.toWorld0, inst.toWorld1, inst.toWorld2, tri.v1);
    vec3 v2 = xform_point(inst.toWorld0, inst.toWorld1, inst.toWorld2, tri.v2);
    tri.v0 = xform_point(inst.toWorld0, inst.toWorld1, inst.toWorld2, tri.v0);
    tri.v1 = turned ? v2 : v1;
    tri.v2 = turned ? v1 : v2;
    float b = b1;
    b1 = turned ? b2 : b1;
    b2 = turned ? b : b2;
  }
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
    if (turned) {
      vec3 n1 = sh.n1;
      sh.n1 = sh.n2;
      sh.n2 = n1;
      sh.uv12 = vec4(sh.uv12.z, sh.uv12.w, sh.uv12.x, sh.uv12.y);
    }
    t0 = vec2(sh.u0, sh.v0);
    t1 = vec2(sh.uv12.x, sh.uv12.y);
    t2 = vec2(sh.uv12.z, sh.uv12.w);
    vec2 uv = t0 * b0 + t1 * b1 + t2 * b2;
    s.uv = vec4(uv.x, uv.y, uv.x, uv.y);
    if ((sh.flags & SHADING_NORMALS) != 0u) {
      if (placed) {
        sh.n0 = normalize(xform_normal_by_inverse(inst.toObject0, inst.toObject1, inst.toObject2, sh.n0));
        sh.n1 = normalize(xform_normal_by_inverse(inst.toObject0, inst.toObject1, inst.toObject2, sh.n1));
        sh.n2 = normalize(xform_normal_by_inverse(inst.toObject0, inst.toObject1, inst.toObject2, sh.n2));
      }
      vec3 n = sh.n0 * b0 + sh.n1 * b1 + sh.n2 * b2;
      float len = length(n);
      if (len > 0.0f) s.ns = dot(n, s.ng) >= 0.0f ? n / len : -n / len;
    }
    if (FEATURE_COMPILED(FEATURE_VERTEX_DATA) && (sh.flags & SHADING_VERTEX_DATA) != 0u) {
      TriangleVertexData vd = load_vertex_data(tri.shading);
      if (turned) {
        vec4 t1 = vd.tangent1;
        vd.tangent1 = vd.tangent2;
        vd.tangent2 = t1;
        vec4 c1 = vd.color1;
        vd.color1 = vd.color2;
        vd.color2 = c1;
        vec4 u = vd.uv1_01;
        vd.uv1_01 = vec4(u.x, u.y, vd.uv1_2.x, vd.uv1_2.y);
        vd.uv1_2 = vec4(u.z, u.w, 0.0f, 0.0f);
      }
      s.color = vd.color0 * b0 + vd.color1 * b1 + vd.color2 * b2;
      vec2 uv1 = vec2(vd.uv1_01.x, vd.uv1_01.y) * b0 + vec2(vd.uv1_01.z, vd.uv1_01.w) * b1 + vec2(vd.uv1_2.x, vd.uv1_2.y) * b2;
      s.uv = vec4(uv.x, uv.y, uv1.x, uv1.y);
      if (TANGENTS_COMPILED) {
        float handedness = vd.tangent0.w < 0.0f ? -1.0f : 1.0f;
        if (placed) {
          vd.tangent0 = vec4(placed_tangent(inst, vec3(vd.tangent0.x, vd.tangent0.y, vd.tangent0.z)), 0.0f);
          vd.tangent1 = vec4(placed_tangent(inst, vec3(vd.tangent1.x, vd.tangent1.y, vd.tangent1.z)), 0.0f);
          vd.tangent2 = vec4(placed_tangent(inst, vec3(vd.tangent2.x, vd.tangent2.y, vd.tangent2.z)), 0.0f);
          if (turned) handedness = -handedness;
        }
        vec4 t = vd.tangent0 * b0 + vd.tangent1 * b1 + vd.tangent2 * b2;
        s.tangent = vec4(t.x, t.y, t.z, handedness);
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

// The same for a triangle in world space.
SurfaceHit triangle_surface_of(Triangle tri, float b1, float b2) {
  return triangle_surface_placed(tri, b1, b2, WP_INVALID);
}

SurfaceHit triangle_surface(uint i, float b1, float b2) {
  return triangle_surface_of(load_triangle(i), b1, b2);
}

// The surface at a hit of the ray (o, d).
SurfaceHit surface_at(vec3 o, vec3 d, Hit h) {
  if (FEATURE_COMPILED(FEATURE_SPHERES) && (h.prim & HIT_SPHERE_BIT) != 0u) return sphere_surface(h.prim & ~HIT_SPHERE_BIT, o + d * h.t);
  return triangle_surface_placed(load_triangle(h.prim), h.u, h.v, h.instance);
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
