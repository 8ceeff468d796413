// kernel.glsl — prelude of every compute kernel: the shared headers in order.
#include "common.glsl"
#include "types.glsl"
#include "bindings.glsl"
#include "rng.glsl"
#include "sampling.glsl"
#include "intersect.glsl"
#include "bsdf.glsl"
#include "scene.glsl"
#include "integrator.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;
