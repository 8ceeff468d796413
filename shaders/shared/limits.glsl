// limits.glsl — the bounds that loaders, the host and the kernels must agree
// on, each defined once. Shared by GLSL and C++ (plain defines).
#ifndef WP_LIMITS_GLSL
#define WP_LIMITS_GLSL

// Deepest binary BVH the builder may produce; the traversal stack never needs
// more slots than that.
#define BVH_MAX_DEPTH 80
#define BVH_MAX_LEAF_SIZE 255
// Lobes a BSDF holds at most: a blend tree flattens to at most this many
// leaves (the loaders refuse more), so bsdf_at's loops are bounded.
#define BSDF_MAX_LOBES 4
// Layers (clearcoat, sheen) lie at most this deep over a base material, and
// a material holds at most one sheen (the loaders refuse more).
#define LAYERS_MAX 2
// The narrowest GGX lobe (alpha, roughness squared) the microfacet
// materials take: below it a conductor or dielectric is a smooth delta lobe,
// and glTF's metal-rough (which has no delta lobe) is widened to it.
#define GGX_MIN_ALPHA 1e-3f
// The least index metal-rough refracts with: at an index of exactly 1 (which
// glTF allows, and dispersion's red reaches) Walter et al.'s BTDF divides by
// wo.h + eta wi.h, which float rounding leaves at about 0 (non-finite
// samples); at 1.001 the reflectance differs by 2.5e-7.
#define METAL_ROUGH_MIN_IOR 1.001f
// Checker textures nest at most this deep (texture_eval follows the picks).
#define TEXTURE_MAX_NESTING 8
// Most next-event-estimation samples per path vertex (CS184's -l: its
// assignment renders with up to 64).
#define MAX_LIGHT_SAMPLES 64u
// Widest and tallest image, in pixels: the kernels find a pixel's row and
// column by a float division that is exact for quotients below 2^14
// (pixel_xy in integrator.glsl).
#define MAX_IMAGE_SIZE 16384
// Most samples per pixel a render may ask for.
#define MAX_SAMPLES_PER_PIXEL (1 << 24)
// Iterations one BVH traversal may take before it reports itself truncated.
// lavapipe ends all loops of an invocation silently after 65,535 iterations
// in total; a traversal capped here stays below that, and the megakernel
// shares it among a whole path's traversals.
#define TRAVERSAL_STEP_BUDGET 60000u
// Invocations a tracing dispatch that shares rays among a subgroup's lanes
// (trace_items.glsl) has at least on a GPU, rays permitting: an H200's 132
// SMs hold about 30 warps each of the tracing kernels (68 registers), and
// sixteen rays to an invocation left most of them empty.
#define TRACING_INVOCATIONS_ON_GPUS 131072u
// The invocations of a tracing dispatch of n rays, `rays` to an invocation,
// and at least `fill` (or n) of them.
#define TRACING_INVOCATIONS(n, rays, fill) \
  ((n) < (fill) ? (n) : (((n) + (rays) - 1u) / (rays) > (fill) ? ((n) + (rays) - 1u) / (rays) : (fill)))
// Most emitters the mixture integrator allows: its exact light density visits
// every emitter at every bounce.
#define MAX_MIXTURE_EMITTERS 16384u
// Participating media (media.glsl). Collisions one free flight or one
// transmittance estimate takes at most (loops must be bounded on lavapipe).
#define MEDIUM_COLLISIONS_MAX 256u
// Interfaces (surfaces without scattering, MAT_INTERFACE) one path passes
// at most, in all: each costs the path a trace without a bounce, so the
// kernels run this many passes beyond max bounces + 1. A path that would
// pass more ends there.
#define MEDIUM_CROSSINGS_MAX 16u
// Media a scene may have: a shadow ray keeps its medium in 16 bits.
#define MEDIA_MAX 65535u
// A grid medium's majorant grid has at most this many cells along an axis
// (Medium.info.w packs them in 10 bits each); a flight walks at most three
// times this many cells besides its collisions.
#define MAJORANT_GRID_CELLS_MAX 64u
// Root tiles a NanoVDB grid may have (each spans 4096^3 voxels): a lookup
// that misses its accessor's cache searches them one by one, a loop that
// shares lavapipe's budget.
#define NANOVDB_ROOT_TILES_MAX 64u
// Photon mapping (photons.glsl): photons one gather may take (the search count), the
// levels of its heap, the kd-tree ranges its search keeps (a tree of 2^31
// photons is 31 deep) and the nodes it visits at most (lavapipe's loop
// budget; a search that reaches it ends with what it found).
#define PHOTON_SEARCH_MAX 128u
#define PHOTON_HEAP_LEVELS 8u
#define PHOTON_STACK_MAX 64u
#define PHOTON_SEARCH_STEPS_MAX 16384u

#endif  // WP_LIMITS_GLSL
