// intersect.glsl — ray / primitive intersection shared by kernels and CPU.
// Rays are (origin o, direction d) with d not necessarily unit length; hits are
// reported as the ray parameter t, valid on (0, tmax). Self-intersection is
// avoided by offsetting origins off the surface (offset_ray), not by a tmin.
#ifndef WP_INTERSECT_GLSL
#define WP_INTERSECT_GLSL

// Robust origin offset (Waechter & Binder, Ray Tracing Gems ch. 6): move p
// along the geometric normal n by a few ulps in integer space, which scales with
// the magnitude of each coordinate; near zero use a small absolute offset.
vec3 offset_ray(vec3 p, vec3 n) {
  const float origin = 1.0f / 32.0f;
  const float floatScale = 1.0f / 65536.0f;
  const float intScale = 256.0f;
  int ox = int(intScale * n.x);
  int oy = int(intScale * n.y);
  int oz = int(intScale * n.z);
  vec3 pi = vec3(intBitsToFloat(floatBitsToInt(p.x) + (p.x < 0.0f ? -ox : ox)),
                 intBitsToFloat(floatBitsToInt(p.y) + (p.y < 0.0f ? -oy : oy)),
                 intBitsToFloat(floatBitsToInt(p.z) + (p.z < 0.0f ? -oz : oz)));
  return vec3(abs(p.x) < origin ? p.x + floatScale * n.x : pi.x,
              abs(p.y) < origin ? p.y + floatScale * n.y : pi.y,
              abs(p.z) < origin ? p.z + floatScale * n.z : pi.z);
}

// Slab test; returns the entry distance, or WP_INF when the box is missed or lies
// beyond tmax. invDir may hold infinities (x/0 = inf is IEEE on every target).
float intersect_aabb(vec3 o, vec3 invDir, vec3 bmin, vec3 bmax, float tmax) {
  vec3 t0 = (bmin - o) * invDir;
  vec3 t1 = (bmax - o) * invDir;
  vec3 lo = min(t0, t1);
  vec3 hi = max(t0, t1);
  float tnear = max(max(lo.x, lo.y), max(lo.z, 0.0f));
  float tfar = min(min(hi.x, hi.y), min(hi.z, tmax));
  // NaN (0 * inf on a slab plane) makes the comparisons false: treat as a hit
  // of that slab, which is conservative.
  return tnear <= tfar ? tnear : WP_INF;
}

// Per-ray constants of the watertight triangle test (Woop, Benthin & Wald,
// JCGT 2013): the axis permutation and shear that map the ray onto +Z.
struct RayShear {
  uint kx;
  uint ky;
  uint kz;
  vec3 s;  // Sx, Sy, Sz
};

float vec_component(vec3 v, uint i) {
  return i == 0u ? v.x : (i == 1u ? v.y : v.z);
}

RayShear make_ray_shear(vec3 d) {
  RayShear r;
  vec3 a = abs(d);
  r.kz = (a.x > a.y) ? (a.x > a.z ? 0u : 2u) : (a.y > a.z ? 1u : 2u);
  r.kx = r.kz == 2u ? 0u : r.kz + 1u;
  r.ky = r.kx == 2u ? 0u : r.kx + 1u;
  // Keep the winding: swap kx and ky when the dominant component is negative.
  if (vec_component(d, r.kz) < 0.0f) {
    uint tmp = r.kx;
    r.kx = r.ky;
    r.ky = tmp;
  }
  float dz = vec_component(d, r.kz);
  r.s = vec3(vec_component(d, r.kx) / dz, vec_component(d, r.ky) / dz, 1.0f / dz);
  return r;
}

// Watertight ray/triangle test. On a hit with t in (0, tmax) writes t and the
// barycentrics (u, v) of v1 and v2 and returns true. Edges shared by two
// triangles are never missed by both.
bool intersect_triangle(vec3 o, RayShear sh, vec3 v0, vec3 v1, vec3 v2, float tmax,
                        OUT(float) tHit, OUT(float) uHit, OUT(float) vHit) {
  vec3 A = v0 - o;
  vec3 B = v1 - o;
  vec3 C = v2 - o;
  float Az = vec_component(A, sh.kz);
  float Bz = vec_component(B, sh.kz);
  float Cz = vec_component(C, sh.kz);
  float Ax = vec_component(A, sh.kx) - sh.s.x * Az;
  float Ay = vec_component(A, sh.ky) - sh.s.y * Az;
  float Bx = vec_component(B, sh.kx) - sh.s.x * Bz;
  float By = vec_component(B, sh.ky) - sh.s.y * Bz;
  float Cx = vec_component(C, sh.kx) - sh.s.x * Cz;
  float Cy = vec_component(C, sh.ky) - sh.s.y * Cz;
  float U = Cx * By - Cy * Bx;
  float V = Ax * Cy - Ay * Cx;
  float W = Bx * Ay - By * Ax;
  // The paper recomputes an edge function that is exactly zero in double
  // precision; doubles are optional on GPUs, so a zero counts as inside instead:
  // a ray through a shared edge may hit both triangles, never neither.
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
  float det = U + V + W;
  if (det == 0.0f) return false;
  float T = sh.s.z * (U * Az + V * Bz + W * Cz);
  // t = T / det must lie in (0, tmax); compare without dividing, sign-aware.
  if (det < 0.0f ? (T >= 0.0f || T <= tmax * det) : (T <= 0.0f || T >= tmax * det)) return false;
  float inv = 1.0f / det;
  tHit = T * inv;
  uHit = V * inv;
  vHit = W * inv;
  return true;
}

// Unit sphere in object space, ray already transformed there (d unnormalised,
// so t is the world-space ray parameter). Numerically robust form of the
// quadratic (Ray Tracing Gems ch. 7). Returns the nearest root in (0, tmax).
bool intersect_unit_sphere(vec3 o, vec3 d, float tmax, OUT(float) tHit) {
  float a = dot(d, d);
  float b = dot(o, d);
  float c = dot(o, o) - 1.0f;
  vec3 l = o - d * (b / a);
  float disc = a * (1.0f - dot(l, l));
  if (disc < 0.0f) return false;
  float q = -(b + (b >= 0.0f ? 1.0f : -1.0f) * sqrt(disc));
  float t0 = c / q;
  float t1 = q / a;
  if (t0 > t1) {
    float tmp = t0;
    t0 = t1;
    t1 = tmp;
  }
  if (t0 > 0.0f && t0 < tmax) {
    tHit = t0;
    return true;
  }
  if (t1 > 0.0f && t1 < tmax) {
    tHit = t1;
    return true;
  }
  return false;
}

vec3 xform_point(vec4 r0, vec4 r1, vec4 r2, vec3 p) {
  vec4 h = vec4(p.x, p.y, p.z, 1.0f);
  return vec3(dot(r0, h), dot(r1, h), dot(r2, h));
}

vec3 xform_vector(vec4 r0, vec4 r1, vec4 r2, vec3 v) {
  vec4 h = vec4(v.x, v.y, v.z, 0.0f);
  return vec3(dot(r0, h), dot(r1, h), dot(r2, h));
}

// Normal transform: multiply by the transpose of the inverse (rows r = inverse).
vec3 xform_normal_by_inverse(vec4 r0, vec4 r1, vec4 r2, vec3 n) {
  return vec3(r0.x, r0.y, r0.z) * n.x + vec3(r1.x, r1.y, r1.z) * n.y + vec3(r2.x, r2.y, r2.z) * n.z;
}

#endif  // WP_INTERSECT_GLSL
