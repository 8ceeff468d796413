// scene.glsl — queries against the uploaded scene: BVH traversal, surface
// interactions, textures, materials and emitter sampling, one concern a file.
// They read the buffers `scene`, `nodeTexels`, `triangleTexels` and the rest:
// in GLSL the descriptor bindings of bindings.glsl; in C++ this file is
// included inside struct wp::shader::SceneView, whose members carry the same
// names.
#ifndef WP_SCENE_GLSL
#define WP_SCENE_GLSL

#include "records.glsl"
#include "spectral.glsl"
#include "surfaces.glsl"
#include "textures.glsl"
#include "traverse_binary.glsl"
#include "traverse_wide.glsl"
#include "material_at.glsl"
#include "lights.glsl"
#include "media.glsl"
#include "photons.glsl"

#endif  // WP_SCENE_GLSL
