// kernel.glsl — prelude of every compute kernel: the shared headers in order.
#include "common.glsl"
#include "types.glsl"
#include "bindings.glsl"
#include "rng.glsl"
#include "sampling.glsl"
#include "noise.glsl"
#include "intersect.glsl"
#include "bsdf.glsl"
#include "scene.glsl"
#include "integrator.glsl"

// The workgroup size is specialization constant 0 (WORKGROUP_SIZE unless a
// kernel variant sets it), so one SPIR-V module serves every size.
layout(local_size_x_id = 0) in;
layout(constant_id = 0) const uint kWorkgroupSize = WORKGROUP_SIZE;
