// kinds.glsl — every kind of material, texture and light, and every other
// feature the kernels can compile out, each listed once.
//
// A kind's id is also its bit in a kind mask (bit 1 << id): SceneParams.kinds
// holds the masks of what a scene uses (x materials, y textures, z lights,
// w features), compile_scene derives them from the ids it packs, and the
// kernels receive them as specialization constants (kernel.glsl). Code for a
// kind is guarded by MATERIAL_COMPILED(MAT_...) and its siblings below, so a
// kernel holds only the kinds its scene uses (on lavapipe every branch of a
// kernel costs every path its time, taken or not), and a kind cannot be left
// out of a mask by forgetting a bit: the bit is the id. Two kinds are never
// compiled out: a light material's check (one comparison) and the constant
// texture every lookup ends in. In C++ (the CPU reference) every kind is
// compiled.
//
// The tables are X-macros: WP_MATERIAL_KINDS(X) expands X(id, name, prefix,
// lobes) once per material kind, and so on. Adding a material kind means a
// define and a row here and its functions in materials/NAME.glsl (included by
// bsdf.glsl); the BSDF dispatch, the masks, `wavepath info` and the loaders'
// lists of valid names follow from the row. docs/architecture.md has the recipe.
#ifndef WP_KINDS_GLSL
#define WP_KINDS_GLSL

// What a material kind's lobe can do (the `lobes` column).
#define LOBE_DIFFUSE 0x1u       // a diffuse lobe: a density over the hemisphere
#define LOBE_GLOSSY 0x2u        // a glossy lobe: a density around a preferred direction
#define LOBE_DELTA 0x4u         // can be a delta lobe (a mirror, smooth glass): no density, no MIS
#define LOBE_TRANSMISSIVE 0x8u  // scatters through the surface
#define LOBE_EMISSIVE 0x10u     // only emits; scatters nothing (bsdf_at gives no lobe)
#define LOBE_COMPOSITE 0x20u    // mixes other materials, which bsdf_at flattens into their lobes
#define LOBE_PARAMS_YZW 0x40u   // reads Material.params beyond x
#define LOBE_PARAMS2 0x80u      // reads Material.params2
#define LOBE_LAYER 0x100u       // a layer over a base material (Material.children.x): bsdf_at adds its lobe and the base's
#define LOBE_NULL 0x200u        // no surface at all: a boundary between media that rays pass straight through (bsdf_at gives no lobe)

// Material kinds (Material.info.x). Columns: id; the kind's name (darts scene
// files use it); the prefix of its lobe functions in materials/*.glsl (kinds
// that have no lobe of their own use no_lobe); what its lobe can do and
// which parameters it reads. Parameters (Material.params, params2; the
// lobe's at the hit): metal roughness, dielectric ior, Phong and
// Blinn-Phong exponent in params.x; the GGX kinds as their files say.
#define MAT_LAMBERTIAN 0u
#define MAT_LIGHT 1u        // darts diffuse_light: emits, does not scatter
#define MAT_METAL 2u        // mirror direction plus `roughness` times a point on the unit sphere
#define MAT_DIELECTRIC 3u   // smooth glass: Fresnel reflection and refraction (delta)
#define MAT_PHONG 4u        // cos^n lobe around the mirror direction
#define MAT_BLINN_PHONG 5u  // cos^n lobe of the half vector around the normal
#define MAT_BLEND 6u        // (1 - amount) * a + amount * b
#define MAT_ROUGH_CONDUCTOR 7u   // GGX microfacet metal: Fresnel of eta + i k, tinted
#define MAT_ROUGH_DIELECTRIC 8u  // GGX microfacet glass: reflection and refraction
#define MAT_METAL_ROUGH 9u       // glTF 2.0 metal-rough: GGX over a Lambertian base, mixed with a metal
#define MAT_BECKMANN_CONDUCTOR 10u  // CS184's microfacet conductor: Beckmann, the course's G and Fresnel
#define MAT_CS184_GLASS 11u         // CS184's glass: Schlick's Fresnel, tinted reflection and refraction, eta^2
#define MAT_CLEARCOAT 12u  // glTF's KHR_materials_clearcoat: an untinted GGX coat with its own normal over a base material
#define MAT_SHEEN 13u      // glTF's KHR_materials_sheen: a Charlie sheen over a base material, which it scales by its albedo
#define MAT_INTERFACE 14u  // the boundary of a participating medium that does not scatter (darts "material": null; media.glsl)
#define WP_MATERIAL_KINDS(X)                                                                                            \
  X(MAT_LAMBERTIAN, "lambertian", lambertian, LOBE_DIFFUSE)                                                             \
  X(MAT_LIGHT, "diffuse_light", no_lobe, LOBE_EMISSIVE)                                                                 \
  X(MAT_METAL, "metal", metal, LOBE_GLOSSY | LOBE_DELTA)                                                                \
  X(MAT_DIELECTRIC, "dielectric", dielectric, LOBE_DELTA | LOBE_TRANSMISSIVE)                                           \
  X(MAT_PHONG, "phong", phong, LOBE_GLOSSY)                                                                             \
  X(MAT_BLINN_PHONG, "blinn-phong", blinn_phong, LOBE_GLOSSY)                                                           \
  X(MAT_BLEND, "blend", no_lobe, LOBE_COMPOSITE)                                                                        \
  X(MAT_ROUGH_CONDUCTOR, "rough_conductor", rough_conductor, LOBE_GLOSSY | LOBE_DELTA | LOBE_PARAMS_YZW | LOBE_PARAMS2) \
  X(MAT_ROUGH_DIELECTRIC, "rough_dielectric", rough_dielectric,                                                         \
    LOBE_GLOSSY | LOBE_DELTA | LOBE_TRANSMISSIVE | LOBE_PARAMS_YZW)                                                     \
  X(MAT_METAL_ROUGH, "metal_rough", metal_rough, LOBE_DIFFUSE | LOBE_GLOSSY | LOBE_TRANSMISSIVE | LOBE_PARAMS_YZW) \
  X(MAT_BECKMANN_CONDUCTOR, "beckmann_conductor", beckmann_conductor, LOBE_GLOSSY | LOBE_PARAMS_YZW | LOBE_PARAMS2)        \
  X(MAT_CS184_GLASS, "cs184_glass", cs184_glass, LOBE_DELTA | LOBE_TRANSMISSIVE | LOBE_PARAMS_YZW | LOBE_PARAMS2)        \
  X(MAT_CLEARCOAT, "clearcoat", clearcoat, LOBE_GLOSSY | LOBE_LAYER | LOBE_PARAMS2)                                          \
  X(MAT_SHEEN, "sheen", sheen, LOBE_GLOSSY | LOBE_LAYER)                                                                \
  X(MAT_INTERFACE, "interface", no_lobe, LOBE_NULL)

// A conductor's params2.w (rough_conductor, beckmann_conductor) names its
// measured metal (METAL_*, metal_spectra.glsl): CONDUCTOR_NAMED (metal + 1),
// plus 1 for CS184's skeleton terms (beckmann_conductor.glsl); below
// CONDUCTOR_NAMED its eta and k are the RGB given. The spectral mode reads
// a named metal's eta and k per wavelength (spectral.glsl).
#define CONDUCTOR_NAMED 2.0f

// Texture kinds (Texture.info.x & TEX_TYPE_MASK), and the flag that selects
// solid mapping. Columns: id, name.
#define TEX_CONSTANT 0u
#define TEX_CHECKER 1u
#define TEX_MARBLE 2u
#define TEX_IMAGE 3u    // the environment map's included
#define TEX_FRESNEL 4u  // blend amounts only: dielectric reflectance at the hit
#define WP_TEXTURE_KINDS(X) \
  X(TEX_CONSTANT, "constant") X(TEX_CHECKER, "checker") X(TEX_MARBLE, "marble") X(TEX_IMAGE, "image") X(TEX_FRESNEL, "fresnel")
#define TEX_TYPE_MASK 0xffu
#define TEX_SOLID 0x100u  // look up at the mapped hit point, not at (u, v, 0)
#define TEX_UV1 0x200u    // look up at the second UV set (glTF's TEXCOORD_1)
// How an image texture wraps outside [0, 1] (glTF's sampler modes), u's in
// bits 12-13 of Texture.info.x and v's in bits 14-15.
#define TEX_WRAP_REPEAT 0u
#define TEX_WRAP_CLAMP 1u
#define TEX_WRAP_MIRROR 2u
#define TEX_WRAP_U_SHIFT 12u
#define TEX_WRAP_V_SHIFT 14u

// Light kinds: what next-event estimation samples. Columns: id, name.
#define LIGHT_AREA 0u         // emissive triangles, sampled by area
#define LIGHT_SPHERE 1u       // emissive spheres, sampled by solid angle
#define LIGHT_POINT 2u        // point lights: CS184's, glTF's
#define LIGHT_ENVIRONMENT 3u  // an environment map (also where it only replaces the background)
#define LIGHT_SPOT 4u         // spot lights (glTF's KHR_lights_punctual)
#define LIGHT_DIRECTIONAL 5u  // directional lights (glTF's KHR_lights_punctual, CS184's)
#define LIGHT_HEMISPHERE 6u   // uniform radiance from above a horizon, seen only by light sampling (CS184's ambient light)
#define WP_LIGHT_KINDS(X) \
  X(LIGHT_AREA, "area lights") X(LIGHT_SPHERE, "sphere lights") X(LIGHT_POINT, "point lights") X(LIGHT_ENVIRONMENT, "environment map") \
  X(LIGHT_SPOT, "spot lights") X(LIGHT_DIRECTIONAL, "directional lights") X(LIGHT_HEMISPHERE, "hemisphere lights")

// Participating media (Medium.info.x; media.glsl). Columns: id, name (darts'
// "media" types, src/media/*.cpp of darts-2022).
#define MEDIUM_VACUUM 0u       // nothing: light passes unchanged
#define MEDIUM_HOMOGENEOUS 1u  // the same coefficients everywhere
#define MEDIUM_NANOVDB 2u      // coefficients times a density read from a NanoVDB grid (FEATURE_MEDIA_GRID)
#define WP_MEDIUM_KINDS(X) X(MEDIUM_VACUUM, "vacuum") X(MEDIUM_HOMOGENEOUS, "homogeneous") X(MEDIUM_NANOVDB, "nanovdb")

// Other features a scene may use. Columns: id; name; the slots of
// Material.extra its materials fill (EXTRA_SLOT bits), which load_material
// fetches only where a compiled feature reads them; the slots of Lobe.extra
// its lobes read at the hit, which bsdf_at stores only where one does (on
// lavapipe every store to a lobe's arrays costs every path).
#define FEATURE_SPHERES 0u
#define FEATURE_SHADING_DATA 1u         // triangles with vertex normals or UVs
#define FEATURE_CMJ 2u                  // camera samples from correlated multi-jittered patterns (SAMPLER_CMJ)
#define FEATURE_EMISSION_TEXTURES 3u    // an emitting material whose radiance is not one constant colour
#define FEATURE_UNIFORM_HEMISPHERE 4u   // SCENE_FLAG_HEMISPHERE: directions uniform over the hemisphere (CS184 -H)
#define FEATURE_VERTEX_DATA 5u          // triangles with tangents, vertex colours or a second UV set (TriangleVertexData)
#define FEATURE_NORMAL_MAPS 6u          // a material with a normal map (Material.children.z)
#define FEATURE_ONE_SIDED 7u            // triangles seen from behind are not there (TRIANGLE_ONE_SIDED)
#define FEATURE_CUTOUTS 8u              // triangles cut out by their material's alpha (TRIANGLE_CUTOUT)
#define FEATURE_COSINE_EMISSION 9u      // a light material emitting in proportion to the cosine (params.x; CS184 3-2's light quads)
#define FEATURE_SPECULAR_TINT 10u       // metal-rough with a specular factor or colour other than 1 (KHR_materials_specular; params2)
#define FEATURE_VOLUME 11u              // metal-rough whose transmission refracts into an absorbing volume (KHR_materials_volume)
#define FEATURE_IRIDESCENCE 12u         // metal-rough under a thin film (KHR_materials_iridescence)
#define FEATURE_ANISOTROPY 13u          // metal-rough with anisotropic roughness (KHR_materials_anisotropy)
#define FEATURE_DISPERSION 14u          // a volume whose index of refraction depends on the wavelength (KHR_materials_dispersion)
#define FEATURE_MEDIA 15u               // participating media: the camera or a surface's side in a medium (media.glsl)
#define FEATURE_MEDIA_GRID 16u          // a medium whose density a NanoVDB grid holds (MEDIUM_NANOVDB; pnanovdb.glsl)
#define FEATURE_INSTANCES 17u           // meshes placed by instances: a two-level BVH (Instance; traverse_*.glsl)
#define FEATURE_DIFFUSE_TRANSMISSION 18u  // metal-rough's diffuse base transmitting too (KHR_materials_diffuse_transmission)
#define FEATURE_SPECTRAL 19u            // paths carry radiance at sampled wavelengths, RGB inputs uplifted (spectral.glsl)
#define FEATURE_SPECTRAL_TABLE 20u      // the spectral mode uplifts reflectances the kernels compute, through the table (spectral.glsl)
#define FEATURE_SPECTRAL_UNBOUNDED_TABLE 21u  // and radiances or coefficients they compute
#define EXTRA_SLOT(i) (1u << (i))
// Metal-rough's slots (materials/metal_rough.glsl says what each holds).
#define MR_TEXTURES 0     // Material.extra: the extensions' textures
#define MR_VOLUME 1       // Material.extra: KHR_materials_volume and _dispersion
#define MR_IRIDESCENCE 2  // Material.extra: KHR_materials_iridescence
#define MR_ANISOTROPY 3   // Material.extra: KHR_materials_anisotropy
#define MR_DIFFUSE_TRANSMISSION 4           // Material.extra: KHR_materials_diffuse_transmission's factors
#define MR_DIFFUSE_TRANSMISSION_TEXTURES 5  // Material.extra: and its textures
#define MR_LOBE_FILM 0        // Lobe.extra: the thin film at the hit
#define MR_LOBE_ANISOTROPY 1  // Lobe.extra: the anisotropy at the hit
#define MR_LOBE_DIFFUSE_TRANSMISSION 2  // Lobe.extra: the diffuse transmission at the hit
#define WP_FEATURES(X)                                                                                              \
  X(FEATURE_SPHERES, "spheres", 0u, 0u) X(FEATURE_SHADING_DATA, "vertex normals or UVs", 0u, 0u)                    \
  X(FEATURE_CMJ, "cmj sampler", 0u, 0u) X(FEATURE_EMISSION_TEXTURES, "textured emission", 0u, 0u)                   \
  X(FEATURE_UNIFORM_HEMISPHERE, "uniform hemisphere sampling", 0u, 0u)                                              \
  X(FEATURE_VERTEX_DATA, "tangents, vertex colours or a second UV set", 0u, 0u)                                     \
  X(FEATURE_NORMAL_MAPS, "normal maps", 0u, 0u) X(FEATURE_ONE_SIDED, "one-sided triangles", 0u, 0u)                 \
  X(FEATURE_CUTOUTS, "alpha cut-outs", 0u, 0u) X(FEATURE_COSINE_EMISSION, "cosine emission", 0u, 0u)                \
  X(FEATURE_SPECULAR_TINT, "specular tint", EXTRA_SLOT(MR_TEXTURES), 0u)                                            \
  X(FEATURE_VOLUME, "volumes", EXTRA_SLOT(MR_VOLUME), 0u)                                                           \
  X(FEATURE_IRIDESCENCE, "iridescence", EXTRA_SLOT(MR_TEXTURES) | EXTRA_SLOT(MR_IRIDESCENCE), EXTRA_SLOT(MR_LOBE_FILM)) \
  X(FEATURE_ANISOTROPY, "anisotropy", EXTRA_SLOT(MR_ANISOTROPY), EXTRA_SLOT(MR_LOBE_ANISOTROPY))                    \
  X(FEATURE_DISPERSION, "dispersion", EXTRA_SLOT(MR_VOLUME), 0u)                                                    \
  X(FEATURE_MEDIA, "participating media", 0u, 0u) X(FEATURE_MEDIA_GRID, "grid media", 0u, 0u)                       \
  X(FEATURE_INSTANCES, "instances", 0u, 0u)                                                                        \
  X(FEATURE_DIFFUSE_TRANSMISSION, "diffuse transmission",                                                          \
    EXTRA_SLOT(MR_DIFFUSE_TRANSMISSION) | EXTRA_SLOT(MR_DIFFUSE_TRANSMISSION_TEXTURES), EXTRA_SLOT(MR_LOBE_DIFFUSE_TRANSMISSION)) \
  X(FEATURE_SPECTRAL, "spectral", 0u, 0u) X(FEATURE_SPECTRAL_TABLE, "spectral uplift table", 0u, 0u) \
  X(FEATURE_SPECTRAL_UNBOUNDED_TABLE, "spectral uplift table for light", 0u, 0u)

// The bit of a kind in its mask, and whether the code being compiled holds a
// kind. *_KINDS_OF_SCENE are the masks: specialization constants in the
// kernels (kernel.glsl), every bit in C++ (shader_cpp.h).
#define KIND_BIT(id) (1u << (id))
#define MATERIAL_COMPILED(id) ((MATERIAL_KINDS_OF_SCENE & KIND_BIT(id)) != 0u)
#define TEXTURE_COMPILED(id) ((TEXTURE_KINDS_OF_SCENE & KIND_BIT(id)) != 0u)
#define LIGHT_COMPILED(id) ((LIGHT_KINDS_OF_SCENE & KIND_BIT(id)) != 0u)
#define FEATURE_COMPILED(id) ((FEATURES_OF_SCENE & KIND_BIT(id)) != 0u)
// Whether any of several light kinds is compiled, as one mask test: Mesa
// 22.3's SPIR-V reader refuses a logical or of specialization constants.
#define ANY_LIGHT_COMPILED(bits) ((LIGHT_KINDS_OF_SCENE & (bits)) != 0u)
#define PUNCTUAL_LIGHT_BITS (KIND_BIT(LIGHT_POINT) | KIND_BIT(LIGHT_SPOT) | KIND_BIT(LIGHT_DIRECTIONAL) | KIND_BIT(LIGHT_HEMISPHERE))
// The punctual kinds that read PointLight.direction (types.glsl).
#define LIGHTS_READING_DIRECTION (KIND_BIT(LIGHT_SPOT) | KIND_BIT(LIGHT_DIRECTIONAL) | KIND_BIT(LIGHT_HEMISPHERE))
// Whether surface hits carry tangents: normal maps and anisotropy read them.
#define TANGENTS_COMPILED ((FEATURES_OF_SCENE & (KIND_BIT(FEATURE_NORMAL_MAPS) | KIND_BIT(FEATURE_ANISOTROPY))) != 0u)
#define ALL_KINDS 0xffffffffu

// Bit `slot` of the features' columns above: whether a compiled feature reads
// slot `slot` of Material.extra (material_extra_compiled, records.glsl) or of
// Lobe.extra (lobe_extra_compiled, bsdf.glsl). They name those functions'
// parameter, so that each call folds to one mask.
#define WP_READS_MATERIAL_EXTRA(id, name, material, lobe) | ((((material) >> slot) & 1u) != 0u ? KIND_BIT(id) : 0u)
#define WP_READS_LOBE_EXTRA(id, name, material, lobe) | ((((lobe) >> slot) & 1u) != 0u ? KIND_BIT(id) : 0u)

// Whether a compiled material kind reads params.yzw or params2: kernels
// without one carry one float of parameters per lobe (on lavapipe every
// copy of the unused lanes costs, in bsdf_sample's pick of a lobe most).
#define WP_READS_PARAMS_YZW(id, name, prefix, lobes) | (((lobes) & LOBE_PARAMS_YZW) != 0u ? KIND_BIT(id) : 0u)
#define WP_READS_PARAMS2(id, name, prefix, lobes) | (((lobes) & LOBE_PARAMS2) != 0u ? KIND_BIT(id) : 0u)
#define MATERIAL_PARAMS_YZW_COMPILED ((MATERIAL_KINDS_OF_SCENE & (0u WP_MATERIAL_KINDS(WP_READS_PARAMS_YZW))) != 0u)
// (One test of two masks: Mesa 22.3 refuses a logical or of specialization constants.)
#define MATERIAL_PARAMS2_COMPILED \
  (((MATERIAL_KINDS_OF_SCENE & (0u WP_MATERIAL_KINDS(WP_READS_PARAMS2))) | (FEATURES_OF_SCENE & KIND_BIT(FEATURE_SPECULAR_TINT))) != 0u)
// Whether a compiled kind is a layer or a blend, which bsdf_at flattens into
// several lobes.
#define WP_IS_COMPOSITE(id, name, prefix, lobes) | (((lobes) & (LOBE_COMPOSITE | LOBE_LAYER)) != 0u ? KIND_BIT(id) : 0u)
#define WP_IS_LAYER(id, name, prefix, lobes) | (((lobes) & LOBE_LAYER) != 0u ? KIND_BIT(id) : 0u)
#define COMPOSITE_MATERIALS_COMPILED ((MATERIAL_KINDS_OF_SCENE & (0u WP_MATERIAL_KINDS(WP_IS_COMPOSITE))) != 0u)
#define LAYER_MATERIALS_COMPILED ((MATERIAL_KINDS_OF_SCENE & (0u WP_MATERIAL_KINDS(WP_IS_LAYER))) != 0u)

#endif  // WP_KINDS_GLSL
