// traverse_binary.glsl — the primitive tests of both walks, and the walk of
// the binary BVH (BvhNode).
//
//
// Loop budget: lavapipe silently ends all loops of a shader invocation after
// 65,535 iterations in total, and counts the iterations of nested loops in ways
// a counter cannot follow. So each walk is one flat loop whose every iteration
// does a bounded amount of work and counts itself against scene.counts.z
// (below the budget). A walk that reaches the cap returns TRACE_TRUNCATED,
// which the host turns into an error.

#ifndef WP_TRAVERSE_BINARY_GLSL
#define WP_TRAVERSE_BINARY_GLSL

#define TRACE_OK 0u
#define TRACE_TRUNCATED 1u

// Whether the ray (o, d) that meets triangle record i, `tri`, at
// barycentrics (b1, b2) takes the hit: a one-sided triangle is not there
// from behind, and a cut-out not where its alpha (its material's albedo
// texture's, times the vertex colour's) falls below its material's cutoff.
// A negative cutoff is stochastic transparency: the cutoff is then a number
// in [0, 1) hashed from the ray and the triangle, so that a ray passes with
// probability 1 - alpha, and the same ray always decides the same way.
// Within an instance, (o, d) and `tri` are in its mesh's space; an
// instance's front is its mesh's front placed, even where the transform
// mirrors (glTF's rule, surfaces.glsl), so the test is the same.
bool triangle_is_there(uint i, Triangle tri, vec3 o, vec3 d, float b1, float b2) {
  if (FEATURE_COMPILED(FEATURE_ONE_SIDED) && (tri.material & TRIANGLE_ONE_SIDED) != 0u &&
      dot(cross(tri.v1 - tri.v0, tri.v2 - tri.v0), d) > 0.0f)
    return false;
  if (!FEATURE_COMPILED(FEATURE_CUTOUTS) || (tri.material & TRIANGLE_CUTOUT) == 0u) return true;
  SurfaceHit s = triangle_surface_of(tri, b1, b2);
  Material m = surface_material(load_material(s.material));
  float alpha = texture_alpha(m.info.y, s.uv, s.p) * s.color.w;
  float cutoff = material_alpha_cutoff(m);
  if (cutoff >= 0.0f) return alpha >= cutoff;
  uint h = pcg_hash(i ^ pcg_hash(floatBitsToUint(d.x) ^ pcg_hash(floatBitsToUint(d.y) ^ pcg_hash(floatBitsToUint(d.z) ^
           pcg_hash(floatBitsToUint(o.x) ^ pcg_hash(floatBitsToUint(o.y) ^ pcg_hash(floatBitsToUint(o.z))))))));
  return alpha > float(h >> 8u) * (1.0f / 16777216.0f);
}

// Tests primitive record i (a triangle, or a sphere's placeholder), loaded as
// tri, and keeps the nearer hit. The ray (o, d) is in the space of
// `instance` (WP_INVALID: the world's).
void intersect_loaded_prim(uint i, Triangle tri, vec3 o, vec3 d, RayShear sh, uint instance, INOUT(Hit) hit) {
  float t;
  if (tri.material != WP_INVALID) {
    float u;
    float v;
    if (intersect_triangle(o, sh, tri.v0, tri.v1, tri.v2, hit.t, t, u, v) && triangle_is_there(i, tri, o, d, u, v)) {
      hit.t = t;
      hit.prim = i;
      hit.u = u;
      hit.v = v;
      hit.instance = instance;
    }
  } else if (FEATURE_COMPILED(FEATURE_SPHERES)) {
    Sphere sp = load_sphere(tri.shading);
    vec3 ol = xform_point(sp.toObject0, sp.toObject1, sp.toObject2, o);
    vec3 dl = xform_vector(sp.toObject0, sp.toObject1, sp.toObject2, d);
    if (intersect_unit_sphere(ol, dl, hit.t, t)) {
      hit.t = t;
      hit.prim = tri.shading | HIT_SPHERE_BIT;
      hit.u = 0.0f;
      hit.v = 0.0f;
      hit.instance = WP_INVALID;
    }
  }
}

// A hit of nothing yet, before tmax.
Hit no_hit(float tmax) {
  Hit hit;
  hit.t = tmax;
  hit.prim = WP_INVALID;
  hit.u = 0.0f;
  hit.v = 0.0f;
  hit.instance = WP_INVALID;
  hit.pad0 = 0u;
  hit.pad1 = 0u;
  hit.pad2 = 0u;
  return hit;
}

// Whether the ray o + t invDir^-1, t in (0, tmax), meets an instance's world
// box (its placeholder `tri`, types.glsl).
bool meets_instance(Triangle tri, vec3 o, vec3 invDir, float tmax) {
  return intersect_aabb(o, invDir, tri.v0, tri.v1, tmax) != WP_INF;
}

// Both walks keep one stack across the two levels. Entering an instance sets
// aside what remains of the top level, then an entry (the binary walk's:
// INSTANCE_RETURN_Y in y, which no other entry has; the wide walk's:
// WIDE_RETURN_X, traverse_wide.glsl) whose popping brings the walk back to
// world space; the instance's tree is walked above it with the ray taken into its
// mesh's space. The ray is not renormalized there, so distances along it
// stay those of the world ray and hit.t bounds both levels (as in pbrt-v4's
// TransformedPrimitive).
#define INSTANCE_RETURN_Y 0u

// The ray taken into instance `instance`'s mesh space (ro, rd and their
// derived terms); returns its tree's root as a node to visit.
uvec2 binary_enter_instance(uint instance, vec3 o, vec3 d, INOUT(vec3) ro, INOUT(vec3) rd, INOUT(vec3) invDir,
                            INOUT(RayShear) sh) {
  Instance inst = load_instance(instance);
  ro = xform_point(inst.toObject0, inst.toObject1, inst.toObject2, o);
  rd = xform_vector(inst.toObject0, inst.toObject1, inst.toObject2, d);
  invDir = vec3(1.0f) / rd;
  sh = make_ray_shear(rd);
  BvhNode blasRoot = load_node(inst.root);
  return uvec2(blasRoot.leftFirst, blasRoot.count);
}

// Both binary walks entering the instance `tri` names: set aside the rest of
// the current leaf (a leaf entry: count != 0), then the way back, and walk
// the instance's tree from its root (`node`, to visit). A macro, not a
// function: the stack would be copied into and out of it (lavapipe).
#define BINARY_WALK_ENTER_INSTANCE(tri)                              \
  if (leafNext < leafEnd) {                                          \
    WP_NOTE_STACK_WRITE(sp);                                         \
    stack[sp] = uvec2(leafNext, leafEnd - leafNext);                 \
    sp += 1u;                                                        \
  }                                                                  \
  WP_NOTE_STACK_WRITE(sp);                                           \
  stack[sp] = uvec2(0u, INSTANCE_RETURN_Y);                          \
  sp += 1u;                                                          \
  WP_NOTE_STACK_DEPTH(sp);                                           \
  leafNext = 0u;                                                     \
  leafEnd = 0u;                                                      \
  instance = tri.shading;                                            \
  node = binary_enter_instance(instance, o, d, ro, rd, invDir, sh);  \
  haveNode = true;

// The ray back in world space, out of an instance.
void binary_leave_instance(vec3 o, vec3 d, OUT(vec3) ro, OUT(vec3) rd, OUT(vec3) invDir, OUT(RayShear) sh) {
  ro = o;
  rd = d;
  invDir = vec3(1.0f) / d;
  sh = make_ray_shear(d);
}

// The binary walk's first node to visit, the root (named, as every node the
// walk visits, by its (leftFirst, count) pair): false where the ray misses
// the tree. An empty scene's root has an inverted box, which the slab test
// alone would take for the whole space.
bool binary_walk_root(vec3 o, vec3 invDir, float tmax, OUT(uvec2) node) {
  BvhNode root = load_node(0u);
  node = uvec2(root.leftFirst, root.count);
  bool empty = root.bmin.x > root.bmax.x;
  return root.count != 0u || (!empty && intersect_aabb(o, invDir, root.bmin, root.bmax, tmax) != WP_INF);
}

// Visits interior node `node` of the binary walk (its children's boxes
// tested against the ray in the space being walked): false where the ray
// misses both; else the nearer child hit in `near`, and whether the other
// was hit too, in `far` (to be set aside).
bool binary_visit(uvec2 node, vec3 ro, vec3 invDir, float tmax, OUT(uvec2) near, OUT(uvec2) far, OUT(bool) both) {
  BvhNode n0 = load_node(node.x);
  BvhNode n1 = load_node(node.x + 1u);
  float d0 = intersect_aabb(ro, invDir, n0.bmin, n0.bmax, tmax);
  float d1 = intersect_aabb(ro, invDir, n1.bmin, n1.bmax, tmax);
  near = uvec2(n0.leftFirst, n0.count);
  far = uvec2(n1.leftFirst, n1.count);
  if (d1 < d0) {
    float td = d0;
    d0 = d1;
    d1 = td;
    uvec2 tn = near;
    near = far;
    far = tn;
  }
  both = d1 != WP_INF;
  return d0 != WP_INF;
}

// The binary BVH (BvhNode), ordered and stack-based: each iteration visits one
// node (testing both children's boxes) or tests one primitive; or, fused
// (BINARY_FUSED_OF_SCENE: RenderOptions::binaryFused, the variants
// gpu-bvh2-fused and gpu-mega-bvh2-fused, the CPU reference), both.
//
// Fused, it is Aila and Laine's (2009) speculative traversal in one loop: each
// iteration tests the current leaf's next primitive and also takes a node from
// the stack and visits it, so that in a warp the lanes testing primitives and
// the lanes descending share an iteration instead of taking turns. A leaf the
// descent reaches while another is being tested waits as the node to visit (one
// postponed leaf, as theirs) and becomes the current leaf once that one is
// done: the same hits, in fewer iterations of more work each.
uint trace_binary(vec3 o, vec3 d, float tmax, bool anyHit, OUT(Hit) hit) {
  hit = no_hit(tmax);
  // The ray in the space being walked: the world's, or an instance's.
  vec3 ro = o;
  vec3 rd = d;
  uint instance = WP_INVALID;
  vec3 invDir = vec3(1.0f) / d;
  RayShear sh = make_ray_shear(d);
  // Nodes are named by their (leftFirst, count) pair, read when their parent
  // tested their boxes, so each node is fetched from memory once.
  uvec2 stack[TRAVERSAL_STACK_SIZE];
  uint sp = 0u;
  uvec2 node;
  if (!binary_walk_root(o, invDir, tmax, node)) return TRACE_OK;
  bool haveNode = true;  // `node` is still to be visited
  uint leafNext = 0u;    // primitives [leafNext, leafEnd) of the current leaf remain
  uint leafEnd = 0u;
  uint steps = 0u;
  uint cap = scene.counts.z;
  while (true) {
    steps += 1u;
    if (steps > cap) return TRACE_TRUNCATED;
    WP_NOTE_STEP();
    if (BINARY_FUSED_OF_SCENE) {
      if (leafNext < leafEnd) {
        WP_NOTE_PHASE(WALK_PHASE_PRIM);
        Triangle tri = load_triangle(leafNext);
        leafNext += 1u;
        if (FEATURE_COMPILED(FEATURE_INSTANCES) && tri.material == PRIM_INSTANCE) {
          if (meets_instance(tri, o, invDir, hit.t)) {
            // Set aside the node waiting first (popped last); the instance's
            // root is the node this iteration visits.
            WP_NOTE_PHASE(WALK_PHASE_INSTANCE);
            if (haveNode) {
              WP_NOTE_STACK_WRITE(sp);
              stack[sp] = node;
              sp += 1u;
            }
            BINARY_WALK_ENTER_INSTANCE(tri)
          }
        } else {
          intersect_loaded_prim(leafNext - 1u, tri, ro, rd, sh, instance, hit);
          if (anyHit && hit.prim != WP_INVALID) return TRACE_OK;
        }
      }
      // With no node waiting, take the top of the stack; the way back out of an
      // instance only once the instance's current leaf is done.
      if (!haveNode && sp > 0u) {
        uvec2 top = stack[sp - 1u];
        bool isReturn = FEATURE_COMPILED(FEATURE_INSTANCES) && top.y == INSTANCE_RETURN_Y && top.x == 0u;
        if (!isReturn || leafNext >= leafEnd) {
          WP_NOTE_PHASE(WALK_PHASE_POP);
          sp -= 1u;
          WP_NOTE_STACK_READ(sp);
          if (isReturn) {
            binary_leave_instance(o, d, ro, rd, invDir, sh);
            instance = WP_INVALID;
          } else {
            node = top;
            haveNode = true;
          }
        }
      }
      if (haveNode && node.y == 0u) {
        WP_NOTE_PHASE(WALK_PHASE_NODE);
        WP_NOTE_PHASE(instance != WP_INVALID ? WALK_NOTE_NODE_IN_INSTANCE : 0u);
        uvec2 far;
        bool both;
        haveNode = binary_visit(node, ro, invDir, hit.t, node, far, both);
        if (haveNode && both) {
          WP_NOTE_STACK_WRITE(sp);
          stack[sp] = far;
          sp += 1u;
          WP_NOTE_STACK_DEPTH(sp);
        }
      }
      // A leaf waiting becomes the current one once that is done.
      if (haveNode && node.y != 0u && leafNext >= leafEnd) {
        WP_NOTE_PHASE(WALK_PHASE_LEAF);
        leafNext = node.x;
        leafEnd = node.x + node.y;
        haveNode = false;
      }
      if (!haveNode && sp == 0u && leafNext >= leafEnd) break;
      continue;
    }
    if (leafNext < leafEnd) {
      WP_NOTE_PHASE(WALK_PHASE_PRIM);
      Triangle tri = load_triangle(leafNext);
      leafNext += 1u;
      if (FEATURE_COMPILED(FEATURE_INSTANCES) && tri.material == PRIM_INSTANCE) {
        if (!meets_instance(tri, o, invDir, hit.t)) continue;
        WP_NOTE_PHASE(WALK_PHASE_INSTANCE);
        BINARY_WALK_ENTER_INSTANCE(tri)
        continue;
      }
      intersect_loaded_prim(leafNext - 1u, tri, ro, rd, sh, instance, hit);
      if (anyHit && hit.prim != WP_INVALID) return TRACE_OK;
      continue;
    }
    if (!haveNode) {
      if (sp == 0u) break;
      WP_NOTE_PHASE(WALK_PHASE_POP);
      sp -= 1u;
      WP_NOTE_STACK_READ(sp);
      node = stack[sp];
      if (FEATURE_COMPILED(FEATURE_INSTANCES) && node.y == INSTANCE_RETURN_Y && node.x == 0u) {
        // Back in world space. (An interior node's entry has count 0 too,
        // but never child 0: node 0 is the root.)
        binary_leave_instance(o, d, ro, rd, invDir, sh);
        instance = WP_INVALID;
        continue;
      }
    }
    haveNode = false;
    if (node.y != 0u) {
      WP_NOTE_PHASE(WALK_PHASE_LEAF);
      leafNext = node.x;
      leafEnd = node.x + node.y;
      continue;
    }
    WP_NOTE_PHASE(WALK_PHASE_NODE);
    WP_NOTE_PHASE(instance != WP_INVALID ? WALK_NOTE_NODE_IN_INSTANCE : 0u);
    uvec2 far;
    bool both;
    if (!binary_visit(node, ro, invDir, hit.t, node, far, both)) continue;  // neither child: pop on the next iteration
    haveNode = true;
    if (both) {
      WP_NOTE_STACK_WRITE(sp);
      stack[sp] = far;
      sp += 1u;
      WP_NOTE_STACK_DEPTH(sp);
    }
  }
  return TRACE_OK;
}

#endif  // WP_TRAVERSE_BINARY_GLSL
