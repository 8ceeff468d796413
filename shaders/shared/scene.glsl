// scene.glsl — queries against the uploaded scene: BVH traversal, surface
// interactions and emitter sampling. Reads the buffers `scene`, `nodes`,
// `triangles`, `spheres`, `materials` and `emitters`: in GLSL they are the
// descriptor bindings of bindings.glsl; in C++ this file is included inside
// struct wp::shader::SceneView, whose members carry the same names.
#ifndef WP_SCENE_GLSL
#define WP_SCENE_GLSL

#define TRACE_OK 0u
#define TRACE_TRUNCATED 1u

struct SurfaceHit {
  vec3 p;  // position, reprojected onto the surface
  uint material;
  vec3 ng;  // unit geometric normal; its side is the emitting (front) side
  uint emitter;
};

struct LightSample {
  vec3 p;
  float pdfArea;  // pick probability / area: density per unit area
  vec3 n;
  float pad;
  vec3 emission;
};

// Walks the BVH (ordered, stack-based). With anyHit it stops at the first hit
// (shadow rays).
//
// Loop budget: lavapipe silently ends all loops of a shader invocation after
// 65,535 iterations in total, and counts the iterations of nested loops in ways
// a counter cannot follow. So the walk is one flat loop in which every
// iteration does exactly one thing, visit one node or test one primitive, and
// counts itself against scene.counts.z (below the budget). A walk that reaches
// the cap returns TRACE_TRUNCATED, which the host turns into an error.
uint trace_ray(vec3 o, vec3 d, float tmax, bool anyHit, OUT(Hit) hit) {
  hit.t = tmax;
  hit.prim = WP_INVALID;
  hit.u = 0.0f;
  hit.v = 0.0f;
  vec3 invDir = vec3(1.0f) / d;
  RayShear sh = make_ray_shear(d);
  // Nodes are named by their (leftFirst, count) pair, read when their parent
  // tested their boxes, so each node is fetched from memory once.
  uvec2 stack[BVH_MAX_DEPTH];
  uint sp = 0u;
  BvhNode root = nodes[0];
  uvec2 node = uvec2(root.leftFirst, root.count);
  bool haveNode = true;  // `node` is still to be visited
  uint leafNext = 0u;    // primitives [leafNext, leafEnd) of the current leaf remain
  uint leafEnd = 0u;
  bool leafSpheres = false;
  uint steps = 0u;
  uint cap = scene.counts.z;
  if (root.count == 0u && intersect_aabb(o, invDir, root.bmin, root.bmax, tmax) == WP_INF) return TRACE_OK;
  while (true) {
    steps += 1u;
    if (steps > cap) return TRACE_TRUNCATED;
    if (leafNext < leafEnd) {
      uint i = leafNext;
      leafNext += 1u;
      float t;
      if (leafSpheres) {
        Sphere s = spheres[i];
        vec3 ol = xform_point(s.toObject0, s.toObject1, s.toObject2, o);
        vec3 dl = xform_vector(s.toObject0, s.toObject1, s.toObject2, d);
        if (intersect_unit_sphere(ol, dl, hit.t, t)) {
          hit.t = t;
          hit.prim = i | HIT_SPHERE_BIT;
        }
      } else {
        Triangle tri = triangles[i];
        float u;
        float v;
        if (intersect_triangle(o, sh, tri.v0, tri.v1, tri.v2, hit.t, t, u, v)) {
          hit.t = t;
          hit.prim = i;
          hit.u = u;
          hit.v = v;
        }
      }
      if (anyHit && hit.prim != WP_INVALID) return TRACE_OK;
      continue;
    }
    if (!haveNode) {
      if (sp == 0u) break;
      sp -= 1u;
      node = stack[sp];
    }
    haveNode = false;
    if (node.y != 0u) {
      leafNext = node.x;
      leafEnd = node.x + (node.y & ~BVH_SPHERE_LEAF);
      leafSpheres = (node.y & BVH_SPHERE_LEAF) != 0u;
      continue;
    }
    BvhNode n0 = nodes[node.x];
    BvhNode n1 = nodes[node.x + 1u];
    float d0 = intersect_aabb(o, invDir, n0.bmin, n0.bmax, hit.t);
    float d1 = intersect_aabb(o, invDir, n1.bmin, n1.bmax, hit.t);
    uvec2 near = uvec2(n0.leftFirst, n0.count);
    uvec2 far = uvec2(n1.leftFirst, n1.count);
    if (d1 < d0) {
      float td = d0;
      d0 = d1;
      d1 = td;
      uvec2 tn = near;
      near = far;
      far = tn;
    }
    if (d0 == WP_INF) continue;  // neither child: pop on the next iteration
    node = near;
    haveNode = true;
    if (d1 != WP_INF) {
      stack[sp] = far;
      sp += 1u;
    }
  }
  return TRACE_OK;
}

// Position and normals at a hit of the ray (o, d).
SurfaceHit surface_at(vec3 o, vec3 d, Hit h) {
  SurfaceHit s;
  if ((h.prim & HIT_SPHERE_BIT) != 0u) {
    Sphere sp = spheres[h.prim & ~HIT_SPHERE_BIT];
    // Reproject onto the unit sphere in object space: removes the error of o + t d.
    vec3 pl = normalize(xform_point(sp.toObject0, sp.toObject1, sp.toObject2, o + d * h.t));
    s.p = xform_point(sp.toWorld0, sp.toWorld1, sp.toWorld2, pl);
    s.ng = normalize(xform_normal_by_inverse(sp.toObject0, sp.toObject1, sp.toObject2, pl));
    s.material = sp.material;
    s.emitter = sp.emitter;
  } else {
    Triangle tri = triangles[h.prim];
    s.p = tri.v0 * (1.0f - h.u - h.v) + tri.v1 * h.u + tri.v2 * h.v;
    s.ng = normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
    s.material = tri.material;
    s.emitter = tri.emitter;
  }
  return s;
}

float triangle_area(Triangle tri) {
  return 0.5f * length(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
}

// Density per unit area with which sample_emitter picks points on `emitter`.
float emitter_pdf_area(uint emitter) {
  Emitter e = emitters[emitter];
  if ((e.prim & HIT_SPHERE_BIT) != 0u) return e.pmf / spheres[e.prim & ~HIT_SPHERE_BIT].area;
  return e.pmf / triangle_area(triangles[e.prim]);
}

// Picks an emitter index with the alias table (in proportion to power) and
// returns the probability of that pick.
uint pick_emitter(float u, OUT(float) pmf) {
  uint count = scene.counts.x;
  float x = u * float(count);
  uint i = min(uint(x), count - 1u);
  Emitter e = emitters[i];
  uint chosen = (x - float(i)) < e.threshold ? i : e.alias;
  pmf = emitters[chosen].pmf;
  return chosen;
}

// Picks an emitter, then a uniform point on it.
bool sample_emitter(vec3 u, OUT(LightSample) ls) {
  if (scene.counts.x == 0u) return false;
  float pmf;
  Emitter ec = emitters[pick_emitter(u.x, pmf)];
  vec2 uv = vec2(u.y, u.z);
  if ((ec.prim & HIT_SPHERE_BIT) != 0u) {
    Sphere sp = spheres[ec.prim & ~HIT_SPHERE_BIT];
    vec3 pl = square_to_uniform_sphere(uv);
    ls.p = xform_point(sp.toWorld0, sp.toWorld1, sp.toWorld2, pl);
    ls.n = normalize(xform_normal_by_inverse(sp.toObject0, sp.toObject1, sp.toObject2, pl));
    ls.pdfArea = ec.pmf / sp.area;
    Material m = materials[sp.material];
    ls.emission = vec3(m.emission.x, m.emission.y, m.emission.z);
  } else {
    Triangle tri = triangles[ec.prim];
    vec2 b = square_to_triangle_barycentric(uv);
    ls.p = tri.v0 * (1.0f - b.x - b.y) + tri.v1 * b.x + tri.v2 * b.y;
    vec3 c = cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
    float len = length(c);
    ls.n = c / len;
    ls.pdfArea = ec.pmf / (0.5f * len);
    Material m = materials[tri.material];
    ls.emission = vec3(m.emission.x, m.emission.y, m.emission.z);
  }
  ls.pad = 0.0f;
  return true;
}

#endif  // WP_SCENE_GLSL
