// wide_walk_state.glsl — the wide BVH walk's locals for one ray (scene.glsl).
// A fragment of a function body, not a header: see wide_walk_step.glsl.
// wide_walk_begin.glsl gives them their values for a ray.
vec3 ro;  // the ray in the space being walked: the world's (o, d), or an instance's
vec3 rd;
uint instance;  // the instance being walked, or WP_INVALID: the top level
RayShear sh;
vec3 invDir;
bool negX;
bool negY;
bool negZ;
uint xorSlot;
bool inRegisters = TRAVERSAL_STACK_SLOTS <= WIDE_REGISTER_STACK;
uvec2 regs[WIDE_REGISTER_STACK];    // the stack, top first, when inRegisters
uvec2 stack[TRAVERSAL_STACK_SIZE];  // the stack, bottom first, otherwise
uint sp;
uint primGroupsSetAside;  // primitive groups on the stack
uint visit;               // the node to visit in this iteration (the root first), or WP_INVALID
uvec2 nodeGroup;          // x: first interior child; y: the hit ones still to visit (wide_walk_step.glsl)
uvec2 primGroup;          // x: first primitive; y: remaining hit bits (0-23)
// Cleared once, not at the start of each ray: entries above the top are
// never read, and in the multi-ray loop (trace_items.glsl) a ray's start runs,
// masked, in every iteration (bounce rays about 2 % faster on one core).
WP_CLEAR_REGISTER_STACK(regs);
