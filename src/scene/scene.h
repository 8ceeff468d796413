// scene.h — a scene as the importers produce it, in no renderer's layout:
// the camera and render settings, world-space triangles, spheres with their
// transforms, and descriptions of materials, textures, images and lights by
// their kinds (kinds.glsl). Every importer (darts JSON today) fills one, and
// only compile_scene (src/render) packs it into the records the kernels read.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "../../shaders/shared/common.glsl"
#include "../../shaders/shared/limits.glsl"
#include "image/image_file.h"
#include "scene/kinds.h"
#include "scene/nanovdb_grid.h"
#include "scene/texture_image.h"
#include "shader/types.h"

namespace wp {

struct Camera {
  std::string name;         // a glTF camera's (--camera picks it; empty: the scene's only camera)
  glm::mat4 toWorld{1.0f};  // camera looks down its -Z axis
  float vfovDegrees = 90.0f;
  float orthoHalfHeight = 0.0f;  // > 0: an orthographic camera seeing this half-height (glTF's ymag); 0: perspective
  int width = 512;
  int height = 512;
  float focusDistance = 1.0f;
  float apertureRadius = 0.0f;
  // The horizontal over the vertical tangent of the half-fields; 0: width /
  // height (square pixels). A CS184 camera settings file sets both fields.
  float aspect = 0.0f;
  // A new resolution keeps the focal length in pixels, cropping or widening
  // the frame about its centre, instead of the vertical field (CS184's
  // windowless renders: set_resize_keeps_focal_length).
  bool resizeKeepsFocalLength = false;
  // The part of the frame the image covers (x, y of its top-left corner,
  // width, height, as fractions of the frame): CS184's -p renders a cell.
  glm::vec4 window{0.0f, 0.0f, 1.0f, 1.0f};
};

// Gives the camera a new resolution: the vertical field stays, or (resize
// keeps focal length) the focal length in pixels does.
void set_resolution(Camera& camera, int width, int height);

// Makes the camera see one cell of its frame, as CS184's -p renders one: the
// DX x DY pixels from column X and row Y, rows counted from the bottom as
// the course counts them; the image is then that cell. Throws InputError
// where the cell leaves the frame.
void set_cell(Camera& camera, int x, int y, int dx, int dy);

// How the BVH builder splits a node's primitives (bvh.h): binned SAH; the
// clustered SAH build, faster for large scenes (binned SAH over Morton-order
// clusters at the top, the exact SAH sweep for small nodes); the middle of the
// centroids' extent; or two halves by count (darts' "middle" and "equal").
// Auto, what a scene gets unless it names a method, is one of the two SAH
// builds by the scene's size (split_for in bvh.h).
enum class SplitMethod { Sah, Middle, Equal, ClusteredSah, Auto };

struct AcceleratorSettings {
  int maxLeafSize = 4;
  SplitMethod split = SplitMethod::Auto;
};

// PathHemisphere: BSDF-sampling-only path tracing with directions uniform
// over the hemisphere (CS184's -H), a wavepath extension of the darts names.
enum class IntegratorKind { PathMis, PathNee, PathMats, PathMixture, PathHemisphere, Normals, AmbientOcclusion, PhotonMapper };

enum class SamplerKind { Independent, Cmj };

// The integrator and sampler names scene files and the command line use
// (darts' names); nullopt for an unknown one. The list is for error messages.
std::optional<IntegratorKind> integrator_named(const std::string& name);
std::optional<SamplerKind> sampler_named(const std::string& name);
extern const char* const kIntegratorNames;  // "normals, ao, path tracer mats, ..."
std::string integrator_kind_name(IntegratorKind kind);  // its darts name

struct IntegratorSettings {
  IntegratorKind kind = IntegratorKind::PathMis;
  int maxBounces = 64;
  int russianRouletteDepth = 3;  // first depth at which paths may be ended at random
  float misPower = 2.0f;          // exponent of the MIS heuristic (darts "power"): 2 power, 1 balance heuristic
  // The photon mapper's (photons.glsl): photons traced from the lights, the
  // gather's search radius and count (darts' photon map test's "search
  // radius" and "search count"; count 0: every photon within the radius),
  // and which photons (the map is the same for every render of a seed, so
  // partial renders merge and renderers compare on one map).
  uint32_t photons = 200000;
  float searchRadius = 0.1f;
  uint32_t searchCount = 50;
  uint32_t photonSeed = 0;
  // Render spectrally (spectral.glsl): the darts integrator's "spectral".
  bool spectral = false;
};

struct SceneTriangle {
  glm::vec3 v[3];
  uint32_t material;
  // Its per-vertex normals and UVs (Scene::triangleShading), or WP_INVALID:
  // the normal is flat and the UVs are the barycentrics. Kept apart because
  // most triangles of large scanned meshes have none: 44 bytes a triangle
  // instead of 104.
  uint32_t shading = WP_INVALID;
};

struct SceneTriangleShading {
  bool hasNormals = false;
  bool hasUvs = false;
  glm::vec3 n[3]{};
  glm::vec2 uv[3]{};
  // glTF's further vertex data (TriangleVertexData), where the mesh has any.
  bool hasVertexData = false;
  glm::vec4 tangent[3]{};  // xyz world-space tangent (zero: derived from the UVs), w handedness
  glm::vec4 color[3]{glm::vec4(1.0f), glm::vec4(1.0f), glm::vec4(1.0f)};
  bool hasUv1 = false;
  glm::vec2 uv1[3]{};      // the second UV set (without one, the first serves)
};

struct SceneSphere {
  glm::mat4 toWorld;  // places the unit sphere
  uint32_t material;
};

// A colour (or scalar) over a surface, of a texture kind (TEX_*).
struct SceneTexture {
  uint32_t kind = TEX_CONSTANT;
  glm::vec3 color{0.0f};     // constant: the colour; marble: the base colour; image: a factor (glTF's)
  glm::vec3 veins{0.0f};     // marble: the veins' colour
  float alpha = 1.0f;        // constant and image: opacity (an image's alpha times it)
  float scale = 1.0f;        // checker and marble: squares or pattern per unit
  float ior = 1.5f;          // fresnel: the index whose reflectance is the value
  uint32_t even = WP_INVALID;   // checker: the textures of its even and odd squares
  uint32_t odd = WP_INVALID;
  uint32_t image = WP_INVALID;  // image: index into Scene::images
  bool solid = false;           // looked up at the hit point, not at (u, v, 0)
  bool secondUvSet = false;     // looked up at the second UV set (glTF's TEXCOORD_1)
  uint32_t wrapU = TEX_WRAP_REPEAT;  // image: how it extends beyond [0, 1] (TEX_WRAP_*)
  uint32_t wrapV = TEX_WRAP_REPEAT;
  glm::mat4 mapping{1.0f};      // applied to the lookup point
};

// A material of a material kind (MAT_*). Colours are textures (indices into
// Scene::textures), so any colour may vary over the surface.
struct SceneMaterial {
  uint32_t kind = MAT_LAMBERTIAN;
  std::string name;  // for messages
  // What the kind's module packed (scene/materials/NAME.cpp): the kernels'
  // record (types.glsl's Material) holding the kind's textures, parts and
  // parameters. compile_scene adds the kind, the surface's properties below,
  // its sort key and its media.
  shader::Material record = blank_material_record();
  uint32_t emission = WP_INVALID;  // emitted radiance (any kind may emit; diffuse_light only emits)
  uint32_t normalMap = WP_INVALID; // an image texture of tangent-space normals, its factor (scale, scale, 1)
  // glTF's alphaMode: 0 opaque; > 0 a cut-out where the albedo texture's
  // alpha (times the vertex colour's) is below it (MASK); < 0 stochastic
  // transparency, the alpha the chance of being there (BLEND). Not for blends.
  float alphaCutoff = 0.0f;
  bool doubleSided = true;         // false: triangles are not there from behind (glTF's doubleSided)
  // Participating media: where `boundsMedia`, the surface separates the
  // medium behind it (against its geometric normal) from the one in front
  // (Scene::media indices, WP_INVALID the vacuum); otherwise a ray crossing
  // it stays in its medium.
  bool boundsMedia = false;
  uint32_t interior = WP_INVALID;
  uint32_t exterior = WP_INVALID;

  // What every kind keeps in the same place of its record: its colour
  // texture (a layer's factor or colour), its second texture (a blend's
  // amount, metal-rough's metallic-roughness, a layer's roughness), and a
  // blend's parts or a layer's base (part 0).
  uint32_t albedo() const { return record.info.y; }
  uint32_t amount() const { return record.info.w; }
  uint32_t part(int i) const { return i == 0 ? record.children.x : record.children.y; }
  static shader::Material blank_material_record();
};

// A participating medium (darts' "media"; media.glsl): coefficients per unit
// length, and the Henyey-Greenstein asymmetry of its phase function.
struct SceneMedium {
  uint32_t kind = MEDIUM_HOMOGENEOUS;
  std::string name;  // for messages
  glm::vec3 sigmaA{0.0f};  // absorption (a grid medium's: per unit density)
  glm::vec3 sigmaS{0.0f};  // scattering (a grid medium's: per unit density)
  glm::vec3 sigmaN{0.0f};  // null (fictitious particles; homogeneous media only)
  float g = 0.0f;
  // A grid medium (MEDIUM_NANOVDB): its density grid (shared by the media
  // that read the same grid), where the grid's world space sits in the scene
  // (darts' "transform"), and its majorant cells (0: default_majorant_cells).
  std::shared_ptr<const DensityGrid> grid;
  glm::mat4 gridToScene{1.0f};
  glm::uvec3 majorantCells{0u};
};

// The majorant cells a grid medium is tracked through: its own, or the default.
inline glm::uvec3 majorant_cells(const SceneMedium& m) {
  return m.majorantCells.x > 0u ? m.majorantCells : default_majorant_cells(*m.grid);
}

// A punctual light (PointLight in types.glsl): a point light's radiant
// intensity (W/sr) in every direction (CS184's, glTF's); a spot light's
// within its cone, falling off between the inner and the outer cone's
// half-angles; or a directional light's irradiance (W/m^2) arriving across
// `direction`, the way its light travels.
//
// A hemisphere light (CS184's ambient light) sends radiance `intensity`
// from every direction above the horizon of the zenith `direction`; no ray
// meets it, only light sampling sees it. A point light without `falloff`
// (CS184's) gives every distance the intensity's irradiance of 1 m.
struct ScenePointLight {
  enum class Kind { Point, Spot, Directional, Hemisphere };
  Kind kind = Kind::Point;
  glm::vec3 position{0.0f};
  glm::vec3 intensity{0.0f};        // W/sr; directional: W/m^2; hemisphere: W/(m^2 sr)
  glm::vec3 direction{0, 0, -1};    // spot, directional: unit, the way the light goes; hemisphere: the zenith
  bool falloff = true;              // point: inverse-square falloff
  float cosInner = 1.0f;            // spot: cosines of the cones' half-angles (inner >= outer)
  float cosOuter = 0.70710678f;
};

// A triangle mesh as importers read it (OBJ today, the formats to come), in
// its own space: each corner of a triangle indexes its position, and apart
// its normal and its UV (WP_INVALID: the corner has none), as OBJ and
// COLLADA store them (glTF's one index serves all three). add_mesh places it
// into a scene.
struct SceneMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  std::vector<uint32_t> positionIndices;  // three per triangle
  std::vector<uint32_t> normalIndices;    // three per triangle
  std::vector<uint32_t> uvIndices;        // three per triangle
  // glTF's further vertex data, indexed by positionIndices, each empty or one
  // per position: tangents (xyz, w handedness), RGBA colours, a second UV set.
  std::vector<glm::vec4> tangents;
  std::vector<glm::vec4> colors;
  std::vector<glm::vec2> uvs1;
  std::vector<uint32_t> materials;        // per triangle: the mesh's material slot, or WP_INVALID
  size_t triangle_count() const { return materials.size(); }
};

// A mesh that instances place (Scene::instances), in its own space: its
// triangles, and their shading data, which their `shading` indexes. Built
// by add_to_instanced_mesh; compile_scene gives it a bottom-level BVH of its own.
struct SceneInstancedMesh {
  std::vector<SceneTriangle> triangles;
  std::vector<SceneTriangleShading> shading;
  glm::vec3 lo{INFINITY}, hi{-INFINITY};  // the triangles' bounds
};

// A triangle of a CS184 scene lying in an area light's plane (as the
// course's lamp meshes do, to 5e-8: one plane in floats) and overlapping
// the light, with its corners' heights above that plane along the
// direction the light faces, as the course computes them in double (its
// positions parsed as floats, its matrices as doubles). The sign says which
// of the two surfaces the course's camera meets where the 3-2 skeleton
// makes the light a quad too (use_cs184_3_2_skeleton).
struct Cs184LightPlaneContact {
  uint32_t triangle;  // into Scene::triangles
  uint32_t light;     // the light's first triangle in Scene::lightOnlyTriangles
  double height[3];   // > 0: in front of the light, on the side it faces
};
// How far behind its light's plane the 3-2 skeleton puts the light's quad,
// in units of the light's scale (its largest coordinate, at least 1): far
// above the floats' rounding there, far below what a camera resolves.
inline constexpr double kCs184QuadSetBack = 4e-5;

// A placement of an instanced mesh.
struct SceneInstance {
  uint32_t mesh;  // index into Scene::instancedMeshes
  glm::mat4 toWorld;
};

// One of the cameras a scene file holds, which --camera may pick by name or
// index; `problem` says why it cannot be used (an orthographic camera).
struct NamedCamera {
  std::string name;
  int index = 0;
  Camera camera;
  std::string problem;
};

// Luminous efficacy (lm/W) of 555 nm light, by which photometric light
// units (glTF's candela and lux) become radiometric ones.
inline constexpr double kLumensPerWatt = 683.0;

struct Scene {
  std::string sourcePath;
  // Every file the scene was read from, in the order read: the scene file,
  // then meshes, their material libraries and images. A render's identity
  // hashes their contents (render/partial.h).
  std::vector<std::string> inputFiles;
  Camera camera;
  std::vector<NamedCamera> cameras;  // every camera of a glTF file, in the order of its node tree
  int samplesPerPixel = 1;
  SamplerKind sampler = SamplerKind::Independent;
  glm::vec3 background{0.0f};
  // The background is the white sky an importer added because the file has
  // no light worth the name (default_sky_wanted); the command line says so
  // when it renders with it (apply_environment, load_scene.h).
  bool defaultSky = false;
  // An image texture used as an equirectangular environment map in place of
  // the constant background, or WP_INVALID.
  uint32_t environment = WP_INVALID;
  AcceleratorSettings accelerator;
  IntegratorSettings integrator;
  std::vector<SceneMaterial> materials;
  std::vector<SceneTexture> textures;  // materials refer to these by index
  std::vector<LinearImage> images;     // image textures refer to these by index
  std::vector<ScenePointLight> pointLights;
  std::vector<SceneMedium> media;
  uint32_t cameraMedium = WP_INVALID;  // the medium the camera sits in (index into media), WP_INVALID the vacuum
  std::vector<SceneTriangle> triangles;
  std::vector<SceneTriangleShading> triangleShading;  // SceneTriangle::shading indexes it
  std::vector<SceneSphere> spheres;
  // Meshes placed by instances (glTF's meshes that several nodes place):
  // each mesh's triangles are kept once, in its own space (settle_instances).
  std::vector<SceneInstancedMesh> instancedMeshes;
  std::vector<SceneInstance> instances;
  // Emissive triangles that no ray meets, lighting the scene through light
  // sampling alone (CS184's area lights, which are not geometry there).
  std::vector<SceneTriangle> lightOnlyTriangles;
  // Triangles lying in those lights' planes (CS184's lamp meshes).
  std::vector<Cs184LightPlaneContact> cs184LightPlaneContacts;
  // CS184's estimator (SCENE_FLAG_CS184; docs/scene-format.md, "CS184"):
  // emissive surfaces are not in the light table, so they light nothing and
  // only the camera and specular bounces see them.
  bool cs184Estimator = false;
  bool cs184LatLong = false;  // the environment map in CS184's lat-long layout
  int cs184Skeleton = 0;      // CS184 scenes: the skeleton whose scene conventions are followed, 31 (3-1) or 32 (3-2)
  EightBitCurve eightBitCurve = EightBitCurve::Srgb;  // how its 8-bit images encode radiance, as its format's renderer writes them
};

// Finite inputs can still be placed past the range of floats by the product
// of their transforms; importers refuse such geometry where it is placed,
// with this phrase.
inline bool is_finite(glm::vec3 p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}
inline constexpr const char* kPastFloatRange = "the transforms place it past the range of floats";

// Places `mesh`, transformed by `toWorld`, into `scene` as world-space
// triangles: the mesh's material slot i becomes scene material slots[i], a
// triangle without one `unassigned` (WP_INVALID: that is an error).
// Degenerate triangles are dropped (they can never be hit); a triangle is
// smooth-shaded where every corner has a nonzero normal (carried through
// the normal matrix), and has UVs where every corner has one. A problem is
// passed to `fail` as "triangle N: ..." (N from 1); `fail` must throw.
void add_mesh(Scene& scene, const SceneMesh& mesh, const glm::mat4& toWorld, const std::vector<uint32_t>& slots,
              uint32_t unassigned, const std::function<void(const std::string&)>& fail);

// A new, empty mesh that instances will place (Scene::instancedMeshes);
// returns its index.
uint32_t add_instanced_mesh(Scene& scene);
// Adds `mesh` to instanced mesh `into`, as add_mesh adds one to the scene but
// kept in its own space: a mesh of several parts (glTF's primitives) is one
// instanced mesh.
void add_to_instanced_mesh(Scene& scene, uint32_t into, const SceneMesh& mesh, const std::vector<uint32_t>& slots,
                           uint32_t unassigned, const std::function<void(const std::string&)>& fail);
// Places instanced mesh `mesh` by `toWorld`. A transform that places it
// past the range of floats is passed to `fail` (which must throw); a
// singular one places nothing (its triangles could never be hit).
void add_instance(Scene& scene, uint32_t mesh, const glm::mat4& toWorld, const std::function<void(const std::string&)>& fail);
// Keeps as instances only what gains from it: a mesh placed once, and a
// mesh that emits light (whose every instance's triangles are lights in the
// emitter table, each with its world-space area), are flattened into world
// triangles as add_mesh places them; meshes no instance places are dropped.
// Importers call it once they have placed everything.
void settle_instances(Scene& scene);
// Flattens every instance into world triangles (the scene as it renders
// without instancing; `--flatten-instances`).
void flatten_instances(Scene& scene);
// Whether a file with no punctual light should get the default white sky:
// true unless its emitters light it (docs/scene-format.md, "glTF 2.0"):
// emitters brighter than that sky (radiance above 1 in some channel, which
// glTF reaches only through KHR_materials_emissive_strength) emitting in
// all at least kEmittersLightTheScene of what the sky would pour onto the
// scene's bounding box. Labels, screens and LEDs, authored for viewers,
// emit no more than a white surface under their environment returns; a
// lamp's filament on a product model is a speck against the sky.
bool default_sky_wanted(const Scene& scene);
inline constexpr double kEmittersLightTheScene = 0.05;

// Whether a material of the scene may emit light (it has an emission
// texture that is not constant black).
bool material_emits(const Scene& scene, uint32_t material);
// The triangles the scene's instances place, each mesh's counted once per
// instance.
size_t instanced_triangle_count(const Scene& scene);

// Per-vertex tangents for a normal map on `mesh`, whose corners index
// positions, normals and UVs alike (glTF's single index), from the UV set
// `uvs` (the mesh's first or second): each vertex's is the sum of the
// tangents d p / d u of the triangles around it, made orthogonal to its
// normal, with the handedness of their d p / d v, so that tangents turn
// smoothly across a curved surface as its normals do (the idea of
// MikkTSpace, without its seam rules). Zero where they degenerate (the
// kernels then derive a triangle's own); empty without normals or UVs.
std::vector<glm::vec4> smooth_tangents(const SceneMesh& mesh, const std::vector<glm::vec2>& uvs);

// The bounds of box [lo, hi] placed by `toWorld` (of its eight corners placed).
std::pair<glm::vec3, glm::vec3> placed_bounds(glm::vec3 lo, glm::vec3 hi, const glm::mat4& toWorld);
// The bounds of the scene's triangles, spheres and instances (lo > hi where it has none).
std::pair<glm::vec3, glm::vec3> scene_bounds(const Scene& scene);

// A camera that frames the bounds of the scene's triangles and spheres:
// looking down -Z and slightly down from in front of them, 40 degrees of
// vertical field, their bounding sphere filling the narrower side, 800x600.
Camera framing_camera(const Scene& scene);

// Selects the camera named `which` (a name, or its index in the file) as
// the scene's camera; throws InputError naming the cameras there are when
// none is called that.
void choose_camera(Scene& scene, const std::string& which);

// A texture of one colour everywhere.
SceneTexture constant_texture(glm::vec3 color);

// Appends a texture; returns its index. (Materials: add_material, scene/materials/material_module.h.)
uint32_t add_texture(Scene& scene, const SceneTexture& texture);

// Loads an image file (see texture_image.h) into the scene's images and
// returns an image texture of it (identity mapping), not yet added. `where`
// is appended to error messages.
SceneTexture image_texture(Scene& scene, const std::string& path, const std::string& where);
// The same, added to the scene; returns the texture's index.
uint32_t add_image_texture(Scene& scene, const std::string& path, const std::string& where);

}  // namespace wp
